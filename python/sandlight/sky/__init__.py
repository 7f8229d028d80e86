"""Daylight: the sun's position and spectrum and the Preetham et al. (1999) clear sky.

Frame and units used throughout: directions are (x east, y north, z up) unit vectors; angles in
radians unless the name says ``_deg``; azimuth from north, clockwise (east = π/2); wavelengths in
nm; radiance in W m⁻² sr⁻¹ nm⁻¹, irradiance in W m⁻² nm⁻¹, luminance in kcd m⁻². See
``docs/daylight.md``.

Modules: :mod:`~sandlight.sky.sun` (position), :mod:`~sandlight.sky.sun_spectrum` (direct beam),
:mod:`~sandlight.sky.preetham` (sky model), :mod:`~sandlight.sky.plots` (fisheye pictures).
"""

from sandlight.sky.preetham import LUMINOUS_EFFICACY_LM_W, SKY_WAVELENGTH_RANGE_NM, TURBIDITY_RANGE, PreethamSky
from sandlight.sky.sun import (
    angles_from_direction,
    day_of_year,
    direction_from_angles,
    solar_declination,
    solar_time,
    sun_direction,
    sun_position,
)
from sandlight.sky.sun_spectrum import (
    SUN_SOLID_ANGLE_SR,
    extraterrestrial_spectral_irradiance,
    sun_spectral_irradiance,
    sun_spectral_radiance,
    sun_transmittance,
)

__all__ = [
    "PreethamSky",
    "TURBIDITY_RANGE",
    "LUMINOUS_EFFICACY_LM_W",
    "SKY_WAVELENGTH_RANGE_NM",
    "SUN_SOLID_ANGLE_SR",
    "angles_from_direction",
    "day_of_year",
    "direction_from_angles",
    "extraterrestrial_spectral_irradiance",
    "solar_declination",
    "solar_time",
    "sun_direction",
    "sun_position",
    "sun_spectral_irradiance",
    "sun_spectral_radiance",
    "sun_transmittance",
]
