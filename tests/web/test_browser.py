"""The explorer in a real browser (headless Chromium from the system packages, via selenium):
load the page, move a slider and see the spectrum and swatch change, an inline error, upload a
CSV, start and cancel a Monte Carlo run, follow a shared URL, render a preview.

Screenshots go to the test's tmp_path, and also to the directory named by the environment
variable SANDLIGHT_SCREENSHOTS when set (``SANDLIGHT_SCREENSHOTS=docs/img`` refreshes the
documentation's pictures).
"""

import os
from pathlib import Path

import pytest

pytest.importorskip("selenium", reason="selenium is not installed (pip install selenium)")

from selenium.webdriver.common.by import By  # noqa: E402
from selenium.webdriver.common.keys import Keys  # noqa: E402
from selenium.webdriver.support.ui import WebDriverWait  # noqa: E402

TIMEOUT_S = 30


@pytest.fixture(scope="module")
def page(browser, live_server):
    url, _ = live_server
    browser.get(url + "/")
    _ready(browser)
    return browser


def _ready(driver):
    WebDriverWait(driver, TIMEOUT_S).until(lambda d: d.execute_script("return document.body.dataset.ready"))
    assert driver.execute_script("return document.body.dataset.ready") == "1"


def _text(driver, element_id):
    return driver.find_element(By.ID, element_id).text


def _wait_for(driver, condition, message):
    WebDriverWait(driver, TIMEOUT_S, poll_frequency=0.05).until(lambda d: condition(d), message)


def _swatch(driver, which="a"):
    return driver.execute_script(f"return getComputedStyle(document.getElementById('swatch-{which}')).backgroundColor")


def _spectrum_path(driver, name="model-a"):
    return driver.execute_script(
        f"const p = document.querySelector('#spectrum-svg path.{name}'); return p && p.getAttribute('d')"
    )


def _screenshot(driver, tmp_path, name):
    driver.save_screenshot(str(tmp_path / name))
    folder = os.environ.get("SANDLIGHT_SCREENSHOTS")
    if folder:
        Path(folder).mkdir(parents=True, exist_ok=True)
        driver.save_screenshot(str(Path(folder) / name))


def _reset(driver, live_server, hash_=""):
    driver.get(live_server[0] + "/#" + hash_)
    driver.refresh()
    _ready(driver)


def test_the_page_loads_with_a_model_a_spectrum_and_a_swatch(page, tmp_path):
    assert _text(page, "model-name").startswith("model ")
    assert "hold-out RMS error" in _text(page, "model-error")
    assert _spectrum_path(page)
    assert _swatch(page).startswith("rgb(")
    assert "L*a*b* D50" in _text(page, "lab-a") and "D65" in _text(page, "lab-a")
    _wait_for(page, lambda d: d.execute_script("return !!document.querySelector('#plane-svg path.plane')"), "no BRDF")
    _screenshot(page, tmp_path, "explorer-page.png")


def test_moving_a_slider_changes_the_spectrum_and_the_swatch(page, live_server):
    _reset(page, live_server)
    before_path, before_colour = _spectrum_path(page), _swatch(page)
    slider = page.find_element(By.ID, "range-iron_oxide")
    slider.click()
    slider.send_keys(*[Keys.ARROW_RIGHT] * 20)  # iron oxide up by 20 steps of 0.0005
    _wait_for(page, lambda d: _swatch(d) != before_colour, "the swatch did not change")
    _wait_for(page, lambda d: _spectrum_path(d) != before_path, "the spectrum did not change")
    assert float(page.find_element(By.ID, "input-iron_oxide").get_attribute("value")) > 0.01
    assert "a.iron_oxide=" in page.current_url  # the URL follows


