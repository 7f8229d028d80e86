"""Spectra as colour-science's ``colour.SpectralDistribution``, in and out.

sandlight's spectra are arrays (wavelengths in nm, reflectance as a fraction); colour-science
keeps a spectrum as a ``colour.SpectralDistribution`` (its wavelengths are the domain, the values
the range). These two functions convert, so that a sandlight spectrum goes into colour-science's
own functions (``colour.sd_to_XYZ``, plotting) and a colour-science spectrum into sandlight's
(`~sandlight.colour.spectrum.spectrum_to_xyz` takes one directly).

Public objects
--------------
- :func:`to_spectral_distribution`: a Monte Carlo result, a measured spectrum (``xarray.DataArray``
  over ``wavelength``) or wavelengths and values → ``colour.SpectralDistribution``.
- :func:`from_spectral_distribution`: ``colour.SpectralDistribution`` → (wavelengths, values).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

import colour
from sandlight.errors import ParameterError

__all__ = ["to_spectral_distribution", "from_spectral_distribution"]


def to_spectral_distribution(
    spectrum: Any, values: ArrayLike | None = None, *, name: str | None = None
) -> colour.SpectralDistribution:
    """A sandlight spectrum as a ``colour.SpectralDistribution``.

    Parameters
    ----------
    spectrum
        One of: a result with ``wavelengths`` and ``values`` (`sandlight.ReflectanceResult`); an
        ``xarray.DataArray`` with one ``wavelength`` dimension in nm (the measured spectra of
        `sandlight.measured`); or the wavelengths in nm, shape (n,), strictly increasing, with
        ``values``.
    values
        The spectrum's values, shape (n,), with wavelengths only.
    name
        The distribution's name (default: "sandlight reflectance").

    Returns
    -------
    colour.SpectralDistribution
        Domain: the wavelengths in nm, as given (no resampling); range: the values.

    Examples
    --------
    >>> sd = to_spectral_distribution([400, 500, 600, 700], [0.1, 0.2, 0.4, 0.5])
    >>> sd.wavelengths.tolist(), sd.values.tolist()
    ([400.0, 500.0, 600.0, 700.0], [0.1, 0.2, 0.4, 0.5])
    """
    if values is None:
        if hasattr(spectrum, "wavelengths") and hasattr(spectrum, "values") and not hasattr(spectrum, "dims"):
            wavelengths, values = spectrum.wavelengths, spectrum.values
        elif getattr(spectrum, "dims", None) == ("wavelength",):
            wavelengths, values = spectrum["wavelength"].values, spectrum.values
        else:
            raise ParameterError(
                "spectrum",
                type(spectrum).__name__,
                "a ReflectanceResult, a DataArray over 'wavelength', or wavelengths with values",
            )
    else:
        wavelengths = spectrum
    wl = np.asarray(wavelengths, dtype=float)
    v = np.asarray(values, dtype=float)
    if wl.ndim != 1 or wl.size < 2 or not np.all(np.isfinite(wl)) or np.any(np.diff(wl) <= 0):
        raise ParameterError("wavelengths", wavelengths, "at least 2 finite, strictly increasing wavelengths in nm")
    if v.shape != wl.shape:
        raise ParameterError("values", f"an array of shape {v.shape}", f"one value per wavelength, shape {wl.shape}")
    return colour.SpectralDistribution(v, wl, name=name or "sandlight reflectance")


def from_spectral_distribution(sd: colour.SpectralDistribution) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The wavelengths (nm) and values of a ``colour.SpectralDistribution``, as float arrays.

    Raises
    ------
    ParameterError
        ``sd`` is not a ``colour.SpectralDistribution``.
    """
    if not isinstance(sd, colour.SpectralDistribution):
        raise ParameterError("sd", type(sd).__name__, "a colour.SpectralDistribution")
    return np.asarray(sd.wavelengths, dtype=float).copy(), np.asarray(sd.values, dtype=float).copy()
