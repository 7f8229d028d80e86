"""Spectral reflectance → CIE XYZ tristimulus values (paper §4.1.1).

Public objects
--------------
- :data:`PREDICTOR_WAVELENGTHS_NM`: the 16 bands of the spectral predictor, 400–700 nm every 20 nm.
- :data:`DEFAULT_ILLUMINANT`, :data:`DEFAULT_OBSERVER`: CIE D50 and the CIE 1964 10° observer,
  the choices of the paper.
- :func:`spectrum_to_xyz`: tristimulus values of reflectance spectra sampled at any wavelengths.
- :func:`white_point_xyz`: tristimulus values of the perfect reflecting diffuser.

How a spectrum is integrated
----------------------------
The integrals of §4.1.1,
:math:`X = \\int e(\\lambda) r(\\lambda) \\bar{x}(\\lambda) d\\lambda` etc., are
evaluated as sums on the 1 nm grid of the colour-matching functions (CMFs) as colour-science ships
them (CIE 1964 10°: 360–830 nm, from the CVRL 1 nm tables), following CIE 015:2018 §7.1:

1. **Illuminant.** The tabulated SPD (D50: 300–780 nm every 5 nm) is aligned to the CMF grid
   exactly as colour-science's own ``sd_to_XYZ`` does: Sprague (1880) interpolation of the
   uniformly spaced table, constant extension beyond its last value (780 → 830 nm, where the
   CMFs are below 2·10⁻⁴ of their peak).
2. **Reflectance.** The given samples are interpolated to every 1 nm grid point inside their
   range with the piecewise-cubic Hermite interpolator of Fritsch & Carlson (1980)
   (``scipy.interpolate.PchipInterpolator``). Why this one: it accepts any sampling, uniform or
   not (the predictor's 16 bands, Monte Carlo spectra at arbitrary wavelengths, the irregular
   Beckman grid of USGS spectra); it is shape-preserving, so it never overshoots at the steep
   iron-oxide absorption edge (500–600 nm) and never invents a reflectance outside the range of
   the neighbouring samples (no negative or > 1 reflectance from interpolation); and it
   reproduces samples that lie on the grid exactly, so 1 nm data are summed as given. On the 27
   USGS splib07a Beckman spectra in ``shared/data/measured`` resampled to the 16 bands its colour
   error against the full 1 nm spectrum is at most ΔE₀₀ = 0.36 (Sprague: 0.35, cubic spline:
   0.35, linear: 0.43).
3. **Outside the given range** (e.g. 360–400 and 700–830 nm for the 16 bands) the reflectance is
   **extended as a constant** equal to the first/last sample, the convention of ASTM E308 for
   missing end data. The CMF weight there is small: on the same USGS spectra the colour error
   of this extension alone is below ΔE₀₀ = 0.01. Spectra must cover at least 400–700 nm.
4. **Sum and normalisation** (CIE 015:2018 Eq. 7.1–7.2, :math:`\\Delta\\lambda` = 1 nm cancels):

   .. math:: X = k \\sum_\\lambda S(\\lambda) R(\\lambda) \\bar{x}(\\lambda), \\quad
             k = 1 / \\sum_\\lambda S(\\lambda) \\bar{y}(\\lambda),

   so that the perfect reflecting diffuser (R = 1) has Y = 1 and XYZ equal to the white point
   of the illuminant for that observer.

Domain and range
----------------
===================  ==============  =================================================
quantity             scale           notes
===================  ==============  =================================================
``reflectance``      [0, 1]          fraction, not percent; values slightly below 0
                                     (predictor noise) are accepted
``wavelengths_nm``   nm              strictly increasing, covering 400–700 nm
XYZ (returned)       [0, 1]          Y = 1 for the perfect reflecting diffuser
===================  ==============  =================================================

References
----------
- CIE 015:2018, *Colorimetry*, 4th edition. Commission Internationale de l'Éclairage, Vienna.
  https://doi.org/10.25039/TR.015.2018
- ASTM E308-15, *Standard Practice for Computing the Colors of Objects by Using the CIE System*.
- Fritsch, F. N. and Carlson, R. E. (1980), Monotone piecewise cubic interpolation, *SIAM J.
  Numer. Anal.* 17(2), 238–246. https://doi.org/10.1137/0717021
- Sprague, T. B. (1880), Explanation of a new formula for interpolation, *J. Inst. Actuaries*
  22, 270–285.
- Mansfield, T. et al., colour-science (Colour 0.4), https://www.colour-science.org
"""

