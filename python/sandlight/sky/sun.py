"""Where the sun is: solar time, declination, zenith and azimuth (Preetham et al. 1999, appendix).

Public objects
--------------
- :func:`day_of_year` : day number (1 = 1 January) of a :class:`datetime.date`.
- :func:`day_array` : day numbers given as numbers, arrays or a date, checked.
- :func:`solar_time` : local apparent solar time from standard (clock) time.
- :func:`solar_declination` : declination of the sun.
- :func:`sun_position` : sun zenith and azimuth angles.
- :func:`sun_direction` : unit vector towards the sun.
- :func:`direction_from_angles`, :func:`angles_from_direction` : frame conversions.

Conventions
-----------
- Local frame: **x = east, y = north, z = up** (right-handed).
- Zenith angle θ in radians from the local vertical (0 = overhead, π/2 = horizon).
- **Azimuth φ in radians measured from north, clockwise seen from above** (towards east):
  north 0, east π/2, south π, west 3π/2; returned in [0, 2π). This is the compass bearing used by
  NOAA and pvlib. Preetham et al. measure their φs from *south*, positive towards *west*:
  φs(Preetham) = φ − π.
- Latitude in degrees, north positive. Longitude in degrees, **east positive** (ISO 6709); the
  time zone is given as its offset from UTC in hours (e.g. −7 for US Mountain Standard Time),
  whose standard meridian is 15°·offset.
- Times in decimal hours (10.5 = 10:30). Without longitude and time zone, the time is taken as
  local apparent solar time (12 = solar noon).

Accuracy: the appendix formulas are a low-order fit; against the NOAA/Spencer series and NREL's SPA
the direction agrees within 1° (0.2–0.3° on average; see ``docs/daylight.md``), ample for lighting.
Atmospheric refraction is not modelled.

References
----------
Preetham, A. J., Shirley, P., Smits, B. (1999). A practical analytic model for daylight.
    Proceedings of SIGGRAPH 99, 91–100. Appendix (solar position).
"""

from __future__ import annotations

import datetime as _dt

import numpy as np
import numpy.typing as npt

from sandlight.checks import check_real_array, check_unit_vectors
from sandlight.errors import ParameterError

__all__ = [
    "day_of_year",
    "day_array",
    "solar_time",
    "solar_declination",
    "sun_position",
    "sun_direction",
    "direction_from_angles",
    "angles_from_direction",
]


def day_of_year(date: _dt.date) -> int:
    """Day number of ``date`` in its year: 1 for 1 January, 365 (366 in leap years) for 31 December.

    Parameters
    ----------
    date : datetime.date or datetime.datetime
        Calendar date.

    Examples
    --------
    >>> import datetime
    >>> day_of_year(datetime.date(2023, 6, 21))
    172
    """
    if not isinstance(date, _dt.date):
        raise ParameterError("date", date, "a datetime.date or datetime.datetime")
    return date.timetuple().tm_yday


def day_array(value: object) -> np.ndarray:
    """Day of year J as a float array, checked in [1, 366]; accepts numbers, arrays or a single
    ``datetime.date``."""
    if isinstance(value, _dt.date):
        return np.asarray(float(day_of_year(value)))
    return check_real_array("day_of_year", value, 1.0, 366.0)