def test_a_value_out_of_its_domain_is_explained_beside_the_parameter(page, live_server):
    _reset(page, live_server)
    box = page.find_element(By.ID, "input-iron_oxide")
    box.clear()
    box.send_keys("0.5")
    _wait_for(page, lambda d: _text(d, "error-iron_oxide"), "no inline error")
    assert _text(page, "error-iron_oxide") == "iron_oxide = 0.5 is not allowed: a real number in [0, 0.1]"
    assert "invalid" in page.find_element(By.ID, "param-iron_oxide").get_attribute("class")


def test_an_uploaded_csv_is_drawn_with_its_rms(page, live_server, tmp_path):
    _reset(page, live_server)
    csv = tmp_path / "measured.csv"
    csv.write_text("wavelength_nm,reflectance\n" + "".join(f"{w},{0.1 + w / 2000:.4f}\n" for w in range(350, 2501, 10)))
    page.find_element(By.ID, "measured-file").send_keys(str(csv))
    _wait_for(page, lambda d: _text(d, "rms").startswith("RMS(model − measured) = "), "no RMS")
    assert _spectrum_path(page, "measured")
    assert "measured.csv" in _text(page, "spectrum-legend")


def test_a_monte_carlo_run_can_be_cancelled_and_another_finishes_with_its_band(page, live_server, tmp_path):
    _reset(page, live_server, "rays=5000")
    page.find_element(By.ID, "refine-button").click()
    _wait_for(page, lambda d: d.find_element(By.ID, "cancel-button").is_enabled(), "the run did not start")
    page.find_element(By.ID, "cancel-button").click()
    _wait_for(page, lambda d: _text(d, "refine-status") == "cancelled", "the run was not cancelled")
    assert page.find_element(By.ID, "refine-button").is_enabled()
    assert not _spectrum_path(page, "mc")
    rays = page.find_element(By.ID, "rays")
    rays.clear()
    rays.send_keys("1000")
    page.find_element(By.ID, "refine-button").click()
    _wait_for(page, lambda d: _text(d, "refine-status").startswith("done"), "the run did not finish")
    _wait_for(page, lambda d: _spectrum_path(d, "mc"), "no Monte Carlo curve")
    assert page.execute_script("return !!document.querySelector('#spectrum-svg polygon.mc-band')")
    _screenshot(page, tmp_path, "explorer-monte-carlo.png")


def test_a_shared_url_reproduces_the_view(page, live_server, tmp_path):
    _reset(page, live_server, "a.iron_oxide=0.03&a.saturation=0.4&cmp=1&b.iron_oxide=0.005&inc=50&wl=620")
    _wait_for(page, lambda d: _text(d, "delta-e").startswith("ΔE₀₀(A, B) = "), "no A/B comparison")
    link = page.find_element(By.ID, "share-link").get_attribute("href")
    colour, delta = _swatch(page), _text(page, "delta-e")
    # a fresh load of the link, as another person would open it
    page.get("about:blank")
    page.get(link)
    _ready(page)
    _wait_for(page, lambda d: _text(d, "delta-e") == delta, "the comparison differs")
    assert _swatch(page) == colour
    assert page.find_element(By.ID, "input-saturation").get_attribute("value") == "0.4"
    assert page.find_element(By.ID, "incidence").get_attribute("value") == "50"
    assert page.find_element(By.ID, "wavelength").get_attribute("value") == "620"
    _screenshot(page, tmp_path, "explorer-compare.png")


def test_a_preview_is_rendered_and_refined(page, live_server, tmp_path):
    _reset(page, live_server, "terrain=dunes&time=9")
    page.find_element(By.ID, "preview-button").click()
    _wait_for(
        page,
        lambda d: (d.find_element(By.ID, "preview-img").get_attribute("src") or "").startswith("data:image/png"),
        "no image",
    )
    _wait_for(page, lambda d: d.find_element(By.ID, "preview-progress").get_attribute("value") == "1", "not refined")
    page.execute_script("document.getElementById('preview').scrollIntoView()")
    _screenshot(page, tmp_path, "explorer-preview.png")