from __future__ import annotations

import functools
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.interpolate import PchipInterpolator

import colour
from sandlight.errors import ParameterError

__all__ = [
    "PREDICTOR_WAVELENGTHS_NM",
    "DEFAULT_ILLUMINANT",
    "DEFAULT_OBSERVER",
    "spectrum_to_xyz",
    "spectrum_to_xyz_under",
    "white_point_xyz",
]

# Paper §3.1.1: 16 wavelengths between 400 and 700 nm at 20 nm intervals.
PREDICTOR_WAVELENGTHS_NM: NDArray[np.float64] = np.arange(400.0, 701.0, 20.0)
PREDICTOR_WAVELENGTHS_NM.setflags(write=False)

# Paper §4.1.1: "we used the CIE D50 illuminant ... the CIE 1964 standard observer".
DEFAULT_ILLUMINANT = "D50"
DEFAULT_OBSERVER = "CIE 1964 10 Degree Standard Observer"

# A spectrum must cover this range: outside it the constant extension is harmless (step 3 of the
# module docstring), inside it the CMFs carry nearly all their weight.
REQUIRED_COVERAGE_NM = (400.0, 700.0)

# Reflectance is a fraction. Anything above this is almost surely percent; 1.5 leaves room for
# noisy measurements and fluorescent samples while catching the factor-100 mistake.
_PERCENT_GUARD = 1.5


def _observer_names() -> list[str]:
    # Only the XYZ colour-matching functions qualify; the RGB CMFs and cone fundamentals do not.
    return [name for name in colour.MSDS_CMFS if "Standard Observer" in name]


# colour-science's name lookups slugify every key of the table on each test (about 2.5 ms for
# the illuminants); a name's answer never changes, so it is asked once.
@functools.lru_cache(maxsize=64)
def _is_observer(name: str) -> bool:
    return name in _observer_names()


@functools.lru_cache(maxsize=64)
def _is_illuminant(name: str) -> bool:
    return name in colour.SDS_ILLUMINANTS


def _integration_weights(illuminant: str, observer: str) -> tuple[NDArray, NDArray]:
    """1 nm grid and weights k·S(λ)·[x̄, ȳ, z̄](λ) so that XYZ = R(grid) @ weights."""
    # Validated here, before the cache, which would fail on unhashable arguments.
    if not isinstance(observer, str) or not _is_observer(observer):
        raise ParameterError("observer", observer, f"one of {_observer_names()}")
    if not isinstance(illuminant, str) or not _is_illuminant(illuminant):
        raise ParameterError(
            "illuminant",
            illuminant,
            f"a CIE illuminant name known to colour-science, e.g. 'D50', 'D65', 'A' "
            f"(all: {sorted(colour.SDS_ILLUMINANTS.keys())})",
        )
    return _cached_weights(illuminant, observer)


@functools.lru_cache(maxsize=16)
def _cached_weights(illuminant: str, observer: str) -> tuple[NDArray, NDArray]:
    cmfs = colour.MSDS_CMFS[observer]
    # Same alignment as colour.sd_to_XYZ: Sprague for the uniform table, constant extrapolation.
    spd = colour.SDS_ILLUMINANTS[illuminant].copy().align(cmfs.shape)
    grid = np.asarray(cmfs.wavelengths, dtype=float)
    weighted = spd.values[:, None] * cmfs.values
    # CIE 015:2018 Eq. 7.2: k = 1 / Σ S ȳ, so that the perfect reflector has Y = 1.
    weights = weighted / weighted[:, 1].sum()
    grid.setflags(write=False)
    weights.setflags(write=False)
    return grid, weights


