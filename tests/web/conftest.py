"""Fixtures of the explorer's tests: the ASGI test client, a live loopback server, a browser."""

import shutil
import socket
import tempfile
import threading
import time
import warnings

import pytest

from sandlight.web import Limits, create_app

with warnings.catch_warnings():  # Starlette 1.x prefers httpx2; httpx is what the project depends on
    warnings.simplefilter("ignore")
    from starlette.testclient import TestClient

#: Small limits, so that the limit tests need no large requests.
TEST_LIMITS = Limits(max_rays=5000, max_upload_bytes=64 * 1024, max_jobs_per_client=2)


@pytest.fixture(scope="module")
def client():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with TestClient(create_app(TEST_LIMITS), base_url="http://127.0.0.1") as c:
            yield c


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture(scope="module")
def live_server():
    """A uvicorn server on 127.0.0.1 in a thread; yields its base URL and the app."""
    import uvicorn

    app = create_app(TEST_LIMITS)
    port = _free_port()
    server = uvicorn.Server(uvicorn.Config(app, host="127.0.0.1", port=port, log_level="warning"))
    thread = threading.Thread(target=server.run, daemon=True)
    thread.start()
    deadline = time.monotonic() + 30
    while not server.started:
        if time.monotonic() > deadline or not thread.is_alive():
            raise RuntimeError("the test server did not start")
        time.sleep(0.05)
    yield f"http://127.0.0.1:{port}", app
    server.should_exit = True
    thread.join(timeout=10)


CHROMIUM_FLAGS = (
    "--headless=new",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--window-size=1400,1500",
)


@pytest.fixture(scope="module")
def browser():
    """Headless Chromium from the system packages, driven by selenium; skipped when absent."""
    chromium, driver_path = shutil.which("chromium"), shutil.which("chromedriver")
    if chromium is None or driver_path is None:
        pytest.skip("Chromium and ChromeDriver are not installed (apt-get install chromium chromium-driver)")
    webdriver = pytest.importorskip("selenium.webdriver", reason="selenium is not installed (pip install selenium)")
    from selenium.webdriver.chrome.service import Service

    profile = tempfile.mkdtemp(prefix="sandlight-chromium-")
    options = webdriver.ChromeOptions()
    options.binary_location = chromium
    for flag in CHROMIUM_FLAGS:
        options.add_argument(flag)
    options.add_argument(f"--user-data-dir={profile}")
    driver = webdriver.Chrome(service=Service(driver_path), options=options)
    try:
        yield driver
    finally:
        driver.quit()
        shutil.rmtree(profile, ignore_errors=True)
