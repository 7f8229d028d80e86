"""The Preetham et al. (1999) sky: zenith values, symmetry, brightness, colour, spectra, errors."""

import numpy as np
import pytest

from sandlight.errors import ParameterError
from sandlight.sky import PreethamSky, direction_from_angles, sun_direction, sun_spectral_radiance
from sandlight.sky.preetham import daylight_m1_m2

VISIBLE_NM = np.arange(380.0, 781.0, 5.0)


def sky_with_sun_at(turbidity, elevation_deg, azimuth_deg=135.0):
    return PreethamSky(turbidity, direction_from_angles(np.radians(90.0 - elevation_deg), np.radians(azimuth_deg)))


def random_upper_directions(n, seed):
    d = np.random.default_rng(seed).normal(size=(n, 3))
    d[:, 2] = np.abs(d[:, 2]) + 1e-3
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def cmfs_at(wavelength_nm):
    import colour

    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    return np.stack([np.interp(wavelength_nm, cmfs.wavelengths, cmfs.values[:, i]) for i in range(3)], axis=-1)


class TestZenith:
    def test_zenith_values_by_hand(self):
        # T = 3, θs = 30°, evaluated by hand from the paper's formulas (appendix):
        # χ = (4/9 − 3/120)(π − π/3) = 0.87848, Y_z = 7.1649 tan χ + 1.7727 = 10.413 kcd/m²;
        # x_z: rows (T², T, 1)·(θs³, θs², θs, 1) = 9·0.0003045 + 3·0.00049 + 0.249221 = 0.2534.
        sky = sky_with_sun_at(3.0, 60.0)
        assert sky.zenith_luminance_kcd_m2 == pytest.approx(10.413, abs=2e-3)
        assert sky.zenith_chromaticity[0] == pytest.approx(0.2534, abs=2e-4)
        assert sky.zenith_chromaticity[1] == pytest.approx(0.2598, abs=2e-4)

    @pytest.mark.parametrize("turbidity", [1.7, 2.0, 3.0, 6.0, 10.0])
    @pytest.mark.parametrize("elevation_deg", [2.0, 20.0, 45.0, 89.0])
    def test_luminance_and_chromaticity_at_the_zenith_equal_zenith_values(self, turbidity, elevation_deg):
        sky = sky_with_sun_at(turbidity, elevation_deg)
        assert sky.luminance([0.0, 0.0, 1.0]) == pytest.approx(sky.zenith_luminance_kcd_m2, rel=1e-12)
        np.testing.assert_allclose(sky.chromaticity([0.0, 0.0, 1.0]), sky.zenith_chromaticity, rtol=1e-12)

    def test_zenith_luminance_grows_with_sun_elevation(self):
        values = [sky_with_sun_at(3.0, e).zenith_luminance_kcd_m2 for e in (5, 20, 40, 60, 80)]
        assert np.all(np.diff(values) > 0)
        assert values[0] > 0.0