def white_point_xyz(illuminant: str = DEFAULT_ILLUMINANT, observer: str = DEFAULT_OBSERVER) -> NDArray[np.float64]:
    """Tristimulus values of the perfect reflecting diffuser (R(λ) = 1).

    Parameters
    ----------
    illuminant
        Name of a CIE illuminant in ``colour.SDS_ILLUMINANTS``.
    observer
        Name of a CIE standard observer in ``colour.MSDS_CMFS``.

    Returns
    -------
    numpy.ndarray, shape (3,)
        XYZ with Y = 1. For D50 and the 10° observer: [0.9672, 1, 0.8143], chromaticity
        (0.3477, 0.3595), the tabulated D50/10° white point.
    """
    _, weights = _integration_weights(illuminant, observer)
    return weights.sum(axis=0)


def _validated_wavelengths(wavelengths_nm: ArrayLike) -> NDArray[np.float64]:
    try:
        wl = np.asarray(wavelengths_nm, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError("wavelengths_nm", wavelengths_nm, "a 1-D array of numbers in nm") from None
    lo, hi = REQUIRED_COVERAGE_NM
    allowed = f"a 1-D, finite, strictly increasing array in nm covering at least {lo:g}–{hi:g} nm"
    if wl.ndim != 1 or wl.size < 2:
        raise ParameterError("wavelengths_nm", f"an array of shape {wl.shape}", allowed)
    # Describe the array briefly: a 2000-value spectrum must not flood the message.
    summary = f"{wl.size} values from {wl[0]:g} to {wl[-1]:g} nm"
    if not np.all(np.isfinite(wl)):
        raise ParameterError("wavelengths_nm", f"{summary}, some NaN or inf", allowed)
    if np.any(np.diff(wl) <= 0):
        first = int(np.argmax(np.diff(wl) <= 0))
        raise ParameterError("wavelengths_nm", f"{summary}, not increasing after {wl[first]:g} nm", allowed)
    if wl[0] > lo or wl[-1] < hi:
        raise ParameterError("wavelengths_nm", summary, allowed)
    return wl


def _validated_reflectance(reflectance: ArrayLike, n_wavelengths: int) -> NDArray[np.float64]:
    try:
        r = np.asarray(reflectance, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError("reflectance", reflectance, "an array of numbers") from None
    if r.ndim == 0 or r.shape[-1] != n_wavelengths:
        raise ParameterError(
            "reflectance",
            f"array of shape {r.shape}",
            f"shape (..., {n_wavelengths}): last axis matching wavelengths_nm",
        )
    if not np.all(np.isfinite(r)):
        raise ParameterError(
            "reflectance", "an array containing NaN or inf", "finite values (drop deleted channels before converting)"
        )
    if r.size and r.max() > _PERCENT_GUARD:
        raise ParameterError(
            "reflectance",
            f"an array with maximum {r.max():g}",
            "a fraction in [0, 1]; percent values must be divided by 100",
        )
    return r


def spectrum_to_xyz(
    wavelengths_nm: ArrayLike | colour.SpectralDistribution,
    reflectance: ArrayLike | None = None,
    *,
    illuminant: str = DEFAULT_ILLUMINANT,
    observer: str = DEFAULT_OBSERVER,
) -> NDArray[np.float64]:
    """CIE XYZ tristimulus values of reflectance spectra (paper §4.1.1).

    Parameters
    ----------
    wavelengths_nm
        Wavelengths λ of the samples, nm, shape (n,), strictly increasing, covering at least
        400–700 nm. Any sampling: the predictor's 16 bands or dense spectra. Or a
        ``colour.SpectralDistribution`` of reflectance (then without ``reflectance``).
    reflectance
        Spectral reflectance R(λ) as a fraction, shape (..., n); leading axes are batch axes.
    illuminant
        CIE illuminant e(λ) by name in ``colour.SDS_ILLUMINANTS`` (default D50, as the paper).
    observer
        CIE standard observer by name in ``colour.MSDS_CMFS`` (default CIE 1964 10°).

    Returns
    -------
    numpy.ndarray, shape (..., 3)
        XYZ on the [0, 1] scale: the perfect reflecting diffuser has Y = 1.

    Raises
    ------
    ParameterError
        Wavelengths not strictly increasing or not covering 400–700 nm; reflectance of the wrong
        shape, non-finite, or apparently in percent; unknown illuminant or observer.

    Notes
    -----
    The reflectance is interpolated to 1 nm with a monotone piecewise-cubic Hermite (PCHIP)
    interpolator, extended as a constant outside its range, and summed with the 1 nm CMFs and the
    Sprague-interpolated illuminant; see the module docstring for the reasons and error figures.

    ===============  ======  ================================
    Domain           Scale   Range
    ===============  ======  ================================
    ``reflectance``  [0, 1]  XYZ in [0, 1] (Y = 1 for white)
    ===============  ======  ================================

    Examples
    --------
    >>> import numpy as np
    >>> from sandlight.colour import spectrum_to_xyz, PREDICTOR_WAVELENGTHS_NM
    >>> spectrum_to_xyz(PREDICTOR_WAVELENGTHS_NM, np.full(16, 0.5)).round(4)
    array([ 0.4836,  0.5   ,  0.4071])
    """
    grid, weights = _integration_weights(illuminant, observer)
    return _resampled(*_spectrum(wavelengths_nm, reflectance), grid) @ weights


def spectrum_to_xyz_under(
    wavelengths_nm: ArrayLike | colour.SpectralDistribution,
    reflectance: ArrayLike | None = None,
    *,
    illuminants: Sequence[str] = (DEFAULT_ILLUMINANT,),
    observer: str = DEFAULT_OBSERVER,
) -> NDArray[np.float64]:
    """`spectrum_to_xyz` under several illuminants, the reflectance resampled once.

    Returns
    -------
    numpy.ndarray, shape (..., len(illuminants), 3)
        XYZ under each illuminant, in order; equal to `spectrum_to_xyz` with that illuminant.
    """
    weights = [_integration_weights(name, observer) for name in illuminants]
    if not weights:
        raise ParameterError("illuminants", illuminants, "at least one CIE illuminant name")
    resampled = _resampled(*_spectrum(wavelengths_nm, reflectance), weights[0][0])
    return np.stack([resampled @ w for _, w in weights], axis=-2)


def _spectrum(
    wavelengths_nm: ArrayLike | colour.SpectralDistribution, reflectance: ArrayLike | None
) -> tuple[NDArray, NDArray]:
    """The validated (wavelengths, reflectance) of the two ways of passing a spectrum."""
    if isinstance(wavelengths_nm, colour.SpectralDistribution):
        if reflectance is not None:
            raise ParameterError("reflectance", "an array", "None with a colour.SpectralDistribution (it holds both)")
        from sandlight.colour.spectral_distribution import from_spectral_distribution

        wavelengths_nm, reflectance = from_spectral_distribution(wavelengths_nm)
    elif reflectance is None:
        raise ParameterError("reflectance", None, "the reflectance at each of wavelengths_nm")
    wl = _validated_wavelengths(wavelengths_nm)
    return wl, _validated_reflectance(reflectance, wl.size)


def _resampled(wl: NDArray, r: NDArray, grid: NDArray) -> NDArray:
    """R on the 1 nm ``grid``: PCHIP inside the sampled range, constant beyond it."""
    inside = (grid >= wl[0]) & (grid <= wl[-1])
    resampled = np.empty(r.shape[:-1] + grid.shape)
    resampled[..., inside] = PchipInterpolator(wl, r, axis=-1, extrapolate=False)(grid[inside])
    # Constant extension outside the sampled range (ASTM E308 convention for missing end data).
    resampled[..., grid < wl[0]] = r[..., :1]
    resampled[..., grid > wl[-1]] = r[..., -1:]
    return resampled
