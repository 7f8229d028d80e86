"""spectrum_to_xyz: white point, agreement with colour-science, coarse sampling, errors."""

import warnings

import numpy as np
import pytest
from colour_fakes import logistic_spectrum, read_usgs

import colour
from sandlight.colour import (
    PREDICTOR_WAVELENGTHS_NM,
    spectrum_to_xyz,
    spectrum_to_xyz_under,
    white_point_xyz,
    xyz_to_lab,
)
from sandlight.errors import ParameterError

OBSERVER_10 = "CIE 1964 10 Degree Standard Observer"
DENSE_NM = np.arange(360.0, 831.0, 1.0)


def delta_e_2000(xyz_a, xyz_b):
    return float(colour.delta_E(xyz_to_lab(xyz_a), xyz_to_lab(xyz_b), method="CIE 2000"))


class TestWhiteReflector:
    # colour-science's D50/10° chromaticity (0.34773, 0.35952) gives Z = 0.81428, as ASTM E308
    # (81.427); ours is 0.81415. The 0.016 % comes from the CMF table version (CVRL 1 nm) and
    # the 5 nm → 1 nm interpolation of D50, both as colour-science's own sd_to_XYZ does.
    TABLE_ATOL = 2e-4

    @pytest.mark.parametrize("wavelengths_nm", [PREDICTOR_WAVELENGTHS_NM, DENSE_NM], ids=["16-bands", "1nm"])
    def test_d50_10deg_white_point(self, wavelengths_nm):
        xyz = spectrum_to_xyz(wavelengths_nm, np.ones(wavelengths_nm.size))
        table = colour.xy_to_XYZ(colour.CCS_ILLUMINANTS[OBSERVER_10]["D50"])
        np.testing.assert_allclose(xyz, table, atol=self.TABLE_ATOL)
        assert xyz[1] == pytest.approx(1.0, abs=1e-12)
        np.testing.assert_allclose(xyz, white_point_xyz(), rtol=1e-12)

    def test_equals_colour_science_integration(self):
        sd = colour.SpectralDistribution(np.ones(DENSE_NM.size), DENSE_NM)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # colour-science warns that it aligns the SPD
            ref = (
                colour.sd_to_XYZ(sd, colour.MSDS_CMFS[OBSERVER_10], colour.SDS_ILLUMINANTS["D50"], method="Integration")
                / 100
            )
        np.testing.assert_allclose(white_point_xyz(), ref, rtol=1e-12)

    def test_other_illuminant_and_observer(self):
        xyz = spectrum_to_xyz(
            DENSE_NM, np.ones(DENSE_NM.size), illuminant="D65", observer="CIE 1931 2 Degree Standard Observer"
        )
        # ASTM E308-15 white point of D65 / 2° at 1 nm: (95.047, 100.000, 108.883).
        np.testing.assert_allclose(xyz, [0.95047, 1.0, 1.08883], atol=1e-5)


# Spectra of the shared USGS library: a quartz sand, the 2 % hematite + quartz mixture, a
# goethite (all Beckman, irregular 1–8 nm sampling) and an ASD spectrum (1 nm).
USGS_STEMS = [
    "Quartz_GDS74_Sand_Ottawa_BECKc_AREF",
    "Hematite.02+Quartz.98_GDS76_BECKa_AREF",
    "Goethite_WS222_Medium_Gr._BECKa_AREF",
    "Goethite_GDS134_ASDFRb_AREF",
]


@pytest.mark.parametrize("stem", USGS_STEMS)
def test_measured_spectrum_matches_colour_science_sd_to_xyz(stem):
    wl, r = read_usgs(stem)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # "not uniform, using minimum interval": expected
        # colour-science's own path at 1 nm: its default (cubic spline) interpolation of the
        # irregular data, constant extrapolation, then sd_to_XYZ (ASTM E308 at 1 nm: a sum).
        sd = colour.SpectralDistribution(r, wl).align(colour.SpectralShape(360, 830, 1))
        ref = colour.sd_to_XYZ(sd, colour.MSDS_CMFS[OBSERVER_10], colour.SDS_ILLUMINANTS["D50"]) / 100
    ours = spectrum_to_xyz(wl, r)
    np.testing.assert_allclose(ours, ref, rtol=1e-3)  # 0.1 %


class TestCoarseSampling:
    # Measured (docs/colour.md): ΔE00 ≤ 0.0065 for these edges, 0.013 for the USGS mixture.
    def test_sixteen_bands_of_a_smooth_spectrum(self):
        for edge_nm, width_nm in [(520.0, 25.0), (560.0, 30.0), (600.0, 40.0)]:
            dense = spectrum_to_xyz(DENSE_NM, logistic_spectrum(DENSE_NM, edge_nm, width_nm))
            coarse = spectrum_to_xyz(
                PREDICTOR_WAVELENGTHS_NM, logistic_spectrum(PREDICTOR_WAVELENGTHS_NM, edge_nm, width_nm)
            )
            assert delta_e_2000(dense, coarse) < 0.02

    def test_sixteen_bands_of_a_measured_sand(self):
        wl, r = read_usgs("Hematite.02+Quartz.98_GDS76_BECKa_AREF")
        bands = np.interp(PREDICTOR_WAVELENGTHS_NM, wl, r)  # the 1–2 nm data at the 16 bands
        coarse = spectrum_to_xyz(PREDICTOR_WAVELENGTHS_NM, bands)
        assert delta_e_2000(spectrum_to_xyz(wl, r), coarse) < 0.1

    def test_constant_extension_outside_the_given_range(self):
        # A dense spectrum that is already constant outside 400–700 nm integrates exactly like
        # its 400–700 nm part alone: the documented extrapolation.
        r = np.clip(logistic_spectrum(DENSE_NM), None, None)
        r[DENSE_NM < 400] = r[DENSE_NM == 400]
        r[DENSE_NM > 700] = r[DENSE_NM == 700]
        inner = (DENSE_NM >= 400) & (DENSE_NM <= 700)
        np.testing.assert_allclose(spectrum_to_xyz(DENSE_NM[inner], r[inner]), spectrum_to_xyz(DENSE_NM, r), rtol=1e-12)

    def test_interpolation_does_not_overshoot_a_step(self):
        # A reflectance step between two bands: PCHIP keeps the interpolant between the two
        # levels, so XYZ lies between those of the two flat spectra, channel by channel.
        step = np.where(PREDICTOR_WAVELENGTHS_NM < 550, 0.05, 0.6)
        xyz = spectrum_to_xyz(PREDICTOR_WAVELENGTHS_NM, step)
        assert np.all(xyz > 0.05 * white_point_xyz()) and np.all(xyz < 0.6 * white_point_xyz())
        # the Sprague interpolant of the same data dips below 0.05 next to the step
        sd = colour.SpectralDistribution(step, PREDICTOR_WAVELENGTHS_NM)
        sprague = sd.copy().interpolate(colour.SpectralShape(400, 700, 1))
        assert sprague.values.min() < 0.05 - 1e-3


