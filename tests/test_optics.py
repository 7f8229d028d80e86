"""Tests of sandlight.optics and of the shipped optical-constant tables."""

import importlib.util
import math
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from sandlight.errors import ParameterError
from sandlight.optics import (
    DENSITY_G_CM3,
    MATERIALS,
    absorption_coefficient_per_mm,
    complex_index,
    interpolate_k,
    provenance,
    table,
)

REPO = Path(__file__).resolve().parents[1]
PROVISIONAL = ("goethite", "kaolinite")


def shared_optical():
    """The project's shared data/optical folder (``../shared`` seen from the repository)."""
    for parent in [REPO, *REPO.parents]:
        candidate = parent / "shared" / "data" / "optical"
        if (candidate / "csv").is_dir():
            return candidate
    return None


def load_build_script():
    spec = importlib.util.spec_from_file_location("build_optical_tables", REPO / "scripts/data/build_optical_tables.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses resolve annotations through sys.modules
    spec.loader.exec_module(module)
    return module


# ---------------------------------------------------------------------------- the tables


@pytest.mark.parametrize("material", MATERIALS)
def test_table_covers_domain_with_physical_values(material):
    ds = table(material)
    w = ds["wavelength"].values
    assert w[0] <= 350.0 and w[-1] >= 2500.0
    assert np.all(np.diff(w) > 0)
    assert np.all(np.isfinite(ds["n"])) and np.all(ds["n"] > 1.0)
    assert np.all(np.isfinite(ds["k"])) and np.all(ds["k"] >= 0.0)
    assert ds["wavelength"].attrs["units"] == "nm"
    assert ds["absorption_coefficient"].attrs["units"] == "mm-1"
    assert ds.attrs["material"] == material


@pytest.mark.parametrize("material", MATERIALS)
def test_provenance_names_source_licence_units(material):
    text = provenance(material)
    assert f"material: {material}" in text
    assert "source: " in text and "origin: " in text
    licence = next(line for line in text.splitlines() if line.startswith("licence: "))
    assert any(ok in licence for ok in ("CC0", "MIT", "public domain"))
    assert "units: " in text and "4 pi k / lambda" in text
    # The WOPP water file has no licence: nothing shipped may derive from it.
    for line in text.splitlines():
        if line.startswith(("source: ", "origin: ")):
            assert "WOPP" not in line and "ttgers" not in line


def test_provenance_of_all_materials_and_provisional_status():
    text = provenance()
    for material in MATERIALS:
        assert f"material: {material}" in text
    for material in MATERIALS:
        status = next(line for line in provenance(material).splitlines() if line.startswith("status: "))
        # Goethite's n and kaolinite's k are provisional, clearly marked; the calibrated k of the
        # quartz host and goethite says so (tests/calibration/test_shipped_calibration.py).
        assert ("PROVISIONAL" in status) == (material in PROVISIONAL)
        assert ("k: derived by calibration" in status) == (material in ("quartz", "goethite"))


def test_hematite_k_is_querry_below_the_edge_and_longtin_beyond():
    # README o-ray k (rounded there to 2-3 digits) and Querry 1985 e-ray k at the same points.
    k_o = {400.0: 1.29, 550.0: 0.50}
    k_e = {400.0: 1.096, 550.0: 0.46}
    for wavelength, ko in k_o.items():
        k = complex_index("hematite", wavelength).imag
        assert k == pytest.approx((2 * ko + k_e[wavelength]) / 3, abs=0.004)
        assert min(ko, k_e[wavelength]) - 0.005 <= k <= max(ko, k_e[wavelength]) + 0.005
    # Beyond the edge, Longtin et al. 1988 (o- and e-ray alike): 0.00974 at 633 nm, 1.8e-5 at
    # 1300 nm; the 10 nm grid interpolates log-linearly between their points.
    assert complex_index("hematite", 1300.0).imag == pytest.approx(1.8e-5, rel=1e-3)
    k633 = complex_index("hematite", 633.0).imag
    assert 0.0097 * 0.8 < k633 < 0.0097 * 1.25
    # Between 550 and 633 nm k falls monotonically across the edge, by 50x.
    k = complex_index("hematite", np.arange(550.0, 634.0, 10.0)).imag
    assert np.all(np.diff(k) < 0)
    # n stays Querry's everywhere (o-ray 3.008, e-ray ~2.8 near 680 nm): no jump at the join.
    n = complex_index("hematite", np.arange(540.0, 700.0, 10.0)).real
    assert np.max(np.abs(np.diff(n))) < 0.06


def test_quartz_index_is_orientation_average_at_590nm():
    # Ghosh 1999 at 590 nm: n_o = 1.5442, n_e = 1.5533 (shared README).
    assert complex_index("quartz", 590.0).real == pytest.approx((2 * 1.5442 + 1.5533) / 3, abs=1e-4)


def test_mineralogical_indices_of_provisional_materials():
    # Goethite: mean of the Handbook of Mineralogy principal indices at the Na D line.
    assert complex_index("goethite", 589.3).real == pytest.approx(2.375, abs=0.01)
    # Kaolinite: mean of the mindat principal indices (~1.562).
    assert complex_index("kaolinite", 589.3).real == pytest.approx(1.5623, abs=0.001)


def test_absorption_shapes_that_make_iron_oxides_red_or_yellow():
    def k(material, wavelength):
        return complex_index(material, wavelength).imag

    # Goethite (k calibrated on its powders, docs/optical-constants.md): a strong charge-transfer
    # edge near 540 nm, far weaker in the red.
    assert k("goethite", 450) > 10 * k("goethite", 550) and k("goethite", 500) > 10 * k("goethite", 600)
    # Its 4T1 crystal-field band: the literature's 900-930 nm is the reflectance minimum; the
    # seven goethite powders in ../shared put it at 883-949 nm (904-976 nm continuum-removed), and
    # the calibrated k peaks at 930-950 nm (docs/optical-constants.md), above the 750 nm window
    # and the transparent near infrared.
    band = np.arange(800.0, 1101.0, 5.0)
    assert 900.0 <= band[np.argmax(complex_index("goethite", band).imag)] <= 960.0
    assert k("goethite", 920) > 1.5 * k("goethite", 760) and k("goethite", 920) > 3 * k("goethite", 1300)
    # Goethite's edge lies bluer than hematite's: less absorbing in green and red (yellow vs red).
    assert k("goethite", 550) < k("hematite", 550) / 3
    assert k("goethite", 600) < k("hematite", 600) / 3
    # Hematite is transparent beyond its edge (Longtin): k < 1e-4 from 1000 nm on.
    assert k("hematite", 1000) < 2e-4 and k("hematite", 2000) < 1e-4
    # Kaolinite O-H combination and overtone bands.
    assert k("kaolinite", 2207) > 10 * k("kaolinite", 2000)
    assert k("kaolinite", 1400) > 5 * k("kaolinite", 1300)
    assert k("kaolinite", 350) > k("kaolinite", 450) > k("kaolinite", 650)


def test_water_absorption_bands():
    # Liquid water absorbs ~120 /cm at 1940 nm and ~30 /cm at 1450 nm (Segelstein 1981).
    assert 10.0 < absorption_coefficient_per_mm("water", 1940.0) < 14.0
    assert 2.0 < absorption_coefficient_per_mm("water", 1450.0) < 4.0
    # ...and is transparent in the visible (< 1 /m).
    assert absorption_coefficient_per_mm("water", 550.0) < 1e-3


def test_quartz_host_absorbs_like_natural_grains():
    # The calibrated host (docs/optical-constants.md): natural grains absorb through trace Fe3+,
    # Ti and inclusions far more than optical quartz (< 1e-3 /cm); the quartz powders read with an
    # equivalent-slab model give about 1 /cm. So 0.1-2 /cm = 0.01-0.2 /mm at 550 nm, rising
    # toward the UV.
    alpha = absorption_coefficient_per_mm("quartz", [400.0, 550.0, 1000.0])
    assert 0.01 <= alpha[1] <= 0.2
    assert alpha[0] > alpha[1] > alpha[2]


def test_water_k_close_to_wopp_in_red_if_available():
    """Cross-check only (WOPP has no licence and is never shipped): 550-700 nm within 20 %."""
    src = shared_optical()
    wopp = None if src is None else src / "csv" / "water_H2O_WOPPv3_Roettgers_absorption_k.csv"
    if wopp is None or not wopp.exists():
        pytest.skip("shared WOPP water file not available")
    data = np.genfromtxt(wopp, delimiter=",", skip_header=2)
    wavelengths = np.arange(550.0, 701.0, 10.0)
    ratio = complex_index("water", wavelengths).imag / np.interp(wavelengths, data[:, 0], data[:, 2])
    assert np.all(np.abs(ratio - 1) < 0.2)


def test_shipped_tables_are_exactly_what_the_build_script_writes():
    src = shared_optical()
    if src is None:
        pytest.skip("shared data/optical folder not available")
    build = load_build_script()
    tables = build.build_all(src)
    assert tuple(tables) == MATERIALS
    for material, t in tables.items():
        shipped = REPO / "python" / "sandlight" / "data" / "optical" / f"{material}.csv"
        assert shipped.read_text(encoding="utf-8") == build.render(t), material


# ---------------------------------------------------------------------------- the API


@pytest.mark.parametrize("material", MATERIALS)
def test_values_at_table_points_and_interpolation_rules(material):
    ds = table(material)
    w, n, k = ds["wavelength"].values, ds["n"].values, ds["k"].values
    inside = (w >= 350) & (w <= 2500)
    m = complex_index(material, w[inside])
    np.testing.assert_allclose(m.real, n[inside], rtol=1e-12)
    np.testing.assert_allclose(m.imag, k[inside], rtol=1e-12)
    # Between two table points: n linear (arithmetic mean), k log-linear (geometric mean).
    i = int(np.flatnonzero(w > 1000)[0])
    mid = complex_index(material, 0.5 * (w[i] + w[i + 1]))
    assert mid.real == pytest.approx(0.5 * (n[i] + n[i + 1]), rel=1e-12)
    assert mid.imag == pytest.approx(math.sqrt(k[i] * k[i + 1]), rel=1e-9)


def test_k_interpolation_falls_back_to_linear_next_to_zero():
    grid = np.array([400.0, 500.0, 600.0])
    k = np.array([0.0, 1e-3, 1e-1])
    got = interpolate_k(np.array([450.0, 550.0, 600.0]), grid, k)
    np.testing.assert_allclose(got, [0.5e-3, 1e-2, 1e-1], rtol=1e-12)


def test_interpolate_k_is_the_rule_of_complex_index():
    ds = table("hematite")
    w = np.linspace(350.0, 2500.0, 97)
    np.testing.assert_array_equal(
        interpolate_k(w, ds["wavelength"].values, ds["k"].values), complex_index("hematite", w).imag
    )


@pytest.mark.parametrize(
    "args, name",
    [
        (([450.0], [400.0], [1.0]), "grid_nm"),
        (([450.0], [500.0, 400.0], [1.0, 1.0]), "grid_nm"),
        (([450.0], [400.0, 500.0], [1.0, -1.0]), "k"),
        (([450.0], [400.0, 500.0], [1.0, 1.0, 1.0]), "k"),
        (([650.0], [400.0, 500.0], [1.0, 1.0]), "wavelengths_nm"),
        (([np.nan], [400.0, 500.0], [1.0, 1.0]), "wavelengths_nm"),
    ],
)
def test_interpolate_k_rejects_bad_tables_and_wavelengths(args, name):
    with pytest.raises(ParameterError, match=name):
        interpolate_k(*args)


def test_scalar_vector_and_nd_input():
    scalar = complex_index("hematite", 550.0)
    assert np.ndim(scalar) == 0 and isinstance(scalar, np.complexfloating)
    grid = np.array([[400.0, 550.0], [700.0, 2500.0]])
    m = complex_index("hematite", grid)
    assert m.shape == (2, 2) and m.dtype == np.complex128
    assert m[0, 1] == scalar
    assert complex_index("hematite", [550.0])[0] == scalar
    np.testing.assert_allclose(complex_index("hematite", grid.ravel()), m.ravel())
    alpha = absorption_coefficient_per_mm("hematite", grid)
    assert alpha.shape == (2, 2)
    assert np.ndim(absorption_coefficient_per_mm("hematite", 550.0)) == 0


def test_absorption_coefficient_is_4_pi_k_over_lambda():
    wavelengths = np.array([350.0, 550.0, 1000.0, 2500.0])
    for material in MATERIALS:
        k = complex_index(material, wavelengths).imag
        expected = 4 * np.pi * k / (wavelengths * 1e-6)  # lambda in mm
        np.testing.assert_allclose(absorption_coefficient_per_mm(material, wavelengths), expected, rtol=1e-12)
    # Hematite at 550 nm: k ~ 0.49, absorption length 1/alpha below 0.1 um.
    assert 1.0 / absorption_coefficient_per_mm("hematite", 550.0) < 1e-4


@pytest.mark.parametrize("material", ["sand", "Quartz", "", None, 3])
def test_unknown_material_is_rejected_with_the_allowed_list(material):
    with pytest.raises(ParameterError, match="material") as info:
        complex_index(material, 550.0)
    assert "quartz" in str(info.value) and "kaolinite" in str(info.value)
    with pytest.raises(ParameterError, match="material"):
        absorption_coefficient_per_mm(material, 550.0)
    with pytest.raises(ParameterError, match="material"):
        table(material)
    if material is not None:  # provenance(None) means "every material"
        with pytest.raises(ParameterError, match="material"):
            provenance(material)


@pytest.mark.parametrize(
    "wavelengths", [349.99, 2500.01, np.nan, np.inf, -500.0, "abc", [500.0, 3000.0], [[500.0], [np.nan]], None]
)
def test_bad_wavelengths_are_rejected_naming_the_parameter(wavelengths):
    with pytest.raises(ParameterError, match="wavelengths_nm") as info:
        complex_index("quartz", wavelengths)
    assert "350" in str(info.value) and "2500" in str(info.value)
    assert isinstance(info.value, ValueError)
    with pytest.raises(ParameterError, match="wavelengths_nm"):
        absorption_coefficient_per_mm("quartz", wavelengths)


def test_domain_ends_are_accepted():
    m = complex_index("water", [350.0, 2500.0])
    assert np.all(np.isfinite(m))


def test_callers_cannot_alter_the_cached_tables():
    # Every array a caller gets is its own: writing into them changes nothing read afterwards.
    reference = table("quartz")
    first = table("quartz")
    assert isinstance(first, xr.Dataset)
    for name in ("n", "k", "absorption_coefficient"):
        first[name].values[:] = 0.0
    xr.testing.assert_identical(table("quartz"), reference)
    inside = reference.where((reference["wavelength"] >= 350) & (reference["wavelength"] <= 2500), drop=True)
    w = inside["wavelength"].values
    complex_index("quartz", w)[:] = 0.0
    absorption_coefficient_per_mm("quartz", w)[:] = 0.0
    np.testing.assert_allclose(complex_index("quartz", w).real, inside["n"].values, rtol=1e-12)
    np.testing.assert_allclose(
        absorption_coefficient_per_mm("quartz", w), inside["absorption_coefficient"].values, rtol=1e-12
    )


def test_densities():
    assert set(DENSITY_G_CM3) == set(MATERIALS)
    assert DENSITY_G_CM3["quartz"] == 2.65 and DENSITY_G_CM3["hematite"] == 5.26
    assert DENSITY_G_CM3["goethite"] == 4.27 and DENSITY_G_CM3["magnetite"] == 5.18
    assert DENSITY_G_CM3["kaolinite"] == 2.63 and DENSITY_G_CM3["water"] == 1.00
    with pytest.raises(TypeError):
        DENSITY_G_CM3["quartz"] = 3.0
