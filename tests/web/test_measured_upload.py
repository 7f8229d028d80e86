"""Uploading a measured spectrum: CSV and USGS splib07 ASCII, the RMS against the model, and
the refusals (a file that is no spectrum, too large, missing)."""

from importlib import resources

import numpy as np
import pytest

from sandlight.measured import read_usgs
from sandlight.sample import SandSample
from sandlight.validation.scoring import measured_on_grid
from sandlight.web.spectra import bank

OTTAWA = "splib07a_Quartz_GDS74_Sand_Ottawa_BECKc_AREF.txt"


def _shipped(name: str) -> bytes:
    return (resources.files("sandlight") / "data" / "measured" / name).read_bytes()


def _upload(client, data: bytes, name: str, sample='"ottawa-quartz"', form=None):
    fields = {"sample": sample}  # JSON text, as the page sends it
    if form is not None:
        fields["format"] = form
    return client.post("/api/measured", files={"file": (name, data, "text/plain")}, data=fields)


def test_a_usgs_file_is_read_and_compared_with_the_model_over_their_common_wavelengths(client):
    res = _upload(client, _shipped(OTTAWA), OTTAWA)
    assert res.status_code == 200, res.text
    body = res.json()
    assert body["format"] == "usgs" and body["name"] == OTTAWA and "Ottawa" in body["title"]
    assert len(body["wavelengths_nm"]) == 480
    # the same comparison done with the Python API
    path = resources.files("sandlight") / "data" / "measured" / OTTAWA
    with resources.as_file(path) as p:
        measured = measured_on_grid(read_usgs(p), bank().wavelengths_)
    model, used = bank().predict([SandSample.preset("ottawa-quartz")], return_models=True)
    ok = np.isfinite(measured)
    assert body["model"] == used[0]
    assert body["rms"] == pytest.approx(float(np.sqrt(np.mean((model[0][ok] - measured[ok]) ** 2))), rel=1e-12)


def test_a_csv_of_the_models_own_spectrum_has_zero_rms(client):
    spectrum = client.post("/api/spectrum", json={"sample": "red-dune"}).json()
    text = "wavelength_nm,reflectance\n" + "".join(
        f"{w:g},{r:.17g}\n" for w, r in zip(spectrum["wavelengths_nm"], spectrum["reflectance"])
    )
    body = _upload(client, text.encode(), "mine.csv", sample='"red-dune"').json()
    assert body["format"] == "csv" and body["compared_nm"] == spectrum["wavelengths_nm"]
    assert body["rms"] == pytest.approx(0.0, abs=1e-12)
    # a spectrum 0.05 above the model is 0.05 away in RMS
    shifted = "".join(f"{w:g},{r + 0.05:.17g}\n" for w, r in zip(spectrum["wavelengths_nm"], spectrum["reflectance"]))
    body = _upload(client, shifted.encode(), "shifted.csv", sample='"red-dune"').json()
    assert body["rms"] == pytest.approx(0.05, abs=1e-9)


def test_a_file_that_is_no_spectrum_is_a_422_naming_the_upload_not_a_server_path(client):
    res = _upload(client, b"wavelength_nm,reflectance\n400,0.1\n420,abc\n", "../../etc/bad.csv")
    assert res.status_code == 422, res.text
    message = res.json()["message"]
    assert message.startswith("bad.csv") and "line 3" in message
    assert "sandlight-upload" not in message and "/tmp" not in message


def test_a_usgs_file_of_another_spectrometer_is_refused_with_the_channel_counts(client):
    data = b"splib07a Record=1: made up ASD\n" + b"0.5\n" * 2151
    res = _upload(client, data, "asd.txt")
    assert res.status_code == 422 and "2151 channels" in res.json()["message"], res.text


@pytest.mark.parametrize(
    ("kwargs", "status", "named"),
    [
        ({"form": "xls"}, 400, "format"),
        ({"sample": '{"iron_oxide": 2}'}, 400, "iron_oxide"),
        ({"sample": "{oops"}, 400, "sample"),
    ],
)
def test_bad_fields_of_an_upload_are_named(client, kwargs, status, named):
    res = _upload(client, _shipped(OTTAWA), OTTAWA, **kwargs)
    assert res.status_code == status and res.json()["parameter"] == named, res.text


def test_an_upload_without_a_file_or_over_the_limit_is_refused(client):
    res = client.post("/api/measured", data={"sample": '"red-dune"'})
    assert res.status_code == 400 and res.json()["parameter"] == "file"
    big = b"400,0.1\n" * (client.app.state.limits.max_upload_bytes // 8 + 10)
    res = _upload(client, big, "big.csv")
    assert res.status_code == 413 and res.json()["error"] == "limit", res.text
