"""Pearson's chi-square test of sampled directions against the density they claim to follow.

A sampler of outgoing directions (e.g. `sandlight.appearance.SandAppearance.sample`) is correct
when its directions are distributed with its stated pdf. `hemisphere_chi2` bins directions of the
upper hemisphere in (μ = cos θ, φ), compares the counts with N ∫_bin pdf dω (a midpoint rule in
(μ, φ), where dω = dμ dφ), pools sparse bins and returns the chi-square statistic and p-value.

Constants
---------
MIN_EXPECTED = 5
    Bins expecting fewer counts are pooled (smallest first) until the pool expects at least this
    many: the usual condition for the chi-square approximation of Pearson's statistic.
SIGNIFICANCE = 0.01
    Default level of `ChiSquareResult.passed`: a correct sampler fails with probability 1 % per
    test (tests use fixed seeds, so a given test either always passes or always fails).
QUADRATURE = 8
    Midpoint-rule points per bin and axis for the expected counts. Choose bin edges at the
    density's discontinuities (e.g. the sampler's cell boundaries): the rule is then exact for
    densities linear in μ and φ within a bin, and accurate to O(1/QUADRATURE²) for smooth ones.

Directions outside the binned region (z ≤ 0, or outside the edges) are counted in an extra bin
that expects nothing, which makes the test fail.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from sandlight.errors import ParameterError

__all__ = ["hemisphere_chi2", "ChiSquareResult", "MIN_EXPECTED", "SIGNIFICANCE", "QUADRATURE"]

MIN_EXPECTED = 5.0
SIGNIFICANCE = 0.01
QUADRATURE = 8


@dataclass(frozen=True)
class ChiSquareResult:
    """Outcome of `hemisphere_chi2`.

    Attributes
    ----------
    statistic : float
        Pearson's Σ (O − E)²/E over the pooled bins.
    dof : int
        Degrees of freedom, pooled bins − 1.
    p_value : float
        P(χ²_dof ≥ statistic); 0 if a direction fell where nothing is expected.
    n_bins : int
        Bins after pooling.
    pdf_integral : float
        ∫ pdf dω over the binned region by the quadrature (≈ 1 for a normalised density).
    outside : int
        Directions outside the binned region.
    """

    statistic: float
    dof: int
    p_value: float
    n_bins: int
    pdf_integral: float
    outside: int

    def passed(self, significance: float = SIGNIFICANCE) -> bool:
        return self.p_value >= significance


def hemisphere_chi2(
    directions: ArrayLike,
    pdf: Callable,
    *,
    mu_edges: ArrayLike | None = None,
    phi_edges: ArrayLike | None = None,
    quadrature: int = QUADRATURE,
    min_expected: float = MIN_EXPECTED,
) -> ChiSquareResult:
    """Chi-square test of directions against a density over the upper hemisphere.

    Parameters
    ----------
    directions : array_like, shape (N, 3)
        Sampled directions (any positive length).
    pdf : callable
        ``pdf(dirs)`` for unit directions of shape (M, 3) → density (M,) with respect to solid
        angle, sr⁻¹.
    mu_edges : array_like, optional
        Ascending bin edges in μ = cos θ within [0, 1] (default 20 equal bins).
    phi_edges : array_like, optional
        Ascending bin edges in φ = atan2(y, x) mod 2π within [0, 2π] (default 24 equal bins).
    quadrature : int
        Midpoint-rule points per bin and axis.
    min_expected : float
        Pooling threshold (see the module docstring).

    Returns
    -------
    ChiSquareResult
    """
    from scipy.stats import chi2

    d = np.asarray(directions, dtype=float)
    if d.ndim != 2 or d.shape[1] != 3 or d.shape[0] < 1:
        raise ParameterError("directions", f"an array of shape {d.shape}", "shape (N, 3), N >= 1")
    mu_edges = np.linspace(0.0, 1.0, 21) if mu_edges is None else np.asarray(mu_edges, dtype=float)
    phi_edges = np.linspace(0.0, 2.0 * math.pi, 25) if phi_edges is None else np.asarray(phi_edges, dtype=float)
    for name, e, hi in (("mu_edges", mu_edges, 1.0), ("phi_edges", phi_edges, 2.0 * math.pi)):
        if e.ndim != 1 or e.size < 2 or np.any(np.diff(e) <= 0) or e[0] < 0 or e[-1] > hi + 1e-12:
            raise ParameterError(
                name, e.tolist() if e.size < 10 else f"{e.size} edges", f"ascending edges within [0, {hi:g}]"
            )
    if isinstance(quadrature, bool) or not isinstance(quadrature, int) or quadrature < 1:
        raise ParameterError("quadrature", quadrature, "an integer >= 1")
    n = d.shape[0]
    unit = d / np.linalg.norm(d, axis=1, keepdims=True)
    mu = unit[:, 2]
    phi = np.mod(np.arctan2(unit[:, 1], unit[:, 0]), 2.0 * math.pi)
    inside = (mu > 0) & (mu >= mu_edges[0]) & (mu <= mu_edges[-1]) & (phi >= phi_edges[0]) & (phi <= phi_edges[-1])
    observed, _, _ = np.histogram2d(mu[inside], phi[inside], bins=[mu_edges, phi_edges])
    outside = int(n - inside.sum())

    # Expected counts: N ∫ pdf dμ dφ per bin by the midpoint rule.
    s = (np.arange(quadrature) + 0.5) / quadrature
    mu_pts = (mu_edges[:-1, None] + np.diff(mu_edges)[:, None] * s[None, :]).ravel()
    phi_pts = (phi_edges[:-1, None] + np.diff(phi_edges)[:, None] * s[None, :]).ravel()
    M, P = np.meshgrid(mu_pts, phi_pts, indexing="ij")
    sin = np.sqrt(np.maximum(0.0, 1.0 - M**2))
    dirs = np.stack([sin * np.cos(P), sin * np.sin(P), M], axis=-1).reshape(-1, 3)
    density = np.asarray(pdf(dirs), dtype=float).reshape(M.shape)
    if not np.isfinite(density).all() or (density < 0).any():
        raise ParameterError("pdf", "negative or non-finite values", "a density >= 0")
    nm, npf = mu_edges.size - 1, phi_edges.size - 1
    cell = (np.diff(mu_edges)[:, None] * np.diff(phi_edges)[None, :]) / quadrature**2
    integral = density.reshape(nm, quadrature, npf, quadrature).sum(axis=(1, 3)) * cell
    expected = n * integral

    # Pool sparse bins, smallest expectation first, into groups expecting >= min_expected.
    obs, exp = observed.ravel(), expected.ravel()
    order = np.argsort(exp)
    pooled_o, pooled_e = [], []
    acc_o = acc_e = 0.0
    for i in order:
        if exp[i] >= min_expected and acc_e == 0.0:
            pooled_o.append(obs[i])
            pooled_e.append(exp[i])
            continue
        acc_o += obs[i]
        acc_e += exp[i]
        if acc_e >= min_expected:
            pooled_o.append(acc_o)
            pooled_e.append(acc_e)
            acc_o = acc_e = 0.0
    if acc_e > 0 or acc_o > 0:  # a remainder below the threshold joins the smallest pooled bin
        if pooled_e:
            j = int(np.argmin(pooled_e))
            pooled_o[j] += acc_o
            pooled_e[j] += acc_e
        else:
            pooled_o.append(acc_o)
            pooled_e.append(acc_e)
    o, e = np.array(pooled_o), np.array(pooled_e)
    if outside > 0 or np.any((e <= 0) & (o > 0)):
        return ChiSquareResult(math.inf, max(len(e) - 1, 1), 0.0, len(e), float(integral.sum()), outside)
    keep = e > 0
    statistic = float(np.sum((o[keep] - e[keep]) ** 2 / e[keep]))
    dof = max(int(keep.sum()) - 1, 1)
    return ChiSquareResult(
        statistic, dof, float(chi2.sf(statistic, dof)), int(keep.sum()), float(integral.sum()), outside
    )
