"""xyz_to_srgb (paper and managed modes), xyz_to_lab, srgb_to_uint8."""

import numpy as np
import pytest

import colour
from sandlight.colour import (
    PAPER_XYZ_TO_LINEAR_RGB,
    paper_encoding,
    srgb_to_uint8,
    white_point_xyz,
    xyz_to_lab,
    xyz_to_srgb,
)
from sandlight.errors import ParameterError

D50_10_XY = colour.XYZ_to_xy(white_point_xyz())


class TestPaperMode:
    def test_printed_matrix(self):
        # §4.1.1 of the paper, digit for digit.
        printed = [[3.2410, -1.5374, -0.4986], [-0.9692, 1.8760, 0.0416], [0.0556, -0.2040, 1.0570]]
        assert PAPER_XYZ_TO_LINEAR_RGB.tolist() == printed

    def test_hand_computed_colour(self):
        # XYZ = (0.2, 0.3, 0.1), by hand:
        #   R' = 3.2410·0.2 − 1.5374·0.3 − 0.4986·0.1 = 0.6482 − 0.46122 − 0.04986 = 0.13712
        #   G' = −0.9692·0.2 + 1.8760·0.3 + 0.0416·0.1 = −0.19384 + 0.5628 + 0.00416 = 0.37312
        #   B' = 0.0556·0.2 − 0.2040·0.3 + 1.0570·0.1 = 0.01112 − 0.0612 + 0.1057 = 0.05562
        #   R = 1.055·R'^(1/2.4) − 0.055, e.g. 0.13712^(1/2.4) = exp(ln(0.13712)/2.4)
        #     = exp(−1.98692/2.4) = exp(−0.82788) = 0.43697 → R = 0.40601
        linear = np.array([0.13712, 0.37312, 0.05562])
        expected = 1.055 * linear ** (1 / 2.4) - 0.055
        np.testing.assert_allclose(expected, [0.40601, 0.64461, 0.26154], atol=1e-5)
        np.testing.assert_allclose(xyz_to_srgb([0.2, 0.3, 0.1], mode="paper"), expected, rtol=1e-12)

    def test_no_linear_segment_near_black(self):
        # The printed curve has no 12.92·v segment: v = 0.001 → 0.004327, where sRGB has 0.01292.
        assert paper_encoding(0.001) == pytest.approx(0.0043270098, rel=1e-8)
        assert paper_encoding(0.0) == pytest.approx(-0.055)
        # The XYZ whose linear R' under the printed matrix is exactly 0.001.
        xyz = np.linalg.solve(PAPER_XYZ_TO_LINEAR_RGB, [0.001, 0.5, 0.5])
        rgb = xyz_to_srgb(xyz, mode="paper")
        assert rgb[0] == pytest.approx(0.0043270098, rel=1e-6)
        managed_curve = colour.models.eotf_inverse_sRGB(0.001)
        assert managed_curve == pytest.approx(0.01292)

    def test_encoded_result_clamped_at_zero(self):
        # Documented choice: the printed curve's −0.055 at black is clamped to 0.
        np.testing.assert_array_equal(xyz_to_srgb([0.0, 0.0, 0.0], mode="paper"), [0, 0, 0])
        # Below R' = (0.055/1.055)^2.4 ≈ 8.3e-4 the printed curve is negative, so clamped too.
        xyz = np.linalg.solve(PAPER_XYZ_TO_LINEAR_RGB, [5e-4, 0.5, 0.5])
        assert xyz_to_srgb(xyz, mode="paper")[0] == 0.0

    def test_white_is_warm_and_clipped(self):
        rgb, out = xyz_to_srgb(white_point_xyz(), mode="paper", return_out_of_gamut=True)
        np.testing.assert_allclose(rgb, [1.0, 0.98779, 0.85987], atol=1e-5)
        assert out


