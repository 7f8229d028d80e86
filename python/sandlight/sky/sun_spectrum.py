"""Spectrum of the direct sunlight at the ground after atmospheric attenuation.

Public objects
--------------
- :data:`SUN_SOLID_ANGLE_SR` : solid angle of the solar disc at 1 au.
- :data:`METHODS` : ``("Preetham 1999", "Bird-Riordan 1986")``.
- :func:`angstrom_beta` : Ångström turbidity coefficient β from Linke-style turbidity T.
- :func:`relative_optical_mass` : relative air mass m (Kasten 1966).
- :func:`earth_sun_distance_factor` : (r0/r)² eccentricity correction (Spencer 1971).
- :func:`extraterrestrial_spectral_irradiance` : solar spectrum above the atmosphere.
- :func:`transmittance_components` : Rayleigh, aerosol, ozone, mixed-gas and water-vapour
  transmittances of the beam (Preetham 1999 / Iqbal 1983).
- :func:`sun_transmittance` : their product, by either method.
- :func:`sun_spectral_irradiance` : direct normal spectral irradiance, W m⁻² nm⁻¹.
- :func:`sun_spectral_radiance` : radiance of the solar disc, W m⁻² sr⁻¹ nm⁻¹.

Model ("Preetham 1999", the default)
------------------------------------
Preetham et al. (1999), appendix, after Iqbal (1983), with the relative optical mass m placed
*as in the authors' code* (a factor of every optical depth), not as printed in the paper's
appendix, where m appears inside the exponent of λ for the Rayleigh and aerosol terms::

    τ_R  = exp(−m · 0.008735 · λ^−4.08)                       Rayleigh (λ in µm)
    τ_a  = exp(−m · β · λ^−α),  α = 1.3,
           β = 0.04608365822050 T − 0.04586025928522          aerosol (Ångström)
    τ_o  = exp(−m · k_o(λ) · l),  l = 0.35 cm                 ozone
    τ_g  = exp(−1.41 k_g m / (1 + 118.93 k_g m)^0.45)         uniformly mixed gases
    τ_wa = exp(−0.2385 k_wa w m / (1 + 20.07 k_wa w m)^0.45), w = 2 cm   water vapour
    m    = 1 / (cos θs + 0.15 (93.885 − θs[deg])^−1.253)      Kasten (1966)

The paper tabulates the extraterrestrial spectrum and k_o, k_g, k_wa from Iqbal (1983), who takes
the absorption coefficients from Leckner (1978). We do not ship a copy of those tables. Instead we
use the same Leckner absorption coefficients and the extraterrestrial spectrum as tabulated for
SPECTRL2 by Bird & Riordan (1986), read at run time from **pvlib** (BSD-3-Clause; the NREL
SPECTRL2 tables it carries are U.S. government work). The grid has 122 wavelengths from 300 to
4000 nm (10 nm steps in the blue, coarser beyond 550 nm); values between grid points are linearly
interpolated (coefficients, then the formulas, as the authors' code does).

Cross-check ("Bird-Riordan 1986")
---------------------------------
:func:`pvlib.spectrum.spectrl2` is an independent clear-sky direct-beam model (its own Rayleigh
law, pressure-corrected air mass, ozone-layer air mass). We feed it Preetham's atmosphere
(α = 1.3, aerosol optical depth at 500 nm β·0.5^−α, l = 0.35 cm, w = 2 cm, sea level) and use the
ratio of its direct normal irradiance to its extraterrestrial irradiance as the transmittance.
The two agree within a few per cent in the visible at moderate zenith angles (figures in
``docs/daylight.md``).

Units
-----
Wavelengths in nm; irradiance in W m⁻² nm⁻¹ on a surface normal to the beam; radiance of the
solar disc L = E / Ω with Ω = :data:`SUN_SOLID_ANGLE_SR` (uniform disc, limb darkening ignored).
Radiance does not depend on the Earth–Sun distance (E and Ω both scale as 1/r²), so
:func:`sun_spectral_radiance` uses the mean distance; only :func:`sun_spectral_irradiance` takes
``day_of_year``.

References
----------
Preetham, A. J., Shirley, P., Smits, B. (1999). A practical analytic model for daylight.
    SIGGRAPH 99, 91–100, appendix (sun spectral radiance).
Iqbal, M. (1983). An Introduction to Solar Radiation. Academic Press.
Leckner, B. (1978). The spectral distribution of solar radiation at the earth's surface—elements
    of a model. Solar Energy 20, 143–150.
Bird, R. E., Riordan, C. (1986). Simple solar spectral model for direct and diffuse irradiance on
    horizontal and tilted planes at the earth's surface for cloudless atmospheres. J. Climate
    Appl. Meteor. 25, 87–97.
Kasten, F. (1966). A new table and approximation formula for the relative optical air mass.
    Arch. Meteor. Geophys. Bioklim. B14, 206–223.
Spencer, J. W. (1971). Fourier series representation of the position of the sun. Search 2, 172.
"""

