"""Sun position (Preetham et al. 1999, appendix) against an independent formula and known cases."""

import datetime

import numpy as np
import pytest

from sandlight.errors import ParameterError
from sandlight.sky import (
    angles_from_direction,
    day_of_year,
    direction_from_angles,
    solar_declination,
    solar_time,
    sun_direction,
    sun_position,
)


def noaa_sun_direction(latitude_deg, day, solar_time_h):
    """Independent reference: NOAA's general solar position formulas, i.e. Spencer's (1971)
    Fourier series for the declination, with the textbook hour-angle geometry. Returns
    (x east, y north, z up) unit vectors."""
    gamma = 2.0 * np.pi / 365.0 * (day - 1.0 + (solar_time_h - 12.0) / 24.0)
    declination = (
        0.006918
        - 0.399912 * np.cos(gamma)
        + 0.070257 * np.sin(gamma)
        - 0.006758 * np.cos(2 * gamma)
        + 0.000907 * np.sin(2 * gamma)
        - 0.002697 * np.cos(3 * gamma)
        + 0.00148 * np.sin(3 * gamma)
    )
    hour_angle = np.radians(15.0 * (solar_time_h - 12.0))  # 0 at noon, + afternoon
    lat = np.radians(latitude_deg)
    east = -np.cos(declination) * np.sin(hour_angle)
    north = np.cos(lat) * np.sin(declination) - np.sin(lat) * np.cos(declination) * np.cos(hour_angle)
    up = np.sin(lat) * np.sin(declination) + np.cos(lat) * np.cos(declination) * np.cos(hour_angle)
    return np.stack(np.broadcast_arrays(east, north, up), axis=-1)


def noaa_equation_of_time_min(day):
    """Spencer/NOAA equation of time in minutes (true solar minus mean solar time)."""
    gamma = 2.0 * np.pi / 365.0 * (day - 1.0)
    return 229.18 * (
        0.000075
        + 0.001868 * np.cos(gamma)
        - 0.032077 * np.sin(gamma)
        - 0.014615 * np.cos(2 * gamma)
        - 0.040849 * np.sin(2 * gamma)
    )


def angle_between_deg(a, b):
    return np.degrees(np.arccos(np.clip(np.sum(a * b, axis=-1), -1.0, 1.0)))


class TestAgainstNOAA:
    def test_direction_within_one_degree_over_a_year(self):
        latitude = np.array([-60.0, -35.0, 0.0, 23.4, 30.0, 52.0, 70.0])[:, None, None]
        day = np.arange(1.0, 366.0, 7.0)[None, :, None]
        time = np.arange(0.0, 24.01, 1.5)[None, None, :]
        ours = sun_direction(latitude, day, time)
        reference = noaa_sun_direction(latitude, day, time)
        separation = angle_between_deg(ours, reference)
        assert separation.max() < 1.0
        # The fit is much better than the tolerance on average.
        assert separation.mean() < 0.4

    def test_clock_time_uses_equation_of_time_and_meridian(self):
        # Phoenix (33.45 N, 112.07 W, UTC−7): clock time → solar time via NOAA's time offset.
        day = np.arange(1.0, 366.0, 5.0)
        clock = 9.25
        ours = sun_direction(33.45, day, clock, longitude_deg=-112.07, utc_offset_h=-7.0)
        offset_min = noaa_equation_of_time_min(day) + 4.0 * -112.07 - 60.0 * -7.0
        reference = noaa_sun_direction(33.45, day, clock + offset_min / 60.0)
        assert angle_between_deg(ours, reference).max() < 1.0

    def test_solar_time_equation_of_time_within_two_minutes(self):
        day = np.arange(1.0, 366.0)
        ours_min = (solar_time(12.0, day, 0.0, 0.0) - 12.0) * 60.0
        assert np.abs(ours_min - noaa_equation_of_time_min(day)).max() < 2.0


