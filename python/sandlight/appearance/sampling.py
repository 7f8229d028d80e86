"""Importance sampling of the appearance's BRDF: cells, tables, pdf and the sampler.

Public objects
--------------
SAMPLING_METHODS
    ``"brdf"`` (follow the tabulated BRDF) and ``"cosine"`` (the paper's choice).
DEFENSIVE_COSINE_SHARE, SAMPLING_SUBDIVISIONS
    ε of the mixture below; midpoint-rule points per cell and axis for the tables.
SamplingTables
    The per-node discrete laws over outgoing cells, their pdf and the sampler.
outgoing_cells
    Bounds of the outgoing cells of a collector hemisphere.
check_sampling_method
    Refuse an unknown method name.

``method="cosine"``: the paper's choice, pdf = cos θ_o/π, weight = π f.
``method="brdf"``: follows the tabulated BRDF. For each incoming node μ_b a table holds, for every
outgoing *cell* — the collector patches turned to be centred on the grid's Δφ nodes (band b_o and
Δφ ∈ [2π(k − ½)/L, 2π(k + ½)/L), or the cap) — the integral of f·cos θ_o at the reference
spectrum (the mean of the per-wavelength weights), by a 4 × 4 midpoint rule. An incoming
direction between nodes μ_b0 and μ_b1 with interpolation weight t uses the mixture
(1 − t)·row b0 + t·row b1, as the BRDF itself does. A cell is drawn from that discrete law and the
direction within it with density ∝ cos θ_o (uniform azimuth, μ_o² uniform), so that a Lambertian
BRDF is sampled exactly. A defensive share ε = 0.1 of cosine sampling keeps the pdf positive
wherever f can be:

    pdf(ω_o | ω_i) = ε cos θ_o/π + (1 − ε) [(1 − t) P_b0(cell) + t P_b1(cell)] cos θ_o / W_cell,

with W_cell = ∫_cell cos θ dω the cell's projected solid angle,

and weight = f(ω_i, ω_o, λ) cos θ_o / pdf. The pdf does not depend on λ.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from sandlight.appearance.band_grid import BandGrid
from sandlight.errors import ParameterError
from sandlight.gonio.hemisphere import CollectorHemisphere

__all__ = [
    "SAMPLING_METHODS",
    "DEFENSIVE_COSINE_SHARE",
    "SAMPLING_SUBDIVISIONS",
    "SamplingTables",
    "outgoing_cells",
    "check_sampling_method",
]

#: Share ε of cosine-weighted sampling mixed into the BRDF-following sampler (keeps pdf > 0
#: wherever cos θ_o > 0, and bounds the weight by π f / ε).
DEFENSIVE_COSINE_SHARE = 0.1
#: Midpoint-rule points per cell and axis for the sampling tables.
SAMPLING_SUBDIVISIONS = 4
SAMPLING_METHODS = ("brdf", "cosine")


def check_sampling_method(method: str) -> str:
    """``method`` if it is one of `SAMPLING_METHODS`, else `ParameterError` naming ``method``."""
    if method not in SAMPLING_METHODS:
        raise ParameterError("method", method, f"one of {SAMPLING_METHODS}")
    return method


def outgoing_cells(hemisphere: CollectorHemisphere) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Bounds of the outgoing cells in the frame of the incident azimuth.

    Returns
    -------
    z0, z1, phi0, phi1 : numpy.ndarray, shape (r,)
        μ range and Δφ range (rad) of each cell, one row per cell in patch order (cap, then band
        by band): the patches turned to be centred on the Δφ nodes 2πk/L.
    """
    z0, z1 = hemisphere.bounds[:, 0], hemisphere.bounds[:, 1]
    step = 2.0 * math.pi / hemisphere.slices
    centre = hemisphere.slice * step
    phi0 = np.where(hemisphere.band == 0, 0.0, centre - step / 2)
    phi1 = np.where(hemisphere.band == 0, 2.0 * math.pi, centre + step / 2)
    return z0, z1, phi0, phi1


