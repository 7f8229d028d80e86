"""Synthetic end-member spectra with a known k(λ): the round trip of issue 17 §1 (a).

Public objects
--------------
synthetic_spectra
    Spectra of end-members computed with a forward model at a known k(λ), one run per
    wavelength (not from the tables), plus Gaussian measurement noise.
edge_and_band_log10_k
    A smooth, hematite-like test k(λ): an absorption edge and one crystal-field band.

The spectra must come from the forward model itself, with its own random numbers, not from the
tables the fit uses: the round trip then tests the tabulation and interpolation in k as well as
the fit, and the tables' Monte Carlo noise is independent of the synthetic spectra's.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

if TYPE_CHECKING:
    from sandlight.calibration.end_members import EndMember
    from sandlight.calibration.forward import ForwardModel

__all__ = ["synthetic_spectra", "edge_and_band_log10_k"]


def edge_and_band_log10_k(
    wavelengths_nm: ArrayLike,
    *,
    opaque: float = -0.2,
    floor: float = -3.5,
    edge_nm: float = 600.0,
    edge_width_nm: float = 25.0,
    band_nm: float = 870.0,
    band_width_nm: float = 60.0,
    band_depth: float = 1.0,
) -> np.ndarray:
    """log10 k(λ): ``opaque`` below an absorption edge at ``edge_nm`` (a logistic step of width
    ``edge_width_nm``) down to ``floor``, plus a Gaussian band of ``band_depth`` decades at
    ``band_nm`` (standard deviation ``band_width_nm``). Defaults resemble hematite's charge-
    transfer edge and its 860–880 nm Fe³⁺ band."""
    wl = np.asarray(wavelengths_nm, dtype=float)
    step = 1.0 / (1.0 + np.exp((wl - edge_nm) / edge_width_nm))
    band = band_depth * np.exp(-0.5 * ((wl - band_nm) / band_width_nm) ** 2)
    return floor + (opaque - floor) * step + band


def synthetic_spectra(
    forward: ForwardModel,
    members: Sequence[EndMember],
    wavelengths_nm: ArrayLike,
    log10_k: ArrayLike,
    *,
    sigma: float,
    seed: int = 0,
) -> tuple[np.ndarray, np.ndarray]:
    """Reflectance of each end-member at k(λ) = 10**log10_k, with noise.

    Parameters
    ----------
    forward : forward model
        See :mod:`sandlight.calibration.forward`; use another seed than the tables'.
    members : sequence of EndMember
    wavelengths_nm : array_like, shape (nλ,)
    log10_k : array_like, shape (nλ,)
        The known log10 k at each wavelength.
    sigma : float
        Standard deviation of the added Gaussian measurement noise (≥ 0).
    seed : int
        Seed of the measurement noise.

    Returns
    -------
    values, sigma : numpy.ndarray, shape (len(members), nλ)
        The spectra and their standard error: the added noise ⊕ the forward model's own
        Monte Carlo error, which a fit of them must count as measurement error.
    """
    wl = np.asarray(wavelengths_nm, dtype=float)
    x = np.broadcast_to(np.asarray(log10_k, dtype=float), wl.shape)
    rng = np.random.default_rng(seed)
    out = np.empty((len(members), wl.size))
    mc = np.empty_like(out)
    for s, member in enumerate(members):
        for i, (lam, xi) in enumerate(zip(wl, x)):
            values, errors = forward.reflectance(member, [lam], float(10.0**xi))
            out[s, i], mc[s, i] = values[0], errors[0]
    return out + sigma * rng.standard_normal(out.shape), np.sqrt(sigma**2 + mc**2)
