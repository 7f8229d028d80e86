"""CIELAB lightness, chroma and hue (L*, C*ab, h°) of a reflectance spectrum, with the Monte Carlo
standard error of the chroma.

L*a*b* as :func:`sandlight.colour.srgb.xyz_to_lab` (D50, CIE 1964 10°); C*ab = √(a*² + b*²) and
h° = atan2(b*, a*) in degrees (CIE 015:2018 §8.2.1, by ``colour.Lab_to_LCHab``). The error of
C*ab is the linear propagation σ² = J Σ Jᵀ of the spectrum's covariance Σ (a shared run's
covariance couples the wavelengths of a group), J by forward differences.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

import colour
from sandlight.colour.spectrum import spectrum_to_xyz
from sandlight.colour.srgb import xyz_to_lab

__all__ = ["lch", "lch_with_chroma_error"]

_STEP = 1e-6


def lch(wavelengths_nm: ArrayLike, reflectance: ArrayLike) -> np.ndarray:
    """``[L*, C*ab, h°]`` of a reflectance spectrum sampled at ``wavelengths_nm`` (nm)."""
    return colour.Lab_to_LCHab(xyz_to_lab(spectrum_to_xyz(wavelengths_nm, reflectance)))


def lch_with_chroma_error(
    wavelengths_nm: ArrayLike, reflectance: ArrayLike, covariance: ArrayLike
) -> tuple[float, float, float, float]:
    """``(L*, C*ab, h°, σ(C*ab))`` for a spectrum and its covariance matrix (one row and column
    per wavelength)."""
    r = np.asarray(reflectance, dtype=float)
    base = lch(wavelengths_nm, r)
    jac = np.array([(lch(wavelengths_nm, r + _STEP * e)[1] - base[1]) / _STEP for e in np.eye(r.size)])
    return float(base[0]), float(base[1]), float(base[2]), float(np.sqrt(jac @ np.asarray(covariance) @ jac))