class TestManagedMode:
    def test_white_reflector_is_white(self):
        rgb, out = xyz_to_srgb(white_point_xyz(), return_out_of_gamut=True)
        np.testing.assert_allclose(rgb, [1.0, 1.0, 1.0], atol=1e-12)
        assert not out

    def test_black_is_black(self):
        np.testing.assert_array_equal(xyz_to_srgb([0.0, 0.0, 0.0]), [0.0, 0.0, 0.0])

    def test_grey_has_equal_channels_and_sRGB_curve(self):
        # A spectrally flat 18 % grey: after adaptation R = G = B = 0.18, encoded by IEC 61966-2-1.
        rgb = xyz_to_srgb(0.18 * white_point_xyz())
        np.testing.assert_allclose(rgb, 1.055 * 0.18 ** (1 / 2.4) - 0.055, atol=1e-12)

    def test_agrees_with_colour_science_pipeline(self):
        # colour-science's XYZ_to_sRGB with Bradford from our D50/10° white. It uses the IEC
        # printed 4-decimal matrix, which differs from the derived one by ~1e-4.
        xyz = np.array([[0.25, 0.22, 0.12], [0.40, 0.42, 0.30], [0.08, 0.07, 0.04]])
        ref = colour.XYZ_to_sRGB(xyz, illuminant=D50_10_XY, chromatic_adaptation_transform="Bradford")
        np.testing.assert_allclose(xyz_to_srgb(xyz), ref, atol=3e-4)

    def test_out_of_gamut_flag(self):
        # A saturated green (spectral 520 nm light, scaled) is outside sRGB; a sand colour is not.
        cmfs = colour.MSDS_CMFS["CIE 1964 10 Degree Standard Observer"]
        green = 0.3 * cmfs[520] / cmfs[520][1]
        sand = 0.3 * white_point_xyz() * [1.05, 1.0, 0.7]
        rgb, out = xyz_to_srgb(np.stack([green, sand]), return_out_of_gamut=True)
        assert out.tolist() == [True, False]
        assert np.all((rgb >= 0) & (rgb <= 1))

    def test_modes_differ(self):
        xyz = 0.3 * white_point_xyz()
        assert np.max(np.abs(xyz_to_srgb(xyz) - xyz_to_srgb(xyz, mode="paper"))) > 0.02


class TestShapesAndErrors:
    @pytest.mark.parametrize("mode", ["managed", "paper"])
    def test_broadcast(self, mode):
        xyz = np.random.default_rng(3).uniform(0.05, 0.4, (2, 4, 3))
        rgb = xyz_to_srgb(xyz, mode=mode)
        assert rgb.shape == (2, 4, 3)
        np.testing.assert_allclose(rgb[1, 3], xyz_to_srgb(xyz[1, 3], mode=mode), rtol=1e-14)
        assert xyz_to_lab(xyz).shape == (2, 4, 3)

    def test_bad_mode(self):
        with pytest.raises(ParameterError, match="mode = 'sRGB'.*managed.*paper"):
            xyz_to_srgb([0.2, 0.2, 0.2], mode="sRGB")

    def test_nan(self):
        with pytest.raises(ParameterError, match="xyz"):
            xyz_to_srgb([0.2, np.nan, 0.2])
        with pytest.raises(ParameterError, match="xyz"):
            xyz_to_lab([0.2, np.nan, 0.2])

    def test_bad_shape(self):
        with pytest.raises(ParameterError, match=r"shape \(\.\.\., 3\)"):
            xyz_to_srgb([0.2, 0.2])


class TestLab:
    def test_white_and_grey(self):
        np.testing.assert_allclose(xyz_to_lab(white_point_xyz()), [100.0, 0.0, 0.0], atol=1e-10)
        # CIE 015 Eq. 8.4: L* = 116 (Y/Yn)^(1/3) − 16; flat 18 % grey is neutral.
        np.testing.assert_allclose(
            xyz_to_lab(0.18 * white_point_xyz()), [116 * 0.18 ** (1 / 3) - 16, 0.0, 0.0], atol=1e-10
        )

    def test_matches_colour_science(self):
        xyz = np.array([0.25, 0.22, 0.12])
        np.testing.assert_allclose(xyz_to_lab(xyz), colour.XYZ_to_Lab(xyz, D50_10_XY), rtol=1e-12)

    def test_scale_invariance_of_hue(self):
        # Scaling XYZ changes L* but not the hue angle (a*, b* scale together).
        xyz = np.array([0.25, 0.22, 0.12])
        lab1, lab2 = xyz_to_lab(xyz), xyz_to_lab(0.5 * xyz)
        assert lab2[0] < lab1[0]
        assert np.degrees(np.arctan2(lab1[2], lab1[1])) == pytest.approx(
            np.degrees(np.arctan2(lab2[2], lab2[1])), abs=1e-9
        )


def test_srgb_to_uint8():
    np.testing.assert_array_equal(srgb_to_uint8([0.0, 0.5, 1.0, -0.2, 1.3]), [0, 128, 255, 0, 255])
    assert srgb_to_uint8(np.zeros((2, 2, 3))).dtype == np.uint8
    with pytest.raises(ParameterError, match="rgb"):
        srgb_to_uint8([np.nan, 0.0, 0.0])
