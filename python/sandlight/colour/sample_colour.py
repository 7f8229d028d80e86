"""The colour of sand samples: reflectance (from a provider) → XYZ → sRGB or CIELAB.

Public objects
--------------
- :func:`sample_xyz`, :func:`sample_rgb`, :func:`sample_lab`: one sample or a list of samples.

All three take ``reflectance=``, a provider ``(samples, wavelengths_nm) -> (n, m)`` (see
:mod:`sandlight.colour.provider`); ``None`` uses the shipped spectral predictor. The reflectance
is requested at ``wavelengths_nm`` (default: the predictor's 16 bands, 400–700 nm every 20 nm)
and integrated as :func:`~sandlight.colour.spectrum.spectrum_to_xyz` documents.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from sandlight.colour.provider import ReflectanceProvider, reflectance_of
from sandlight.colour.spectrum import (
    DEFAULT_ILLUMINANT,
    DEFAULT_OBSERVER,
    PREDICTOR_WAVELENGTHS_NM,
    spectrum_to_xyz,
)
from sandlight.colour.srgb import xyz_to_lab, xyz_to_srgb

__all__ = ["sample_xyz", "sample_rgb", "sample_lab"]


def _as_list(samples: Any) -> tuple[list[Any], bool]:
    """(list of samples, whether a single sample was given). Lists and tuples are batches."""
    if isinstance(samples, (list, tuple)):
        return list(samples), False
    return [samples], True


def sample_xyz(
    samples: Any | Sequence[Any],
    *,
    reflectance: ReflectanceProvider | None = None,
    wavelengths_nm: ArrayLike = PREDICTOR_WAVELENGTHS_NM,
    illuminant: str = DEFAULT_ILLUMINANT,
    observer: str = DEFAULT_OBSERVER,
) -> NDArray[np.float64]:
    """CIE XYZ of sand samples (Y = 1 for the perfect reflector).

    Parameters
    ----------
    samples
        One sample, or a list/tuple of n samples.
    reflectance
        Reflectance provider; ``None`` uses the shipped spectral predictor.
    wavelengths_nm
        Wavelengths at which the provider is asked, nm, covering 400–700 nm.
    illuminant, observer
        See :func:`~sandlight.colour.spectrum.spectrum_to_xyz`.

    Returns
    -------
    numpy.ndarray
        Shape (3,) for one sample, (n, 3) for a list.
    """
    batch, single = _as_list(samples)
    wl = np.asarray(wavelengths_nm, dtype=float)
    values = reflectance_of(batch, wl, reflectance)
    xyz = spectrum_to_xyz(wl, values, illuminant=illuminant, observer=observer)
    return xyz[0] if single else xyz


def sample_rgb(
    samples: Any | Sequence[Any],
    *,
    mode: str = "managed",
    reflectance: ReflectanceProvider | None = None,
    wavelengths_nm: ArrayLike = PREDICTOR_WAVELENGTHS_NM,
    illuminant: str = DEFAULT_ILLUMINANT,
    observer: str = DEFAULT_OBSERVER,
    return_out_of_gamut: bool = False,
) -> NDArray[np.float64] | tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Encoded sRGB in [0, 1] of sand samples (paper §4.1.1).

    Parameters
    ----------
    samples
        One sample, or a list/tuple of n samples.
    mode
        ``"managed"`` or ``"paper"``; see :mod:`sandlight.colour.srgb`.
    reflectance, wavelengths_nm, illuminant, observer
        See :func:`sample_xyz`.
    return_out_of_gamut
        Also return the out-of-gamut flag (shape () or (n,)).

    Returns
    -------
    numpy.ndarray
        Shape (3,) for one sample, (n, 3) for a list; with ``return_out_of_gamut`` a tuple
        ``(rgb, out_of_gamut)``.
    """
    xyz = sample_xyz(
        samples, reflectance=reflectance, wavelengths_nm=wavelengths_nm, illuminant=illuminant, observer=observer
    )
    return xyz_to_srgb(xyz, mode, illuminant=illuminant, observer=observer, return_out_of_gamut=return_out_of_gamut)


def sample_lab(
    samples: Any | Sequence[Any],
    *,
    reflectance: ReflectanceProvider | None = None,
    wavelengths_nm: ArrayLike = PREDICTOR_WAVELENGTHS_NM,
    illuminant: str = DEFAULT_ILLUMINANT,
    observer: str = DEFAULT_OBSERVER,
) -> NDArray[np.float64]:
    """CIELAB of sand samples relative to the perfect reflector (D50/10° by default).

    Parameters
    ----------
    samples, reflectance, wavelengths_nm, illuminant, observer
        See :func:`sample_xyz`.

    Returns
    -------
    numpy.ndarray
        L*, a*, b*: shape (3,) for one sample, (n, 3) for a list.
    """
    xyz = sample_xyz(
        samples, reflectance=reflectance, wavelengths_nm=wavelengths_nm, illuminant=illuminant, observer=observer
    )
    return xyz_to_lab(xyz, illuminant=illuminant, observer=observer)
