"""The spatial part of the appearance: the normalised BRDF f̂ on its band grid in μ.

Public objects
--------------
BandGrid
    The node grid of f̂ (with the cap as a step), symmetrised, non-negative and normalised, and
    its exact albedo A(μ) at the nodes.
mu_integral_weights
    c_q = ∫_0^1 μ φ_q(μ) dμ for the interpolant's piecewise-linear basis φ_q.
hat_quadrature
    Gauss quadrature of cos-weighted averages over the hats of a regular table's nodes.

f̂ is the spatial model's prediction for the sample, interpolated over the hemisphere as the
goniophotometer's continuous BRDF (`sandlight.gonio.brdf.interpolate_band_grid`: trilinear in
μ_i = cos θ_i, μ_o = cos θ_o and Δφ = φ_o − φ_i on the band-centroid grid, held constant below the
lowest band's centroid), with four changes to its nodes:

1. **The cap as a step.** The goniophotometer's interpolant puts the cap's node at μ = 1 and ramps
   linearly to the first band's centroid (μ = 0.982 at 31 × 30), so the cap's value covers a
   projected solid angle about 8 times the cap's own (μ ≥ 0.9989). Where that value is a narrow
   peak — the mirror reflection of flat water surfaces back towards normal incidence, 70 sr⁻¹ for
   saturated sand against 0.14 sr⁻¹ in the first band — the interpolant's ∫ f̂(n, ω_o) cos θ_o dω_o
   is 4.4 instead of 1. Here the cap's value holds over the cap (nodes at μ = 1 and at its lower
   edge z_c) and the first band's value from just below z_c (10⁻⁶ of the gap) to its centroid:
   integrals over the cap and the first band match the patch values, elsewhere nothing changes.
2. **Mirror symmetry.** F[b_i, b_o, k] and F[b_i, b_o, −k] are averaged. The medium is
   statistically invariant under reflection in any vertical plane (spheroids of uniformly random
   orientation, unpolarised light), so f depends on |Δφ| only; the goniophotometer does not
   impose this (its classes use isotropy and reciprocity), so averaging halves the noise variance
   of most values. Reciprocity is kept.
3. **Non-negativity.** Negative node values (possible only where the PCA reconstruction of a
   near-zero value undershoots) are set to 0; `BandGrid.n_negative_nodes` counts them.
4. **Normalisation of the continuous BRDF.** The measured values satisfy Σ_k ω_p(k) f̂[cap, k] = 1
   over patches; the piecewise-linear interpolant integrates to slightly different values. The
   grid is divided by the exact integral ∫ f̂(n, ω_o) cos θ_o dω_o of the interpolant, so that the
   continuous BRDF satisfies the paper's §3.3 normalisation exactly.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from sandlight.errors import ParameterError
from sandlight.gonio.brdf import mu_bracket
from sandlight.gonio.hemisphere import CollectorHemisphere

if TYPE_CHECKING:
    from sandlight.spatial.model import SpatialBRDF

__all__ = ["BandGrid", "mu_integral_weights", "hat_quadrature"]


def mu_integral_weights(band_cos_theta: np.ndarray) -> np.ndarray:
    """c_q = ∫_0^1 μ φ_q(μ) dμ for the piecewise-linear basis φ_q on the nodes (band order).

    The basis is the one of the interpolant: hat functions on the ascending nodes a_0 < … < a_{n−1}
    = 1, with φ_0 = 1 on [0, a_0] (values held below the lowest node). So ∫ μ g(μ) dμ = Σ c_q g_q
    exactly for the interpolant g; Σ c_q = 1/2.

    Parameters
    ----------
    band_cos_theta : array_like, shape (n,)
        μ of the nodes, strictly decreasing, the first 1.

    Returns
    -------
    numpy.ndarray, shape (n,)
        c_q, in the nodes' order.
    """
    a = np.asarray(band_cos_theta, dtype=float)[::-1]
    c = np.zeros_like(a)
    h = np.diff(a)
    # Rising flank of node q on [a_{q−1}, a_q]: ∫ μ (μ − a_{q−1})/h dμ = h (a_{q−1} + 2 a_q)/6.
    c[1:] += h * (a[:-1] + 2.0 * a[1:]) / 6.0
    # Falling flank of node q on [a_q, a_{q+1}]: h (2 a_q + a_{q+1})/6.
    c[:-1] += h * (2.0 * a[:-1] + a[1:]) / 6.0
    c[0] += a[0] ** 2 / 2.0  # held value on [0, a_0]
    return c[::-1]


def hat_quadrature(model_nodes: np.ndarray, mu: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Quadrature of ∫ g(μ) h_q(μ) μ dμ / ∫ h_q(μ) μ dμ for the hats h_q of the table nodes μ.

    Each hat's support is cut at the model's μ nodes, where the model is linear between
    cuts, and integrated by 2-point Gauss–Legendre, exact for the cubic g·h_q·μ.

    Parameters
    ----------
    model_nodes : numpy.ndarray
        μ nodes of the model (any order), where it may bend.
    mu : numpy.ndarray, shape (n_mu,)
        Table nodes, ascending on [0, 1].

    Returns
    -------
    points : numpy.ndarray, shape (P,)
        μ at which to evaluate g.
    weights : numpy.ndarray, shape (n_mu, P)
        Row q sums to 1 (normalised by ∫ h_q μ dμ).
    """
    cuts = np.unique(np.r_[model_nodes, mu])
    cuts = cuts[(cuts >= 0.0) & (cuts <= 1.0)]
    gx = np.array([-1.0, 1.0]) / math.sqrt(3.0)
    pieces_lo, pieces_hi = cuts[:-1], cuts[1:]
    mid, half = 0.5 * (pieces_lo + pieces_hi), 0.5 * (pieces_hi - pieces_lo)
    points = (mid[:, None] + half[:, None] * gx[None, :]).ravel()
    base = np.repeat(half, 2)  # Gauss weights are 1 on [−1, 1]
    n = mu.size
    weights = np.zeros((n, points.size))
    for q in range(n):
        lo = mu[q - 1] if q > 0 else mu[q]
        hi = mu[q + 1] if q < n - 1 else mu[q]
        hat = np.where(
            points <= mu[q],
            (points - lo) / (mu[q] - lo) if q > 0 else 0.0,
            (hi - points) / (hi - mu[q]) if q < n - 1 else 0.0,
        )
        hat = np.where((points >= lo) & (points <= hi), np.clip(hat, 0.0, 1.0), 0.0)
        weights[q] = base * hat * points
    weights /= weights.sum(axis=1, keepdims=True)
    return points, weights


