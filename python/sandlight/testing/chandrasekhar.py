"""Chandrasekhar's H-function and the reflection of a semi-infinite isotropic scatterer.

A half-space of isotropic point scatterers with single-scattering albedo ω and exponential free
paths reflects with the exact BRDF (Chandrasekhar 1950, ch. IV; docs/model.md §2.7)

    f(μ, μ0) = ω H(μ) H(μ0) / (4π (μ + μ0))   [sr⁻¹]

and directional-hemispherical reflectance 1 − H(μ0) √(1 − ω), where μ0 and μ are the cosines of
the incident and reflected zenith angles and H is the H-function for isotropic scattering. It is
the independent check of the transport engine and of the goniophotometer.

Public objects
--------------
h_function
    H(μ; ω), solved numerically.
dhr
    Directional-hemispherical reflectance 1 − H(μ0)√(1 − ω).
brdf
    The BRDF above.

Method
------
H is the solution of Chandrasekhar's integral equation in its second form (Chandrasekhar 1950,
eq. IV.(40)), which converges for all ω ≤ 1:

    1/H(μ) = √(1 − ω) + (ω/2) ∫₀¹ μ' H(μ') / (μ + μ') dμ'.

The integral is discretised with composite Gauss–Legendre quadrature on intervals graded
geometrically towards μ' = 0 (where the kernel varies on the scale μ and H has a μ ln μ
term); the discrete equations are solved by Newton's method, and H at any μ follows from the
same formula with the converged node values (Nyström interpolation). The result satisfies
H(0) = 1 and the moment identity ∫₀¹ H dμ = 2(1 − √(1 − ω))/ω to about 1e-12, and reproduces
Chandrasekhar's table for ω = 1 (H(1) = 2.9078) to the table's precision.

References
----------
Chandrasekhar, S. (1950). *Radiative Transfer*. Oxford: Clarendon Press (Dover reprint 1960),
chapter IV and table XI.
"""

from __future__ import annotations

import functools
import math

import numpy as np
from numpy.typing import ArrayLike

from sandlight.errors import ParameterError

__all__ = ["h_function", "dhr", "brdf"]

# Composite Gauss–Legendre quadrature on [0, 1]: breakpoints graded towards 0, 24 nodes each.
_BREAKS = np.array([0.0, 1e-8, 1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 0.05, 0.15, 0.35, 0.65, 1.0])
_ORDER = 24


@functools.lru_cache(maxsize=1)
def _quadrature() -> tuple[np.ndarray, np.ndarray]:
    x, w = np.polynomial.legendre.leggauss(_ORDER)
    lo, hi = _BREAKS[:-1, None], _BREAKS[1:, None]
    nodes = (0.5 * (hi - lo) * (x + 1.0) + lo).ravel()
    weights = (0.5 * (hi - lo) * w).ravel()
    return nodes, weights


@functools.lru_cache(maxsize=64)
def _node_values(omega: float) -> np.ndarray:
    """H at the quadrature nodes for albedo ``omega``, by Newton's method on
    F(H) = H·(√(1 − ω) + (ω/2) K H) − 1 = 0 with K[i, k] = w_k μ_k / (μ_i + μ_k)."""
    nodes, weights = _quadrature()
    kernel = 0.5 * omega * weights * nodes / (nodes[:, None] + nodes[None, :])
    s = math.sqrt(1.0 - omega)
    h = np.ones_like(nodes)
    for _ in range(100):
        d = s + kernel @ h
        residual = h * d - 1.0
        if np.max(np.abs(residual)) < 1e-14:
            return h
        jacobian = np.diag(d) + h[:, None] * kernel
        h = h - np.linalg.solve(jacobian, residual)
    raise RuntimeError(f"H-function iteration did not converge for omega = {omega}")