def solar_time(
    standard_time_h: npt.ArrayLike,
    day_of_year: npt.ArrayLike | _dt.date,
    longitude_deg: npt.ArrayLike,
    utc_offset_h: npt.ArrayLike,
) -> np.ndarray:
    """Local apparent solar time from standard (clock) time.

    Preetham et al. (1999), appendix:
    t = ts + 0.170 sin(4π(J − 80)/373) − 0.129 sin(2π(J − 8)/355) + 12 (SM − L)/π,
    with SM and L the standard meridian and longitude in radians measured *west* positive. With
    east-positive degrees the last term is (L_east − SM_east)/15 hours.

    Parameters
    ----------
    standard_time_h : array_like
        Standard (clock, no daylight saving) time ts in hours, in [0, 24].
    day_of_year : array_like or datetime.date
        Day number J in [1, 366] (fractions allowed), or a date.
    longitude_deg : array_like
        Longitude in degrees, east positive, in [−180, 180].
    utc_offset_h : array_like
        Offset of the time zone from UTC in hours, in [−12, 14]; its standard meridian is
        15°·offset.

    Returns
    -------
    numpy.ndarray
        Solar time t in hours (may lie slightly outside [0, 24] near midnight; the sun formulas
        are 24 h periodic).
    """
    ts = check_real_array("standard_time_h", standard_time_h, 0.0, 24.0)
    j = day_array(day_of_year)
    lon = check_real_array("longitude_deg", longitude_deg, -180.0, 180.0)
    offset = check_real_array("utc_offset_h", utc_offset_h, -12.0, 14.0)
    # Equation of time, Preetham appendix (hours).
    equation_of_time_h = 0.170 * np.sin(4.0 * np.pi * (j - 80.0) / 373.0) - 0.129 * np.sin(
        2.0 * np.pi * (j - 8.0) / 355.0
    )
    # 12 (SM − L)/π with west-positive radians == (L_east − SM_east)/15 with degrees.
    meridian_correction_h = (lon - 15.0 * offset) / 15.0
    return ts + equation_of_time_h + meridian_correction_h


def solar_declination(day_of_year: npt.ArrayLike | _dt.date) -> np.ndarray:
    """Solar declination δ in radians (Preetham et al. 1999, appendix).

    δ = 0.4093 sin(2π(J − 81)/368).

    Parameters
    ----------
    day_of_year : array_like or datetime.date
        Day number J in [1, 366] (fractions allowed), or a date.

    Returns
    -------
    numpy.ndarray
        Declination in radians, within ±0.4093 (±23.45°).
    """
    j = day_array(day_of_year)
    return 0.4093 * np.sin(2.0 * np.pi * (j - 81.0) / 368.0)


