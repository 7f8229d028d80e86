"""Tests of sandlight.measured: USGS splib07 ASCII and two-column CSV readers."""

from pathlib import Path

import numpy as np
import pytest

import sandlight
from sandlight.errors import ModelFileError, ParameterError
from sandlight.measured import read_csv, read_usgs, usgs_library

REPO = Path(__file__).resolve().parents[1]
# The copies shipped with the package as it is imported (installed or source tree).
PACKAGE_MEASURED = Path(sandlight.__file__).parent / "data" / "measured"
VALIDATION_STEMS = ("Quartz_GDS74_Sand_Ottawa_BECKc_AREF", "Hematite.02+Quartz.98_GDS76_BECKa_AREF")
BECKMAN = "splib07a_Wavelengths_BECK_Beckman_0.2-3.0_microns.txt"
ASD = "splib07a_Wavelengths_ASD_0.35-2.5_microns_2151_ch.txt"


def shared_usgs():
    """The shared ``data/measured/usgs_splib07a`` folder (``../shared`` from the repository)."""
    for parent in [REPO, *REPO.parents]:
        candidate = parent / "shared" / "data" / "measured" / "usgs_splib07a"
        if (candidate / "ascii").is_dir() and (candidate / "csv").is_dir():
            return candidate
    return None


def write(path: Path, text: str) -> Path:
    path.write_text(text, encoding="utf-8")
    return path


@pytest.fixture
def tiny_library(tmp_path):
    """A 4-channel spectrometer: wavelength file (um) and a spectrum with a deleted channel."""
    write(
        tmp_path / "splib07a_Wavelengths_TINY_4ch.txt", " splib07a Record=1: Wavelengths TINY\n 0.4\n 0.5\n 0.6\n 0.7\n"
    )
    spectrum = write(
        tmp_path / "splib07a_Thing_TINYa_AREF.txt",
        " splib07a Record=2: Thing   TINYa AREF\n 1.0e-001\n-1.2300000e+034\n 3.0e-001\n 4.0e-001\n\n",
    )
    return spectrum


# ---------------------------------------------------------------------------- read_usgs


def test_round_trip_against_shared_csv_versions():
    shared = shared_usgs()
    if shared is None:
        pytest.skip("shared USGS splib07a folder not available")
    csv_files = sorted((shared / "csv").glob("*.csv"))
    assert len(csv_files) >= 3
    for csv_file in csv_files:
        ascii_file = shared / "ascii" / f"splib07a_{csv_file.stem}.txt"
        from_ascii = read_usgs(ascii_file)
        from_csv = read_csv(csv_file)
        assert from_csv.attrs["reflectance_scale_in_file"] == "fraction"
        # The CSV rounds wavelengths to 0.01 nm and reflectance to 1e-6.
        np.testing.assert_allclose(from_ascii["wavelength"], from_csv["wavelength"], atol=0.006)
        np.testing.assert_array_equal(np.isnan(from_ascii.values), np.isnan(from_csv.values))
        np.testing.assert_allclose(from_ascii.values, from_csv.values, atol=6e-7, equal_nan=True, err_msg=csv_file.name)


def test_shipped_copies_are_the_shared_files():
    shared = shared_usgs()
    if shared is None:
        pytest.skip("shared USGS splib07a folder not available")
    for name in [f"splib07a_{s}.txt" for s in VALIDATION_STEMS] + [BECKMAN]:
        assert (PACKAGE_MEASURED / name).read_bytes() == (shared / "ascii" / name).read_bytes()