class TestKnownCases:
    def test_solstice_noon_zenith_is_latitude_minus_tilt(self):
        zenith, azimuth = sun_position(40.0, 172, 12.0)
        assert np.degrees(zenith) == pytest.approx(40.0 - 23.45, abs=0.05)
        assert np.degrees(azimuth) == pytest.approx(180.0, abs=1e-6)  # due south

    def test_southern_hemisphere_noon_sun_is_north(self):
        zenith, azimuth = sun_position(-35.0, 172, 12.0)
        assert np.degrees(zenith) == pytest.approx(35.0 + 23.45, abs=0.05)
        assert np.degrees(azimuth) == pytest.approx(0.0, abs=1e-6) or np.degrees(azimuth) == pytest.approx(
            360.0, abs=1e-6
        )

    def test_equinox_sun_rises_east_sets_west_at_six(self):
        day = 81  # Preetham's declination is zero on day 81
        assert solar_declination(day) == pytest.approx(0.0, abs=1e-12)
        morning = sun_direction(45.0, day, 6.0)
        evening = sun_direction(45.0, day, 18.0)
        np.testing.assert_allclose(morning, [1.0, 0.0, 0.0], atol=1e-9)
        np.testing.assert_allclose(evening, [-1.0, 0.0, 0.0], atol=1e-9)

    def test_morning_and_afternoon_mirror_about_the_meridian(self):
        zenith_am, azimuth_am = sun_position(30.0, 100, 12.0 - 2.5)
        zenith_pm, azimuth_pm = sun_position(30.0, 100, 12.0 + 2.5)
        assert zenith_am == pytest.approx(zenith_pm, abs=1e-12)
        assert azimuth_am + azimuth_pm == pytest.approx(2.0 * np.pi, abs=1e-12)
        assert azimuth_am < np.pi < azimuth_pm

    def test_night_is_below_horizon(self):
        assert sun_direction(30.0, 172, 0.0)[2] < 0.0

    def test_date_objects_and_day_numbers_agree(self):
        date = datetime.date(2023, 6, 21)
        assert day_of_year(date) == 172
        np.testing.assert_allclose(sun_direction(30.0, date, 10.0), sun_direction(30.0, 172, 10.0))

    def test_direction_and_angles_round_trip(self):
        rng = np.random.default_rng(3)
        zenith = rng.uniform(0.01, np.pi - 0.01, 50)
        azimuth = rng.uniform(0.0, 2 * np.pi, 50)
        d = direction_from_angles(zenith, azimuth)
        np.testing.assert_allclose(np.linalg.norm(d, axis=-1), 1.0)
        z2, a2 = angles_from_direction(d)
        np.testing.assert_allclose(z2, zenith, atol=1e-12)
        np.testing.assert_allclose(a2, azimuth, atol=1e-12)
        # Frame: azimuth π/2 is east (+x), 0 is north (+y).
        np.testing.assert_allclose(direction_from_angles(np.pi / 2, np.pi / 2), [1, 0, 0], atol=1e-15)

    def test_broadcasting_shapes(self):
        zenith, azimuth = sun_position(np.zeros((4, 1)), 100, np.linspace(6, 18, 5))
        assert zenith.shape == azimuth.shape == (4, 5)
        assert sun_direction(np.zeros((4, 1)), 100, np.linspace(6, 18, 5)).shape == (4, 5, 3)


class TestInvalidInputs:
    @pytest.mark.parametrize(
        "kwargs, name",
        [
            (dict(latitude_deg=91.0, day_of_year=1, time_h=12.0), "latitude_deg"),
            (dict(latitude_deg=np.nan, day_of_year=1, time_h=12.0), "latitude_deg"),
            (dict(latitude_deg=10.0, day_of_year=0, time_h=12.0), "day_of_year"),
            (dict(latitude_deg=10.0, day_of_year=367, time_h=12.0), "day_of_year"),
            (dict(latitude_deg=10.0, day_of_year=10, time_h=24.5), "time_h"),
            (dict(latitude_deg=10.0, day_of_year=10, time_h=[1.0, -1.0]), "time_h"),
            (dict(latitude_deg="north", day_of_year=10, time_h=12.0), "latitude_deg"),
            (
                dict(latitude_deg=10.0, day_of_year=10, time_h=12.0, longitude_deg=200.0, utc_offset_h=0.0),
                "longitude_deg",
            ),
            (
                dict(latitude_deg=10.0, day_of_year=10, time_h=12.0, longitude_deg=20.0, utc_offset_h=15.0),
                "utc_offset_h",
            ),
            (dict(latitude_deg=10.0, day_of_year=10, time_h=12.0, longitude_deg=20.0), "utc_offset_h"),
        ],
    )
    def test_raises_parameter_error_naming_the_parameter(self, kwargs, name):
        with pytest.raises(ParameterError) as info:
            sun_position(**kwargs)
        assert info.value.name == name
        assert name in str(info.value)

    def test_error_reports_offending_element(self):
        with pytest.raises(ParameterError) as info:
            sun_position(10.0, 10, [1.0, 30.0, 2.0])
        assert info.value.value == 30.0
        assert "[0, 24]" in str(info.value)
