"""Direct-beam sun spectrum: physics checks and the SPECTRL2 cross-check."""

import numpy as np
import pytest

from sandlight.errors import ParameterError
from sandlight.sky import sun_spectrum as ss

# Visible wavelengths away from the O2 and H2O bands (690 nm and beyond), where interpolating
# absorption coefficients (ours) or transmittances (SPECTRL2 grid) makes no difference.
CONTINUUM_NM = np.array([400.0, 450.0, 500.0, 550.0, 600.0, 650.0, 665.0])
CIE_Y_NM = np.arange(380.0, 781.0, 5.0)


def photopic_ybar(wavelength_nm):
    import colour

    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    return np.interp(wavelength_nm, cmfs.wavelengths, cmfs.values[:, 1])


class TestTables:
    def test_extraterrestrial_spectrum_integrates_near_the_solar_constant(self):
        # 300–4000 nm holds about 98 % of the ~1361–1367 W m⁻² solar constant.
        grid = np.linspace(300.0, 4000.0, 7401)
        total = np.trapezoid(ss.extraterrestrial_spectral_irradiance(grid), grid)
        assert 1300.0 < total < 1367.0

    def test_extraterrestrial_illuminance_is_about_133_klx(self):
        e = ss.extraterrestrial_spectral_irradiance(CIE_Y_NM)
        illuminance = 683.0 * np.sum(e * photopic_ybar(CIE_Y_NM)) * 5.0
        assert illuminance == pytest.approx(133.3e3, rel=0.02)

    def test_solid_angle_of_the_sun(self):
        # Angular radius 0.2666° (959.6″) → π r² ≈ 6.79e-5 sr.
        assert pytest.approx(np.pi * np.radians(959.63 / 3600) ** 2, rel=1e-3) == ss.SUN_SOLID_ANGLE_SR


class TestPreethamTransmittance:
    def test_rayleigh_reference_value(self):
        # Iqbal/Preetham: τ_R(0.5 µm, m ≈ 1) = exp(−0.008735 · 0.5^−4.08).
        m = ss.relative_optical_mass(0.0)
        c = ss.transmittance_components(0.0, 500.0, 3.0)
        assert m == pytest.approx(0.99949, abs=1e-5)
        assert c["rayleigh"] == pytest.approx(np.exp(-m * 0.008735 * 0.5**-4.08), rel=1e-12)
        assert c["rayleigh"] == pytest.approx(0.863, abs=0.001)

    def test_aerosol_follows_angstrom_with_beta_from_turbidity(self):
        beta = ss.angstrom_beta(3.0)
        assert beta == pytest.approx(0.04608365822050 * 3 - 0.04586025928522)
        c = ss.transmittance_components(np.radians(60.0), 1000.0, 3.0)
        m = ss.relative_optical_mass(np.radians(60.0))
        # At 1 µm the Ångström law gives τ_a = exp(−m β) whatever α.
        assert c["aerosol"] == pytest.approx(np.exp(-m * beta), rel=1e-12)

    def test_air_mass_matches_secant_at_moderate_angles(self):
        zenith = np.radians([0.0, 30.0, 60.0])
        np.testing.assert_allclose(ss.relative_optical_mass(zenith), 1 / np.cos(zenith), rtol=4e-3)
        assert 30.0 < ss.relative_optical_mass(np.pi / 2) < 40.0

    def test_components_within_zero_one_and_absorption_bands_show(self):
        wavelength = np.linspace(300.0, 4000.0, 500)
        for value in ss.transmittance_components(np.radians(45.0), wavelength, 4.0).values():
            assert np.all((value > 0.0) & (value <= 1.0))
        c = ss.transmittance_components(0.0, [550.0, 600.0, 762.5, 940.0], 3.0)
        assert c["ozone"][1] < c["ozone"][0] < 1.0  # Chappuis band peaks near 600 nm
        assert c["mixed_gases"][2] < 0.9  # O2 A band
        assert c["water_vapour"][3] < 0.5  # 940 nm water band