from __future__ import annotations

import functools
import importlib

import numpy as np
import numpy.typing as npt

from sandlight.checks import check_real, check_real_array
from sandlight.errors import ParameterError

__all__ = [
    "SUN_SOLID_ANGLE_SR",
    "METHODS",
    "OZONE_CM",
    "WATER_VAPOUR_CM",
    "ANGSTROM_ALPHA",
    "TURBIDITY_RANGE",
    "WAVELENGTH_RANGE_NM",
    "angstrom_beta",
    "relative_optical_mass",
    "earth_sun_distance_factor",
    "extraterrestrial_spectral_irradiance",
    "transmittance_components",
    "sun_transmittance",
    "sun_spectral_irradiance",
    "sun_spectral_radiance",
]

#: Solid angle of the solar disc seen from 1 au, in sr: 2π(1 − cos α) with sin α = R☉/au,
#: R☉ = 695 700 km (IAU 2015 nominal), 1 au = 149 597 870.7 km. ≈ 6.794e-5 sr. (Preetham's code
#: uses 0.25π(1.39/150)² = 6.744e-5 sr, 0.7 % smaller.)
SUN_SOLID_ANGLE_SR = float(2.0 * np.pi * (1.0 - np.cos(np.arcsin(695_700.0 / 149_597_870.7))))

#: Names accepted by the ``method`` argument.
METHODS = ("Preetham 1999", "Bird-Riordan 1986")

#: Ozone column l in cm (atm-cm) used by Preetham et al.
OZONE_CM = 0.35
#: Precipitable water vapour w in cm used by Preetham et al.
WATER_VAPOUR_CM = 2.0
#: Ångström wavelength exponent α used by Preetham et al.
ANGSTROM_ALPHA = 1.3
#: Admissible turbidity for the sun spectrum: T = 1 gives β ≈ 0 (no aerosol); the upper bound is
#: that of the sky model.
TURBIDITY_RANGE = (1.0, 10.0)
#: Wavelength range of the tables, nm.
WAVELENGTH_RANGE_NM = (300.0, 4000.0)

# Sea-level pressure handed to SPECTRL2 (Pa); Preetham's formulas assume sea level too.
_SEA_LEVEL_PRESSURE_PA = 101_325.0


def angstrom_beta(turbidity: npt.ArrayLike) -> np.ndarray:
    """Ångström turbidity coefficient β from the turbidity T.

    β = 0.04608365822050 T − 0.04586025928522 (Preetham et al. 1999, appendix; the digits are
    those of the authors' code, printed rounded in the paper).

    Parameters
    ----------
    turbidity : array_like
        Turbidity T, in [1, 10].

    Returns
    -------
    numpy.ndarray
        β, dimensionless (aerosol optical depth at 1 µm).
    """
    t = check_real_array("turbidity", turbidity, *TURBIDITY_RANGE)
    return 0.04608365822050 * t - 0.04586025928522


def relative_optical_mass(zenith_rad: npt.ArrayLike) -> np.ndarray:
    """Relative optical air mass m of Kasten (1966), as used by Preetham et al. (1999).

    m = 1 / (cos θ + 0.15 (93.885 − θ[deg])^−1.253). Finite at the horizon (m ≈ 36.3 at 90°).

    Parameters
    ----------
    zenith_rad : array_like
        Sun zenith angle θ in radians, in [0, π/2].

    Returns
    -------
    numpy.ndarray
        m, dimensionless (1 at the zenith).
    """
    theta = check_real_array("zenith_rad", zenith_rad, 0.0, np.pi / 2.0)
    return 1.0 / (np.cos(theta) + 0.15 * (93.885 - np.degrees(theta)) ** -1.253)


def earth_sun_distance_factor(day_of_year: npt.ArrayLike) -> np.ndarray:
    """Eccentricity correction (r0/r)² of the Earth–Sun distance (Spencer 1971; Iqbal eq. 1.2.1).

    E0 = 1.000110 + 0.034221 cos Γ + 0.001280 sin Γ + 0.000719 cos 2Γ + 0.000077 sin 2Γ,
    Γ = 2π(J − 1)/365.

    Parameters
    ----------
    day_of_year : array_like
        Day number J in [1, 366].

    Returns
    -------
    numpy.ndarray
        Dimensionless factor in about [0.967, 1.035] (1 at the mean distance).
    """
    j = check_real_array("day_of_year", day_of_year, 1.0, 366.0)
    gamma = 2.0 * np.pi * (j - 1.0) / 365.0
    return (
        1.000110
        + 0.034221 * np.cos(gamma)
        + 0.001280 * np.sin(gamma)
        + 0.000719 * np.cos(2.0 * gamma)
        + 0.000077 * np.sin(2.0 * gamma)
    )


