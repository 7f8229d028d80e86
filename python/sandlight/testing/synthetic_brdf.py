"""Synthetic goniophotometer counts drawn from a known BRDF, to test the reduction pipeline.

Public objects
--------------
band_probabilities
    Patch-to-patch escape probabilities of any azimuth-independent BRDF f(μ_out, μ_in).
lambertian_probabilities
    The same for a Lambertian surface of albedo a, f = a/π (exact, no quadrature).
chandrasekhar_probabilities
    The same for Chandrasekhar's isotropic half-space of albedo ω.
expected_brdf
    E[f[i, j]] = P[i, j] / ω_p(j): what the estimator of paper §3.2.1 converges to.
sample_counts
    Multinomial counts of a uniform-incidence run with given escape probabilities.

A trial of the virtual goniophotometer draws its incident direction uniformly over the
hemisphere, so with patches of equal solid angle it lands in patch i with probability 1/r, and
then escapes into patch j with probability

    P[i, j] = (1/Ω_i) ∫_{Ω_i} dω_i ∫_{Ω_j} f(ω_i, ω_o) cos θ_o dω_o,

is absorbed with probability 1 − Σ_j P[i, j] (or lost, see `sample_counts`). The estimator
f[i, j] = n[i, j] / (ω_p(j) N_i) therefore converges to P[i, j] / ω_p(j), the cos θ_o-weighted
average of f over the outgoing patch and the plain average over the incoming one. This is not
exactly reciprocal (the two patches are weighted differently), so the reduced values converge
to the class averages of P[i, j] / ω_p(j), which `expected_brdf` and
`EquivalenceClasses.mean` give.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike

from sandlight.errors import ParameterError
from sandlight.gonio.hemisphere import CollectorHemisphere
from sandlight.testing import chandrasekhar

__all__ = [
    "band_probabilities",
    "lambertian_probabilities",
    "chandrasekhar_probabilities",
    "expected_brdf",
    "sample_counts",
]


def _check_fraction(name: str, value: object, *, low_open: bool = False) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ParameterError(name, value, "must be a real number in [0, 1]") from None
    if not (0.0 < v <= 1.0 if low_open else 0.0 <= v <= 1.0):
        raise ParameterError(
            name, value, "must be a real number in (0, 1]" if low_open else "must be a real number in [0, 1]"
        )
    return v


def band_probabilities(
    hemisphere: CollectorHemisphere, brdf_mu: Callable[[np.ndarray, np.ndarray], np.ndarray], *, order: int = 12
) -> np.ndarray:
    """Escape probabilities P[i, j] of an azimuth-independent BRDF.

    Parameters
    ----------
    hemisphere : CollectorHemisphere
        r patches.
    brdf_mu : callable
        ``brdf_mu(mu_out, mu_in)`` → f in sr⁻¹, vectorised over broadcast arrays of cosines in
        (0, 1].
    order : int, default 12
        Gauss–Legendre nodes per band and per direction.

    Returns
    -------
    numpy.ndarray, shape (r, r)
        P[i, j] = (Δφ_j / (z1_i − z0_i)) ∫_{band i} dμ_i ∫_{band j} f(μ_o, μ_i) μ_o dμ_o,
        where Δφ_j is the azimuth width of patch j (the azimuth integral of the incoming patch
        cancels against Ω_i because f does not depend on azimuth).
    """
    x, w = np.polynomial.legendre.leggauss(order)
    bands = np.concatenate([[0], 1 + hemisphere.slices * np.arange(hemisphere.n_bands)])
    z0 = hemisphere.bounds[bands, 0][:, None]
    z1 = hemisphere.bounds[bands, 1][:, None]
    mu = 0.5 * (z1 - z0) * (x + 1.0) + z0  # (stacks, order) nodes of each band
    wt = 0.5 * (z1 - z0) * w
    # f at every (band_in node, band_out node): shape (stacks, order, stacks, order).
    f = brdf_mu(mu[None, None, :, :], mu[:, :, None, None])
    integral = np.einsum("ia,jb,iajb->ij", wt, wt * mu, f)
    per_band = integral / (z1 - z0)  # divide by the band height of the incoming band
    dphi = hemisphere.bounds[:, 3] - hemisphere.bounds[:, 2]
    return per_band[hemisphere.band[:, None], hemisphere.band[None, :]] * dphi[None, :]


def lambertian_probabilities(hemisphere: CollectorHemisphere, albedo: float) -> np.ndarray:
    """Escape probabilities of a Lambertian surface, P[i, j] = a ω_p(j) / π (exact).

    Parameters
    ----------
    albedo : float
        Albedo a ∈ [0, 1] (directional-hemispherical reflectance at every incidence).
    """
    a = _check_fraction("albedo", albedo)
    r = hemisphere.n_patches
    return np.broadcast_to(a * hemisphere.projected_solid_angles / math.pi, (r, r)).copy()


def chandrasekhar_probabilities(hemisphere: CollectorHemisphere, omega: float, *, order: int = 12) -> np.ndarray:
    """Escape probabilities of the isotropic half-space, f = ω H(μ)H(μ0) / (4π(μ + μ0)).

    Parameters
    ----------
    omega : float
        Single-scattering albedo ω ∈ (0, 1].
    order : int, default 12
        Gauss–Legendre nodes per band (12 resolves the grazing corner μ, μ0 → 0 to ~1e-6).
    """
    w = _check_fraction("omega", omega, low_open=True)
    return band_probabilities(hemisphere, lambda mu, mu0: chandrasekhar.brdf(mu, mu0, w), order=order)


def expected_brdf(hemisphere: CollectorHemisphere, probabilities: ArrayLike) -> np.ndarray:
    """E[f[i, j]] = P[i, j] / ω_p(j) in sr⁻¹, the limit of the estimator of paper §3.2.1."""
    return np.asarray(probabilities, dtype=float) / hemisphere.projected_solid_angles[None, :]


def sample_counts(
    hemisphere: CollectorHemisphere,
    probabilities: ArrayLike,
    rays: int,
    *,
    seed: int = 0,
    lost_probability: float = 0.0,
) -> dict[str, np.ndarray]:
    """Counts of a simulated uniform-incidence run.

    Each of ``rays`` trials picks its incoming patch uniformly (uniform incidence over patches of
    equal solid angle); it is lost with probability ``lost_probability``, else escapes into patch
    j with probability P[i, j] or is absorbed. All draws are multinomial (numpy Generator).

    Parameters
    ----------
    hemisphere : CollectorHemisphere
    probabilities : array_like, shape (r, r)
        P[i, j] ≥ 0 with row sums ≤ 1.
    rays : int
        Number of trials, ≥ 1.
    seed : int, default 0
        Seed of ``numpy.random.default_rng``.
    lost_probability : float, default 0
        Chance that a trial is lost (event cap or transmission), in [0, 1].

    Returns
    -------
    dict
        ``counts`` (r, r), ``absorbed``, ``launched``, ``lost`` (r,), all int64: the arguments of
        `reduce_counts` and `MeasuredBRDF.from_counts`.
    """
    r = hemisphere.n_patches
    p = np.asarray(probabilities, dtype=float)
    if p.shape != (r, r):
        raise ParameterError("probabilities", f"an array of shape {p.shape}", f"must have shape ({r}, {r})")
    row_sum = p.sum(axis=1)
    if np.any(p < 0) or np.any(row_sum > 1.0 + 1e-12):
        raise ParameterError("probabilities", float(row_sum.max()), "must be non-negative with row sums ≤ 1")
    if isinstance(rays, bool) or int(rays) != rays or rays < 1:
        raise ParameterError("rays", rays, "must be a positive integer")
    q = _check_fraction("lost_probability", lost_probability)
    rng = np.random.default_rng(seed)
    launched = rng.multinomial(int(rays), np.full(r, 1.0 / r))
    outcomes = np.empty((r, r + 2))
    outcomes[:, :r] = (1.0 - q) * p
    outcomes[:, r] = q
    outcomes[:, r + 1] = np.clip(1.0 - outcomes[:, : r + 1].sum(axis=1), 0.0, 1.0)  # absorbed
    outcomes /= outcomes.sum(axis=1, keepdims=True)  # remove rounding before numpy's check
    drawn = rng.multinomial(launched, outcomes)
    return {
        "counts": drawn[:, :r].astype(np.int64),
        "absorbed": drawn[:, r + 1].astype(np.int64),
        "launched": launched.astype(np.int64),
        "lost": drawn[:, r].astype(np.int64),
    }