class TestSunSpectrum:
    @pytest.mark.parametrize("method", ss.METHODS)
    def test_positive_and_reddening_with_zenith(self, method):
        zenith = np.radians([0.0, 30.0, 50.0, 70.0, 80.0, 85.0])
        e = ss.sun_spectral_irradiance(zenith, [450.0, 650.0], 3.0, method=method)
        assert np.all(e > 0.0)
        blue_to_red = e[:, 0] / e[:, 1]
        assert np.all(np.diff(blue_to_red) < 0.0)
        assert blue_to_red[-1] < 0.5 * blue_to_red[0]

    def test_haze_dims_and_reddens(self):
        e = ss.sun_spectral_irradiance(np.radians(40.0), [450.0, 650.0], 2.0)
        e_hazy = ss.sun_spectral_irradiance(np.radians(40.0), [450.0, 650.0], 6.0)
        assert np.all(e_hazy < e)
        assert e_hazy[0] / e_hazy[1] < e[0] / e[1]

    def test_direct_normal_illuminance_clear_high_sun(self):
        # Clear sky, sun overhead, sea level: direct normal illuminance ≈ 90–110 klx.
        e = ss.sun_spectral_irradiance(0.0, CIE_Y_NM, 3.0)
        illuminance = 683.0 * np.sum(e * photopic_ybar(CIE_Y_NM)) * 5.0
        assert 85e3 < illuminance < 110e3

    @pytest.mark.parametrize("zenith_deg, tolerance", [(0.0, 0.01), (30.0, 0.01), (60.0, 0.02), (80.0, 0.05)])
    def test_agrees_with_spectrl2_in_the_continuum(self, zenith_deg, tolerance):
        zenith = np.radians(zenith_deg)
        ours = ss.sun_spectral_irradiance(zenith, CONTINUUM_NM, 3.0)
        spectrl2 = ss.sun_spectral_irradiance(zenith, CONTINUUM_NM, 3.0, method="Bird-Riordan 1986")
        np.testing.assert_allclose(ours, spectrl2, rtol=tolerance)

    def test_radiance_is_irradiance_over_solid_angle_and_distance_free(self):
        zenith = np.radians(35.0)
        radiance = ss.sun_spectral_radiance(zenith, CONTINUUM_NM, 2.5)
        irradiance = ss.sun_spectral_irradiance(zenith, CONTINUUM_NM, 2.5)
        np.testing.assert_allclose(radiance * ss.SUN_SOLID_ANGLE_SR, irradiance, rtol=1e-12)
        january = ss.sun_spectral_irradiance(zenith, CONTINUUM_NM, 2.5, day_of_year=3)
        july = ss.sun_spectral_irradiance(zenith, CONTINUUM_NM, 2.5, day_of_year=185)
        np.testing.assert_allclose(january / july, 1.0709, rtol=2e-3)  # (r_aph / r_per)²

    @pytest.mark.parametrize("method", ss.METHODS)
    def test_vectorised_shapes_match_loops(self, method):
        zenith = np.radians(np.array([[10.0, 40.0, 70.0], [0.0, 20.0, 89.0]]))
        wavelength = np.array([380.0, 555.0, 720.0, 1200.0])
        out = ss.sun_spectral_radiance(zenith, wavelength, 4.0, method=method)
        assert out.shape == (2, 3, 4)
        for index in np.ndindex(zenith.shape):
            for k, lam in enumerate(wavelength):
                assert out[index + (k,)] == pytest.approx(
                    ss.sun_spectral_radiance(zenith[index], lam, 4.0, method=method), rel=1e-12
                )
        assert ss.sun_spectral_radiance(zenith, 500.0, 4.0, method=method).shape == (2, 3)

    @pytest.mark.parametrize(
        "call, name",
        [
            (lambda: ss.sun_spectral_irradiance(1.6, 500.0, 3.0), "zenith_rad"),
            (lambda: ss.sun_spectral_irradiance(-0.1, 500.0, 3.0), "zenith_rad"),
            (lambda: ss.sun_spectral_irradiance(0.5, 250.0, 3.0), "wavelength_nm"),
            (lambda: ss.sun_spectral_irradiance(0.5, [[500.0]], 3.0), "wavelength_nm"),
            (lambda: ss.sun_spectral_irradiance(0.5, 500.0, 0.5), "turbidity"),
            (lambda: ss.sun_spectral_irradiance(0.5, 500.0, np.nan), "turbidity"),
            (lambda: ss.sun_spectral_irradiance(0.5, 500.0, 3.0, ozone_cm=-1.0), "ozone_cm"),
            (lambda: ss.sun_spectral_irradiance(0.5, 500.0, 3.0, water_vapour_cm=20.0), "water_vapour_cm"),
            (lambda: ss.sun_spectral_irradiance(0.5, 500.0, 3.0, method="Hosek"), "method"),
            (lambda: ss.sun_spectral_irradiance(0.5, 500.0, 3.0, day_of_year=0), "day_of_year"),
        ],
    )
    def test_invalid_inputs_raise_parameter_error(self, call, name):
        with pytest.raises(ParameterError) as info:
            call()
        assert info.value.name == name