def test_shipped_validation_spectra_load():
    quartz = read_usgs(usgs_library(VALIDATION_STEMS[0]))
    mixture = read_usgs(usgs_library("Hematite.02+Quartz.98"))
    for spectrum in (quartz, mixture):
        assert Path(spectrum.attrs["source_file"]).parent == PACKAGE_MEASURED
        assert Path(spectrum.attrs["wavelength_file"]).name == BECKMAN
        w = spectrum["wavelength"].values
        assert w.size == 480 and np.all(np.diff(w) > 0)
        assert w[0] == pytest.approx(205.1, abs=0.01) and w[-1] == pytest.approx(2976.0, abs=0.01)
        assert spectrum["wavelength"].attrs["units"] == "nm"
        assert spectrum.attrs["deleted_channels"] == int(np.isnan(spectrum.values).sum()) >= 1
        visible = spectrum.sel(wavelength=slice(400, 2400)).values
        assert np.all((visible > 0.1) & (visible < 1.0))
    assert "Quartz GDS74 Sand Ottawa" in quartz.attrs["title"]

    def ratio(s):
        return float(s.sel(wavelength=650, method="nearest") / s.sel(wavelength=550, method="nearest"))

    # 2 wt% hematite gives the mixture hematite's absorption edge between 550 and 650 nm.
    assert ratio(mixture) > 2.0 > 1.2 > ratio(quartz)


def test_deleted_channels_become_nan_and_microns_become_nm(tiny_library):
    spectrum = read_usgs(tiny_library)
    np.testing.assert_allclose(spectrum["wavelength"], [400.0, 500.0, 600.0, 700.0])
    np.testing.assert_allclose(spectrum.values, [0.1, np.nan, 0.3, 0.4], equal_nan=True)
    assert spectrum.attrs["deleted_channels"] == 1
    assert spectrum.attrs["title"] == "splib07a Record=2: Thing TINYa AREF"
    assert spectrum.name == "reflectance" and spectrum.dims == ("wavelength",)


def test_explicit_wavelength_file(tiny_library, tmp_path):
    other = tmp_path / "elsewhere"
    other.mkdir()
    moved = other / tiny_library.name
    tiny_library.rename(moved)
    with pytest.raises(ModelFileError, match="wavelengths="):
        read_usgs(moved)
    spectrum = read_usgs(moved, wavelengths=tmp_path / "splib07a_Wavelengths_TINY_4ch.txt")
    assert spectrum.sizes["wavelength"] == 4


def test_wrong_channel_count_names_both_files(tiny_library, tmp_path):
    wavelengths = write(tmp_path / "w5.txt", "header\n0.4\n0.5\n0.6\n0.7\n0.8\n")
    with pytest.raises(ModelFileError, match="4 channels.*w5.txt has 5"):
        read_usgs(tiny_library, wavelengths=wavelengths)
    shared = shared_usgs()
    if shared is not None:
        with pytest.raises(ModelFileError, match="480 channels.*2151"):
            read_usgs(PACKAGE_MEASURED / f"splib07a_{VALIDATION_STEMS[0]}.txt", wavelengths=shared / "ascii" / ASD)


@pytest.mark.parametrize(
    "content, message",
    [
        ("", "empty file"),
        ("\n\n", "empty file"),
        (" splib07a Record=3: header only\n", "no values"),
        (" 0.1\n 0.2\n 0.3\n 0.4\n", "line 1: expected the splib07 header"),
        (" splib07a Record=3: x\n 0.1\n 0.2\n oops\n 0.4\n", "line 4: expected one number"),
        (" splib07a Record=3: x\n 0.1\n\n 0.3\n 0.4\n", "line 3: expected one number"),
        (" splib07a Record=3: x\n 0.1\n nan\n 0.3\n 0.4\n", "line 3: non-finite"),
        (" splib07a Record=3: x\n 0.1 0.2\n 0.3\n 0.4\n 0.5\n", "line 2: expected one number"),
    ],
)
def test_malformed_usgs_spectra(tmp_path, content, message):
    write(tmp_path / "splib07a_Wavelengths_TINY_4ch.txt", "w\n0.4\n0.5\n0.6\n0.7\n")
    bad = write(tmp_path / "splib07a_Bad_TINYa_AREF.txt", content)
    with pytest.raises(ModelFileError, match=message) as info:
        read_usgs(bad)
    assert "splib07a_Bad_TINYa_AREF.txt" in str(info.value)