@functools.lru_cache(maxsize=1)
def _tables() -> dict[str, np.ndarray]:
    """SPECTRL2 extraterrestrial spectrum and Leckner absorption coefficients, from pvlib.

    Columns: wavelength (nm), extraterrestrial irradiance (W m⁻² nm⁻¹ at 1 au), water-vapour,
    ozone (cm⁻¹) and mixed-gas absorption coefficients, 122 rows, 300–4000 nm.
    """
    message = (
        "the sun spectrum needs pvlib >= 0.10 (its SPECTRL2 tables: Bird & Riordan 1986); "
        "install it with `pip install pvlib`"
    )
    try:
        # import_module returns the module; the package attribute of the same name is the function.
        module = importlib.import_module("pvlib.spectrum.spectrl2")
    except ImportError as err:
        raise ImportError(message) from err
    table = getattr(module, "_SPECTRL2_COEFFS", None)
    fields = ("wavelength", "spectral_irradiance_et", "water_vapor_absorption", "ozone_absorption", "mixed_absorption")
    if table is None or table.dtype.names is None or not set(fields) <= set(table.dtype.names):
        raise ImportError(
            message + f" (this pvlib, {getattr(module, '__name__', '?')}, "
            "no longer exposes the SPECTRL2 table in the expected form)"
        )
    out = {name: np.array(table[name], dtype=np.float64) for name in fields}
    if out["wavelength"][0] != 300.0 or out["wavelength"][-1] != 4000.0:
        raise ImportError(message + " (unexpected SPECTRL2 wavelength grid)")
    for array in out.values():
        array.setflags(write=False)
    return out


def _wavelengths(wavelength_nm: npt.ArrayLike) -> np.ndarray:
    wavelength = check_real_array("wavelength_nm", wavelength_nm, *WAVELENGTH_RANGE_NM)
    if wavelength.ndim > 1:
        raise ParameterError(
            "wavelength_nm", f"array of shape {wavelength.shape}", "a scalar or a 1-D array of wavelengths in nm"
        )
    return wavelength


def extraterrestrial_spectral_irradiance(wavelength_nm: npt.ArrayLike) -> np.ndarray:
    """Solar spectral irradiance above the atmosphere at the mean Earth–Sun distance.

    Linear interpolation of the SPECTRL2 table (Bird & Riordan 1986, via pvlib).

    Parameters
    ----------
    wavelength_nm : array_like
        Wavelengths in nm, scalar or 1-D, in [300, 4000].

    Returns
    -------
    numpy.ndarray
        W m⁻² nm⁻¹, same shape as ``wavelength_nm``.
    """
    wavelength = _wavelengths(wavelength_nm)
    table = _tables()
    return np.interp(wavelength, table["wavelength"], table["spectral_irradiance_et"])


def _check_atmosphere(turbidity: float, ozone_cm: float, water_vapour_cm: float):
    t = check_real("turbidity", turbidity, *TURBIDITY_RANGE)
    ozone = check_real("ozone_cm", ozone_cm, 0.0, 1.0)
    water = check_real("water_vapour_cm", water_vapour_cm, 0.0, 10.0)
    return t, ozone, water


