"""Particle size distributions and the sizes a ray meets.

A sieve (mass) distribution p_m(D) becomes a number distribution p_n(D) ∝ p_m(D)/D³
(docs/model.md §2.2); a ray meets particles in proportion to their mean projected area, which
for a convex body of fixed shape is S/4 ∝ D² (Cauchy's theorem), so the sizes met are
distributed as p_enc(D) ∝ p_n(D) D² ∝ p_m(D)/D. The engine samples those sizes from a quantile
table computed here.

Sizes are volume-equivalent diameters in mm throughout.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

N_QUANTILES = 257
_GRID = 4097


@dataclass(frozen=True)
class SizeDistribution:
    """A mass (sieve) size distribution on [d_min_mm, d_max_mm].

    kind ``"lognormal"``: log-normal by mass with median ``median_mm`` and geometric standard
    deviation ``spread`` (σ_g ≥ 1; 1 means all particles have the median size), truncated to
    [d_min_mm, d_max_mm]. kind ``"loguniform"``: equal mass per logarithmic size interval.
    """

    kind: str
    d_min_mm: float
    d_max_mm: float
    median_mm: float = float("nan")
    spread: float = 1.0

    @property
    def monodisperse(self) -> bool:
        return self.kind == "lognormal" and self.spread <= 1.0 + 1e-9

    def _log_grid(self) -> tuple[np.ndarray, np.ndarray]:
        """log D grid and the mass density per unit log D on it (unnormalised)."""
        x = np.linspace(np.log(self.d_min_mm), np.log(self.d_max_mm), _GRID)
        if self.kind == "loguniform":
            return x, np.ones_like(x)
        s = np.log(self.spread)
        return x, np.exp(-0.5 * ((x - np.log(self.median_mm)) / s) ** 2)

    def mass_mean_inverse_diameter(self) -> float:
        """E_m[1/D] (mm⁻¹): with p_n ∝ p_m/D³, ⟨D²⟩_n/⟨D³⟩_n = E_m[1/D]."""
        if self.monodisperse:
            return 1.0 / self.median_mm
        x, w = self._log_grid()
        return float(np.trapezoid(w * np.exp(-x), x) / np.trapezoid(w, x))

    def encounter_quantiles(self, n: int = N_QUANTILES) -> np.ndarray:
        """Quantiles of the sizes a ray meets, p_enc ∝ p_m/D, at n equally spaced levels."""
        if self.monodisperse:
            return np.full(1, self.median_mm)
        x, w = self._log_grid()
        dens = w * np.exp(-x)  # p_enc per unit log D: (p_m/D)·D = p_m = w/D
        cdf = np.concatenate([[0.0], np.cumsum(0.5 * (dens[1:] + dens[:-1]) * np.diff(x))])
        cdf /= cdf[-1]
        levels = np.linspace(0.0, 1.0, n)
        q = np.exp(np.interp(levels, cdf, x))
        return np.maximum.accumulate(q)


def spheroid_surface_factor(aspect_ratio: ArrayLike) -> float | np.ndarray:
    """Surface of a prolate spheroid over that of the sphere of equal volume (≥ 1); a float for a
    float, an array for an array.

    S = 2πa²[1 + (c/(a e)) arcsin e], e² = 1 − a²/c², with a = (D/2) ε^(−1/3), c = ε a
    (docs/model.md §2.3).
    """
    eps = np.asarray(aspect_ratio, dtype=float)
    sphere = eps <= 1.0 + 1e-12
    eps_ = np.where(sphere, 2.0, eps)  # any ε > 1 where the sphere's 1 is returned
    a = 0.5 * eps_ ** (-1.0 / 3.0)
    c = eps_ * a
    e = np.sqrt(1.0 - (a / c) ** 2)
    s = 2.0 * np.pi * a * a * (1.0 + c / (a * e) * np.arcsin(e))
    factor = np.where(sphere, 1.0, s / np.pi)  # sphere of D = 1: S = π
    return float(factor) if factor.ndim == 0 else factor


def lognormal_mass_mean_inverse_diameter(
    median_mm: ArrayLike, spread: ArrayLike, d_min_mm: float, d_max_mm: float
) -> np.ndarray:
    """E_m[1/D] (mm⁻¹) of log-normal mass distributions truncated to [d_min_mm, d_max_mm], in
    closed form, for arrays of medians and spreads (σ_g = 1: 1/median).

    With ln D ~ N(μ, s²) by mass, s = ln σ_g, on [ln a, ln b]:
    E_m[1/D] = e^(−μ + s²/2) [Φ(β + s) − Φ(α + s)] / [Φ(β) − Φ(α)], α = (ln a − μ)/s,
    β = (ln b − μ)/s (the integrand e^(−x) N(x; μ, s²) is e^(−μ + s²/2) N(x; μ − s², s²)).
    ``SizeDistribution.mass_mean_inverse_diameter`` integrates the same numerically.
    """
    from scipy.special import ndtr

    mu = np.log(np.asarray(median_mm, dtype=float))
    s = np.log(np.asarray(spread, dtype=float))
    mono = s <= 1e-9
    s_ = np.where(mono, 1.0, s)
    alpha, beta = (np.log(d_min_mm) - mu) / s_, (np.log(d_max_mm) - mu) / s_
    ratio = (ndtr(beta + s_) - ndtr(alpha + s_)) / (ndtr(beta) - ndtr(alpha))
    return np.where(mono, np.exp(-mu), np.exp(-mu + 0.5 * s_**2) * ratio)