class TestShapesAndScale:
    def test_broadcast_over_leading_axes(self):
        edges = np.linspace(480.0, 620.0, 6).reshape(2, 3, 1)
        spectra = logistic_spectrum(PREDICTOR_WAVELENGTHS_NM, edges)
        xyz = spectrum_to_xyz(PREDICTOR_WAVELENGTHS_NM, spectra)
        assert xyz.shape == (2, 3, 3)
        np.testing.assert_allclose(xyz[1, 2], spectrum_to_xyz(PREDICTOR_WAVELENGTHS_NM, spectra[1, 2]), rtol=1e-14)

    def test_linear_in_reflectance_scale(self):
        r = logistic_spectrum(PREDICTOR_WAVELENGTHS_NM)
        np.testing.assert_allclose(
            spectrum_to_xyz(PREDICTOR_WAVELENGTHS_NM, 0.5 * r),
            0.5 * spectrum_to_xyz(PREDICTOR_WAVELENGTHS_NM, r),
            rtol=1e-12,
        )
        np.testing.assert_allclose(
            spectrum_to_xyz(PREDICTOR_WAVELENGTHS_NM, np.full(16, 0.25)), 0.25 * white_point_xyz(), rtol=1e-12
        )


class TestErrors:
    def test_nan_reflectance(self):
        r = logistic_spectrum(PREDICTOR_WAVELENGTHS_NM)
        r[3] = np.nan
        with pytest.raises(ParameterError, match="reflectance"):
            spectrum_to_xyz(PREDICTOR_WAVELENGTHS_NM, r)

    def test_percent_reflectance(self):
        with pytest.raises(ParameterError, match="divided by 100"):
            spectrum_to_xyz(PREDICTOR_WAVELENGTHS_NM, np.full(16, 45.0))

    @pytest.mark.parametrize(
        "wavelengths_nm",
        [
            np.arange(420.0, 701.0, 20.0),  # starts after 400 nm
            np.arange(400.0, 681.0, 20.0),  # ends before 700 nm
            PREDICTOR_WAVELENGTHS_NM[::-1],  # decreasing
            np.array([400.0, 400.0, 700.0]),  # repeated
        ],
    )
    def test_bad_wavelengths(self, wavelengths_nm):
        with pytest.raises(ParameterError, match="wavelengths_nm.*400–700 nm"):
            spectrum_to_xyz(wavelengths_nm, np.full(wavelengths_nm.size, 0.3))

    def test_shape_mismatch(self):
        with pytest.raises(ParameterError, match=r"reflectance.*\(\.\.\., 16\)"):
            spectrum_to_xyz(PREDICTOR_WAVELENGTHS_NM, np.full(15, 0.3))

    def test_unknown_illuminant_and_observer(self):
        r = np.full(16, 0.3)
        with pytest.raises(ParameterError, match="illuminant = 'D51'"):
            spectrum_to_xyz(PREDICTOR_WAVELENGTHS_NM, r, illuminant="D51")
        with pytest.raises(ParameterError, match="observer"):
            spectrum_to_xyz(PREDICTOR_WAVELENGTHS_NM, r, observer="CIE 1931 2 Degree")
        with pytest.raises(ParameterError, match="illuminant"):  # names only, not SPD objects
            spectrum_to_xyz(PREDICTOR_WAVELENGTHS_NM, r, illuminant=colour.SDS_ILLUMINANTS["D50"])


def test_xyz_under_several_illuminants_equals_each_one_alone():
    wl = PREDICTOR_WAVELENGTHS_NM
    r = np.stack([logistic_spectrum(wl, 550.0), logistic_spectrum(wl, 620.0)])
    both = spectrum_to_xyz_under(wl, r, illuminants=("D50", "D65", "A"))
    assert both.shape == (2, 3, 3)
    for i, name in enumerate(("D50", "D65", "A")):
        np.testing.assert_allclose(both[:, i, :], spectrum_to_xyz(wl, r, illuminant=name), rtol=0, atol=1e-14)


def test_xyz_under_refuses_no_illuminant_or_an_unknown_one():
    wl = PREDICTOR_WAVELENGTHS_NM
    with pytest.raises(ParameterError, match="illuminants"):
        spectrum_to_xyz_under(wl, np.full(16, 0.5), illuminants=())
    with pytest.raises(ParameterError, match="illuminant"):
        spectrum_to_xyz_under(wl, np.full(16, 0.5), illuminants=("D50", "D99"))