def sun_position(
    latitude_deg: npt.ArrayLike,
    day_of_year: npt.ArrayLike | _dt.date,
    time_h: npt.ArrayLike,
    *,
    longitude_deg: npt.ArrayLike | None = None,
    utc_offset_h: npt.ArrayLike | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Zenith and azimuth angles of the sun (Preetham et al. 1999, appendix).

    θs = π/2 − arcsin(sin l sin δ − cos l cos δ cos(πt/12)),
    φs = atan2(−cos δ sin(πt/12), −(cos l sin δ + sin l cos δ cos(πt/12)))   (from south, + west),
    with l the latitude, δ the declination and t the solar time in hours. The returned azimuth is
    converted to the compass convention (from north, clockwise): φ = φs + π.

    Parameters
    ----------
    latitude_deg : array_like
        Latitude in degrees, north positive, in [−90, 90].
    day_of_year : array_like or datetime.date
        Day number J in [1, 366] (fractions allowed), or a date.
    time_h : array_like
        Time of day in hours, in [0, 24]: local apparent solar time if ``longitude_deg`` and
        ``utc_offset_h`` are omitted, otherwise standard (clock) time of that time zone.
    longitude_deg : array_like, optional
        Longitude in degrees, east positive, in [−180, 180]. Give it together with
        ``utc_offset_h``.
    utc_offset_h : array_like, optional
        Time zone offset from UTC in hours, in [−12, 14] (standard meridian 15°·offset).

    Returns
    -------
    zenith_rad : numpy.ndarray
        Sun zenith angle in radians, [0, π] (> π/2: below the horizon).
    azimuth_rad : numpy.ndarray
        Sun azimuth in radians from north, clockwise (east = π/2), in [0, 2π).
    All inputs broadcast together.

    Examples
    --------
    >>> import numpy as np
    >>> zenith, azimuth = sun_position(30.0, 172, 12.0)   # solar noon, June solstice
    >>> round(float(np.degrees(zenith)), 1), round(float(np.degrees(azimuth)), 1)
    (6.6, 180.0)
    """
    lat = np.radians(check_real_array("latitude_deg", latitude_deg, -90.0, 90.0))
    if (longitude_deg is None) != (utc_offset_h is None):
        given, missing = (
            ("longitude_deg", "utc_offset_h") if utc_offset_h is None else ("utc_offset_h", "longitude_deg")
        )
        raise ParameterError(
            missing,
            None,
            f"a value whenever {given} is given (both convert clock time to "
            "solar time; omit both to give solar time directly)",
        )
    if longitude_deg is None:
        t = check_real_array("time_h", time_h, 0.0, 24.0)
    else:
        check_real_array("time_h", time_h, 0.0, 24.0)
        t = solar_time(time_h, day_of_year, longitude_deg, utc_offset_h)
    delta = solar_declination(day_of_year)
    hour_angle = np.pi * t / 12.0  # Preetham's πt/12 (π at solar noon)
    # Preetham appendix. The clip guards arcsin against rounding just beyond ±1 at the poles.
    sin_elevation = np.clip(np.sin(lat) * np.sin(delta) - np.cos(lat) * np.cos(delta) * np.cos(hour_angle), -1.0, 1.0)
    zenith = np.pi / 2.0 - np.arcsin(sin_elevation)
    # Azimuth as in the authors' code: atan2(west component, south component). The denominator
    # is −(cos l sin δ + sin l cos δ cos(πt/12)); the form cos l sin δ − sin l cos δ cos(πt/12)
    # found in reproductions of the appendix is wrong whenever δ ≠ 0 (tens of degrees in winter
    # mornings; see docs/daylight.md).
    phi_south = np.arctan2(
        -np.cos(delta) * np.sin(hour_angle),
        -(np.cos(lat) * np.sin(delta) + np.sin(lat) * np.cos(delta) * np.cos(hour_angle)),
    )
    azimuth = np.mod(phi_south + np.pi, 2.0 * np.pi)
    zenith, azimuth = np.broadcast_arrays(zenith, azimuth)
    return zenith.copy(), azimuth.copy()


def sun_direction(
    latitude_deg: npt.ArrayLike,
    day_of_year: npt.ArrayLike | _dt.date,
    time_h: npt.ArrayLike,
    *,
    longitude_deg: npt.ArrayLike | None = None,
    utc_offset_h: npt.ArrayLike | None = None,
) -> np.ndarray:
    """Unit vector towards the sun in the local frame (x east, y north, z up).

    Parameters are those of :func:`sun_position`.

    Returns
    -------
    numpy.ndarray
        Shape (..., 3): broadcast shape of the inputs plus a last axis (x, y, z). z < 0 when the
        sun is below the horizon.

    Examples
    --------
    >>> d = sun_direction(0.0, 80, 6.0)     # equator, near the equinox, 6 h solar time
    >>> bool(d[0] > 0.99)                   # rising in the east
    True
    """
    zenith, azimuth = sun_position(
        latitude_deg, day_of_year, time_h, longitude_deg=longitude_deg, utc_offset_h=utc_offset_h
    )
    return direction_from_angles(zenith, azimuth)


def direction_from_angles(zenith_rad: npt.ArrayLike, azimuth_rad: npt.ArrayLike) -> np.ndarray:
    """Unit vectors from zenith and compass azimuth angles.

    x = sin θ sin φ (east), y = sin θ cos φ (north), z = cos θ (up).

    Parameters
    ----------
    zenith_rad : array_like
        Zenith angle θ in radians, [0, π].
    azimuth_rad : array_like
        Azimuth φ in radians from north, clockwise (east = π/2); any real value.

    Returns
    -------
    numpy.ndarray
        Shape (..., 3), broadcast over the inputs.
    """
    theta = check_real_array("zenith_rad", zenith_rad, 0.0, np.pi)
    phi = check_real_array("azimuth_rad", azimuth_rad)
    sin_theta = np.sin(theta)
    return np.stack(np.broadcast_arrays(sin_theta * np.sin(phi), sin_theta * np.cos(phi), np.cos(theta)), axis=-1)


def angles_from_direction(direction: npt.ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Zenith angle and compass azimuth of direction vectors (inverse of
    :func:`direction_from_angles`).

    Parameters
    ----------
    direction : array_like
        Shape (..., 3) in the local frame (x east, y north, z up); normalised here.

    Returns
    -------
    zenith_rad : numpy.ndarray
        In [0, π].
    azimuth_rad : numpy.ndarray
        From north, clockwise, in [0, 2π); 0 for vertical vectors.
    """
    d = check_unit_vectors("direction", direction)
    zenith = np.arccos(np.clip(d[..., 2], -1.0, 1.0))
    azimuth = np.mod(np.arctan2(d[..., 0], d[..., 1]), 2.0 * np.pi)
    return zenith, azimuth