def transmittance_components(
    zenith_rad: npt.ArrayLike,
    wavelength_nm: npt.ArrayLike,
    turbidity: npt.ArrayLike,
    *,
    ozone_cm: float = OZONE_CM,
    water_vapour_cm: float = WATER_VAPOUR_CM,
) -> dict[str, np.ndarray]:
    """The five beam transmittances of Preetham et al. (1999), appendix (see module docstring).

    Parameters
    ----------
    zenith_rad : array_like
        Sun zenith angle θs in radians, any shape, in [0, π/2].
    wavelength_nm : array_like
        Wavelengths in nm, scalar or 1-D, in [300, 4000].
    turbidity : float
        Turbidity T in [1, 10].
    ozone_cm : float, default 0.35
        Ozone column l in cm (atm-cm), in [0, 1].
    water_vapour_cm : float, default 2.0
        Precipitable water w in cm, in [0, 10].

    Returns
    -------
    dict of str to numpy.ndarray
        Keys ``rayleigh``, ``aerosol``, ``ozone``, ``mixed_gases``, ``water_vapour``; each of shape
        ``zenith.shape + wavelength.shape``, dimensionless in (0, 1].
    """
    t, ozone, water = _check_atmosphere(turbidity, ozone_cm, water_vapour_cm)
    m = relative_optical_mass(zenith_rad)[..., np.newaxis]
    wavelength = _wavelengths(wavelength_nm)
    scalar_wavelength = wavelength.ndim == 0
    wavelength = np.atleast_1d(wavelength)
    table = _tables()
    grid = table["wavelength"]
    k_o = np.interp(wavelength, grid, table["ozone_absorption"])
    k_g = np.interp(wavelength, grid, table["mixed_absorption"])
    k_wa = np.interp(wavelength, grid, table["water_vapor_absorption"])
    lambda_um = wavelength / 1000.0
    beta = 0.04608365822050 * t - 0.04586025928522
    # Preetham appendix with m multiplying each optical depth (the authors' code): see docstring.
    components = {
        "rayleigh": np.exp(-m * 0.008735 * lambda_um**-4.08),
        "aerosol": np.exp(-m * beta * lambda_um**-ANGSTROM_ALPHA),
        "ozone": np.exp(-m * k_o * ozone),
        "mixed_gases": np.exp(-1.41 * k_g * m / (1.0 + 118.93 * k_g * m) ** 0.45),
        "water_vapour": np.exp(-0.2385 * k_wa * water * m / (1.0 + 20.07 * k_wa * water * m) ** 0.45),
    }
    if scalar_wavelength:
        components = {key: value[..., 0] for key, value in components.items()}
    return components


def sun_transmittance(
    zenith_rad: npt.ArrayLike,
    wavelength_nm: npt.ArrayLike,
    turbidity: npt.ArrayLike,
    *,
    ozone_cm: float = OZONE_CM,
    water_vapour_cm: float = WATER_VAPOUR_CM,
    method: str = "Preetham 1999",
) -> np.ndarray:
    """Spectral transmittance of the atmosphere along the direct solar beam.

    Parameters
    ----------
    zenith_rad : array_like
        Sun zenith angle θs in radians, any shape, in [0, π/2].
    wavelength_nm : array_like
        Wavelengths in nm, scalar or 1-D, in [300, 4000].
    turbidity : float
        Turbidity T in [1, 10]; sets the Ångström β (:func:`angstrom_beta`), α = 1.3.
    ozone_cm : float, default 0.35
        Ozone column in cm (atm-cm), in [0, 1].
    water_vapour_cm : float, default 2.0
        Precipitable water in cm, in [0, 10].
    method : {"Preetham 1999", "Bird-Riordan 1986"}
        Preetham/Iqbal formulas (default) or pvlib's SPECTRL2 direct beam.

    Returns
    -------
    numpy.ndarray
        Dimensionless, shape ``zenith.shape + wavelength.shape``.
    """
    if method == "Preetham 1999":
        components = transmittance_components(
            zenith_rad, wavelength_nm, turbidity, ozone_cm=ozone_cm, water_vapour_cm=water_vapour_cm
        )
        return functools.reduce(np.multiply, components.values())
    if method == "Bird-Riordan 1986":
        return _spectrl2_transmittance(zenith_rad, wavelength_nm, turbidity, ozone_cm, water_vapour_cm)
    raise ParameterError("method", method, f"one of {', '.join(map(repr, METHODS))}")