@pytest.mark.parametrize(
    "content, message",
    [
        ("w\n0.4\n0.6\n0.5\n0.7\n", "line 4: wavelengths are not strictly increasing"),
        ("w\n0.4\n0.5\n-1.23e34\n0.7\n", "line 4: deleted value"),
        ("w\n0.4\n0.5\nzero\n0.7\n", "line 4: expected one number"),
    ],
)
def test_malformed_wavelength_files(tiny_library, tmp_path, content, message):
    wavelengths = write(tmp_path / "bad_wavelengths.txt", content)
    with pytest.raises(ModelFileError, match=message) as info:
        read_usgs(tiny_library, wavelengths=wavelengths)
    assert "bad_wavelengths.txt" in str(info.value)


def test_missing_files_raise_file_not_found(tmp_path, tiny_library):
    with pytest.raises(FileNotFoundError):
        read_usgs(tmp_path / "nothing.txt")
    with pytest.raises(FileNotFoundError):
        read_usgs(tiny_library, wavelengths=tmp_path / "nothing.txt")
    with pytest.raises(FileNotFoundError):
        read_csv(tmp_path / "nothing.csv")


def test_binary_file_is_a_model_file_error(tmp_path):
    bad = tmp_path / "binary.txt"
    bad.write_bytes(b"\xff\xfe\x00\x01" * 10)
    with pytest.raises(ModelFileError, match="not a text file"):
        read_usgs(bad)


# ---------------------------------------------------------------------------- read_csv


def test_csv_with_and_without_header_and_comments(tmp_path):
    plain = write(tmp_path / "plain.csv", "400,0.1\n500,0.2\n600,0.3\n")
    with_header = write(
        tmp_path / "header.csv",
        "# my sand, measured 2024\n\nwavelength_nm,reflectance\n400,0.1\n# a comment between rows\n500,0.2\n600,0.3\n",
    )
    for path in (plain, with_header):
        spectrum = read_csv(path)
        np.testing.assert_allclose(spectrum["wavelength"], [400, 500, 600])
        np.testing.assert_allclose(spectrum.values, [0.1, 0.2, 0.3])
        assert spectrum.attrs["reflectance_scale_in_file"] == "fraction"
        assert spectrum["wavelength"].attrs["units"] == "nm"


@pytest.mark.parametrize(
    "text", ["400;0.1\n500;0.2\n", "400\t0.1\n500\t0.2\n", "400   0.1\n500 0.2\n", "400, 0.1\n500 ,0.2\n"]
)
def test_csv_delimiters(tmp_path, text):
    spectrum = read_csv(write(tmp_path / "d.csv", text))
    np.testing.assert_allclose(spectrum.values, [0.1, 0.2])


def test_csv_percent_is_detected_and_converted(tmp_path):
    fraction = read_csv(write(tmp_path / "f.csv", "400,0.05\n500,0.42\n600,0.6\n"))
    percent = read_csv(write(tmp_path / "p.csv", "400,5\n500,42\n600,60\n"))
    np.testing.assert_allclose(percent.values, fraction.values)
    assert percent.attrs["reflectance_scale_in_file"] == "percent"
    # A very dark sample in percent is only recognisable from its header.
    dark = read_csv(write(tmp_path / "dark.csv", "wavelength_nm,reflectance_%\n400,0.9\n500,1.1\n"))
    np.testing.assert_allclose(dark.values, [0.009, 0.011])
    # Bright calibrated targets may slightly exceed 1 and stay fractions.
    bright = read_csv(write(tmp_path / "b.csv", "400,1.02\n500,0.99\n"))
    assert bright.attrs["reflectance_scale_in_file"] == "fraction"
    with pytest.raises(ModelFileError, match="line 2: reflectance 250"):
        read_csv(write(tmp_path / "x.csv", "400,50\n500,250\n"))