class TestAngularStructure:
    @pytest.mark.parametrize("turbidity, elevation_deg", [(2.0, 15.0), (3.0, 40.0), (7.0, 70.0)])
    def test_mirror_symmetry_about_the_sun_vertical_plane(self, turbidity, elevation_deg):
        sky = sky_with_sun_at(turbidity, elevation_deg, azimuth_deg=110.0)
        # Normal of the vertical plane through the sun: horizontal, perpendicular to the sun.
        normal = np.cross(sky.sun_direction, [0.0, 0.0, 1.0])
        normal /= np.linalg.norm(normal)
        d = random_upper_directions(400, seed=1)
        mirrored = d - 2.0 * (d @ normal)[:, None] * normal
        assert not np.allclose(d, mirrored)
        np.testing.assert_allclose(sky.luminance(mirrored), sky.luminance(d), rtol=1e-10)
        np.testing.assert_allclose(sky.chromaticity(mirrored), sky.chromaticity(d), rtol=1e-10)
        np.testing.assert_allclose(
            sky.radiance(mirrored, VISIBLE_NM[::8]), sky.radiance(d, VISIBLE_NM[::8]), rtol=1e-10
        )

    @pytest.mark.parametrize("turbidity", [2.0, 3.0, 6.0, 10.0])
    @pytest.mark.parametrize("sun_elevation_deg", [10.0, 30.0, 60.0])
    @pytest.mark.parametrize("view_elevation_deg", [5.0, 30.0, 60.0])
    def test_brighter_toward_the_sun_along_an_almucantar(self, turbidity, sun_elevation_deg, view_elevation_deg):
        sun_azimuth = 200.0
        sky = sky_with_sun_at(turbidity, sun_elevation_deg, azimuth_deg=sun_azimuth)
        offsets = np.radians(np.linspace(0.0, 90.0, 91))
        d = direction_from_angles(np.radians(90.0 - view_elevation_deg), np.radians(sun_azimuth) + offsets)
        luminance = sky.luminance(d)
        assert np.all(np.diff(luminance) < 0.0)  # falls steadily away from the sun's azimuth
        opposite = sky.luminance(
            direction_from_angles(np.radians(90.0 - view_elevation_deg), np.radians(sun_azimuth + 180.0))
        )
        assert luminance[0] > opposite

    def test_clear_sky_zenith_is_blue_and_horizon_whiter(self):
        for turbidity in (2.0, 2.5, 3.0):
            for elevation in (30.0, 50.0, 70.0):
                sky = sky_with_sun_at(turbidity, elevation)
                x, y = sky.zenith_chromaticity
                assert x < 0.3 and y < 0.3
                # D65 is (0.3127, 0.3290): a clear zenith is bluer than daylight white.
                assert x < 0.3127 and y < 0.3290
                horizon = direction_from_angles(np.pi / 2 - 0.02, np.radians(315.0))
                assert sky.chromaticity(horizon)[0] > x

    def test_all_values_physical_over_the_supported_range(self):
        d = random_upper_directions(500, seed=2)
        for turbidity in (1.7, 2.0, 4.0, 7.0, 10.0):
            for elevation in (0.5, 5.0, 30.0, 89.5):
                sky = sky_with_sun_at(turbidity, elevation)
                assert np.all(sky.luminance(d) > 0.0)
                xy = sky.chromaticity(d)
                assert np.all((xy > 0.2) & (xy < 0.5))


class TestSpectralRadiance:
    @pytest.mark.parametrize("turbidity, elevation_deg", [(2.0, 60.0), (3.0, 25.0), (8.0, 10.0)])
    def test_spectrum_reproduces_luminance_and_chromaticity(self, turbidity, elevation_deg):
        sky = sky_with_sun_at(turbidity, elevation_deg)
        d = random_upper_directions(50, seed=3)
        radiance = sky.radiance(d, VISIBLE_NM)  # W m⁻² sr⁻¹ nm⁻¹
        xyz = 683.0 * radiance @ cmfs_at(VISIBLE_NM) * 5.0  # cd m⁻²
        np.testing.assert_allclose(xyz[:, 1], 1000.0 * sky.luminance(d), rtol=5e-3)
        xy = xyz[:, :2] / xyz.sum(axis=-1, keepdims=True)
        np.testing.assert_allclose(xy, sky.chromaticity(d), atol=1e-3)

    def test_radiance_magnitude_for_a_clear_blue_sky(self):
        # Y ≈ 10 kcd/m² over a flat-ish visible spectrum → of order 10⁴/(683·107) ≈ 0.14 W/m²/sr/nm.
        sky = sky_with_sun_at(3.0, 60.0)
        radiance = sky.radiance([0.0, 0.0, 1.0], 550.0)
        assert 0.05 < radiance < 0.5
        # A blue sky: more radiance at 450 nm than at 650 nm.
        blue, red = sky.radiance([0.0, 0.0, 1.0], [450.0, 650.0])
        assert blue > red

    def test_vectorised_over_directions_and_wavelengths(self):
        sky = sky_with_sun_at(3.0, 35.0)
        d = random_upper_directions(12, seed=4).reshape(3, 4, 3)
        wavelengths = np.array([400.0, 480.0, 555.0, 610.0, 700.0])
        out = sky.radiance(d, wavelengths)
        assert out.shape == (3, 4, 5)
        for index in np.ndindex(3, 4):
            for k, lam in enumerate(wavelengths):
                assert out[index + (k,)] == pytest.approx(sky.radiance(d[index], lam), rel=1e-12)
        assert sky.radiance(d, 555.0).shape == (3, 4)
        assert sky.luminance(d).shape == (3, 4)
        assert sky.chromaticity(d).shape == (3, 4, 2)

    def test_unrounded_daylight_factors(self):
        # CIE 015 rounds M1, M2 to 3 decimals for its tables; we keep them exact.
        m1, m2 = daylight_m1_m2(0.3127, 0.3290)
        assert m1 != round(float(m1), 3) and m2 != round(float(m2), 3)

    def test_below_horizon_takes_the_horizon_value(self):
        sky = sky_with_sun_at(3.0, 30.0)
        below = np.array([[0.6, 0.3, -0.5], [-0.2, 0.9, -0.01]])
        horizon = below.copy()
        horizon[:, 2] = 0.0
        np.testing.assert_allclose(sky.radiance(below, VISIBLE_NM), sky.radiance(horizon, VISIBLE_NM), rtol=1e-12)
        straight_down = sky.radiance([0.0, 0.0, -1.0], VISIBLE_NM)
        assert np.all(np.isfinite(straight_down)) and np.all(straight_down > 0.0)


