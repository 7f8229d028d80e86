"""Reading and checking the measured spectrum: pairs, DataArrays, CSV, USGS splib07, ENVI."""

import numpy as np
import pytest
import xarray as xr

from sandlight.errors import ModelFileError, ParameterError
from sandlight.measured import usgs_library
from sandlight.retrieval.spectrum import as_spectrum

GDS76 = "Hematite.02+Quartz.98_GDS76_BECKa_AREF"


def test_pair_and_dataarray_give_the_same_spectrum():
    wl = np.array([400.0, 500.0, 600.0])
    r = np.array([0.1, 0.2, 0.3])
    a = as_spectrum((wl, r))
    b = as_spectrum(xr.DataArray(r, dims="wavelength", coords={"wavelength": wl}))
    np.testing.assert_array_equal(a.values, b.values)
    np.testing.assert_array_equal(a["wavelength"].values, wl)


@pytest.mark.parametrize(
    ("measured", "message"),
    [
        (([400.0, 500.0], [0.1]), "same length"),
        (([0.4, 0.5, 0.6], [0.1, 0.2, 0.3]), "micrometres"),
        (([400.0, 500.0, 600.0], [0.1, np.nan, 0.3]), "reflectance at 500 nm"),
        (([400.0, 600.0, 500.0], [0.1, 0.2, 0.3]), "strictly increasing"),
        (([400.0, 500.0], [10.0, 20.0]), "percent"),
        (([400.0], [0.1]), "at least 2"),
        ("not a spectrum", "no such spectrum file"),
        (42, "pair"),
    ],
)
def test_bad_input_is_refused_with_a_message(measured, message):
    with pytest.raises((ParameterError, FileNotFoundError), match=message):
        as_spectrum(measured)


def test_dataarray_in_micrometres_is_refused():
    da = xr.DataArray([0.1, 0.2], dims="wavelength", coords={"wavelength": ("wavelength", [0.4, 0.5], {"units": "um"})})
    with pytest.raises(ParameterError, match="units"):
        as_spectrum(da)


def test_usgs_file_is_read_and_deleted_channels_dropped():
    spectrum = as_spectrum(usgs_library(GDS76))
    assert np.all(np.isfinite(spectrum.values))
    assert spectrum["wavelength"].values[0] < 400 < 700 < spectrum["wavelength"].values[-1]
    assert 0.05 < float(spectrum.interp(wavelength=450)) < float(spectrum.interp(wavelength=700)) < 0.8


def test_csv_file_is_read_and_malformed_refused(tmp_path):
    good = tmp_path / "s.csv"
    good.write_text("wavelength_nm,reflectance\n400,0.1\n500,0.2\n600,0.3\n")
    assert as_spectrum(good).values.tolist() == [0.1, 0.2, 0.3]
    bad = tmp_path / "bad.csv"
    bad.write_text("wavelength_nm,reflectance\n400,0.1\n500,zero\n")
    with pytest.raises(ModelFileError, match="line 3"):
        as_spectrum(bad)


def test_envi_library_is_read_with_spectral(tmp_path):
    from spectral.io.envi import SpectralLibrary

    wl_um = np.linspace(0.4, 0.7, 31)
    spectra = np.stack([np.linspace(0.1, 0.4, 31), np.linspace(0.2, 0.5, 31)])
    header = {"wavelength units": "Micrometers", "spectra names": ["dune", "beach"], "wavelength": wl_um.tolist()}
    SpectralLibrary(spectra, header, {}).save(str(tmp_path / "lib"), "test library")
    beach = as_spectrum(tmp_path / "lib.hdr", name="beach")
    np.testing.assert_allclose(beach["wavelength"].values, wl_um * 1000)
    np.testing.assert_allclose(beach.values, spectra[1], rtol=1e-6)
    with pytest.raises(ModelFileError, match="choose one by name"):
        as_spectrum(tmp_path / "lib.hdr")
    with pytest.raises(ModelFileError, match="no spectrum named"):
        as_spectrum(tmp_path / "lib.sli", name="lake")
    (tmp_path / "broken.hdr").write_text("this is not an ENVI header\n")
    (tmp_path / "broken.sli").write_bytes(b"\0" * 16)
    with pytest.raises(ModelFileError, match="broken.hdr"):
        as_spectrum(tmp_path / "broken.hdr")


def test_malformed_usgs_file_is_refused_with_the_line(tmp_path):
    bad = tmp_path / "splib07a_Broken_BECKa_AREF.txt"
    bad.write_text("splib07a Record=1: Broken BECKa AREF\n0.25\nnot a number\n")
    with pytest.raises(ModelFileError, match="line 3"):
        as_spectrum(bad)