@dataclass(frozen=True, eq=False)
class SamplingTables:
    """Discrete laws over the outgoing cells, one per μ node of the BRDF (module docstring).

    Attributes
    ----------
    band_grid : BandGrid
        The BRDF's node grid (its μ nodes index the rows).
    cell_z0, cell_z1, cell_phi0, cell_phi1 : numpy.ndarray, shape (r,)
        Cell bounds (`outgoing_cells`).
    cell_projected : numpy.ndarray, shape (r,)
        W_cell = ∫_cell cos θ dω, sr.
    pmf, cdf : numpy.ndarray, shape (n_nodes, r)
        Probability of each cell for incidence at each node, and its running sum (last 1).
    band_z0 : numpy.ndarray, shape (stacks,)
        Lower μ bound of each band, to locate the cell of a direction.
    """

    band_grid: BandGrid
    cell_z0: np.ndarray
    cell_z1: np.ndarray
    cell_phi0: np.ndarray
    cell_phi1: np.ndarray
    cell_projected: np.ndarray
    pmf: np.ndarray
    cdf: np.ndarray
    band_z0: np.ndarray

    @classmethod
    def build(
        cls,
        band_grid: BandGrid,
        reference: Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray],
    ) -> SamplingTables:
        """Tabulate ∫_cell f cos θ_o dω_o for the reference BRDF f at every μ node.

        Parameters
        ----------
        band_grid : BandGrid
            Its μ nodes index the rows, its hemisphere gives the cells.
        reference : callable
            ``reference(mu_i, mu_o, dphi) -> f`` in sr⁻¹ (arrays of equal length; Δφ in rad): the
            BRDF at the reference spectrum, the mean of the per-wavelength weights.
        """
        z0, z1, phi0, phi1 = outgoing_cells(band_grid.hemisphere)
        r = z0.size
        n = SAMPLING_SUBDIVISIONS
        s = (np.arange(n) + 0.5) / n
        mu = z0[:, None, None] + (z1 - z0)[:, None, None] * s[None, :, None]  # (r, n, 1)
        dphi = phi0[:, None, None] + (phi1 - phi0)[:, None, None] * s[None, None, :]  # (r, 1, n)
        mu, dphi = np.broadcast_arrays(mu, dphi)
        solid = (z1 - z0) * (phi1 - phi0)
        pmf = np.empty((len(band_grid.nodes), r))
        for b, mu_i in enumerate(band_grid.nodes):
            f = reference(np.full(mu.size, mu_i), mu.ravel(), dphi.ravel()).reshape(mu.shape)
            w = (f * mu).mean(axis=(1, 2)) * solid  # ∫_cell f cos θ_o dω_o (midpoint rule)
            total = w.sum()
            pmf[b] = w / total if total > 0 else solid / solid.sum()  # (cosine-like fallback for a black BRDF)
        cdf = np.cumsum(pmf, axis=1)
        cdf /= cdf[:, -1:]
        # Lower bounds of the bands in μ (band order), for locating the cell of a direction.
        first = np.concatenate([[0], 1 + band_grid.slices * np.arange(band_grid.stacks - 1)])
        return cls(
            band_grid=band_grid,
            cell_z0=z0,
            cell_z1=z1,
            cell_phi0=phi0,
            cell_phi1=phi1,
            cell_projected=0.5 * (z1**2 - z0**2) * (phi1 - phi0),  # W_cell = ∫ cos θ dω
            pmf=pmf,
            cdf=cdf,
            band_z0=z0[first],
        )

    def cell_of(self, mu_o: np.ndarray, dphi: np.ndarray) -> np.ndarray:
        """Index of the cell holding each outgoing direction (μ_o, Δφ in rad, any real)."""
        stacks, slices = self.band_grid.stacks, self.band_grid.slices
        band = np.sum(self.band_z0[None, :] > mu_o[:, None], axis=1)  # bands wholly above μ_o
        band = np.minimum(band, stacks - 1)
        k = np.floor(np.mod(dphi, 2.0 * math.pi) * (slices / (2.0 * math.pi)) + 0.5).astype(np.int64) % slices
        return np.where(band == 0, 0, 1 + (band - 1) * slices + k)

    def pdf(self, wi: np.ndarray, wo: np.ndarray, method: str) -> np.ndarray:
        """Density of `sample`'s outgoing directions, sr⁻¹ (0 where ω_o has z ≤ 0).

        Parameters
        ----------
        wi, wo : numpy.ndarray, shape (N, 3)
            Unit directions towards the light and the viewer, row by row.
        method : {'brdf', 'cosine'}
        """
        mu_o = wo[:, 2]
        cosine = np.clip(mu_o, 0.0, None) / math.pi
        if method == "cosine":
            return cosine
        b0, b1, t = self.band_grid.bracket(wi[:, 2])
        dphi = np.arctan2(wo[:, 1], wo[:, 0]) - np.arctan2(wi[:, 1], wi[:, 0])
        cell = self.cell_of(mu_o, dphi)
        tab = ((1 - t) * self.pmf[b0, cell] + t * self.pmf[b1, cell]) * mu_o / self.cell_projected[cell]
        eps = DEFENSIVE_COSINE_SHARE
        return np.where(mu_o > 0, eps * cosine + (1 - eps) * tab, 0.0)

    def sample(self, wi: np.ndarray, u1: np.ndarray, u2: np.ndarray, method: str) -> np.ndarray:
        """Outgoing unit directions (N, 3), z > 0, for unit incoming ones (N, 3) and uniform
        numbers u1, u2 (N,) in [0, 1): cosine-weighted, or the mixture of the module docstring."""
        n = wi.shape[0]
        phi_i = np.arctan2(wi[:, 1], wi[:, 0])
        mu_o = np.empty(n)
        phi_o = np.empty(n)
        if method == "cosine":
            cos_branch = np.ones(n, dtype=bool)
            v1 = u1
        else:
            eps = DEFENSIVE_COSINE_SHARE
            cos_branch = u1 < eps
            v1 = np.where(cos_branch, u1 / eps, (u1 - eps) / (1 - eps))
        # Cosine-weighted hemisphere (Malley): μ = √(1 − u), φ = φ_i + 2π u₂, pdf = μ/π (azimuths are
        # drawn relative to the incident one, so that sampling commutes with rotations about z).
        c = cos_branch
        mu_o[c] = np.sqrt(1.0 - v1[c])
        phi_o[c] = phi_i[c] + 2.0 * math.pi * u2[c]
        t_rows = ~c
        if t_rows.any():
            v = v1[t_rows]
            b0, b1, t = self.band_grid.bracket(wi[t_rows, 2])
            first = v < (1 - t)
            row = np.where(first, b0, b1)
            with np.errstate(divide="ignore", invalid="ignore"):
                v = np.where(first, v / (1 - t), (v - (1 - t)) / t)
            v = np.clip(v, 0.0, np.nextafter(1.0, 0.0))
            cell = np.empty(v.size, dtype=np.int64)
            for b in np.unique(row):
                m = row == b
                j = np.searchsorted(self.cdf[b], v[m], side="right")
                cell[m] = np.minimum(j, np.flatnonzero(self.pmf[b] > 0)[-1])
            lo = np.where(cell > 0, self.cdf[row, np.maximum(cell - 1, 0)], 0.0)
            width = self.cdf[row, cell] - lo
            with np.errstate(divide="ignore", invalid="ignore"):
                within = np.clip(np.where(width > 0, (v - lo) / width, 0.5), 0.0, 1.0)
            z0, z1 = self.cell_z0[cell], self.cell_z1[cell]
            mu_o[t_rows] = np.sqrt(z0**2 + within * (z1**2 - z0**2))  # density ∝ μ within the cell
            ph0, ph1 = self.cell_phi0[cell], self.cell_phi1[cell]
            phi_o[t_rows] = phi_i[t_rows] + ph0 + u2[t_rows] * (ph1 - ph0)
        mu_o = np.clip(mu_o, np.finfo(float).tiny, 1.0)
        sin_o = np.sqrt(np.maximum(0.0, 1.0 - mu_o**2))
        return np.stack([sin_o * np.cos(phi_o), sin_o * np.sin(phi_o), mu_o], axis=1)