class TestSun:
    def test_sun_radiance_matches_module_and_reddens(self):
        high = sky_with_sun_at(3.0, 70.0)
        low = sky_with_sun_at(3.0, 8.0)
        np.testing.assert_allclose(
            high.sun_radiance(VISIBLE_NM), sun_spectral_radiance(high.sun_zenith_rad, VISIBLE_NM, 3.0)
        )
        ratio_high = np.divide(*high.sun_radiance([450.0, 650.0]))
        ratio_low = np.divide(*low.sun_radiance([450.0, 650.0]))
        assert ratio_low < ratio_high
        np.testing.assert_allclose(
            high.sun_irradiance(VISIBLE_NM), high.sun_radiance(VISIBLE_NM) * high.sun_solid_angle
        )
        assert 6.7e-5 < high.sun_solid_angle < 6.9e-5

    def test_from_location_uses_the_sun_position(self):
        sky = PreethamSky.from_location(3.0, 30.0, 172, 10.5)
        np.testing.assert_allclose(sky.sun_direction, sun_direction(30.0, 172, 10.5))


class TestInvalidInputs:
    @pytest.mark.parametrize("turbidity", [1.0, 10.5, np.nan, np.inf, "3", None, [2.0, 3.0]])
    def test_turbidity(self, turbidity):
        with pytest.raises(ParameterError) as info:
            PreethamSky(turbidity, [0.0, 0.0, 1.0])
        assert info.value.name == "turbidity"

    @pytest.mark.parametrize(
        "direction",
        [[0.0, 1.0, 0.0], [0.0, 1.0, -0.2], [0.0, 0.0, 0.0], [0.0, 0.0, np.nan], [[0, 0, 1], [0, 0, 1]], [1.0, 2.0]],
    )
    def test_sun_direction(self, direction):
        with pytest.raises(ParameterError) as info:
            PreethamSky(3.0, direction)
        assert info.value.name == "sun_direction"

    def test_sun_below_horizon_from_location(self):
        with pytest.raises(ParameterError, match="above the horizon"):
            PreethamSky.from_location(3.0, 30.0, 172, 23.0)

    def test_evaluation_inputs(self):
        sky = sky_with_sun_at(3.0, 45.0)
        with pytest.raises(ParameterError) as info:
            sky.luminance([[0.0, 1.0], [1.0, 0.0]])
        assert info.value.name == "directions"
        with pytest.raises(ParameterError) as info:
            sky.radiance([0.0, 0.0, 1.0], [500.0, 900.0])
        assert info.value.name == "wavelengths_nm" and info.value.value == 900.0


def test_radiance_is_never_negative_with_a_low_sun():
    # Near a sun a few degrees up, the daylight basis would dip below zero in the violet.
    import numpy as np

    from sandlight.sky import PreethamSky

    elev = np.radians(4.7)
    sky = PreethamSky(3.0, [np.cos(elev), 0.0, np.sin(elev)])
    theta = np.radians(np.linspace(0, 89, 40))
    phi = np.radians(np.linspace(-30, 30, 31))
    t, p = np.meshgrid(theta, phi)
    dirs = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], axis=-1)
    radiance = sky.radiance(dirs, np.arange(380.0, 781.0, 10.0))
    assert np.all(np.isfinite(radiance)) and radiance.min() >= 0.0 and radiance.max() > 0.0
