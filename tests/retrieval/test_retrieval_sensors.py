"""Sensor bands: shipped Gaussian responses, user SRF files, band values, fitting in band space."""

import numpy as np
import pytest

import sandlight
from sandlight.errors import ModelFileError, ParameterError
from sandlight.retrieval.sensors import SHIPPED_SENSORS, load_sensor


@pytest.mark.parametrize("name", SHIPPED_SENSORS)
def test_shipped_sensors_are_labelled_gaussian_and_peak_at_their_centres(name):
    srf = load_sensor(name)
    assert "Gaussian approximation" in srf.description
    peaks = srf.wavelengths[np.argmax(srf.response, axis=1)]
    np.testing.assert_allclose(peaks, srf.centres, atol=1.0)


def test_band_value_of_a_flat_spectrum_is_that_value_and_of_a_line_its_centre():
    wl = np.arange(300.0, 2601.0, 1.0)  # every band's response inside
    flat = sandlight.bands((wl, np.full(wl.size, 0.3)), "sentinel2-msi")
    np.testing.assert_allclose(flat.values, 0.3, rtol=1e-12)
    assert list(flat["band"].values)[:4] == ["B1", "B2", "B3", "B4"]
    line = sandlight.bands((wl, wl / 1e4), "landsat-oli")
    np.testing.assert_allclose(line.values, line["centre_nm"].values / 1e4, rtol=1e-6)


def test_bands_outside_the_spectrum_are_left_out_and_named():
    wl = np.arange(400.0, 701.0, 5.0)
    result = sandlight.bands((wl, np.full(wl.size, 0.2)), "landsat-oli")
    assert list(result["band"].values) == ["B1", "B2", "B3", "B4"]
    assert "B5" in result.attrs["bands_outside"]
    with pytest.raises(ParameterError, match="covering at least one band"):
        sandlight.bands((np.array([1000.0, 1010.0]), np.array([0.2, 0.2])), "landsat-oli")


def test_user_srf_file_and_malformed_ones(tmp_path):
    good = tmp_path / "cam.csv"
    wl = np.arange(500, 601)
    rows = "\n".join(f"{w},{max(0.0, 1 - abs(w - 550) / 30):.4f}" for w in wl)
    good.write_text("# a triangular band\nwavelength_nm,G\n" + rows + "\n")
    srf = load_sensor(good)
    assert srf.band_names == ("G",)
    assert srf.centres[0] == pytest.approx(550.0, abs=0.01)
    for text, message in [
        ("wl,G\n500,1\n", "header"),
        ("wavelength_nm,G\n500,1\n490,1\n", "strictly increasing"),
        ("wavelength_nm,G\n500,-1\n510,1\n", ">= 0"),
        ("wavelength_nm,G\n0.5,1\n0.6,1\n", "micrometres"),
        ("wavelength_nm,G\n500,1,2\n", "fields"),
        ("wavelength_nm,G\n500,x\n510,1\n", "number"),
    ]:
        bad = tmp_path / "bad.csv"
        bad.write_text(text)
        with pytest.raises(ModelFileError, match=message):
            load_sensor(bad)
    with pytest.raises(ParameterError, match="sensor"):
        load_sensor("landsat-99")


def test_fit_in_band_space_recovers_the_predictor_sample(bank, dry_truth):
    fine = np.arange(380.0, 801.0, 1.0)
    spectrum = (fine, np.interp(fine, bank.wavelengths_, bank.predict([dry_truth])[0]))
    result = sandlight.fit(
        spectrum,
        ["iron_oxide", "hematite_ratio"],
        {"saturation": 0.0},
        sensor="sentinel2-msi",
        noise=0.002,
        check_rays=0,
        bank=bank,  # the bank that made the spectrum (by default 380-800 nm goes to the full range)
    )
    assert result.observation.labels == ("B1", "B2", "B3", "B4")
    assert result.estimate["iron_oxide"] == pytest.approx(dry_truth.iron_oxide, rel=0.01)
    assert result.estimate["hematite_ratio"] == pytest.approx(dry_truth.hematite_ratio, abs=0.01)