def test_csv_blank_reflectance_is_nan(tmp_path):
    spectrum = read_csv(write(tmp_path / "gap.csv", "wavelength_nm,reflectance\n400,\n500,0.2\n"))
    np.testing.assert_allclose(spectrum.values, [np.nan, 0.2], equal_nan=True)


def test_csv_micrometres(tmp_path):
    spectrum = read_csv(write(tmp_path / "um.csv", "wavelength_um,reflectance\n0.4,0.1\n2.5,0.2\n"))
    np.testing.assert_allclose(spectrum["wavelength"], [400.0, 2500.0])
    with pytest.raises(ModelFileError, match="micrometres"):
        read_csv(write(tmp_path / "um2.csv", "0.4,0.1\n2.5,0.2\n"))


@pytest.mark.parametrize(
    "content, message",
    [
        ("", "no data rows"),
        ("# only a comment\n", "no data rows"),
        ("wavelength_nm,reflectance\n", "no data rows"),
        ("400,0.1\n500,0.2,0.3\n", "line 2: expected 2 columns .* found 3"),
        ("400\n500\n", "line 1: expected 2 columns .* found 1"),
        ("wavelength_nm,reflectance\n400,0.1\n500,abc\n", "line 3: expected two numbers"),
        ("wavelength_nm,reflectance\n400,0.1\nfoo,0.2\n", "line 3: expected two numbers"),
        ("400,0.1\n600,0.2\n500,0.3\n", "line 3: wavelengths are not strictly increasing"),
        ("400,0.1\n400,0.2\n", "line 2: wavelengths are not strictly increasing"),
        ("400,0.1\ninf,0.2\n", "line 2: wavelength 'inf' is not finite"),
        ("400,\n500,\n", "no reflectance values"),
    ],
)
def test_malformed_csv(tmp_path, content, message):
    bad = write(tmp_path / "bad_spectrum.csv", content)
    with pytest.raises(ModelFileError, match=message) as info:
        read_csv(bad)
    assert "bad_spectrum.csv" in str(info.value)


# ---------------------------------------------------------------------------- usgs_library


def test_usgs_library_lookup(tiny_library, tmp_path):
    assert usgs_library("Thing_TINYa_AREF", root=tmp_path) == tiny_library
    assert usgs_library("splib07a_Thing_TINYa_AREF.txt", root=tmp_path) == tiny_library
    assert usgs_library("Thing", root=tmp_path) == tiny_library  # unique prefix
    write(tmp_path / "splib07a_Thing_TINYb_AREF.txt", "h\n0.1\n0.2\n0.3\n0.4\n")
    with pytest.raises(ParameterError, match="stem.*Thing_TINYa.*Thing_TINYb"):
        usgs_library("Thing", root=tmp_path)
    with pytest.raises(FileNotFoundError, match="Nothing"):
        usgs_library("Nothing", root=tmp_path)
    with pytest.raises(ParameterError, match="stem"):
        usgs_library("  ", root=tmp_path)
    # Wavelength files are not spectra.
    with pytest.raises(FileNotFoundError):
        usgs_library("Wavelengths", root=tmp_path)


def test_usgs_library_root_may_be_a_library_folder_with_ascii(tmp_path):
    (tmp_path / "ascii").mkdir()
    spectrum = write(tmp_path / "ascii" / "splib07a_Thing_TINYa_AREF.txt", "h\n0.1\n")
    assert usgs_library("Thing", root=tmp_path) == spectrum


def test_usgs_library_finds_shared_spectra_when_present():
    shared = shared_usgs()
    if shared is None:
        pytest.skip("shared USGS splib07a folder not available")
    path = usgs_library("Goethite_WS222_Medium")
    assert path.parent == shared / "ascii"
    assert read_usgs(path).sizes["wavelength"] == 480
