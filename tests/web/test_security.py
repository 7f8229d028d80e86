"""Safety of the explorer: headers on every answer, request limits, host and origin checks, the
page's assets, and a bug answered with a generic 500 (never a traceback)."""

import warnings

import pytest

from sandlight.web import create_app, routes, spectra
from sandlight.web.errors import INTERNAL_MESSAGE
from sandlight.web.security import SECURITY_HEADERS

with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    from starlette.testclient import TestClient


@pytest.mark.parametrize(
    ("method", "path"),
    [("GET", "/"), ("GET", "/static/explorer.js"), ("GET", "/api/schema"), ("GET", "/nope"), ("POST", "/api/validate")],
)
def test_every_answer_has_the_security_headers(client, method, path):
    res = client.request(method, path, content=b"{}", headers={"content-type": "application/json"})
    for name, value in SECURITY_HEADERS.items():
        assert res.headers[name] == value, (path, name)
    csp = res.headers["content-security-policy"]
    assert "default-src 'none'" in csp and "script-src 'self'" in csp and "unsafe-inline" not in csp
    if path.startswith("/api/"):
        assert res.headers["cache-control"] == "no-store"


def test_the_page_and_its_assets_are_served_from_the_package_only(client):
    page = client.get("/")
    assert page.status_code == 200 and page.headers["content-type"].startswith("text/html")
    assert '<script type="module" src="/static/explorer.js">' in page.text
    assert "http://" not in page.text and "https://" not in page.text  # no CDN: works offline
    assert client.get("/static/explorer.css").headers["content-type"].startswith("text/css")
    for name in ("app.py", "..%2Fapp.py", "../app.py", "%2e%2e/%2e%2e/errors.py"):
        res = client.get(f"/static/{name}")
        assert res.status_code == 404 and "import" not in res.text, name


def test_unknown_routes_and_methods_are_json_refusals(client):
    res = client.get("/api/nothing")
    assert res.status_code == 404 and res.json()["error"] == "http"
    res = client.get("/api/spectrum")
    assert res.status_code == 405 and res.json()["error"] == "http"


def test_a_body_over_the_limit_is_refused_before_it_is_read(client):
    limit = client.app.state.limits.max_body_bytes
    res = client.post(
        "/api/spectrum",
        content=b'{"sample": {}, "x": "' + b"a" * limit + b'"}',
        headers={"content-type": "application/json"},
    )
    assert res.status_code == 413 and res.json()["error"] == "limit" and f"{limit:,} bytes" in res.json()["message"]

    def chunks():  # no Content-Length: counted as it arrives
        for _ in range(limit // 1000 + 2):
            yield b" " * 1000

    res = client.post("/api/spectrum", content=chunks(), headers={"content-type": "application/json"})
    assert res.status_code == 413 and res.json()["error"] == "limit"


def test_other_host_names_are_not_answered(client):
    res = client.get("/api/schema", headers={"host": "evil.example"})
    assert res.status_code == 400
    assert client.get("/api/schema", headers={"host": "testserver"}).status_code == 400
    assert client.get("/api/schema", headers={"host": "127.0.0.1:8765"}).status_code == 200
    assert client.get("/api/schema", headers={"host": "localhost:8765"}).status_code == 200


def test_requests_sent_by_a_page_of_another_site_are_refused(client):
    body = {"sample": "red-dune", "rays": 10, "wavelengths_nm": [500]}
    res = client.post("/api/jobs/reflectance", json=body, headers={"origin": "http://evil.example"})
    assert res.status_code == 403 and res.json()["error"] == "origin"
    res = client.post("/api/spectrum", json={}, headers={"origin": "null"})
    assert res.status_code == 403
    res = client.post("/api/spectrum", json={}, headers={"origin": "http://127.0.0.1"})
    assert res.status_code == 200


def test_a_bug_is_a_generic_500_without_a_traceback(monkeypatch, caplog):
    def broken(samples):
        raise RuntimeError("secret internal detail")

    monkeypatch.setattr(spectra, "spectrum_answers", broken)
    assert routes.spectra is spectra
    with TestClient(create_app(), base_url="http://127.0.0.1", raise_server_exceptions=False) as c:
        res = c.post("/api/spectrum", json={"sample": "red-dune"})
        ok = c.post("/api/validate", json={"sample": "red-dune"})
    assert res.status_code == 500
    assert res.json() == {"error": "internal", "message": INTERNAL_MESSAGE}
    assert "secret" not in res.text and "Traceback" not in res.text
    assert "secret internal detail" in caplog.text  # the details are in the server's log
    assert ok.status_code == 200  # user mistakes and good requests are unaffected