def _check_omega(omega: float) -> float:
    try:
        value = float(omega)
    except (TypeError, ValueError):
        raise ParameterError("omega", omega, "must be a real number in [0, 1]") from None
    if not 0.0 <= value <= 1.0:
        raise ParameterError("omega", omega, "must be a real number in [0, 1] (single-scattering albedo)")
    return value


def _check_mu(name: str, mu: ArrayLike) -> np.ndarray:
    arr = np.asarray(mu, dtype=float)
    finite = arr[np.isfinite(arr)]
    if np.any(finite < 0.0) or np.any(finite > 1.0):
        bad = finite[(finite < 0.0) | (finite > 1.0)][0]
        raise ParameterError(name, float(bad), "must lie in [0, 1] (cosine of a zenith angle above the surface)")
    return arr


def h_function(mu: ArrayLike, omega: float) -> np.ndarray:
    """Chandrasekhar's H-function for isotropic scattering.

    Parameters
    ----------
    mu : array_like
        Direction cosine μ ∈ [0, 1] (dimensionless). NaN propagates.
    omega : float
        Single-scattering albedo ω ∈ [0, 1].

    Returns
    -------
    numpy.ndarray
        H(μ; ω), same shape as ``mu``; H ∈ [1, 2.9078] (dimensionless).

    Raises
    ------
    sandlight.errors.ParameterError
        If μ or ω is outside [0, 1].

    Examples
    --------
    >>> round(float(h_function(1.0, 1.0)), 4)
    2.9078
    """
    w = _check_omega(omega)
    mu = _check_mu("mu", mu)
    if w == 0.0:
        return np.where(np.isnan(mu), np.nan, 1.0)
    nodes, weights = _quadrature()
    h_nodes = _node_values(w)
    flat = mu.reshape(-1)
    # 1/H(μ) = √(1 − ω) + (ω/2) Σ_k w_k μ_k H_k / (μ + μ_k): Chandrasekhar eq. IV.(40).
    integral = (weights * nodes * h_nodes / (flat[:, None] + nodes[None, :])).sum(axis=1)
    return (1.0 / (math.sqrt(1.0 - w) + 0.5 * w * integral)).reshape(mu.shape)


def dhr(mu0: ArrayLike, omega: float) -> np.ndarray:
    """Directional-hemispherical reflectance of the isotropic half-space, 1 − H(μ0)√(1 − ω).

    Parameters
    ----------
    mu0 : array_like
        Cosine of the incident zenith angle, μ0 ∈ [0, 1].
    omega : float
        Single-scattering albedo ω ∈ [0, 1].

    Returns
    -------
    numpy.ndarray
        Reflectance ρ(μ0) ∈ [0, 1] (fraction of incident power), same shape as ``mu0``.
    """
    w = _check_omega(omega)
    return 1.0 - h_function(mu0, w) * math.sqrt(1.0 - w)


def brdf(mu: ArrayLike, mu0: ArrayLike, omega: float) -> np.ndarray:
    """BRDF of the isotropic half-space, ω H(μ) H(μ0) / (4π (μ + μ0)).

    Parameters
    ----------
    mu, mu0 : array_like
        Cosines of the reflected and incident zenith angles, in [0, 1], broadcast together;
        μ + μ0 must be positive.
    omega : float
        Single-scattering albedo ω ∈ [0, 1].

    Returns
    -------
    numpy.ndarray
        f(μ, μ0) in sr⁻¹, independent of azimuth, symmetric in (μ, μ0).
    """
    w = _check_omega(omega)
    mu, mu0 = _check_mu("mu", mu), _check_mu("mu0", mu0)
    total = mu + mu0
    if np.any(total == 0.0):
        raise ParameterError("mu + mu0", 0.0, "must be positive (the BRDF diverges at grazing incidence and exit)")
    # H is evaluated before broadcasting: outer-product inputs cost one H per distinct cosine.
    return w * h_function(mu, w) * h_function(mu0, w) / (4.0 * math.pi * total)