def _spectrl2_transmittance(
    zenith_rad: npt.ArrayLike, wavelength_nm: npt.ArrayLike, turbidity: float, ozone_cm: float, water_vapour_cm: float
):
    """Direct-beam transmittance of pvlib's SPECTRL2 for Preetham's atmosphere."""
    t, ozone, water = _check_atmosphere(turbidity, ozone_cm, water_vapour_cm)
    theta = check_real_array("zenith_rad", zenith_rad, 0.0, np.pi / 2.0)
    wavelength = _wavelengths(wavelength_nm)
    table = _tables()  # also reports a missing pvlib clearly
    import pvlib

    zenith_deg = np.degrees(theta).reshape(-1)
    beta = 0.04608365822050 * t - 0.04586025928522
    result = pvlib.spectrum.spectrl2(
        apparent_zenith=zenith_deg,
        aoi=zenith_deg,
        surface_tilt=0.0,
        ground_albedo=0.0,
        surface_pressure=_SEA_LEVEL_PRESSURE_PA,
        relative_airmass=pvlib.atmosphere.get_relative_airmass(zenith_deg, model="kasten1966"),
        precipitable_water=water,
        ozone=ozone,
        # Ångström: τ_a(500 nm) = β · 0.5^−α, with Preetham's α.
        aerosol_turbidity_500nm=beta * 0.5**-ANGSTROM_ALPHA,
        alpha=ANGSTROM_ALPHA,
        dayofyear=np.ones_like(zenith_deg),
    )
    # dni / dni_extra removes the extraterrestrial spectrum and its eccentricity correction.
    transmittance_grid = np.asarray(result["dni"]) / np.asarray(result["dni_extra"])  # (122, N)
    # Linear interpolation along the wavelength grid for all zenith angles at once.
    grid = table["wavelength"]
    targets = np.atleast_1d(wavelength)
    upper = np.clip(np.searchsorted(grid, targets), 1, grid.size - 1)
    weight = (targets - grid[upper - 1]) / (grid[upper] - grid[upper - 1])
    flat = (
        transmittance_grid[upper - 1] * (1.0 - weight)[:, np.newaxis]
        + transmittance_grid[upper] * weight[:, np.newaxis]
    ).T  # (N, n)
    out = flat.reshape(theta.shape + targets.shape)
    return out[..., 0] if wavelength.ndim == 0 else out


def sun_spectral_irradiance(
    zenith_rad: npt.ArrayLike,
    wavelength_nm: npt.ArrayLike,
    turbidity: npt.ArrayLike,
    *,
    ozone_cm: float = OZONE_CM,
    water_vapour_cm: float = WATER_VAPOUR_CM,
    day_of_year: npt.ArrayLike | None = None,
    method: str = "Preetham 1999",
) -> np.ndarray:
    """Direct normal spectral irradiance of the sun at sea level.

    E(λ) = E0 · E_ext(λ) · τ(λ), with E_ext the extraterrestrial spectrum at 1 au, E0 the
    eccentricity correction (1 if ``day_of_year`` is None) and τ :func:`sun_transmittance`.

    Parameters
    ----------
    zenith_rad : array_like
        Sun zenith angle θs in radians, any shape, in [0, π/2].
    wavelength_nm : array_like
        Wavelengths in nm, scalar or 1-D, in [300, 4000].
    turbidity : float
        Turbidity T in [1, 10].
    ozone_cm, water_vapour_cm : float
        Ozone column and precipitable water, cm (defaults 0.35 and 2.0, Preetham's values).
    day_of_year : array_like, optional
        Day J in [1, 366] for the Earth–Sun distance; broadcast with ``zenith_rad``.
    method : {"Preetham 1999", "Bird-Riordan 1986"}
        See :func:`sun_transmittance`.

    Returns
    -------
    numpy.ndarray
        W m⁻² nm⁻¹ on a surface normal to the beam; shape ``zenith.shape + wavelength.shape``.
    """
    transmittance = sun_transmittance(
        zenith_rad, wavelength_nm, turbidity, ozone_cm=ozone_cm, water_vapour_cm=water_vapour_cm, method=method
    )
    irradiance = extraterrestrial_spectral_irradiance(wavelength_nm) * transmittance
    if day_of_year is not None:
        factor = earth_sun_distance_factor(day_of_year)
        if np.ndim(wavelength_nm) == 1:
            factor = factor[..., np.newaxis]
        irradiance = irradiance * factor
    return irradiance


def sun_spectral_radiance(
    zenith_rad: npt.ArrayLike,
    wavelength_nm: npt.ArrayLike,
    turbidity: npt.ArrayLike,
    *,
    ozone_cm: float = OZONE_CM,
    water_vapour_cm: float = WATER_VAPOUR_CM,
    method: str = "Preetham 1999",
) -> np.ndarray:
    """Spectral radiance of the solar disc seen from sea level.

    L(λ) = E(λ) / Ω at the mean Earth–Sun distance, Ω = :data:`SUN_SOLID_ANGLE_SR`; a renderer
    that draws the sun as a disc of that solid angle gets back the irradiance
    :func:`sun_spectral_irradiance`.

    Parameters
    ----------
    zenith_rad, wavelength_nm, turbidity, ozone_cm, water_vapour_cm, method
        As in :func:`sun_spectral_irradiance`.

    Returns
    -------
    numpy.ndarray
        W m⁻² sr⁻¹ nm⁻¹; shape ``zenith.shape + wavelength.shape``.
    """
    return (
        sun_spectral_irradiance(
            zenith_rad, wavelength_nm, turbidity, ozone_cm=ozone_cm, water_vapour_cm=water_vapour_cm, method=method
        )
        / SUN_SOLID_ANGLE_SR
    )