@dataclass(frozen=True, eq=False)
class BandGrid:
    """Node values of the normalised BRDF f̂ on the band grid (module docstring, steps 1–4).

    Attributes
    ----------
    hemisphere : CollectorHemisphere
        The spatial model's collector hemisphere (its patches are the sampler's cells).
    nodes : numpy.ndarray, shape (n,)
        μ of the nodes, decreasing: the pole, the cap's lower edge, just below it, then the band
        centroids (n = stacks + 2).
    grid : numpy.ndarray, shape (n, n, slices)
        F[q_i, q_o, k], sr⁻¹, ≥ 0, normalised so that A(1) = 1.
    mu_weights : numpy.ndarray, shape (n,)
        c_q of `mu_integral_weights`.
    albedo_nodes : numpy.ndarray, shape (n,)
        A(μ_q) = ∫ f̂ cos θ_o dω_o at the nodes, exact for the interpolant; A(1) = 1.
    n_negative_nodes : int
        Node values set to 0 (step 3).
    """

    hemisphere: CollectorHemisphere
    nodes: np.ndarray
    grid: np.ndarray
    mu_weights: np.ndarray
    albedo_nodes: np.ndarray
    n_negative_nodes: int

    @property
    def stacks(self) -> int:
        """Bands of the hemisphere, the cap included."""
        return self.hemisphere.stacks

    @property
    def slices(self) -> int:
        """Azimuth slices L: the Δφ nodes are 2πk/L."""
        return self.hemisphere.slices

    @classmethod
    def from_spatial(cls, spatial: SpatialBRDF) -> BandGrid:
        """Build the grid from a spatial prediction (steps 1–4 of the module docstring).

        Parameters
        ----------
        spatial : sandlight.spatial.SpatialBRDF
            The spatial model's prediction for the sample: F[b_i, b_o, k] on its hemisphere.

        Raises
        ------
        ParameterError
            The prediction reflects nothing at normal incidence (it cannot be normalised).
        """
        hemisphere = spatial.hemisphere
        slices = hemisphere.slices
        # Step 1: the cap's step. Nodes in μ (decreasing): the pole and the cap's lower edge z_c
        # with the cap's values, just below z_c and at the band centroids with the bands' values.
        band_nodes = hemisphere.band_cos_theta
        z_cap = float(hemisphere.bounds[hemisphere.cap, 0])
        below = z_cap - 1e-6 * (z_cap - band_nodes[1])
        nodes = np.ascontiguousarray(np.r_[1.0, z_cap, below, band_nodes[1:]])
        node_band = np.r_[0, 0, 1, np.arange(1, hemisphere.stacks)]
        mu_weights = mu_integral_weights(nodes)

        # Steps 2–4.
        grid = spatial.grid()
        k = np.arange(slices)
        grid = 0.5 * (grid + grid[:, :, (-k) % slices])
        n_negative = int((grid < 0).sum())
        grid = np.maximum(grid, 0.0)[np.ix_(node_band, node_band)]
        # A[b] = ∫ f̂ cos θ_o dω_o for incidence at node b: exact for the interpolant, whose Δφ
        # integral is (2π/L) Σ_k F and whose μ_o integral is Σ c_q (mu_integral_weights).
        albedo_nodes = (grid.sum(axis=2) * (2.0 * math.pi / slices)) @ mu_weights
        if not albedo_nodes[0] > 0:
            raise ParameterError(
                "spatial_model",
                "a BRDF that reflects nothing at normal incidence",
                "a spatial model with positive normalised values",
            )
        grid /= albedo_nodes[0]
        return cls(
            hemisphere=hemisphere,
            nodes=nodes,
            grid=np.ascontiguousarray(grid),
            mu_weights=mu_weights,
            albedo_nodes=albedo_nodes / albedo_nodes[0],
            n_negative_nodes=n_negative,
        )

    def bracket(self, mu: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The interpolant's linear weights (a, b, t) of cosines μ on the nodes (`mu_bracket`)."""
        return mu_bracket(self.nodes, mu)

    def at_mu(self, node_values: np.ndarray, mu: np.ndarray) -> np.ndarray:
        """A function of μ given at the nodes, interpolated as the BRDF is (linear in μ)."""
        a, b, t = self.bracket(mu)
        return (1 - t) * node_values[a] + t * node_values[b]
