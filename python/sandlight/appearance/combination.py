"""The spectral × spatial combination: f(ω_i, ω_o, λ) from r(λ) and the normalised BRDF f̂.

Public objects
--------------
COMBINATIONS
    The names accepted: ``"energy"`` (default) and ``"product"`` (the paper's formula).
Combination
    The per-wavelength weights (a, b) of f = a f̂ + b P(μ_i) P(μ_o), the diffuse profile P and the
    reference reflectance r_0.
check_combination
    Refuse an unknown combination name.
measured_reflectance
    r_0 of the spatial measurements at the sample's mesh position.

With A(μ) = ∫ f̂(ω_i, ω_o) cos θ_o dω_o the normalised albedo of the spatial part (A(1) = 1) and
r_0 the reflectance at normal incidence of the spatial model's measurements at the sample's mesh
position (barycentric interpolation of the node values, at the measurement wavelength):

- ``combination="product"`` — the paper's §3.3 formula, f = r(λ) · f̂. Its albedo is r(λ)·A(μ). The
  measured A(μ) of dark sand rises steeply towards grazing incidence (surface reflection
  dominates there: 3.7 at μ ≈ 0.02 for the dry default sample, 25 for the saturated one, whose
  water surfaces reflect most grazing light), so for any r(λ) above r_0 the product can reflect
  more light than arrives: it is not energy-conserving.
- ``combination="energy"`` (default) — equal to the product wherever r(λ) ≤ r_0 (darker than, or
  as dark as, the measured sand); for brighter wavelengths the extra reflectance is added as a
  diffuse, reciprocal term shaped by what the measured sand absorbs:

      f = r_0 f̂ + (r − r_0)/(1 − r_0) · D(μ_i) D(μ_o) / N,   D(μ) = 1 − r_0 A(μ),
      N = 2π ∫_0^1 D(μ) μ dμ.

  Its albedo is r_0 A(μ) + (r − r_0)/(1 − r_0)·D(μ): exactly r at normal incidence (the spectral
  prediction), at most 1 at every incidence (it is 1 − (1 − r)/(1 − r_0)·D(μ), D ≥ 0), and 1
  everywhere in the non-absorbing limit r → 1, as for a semi-infinite non-absorbing medium. The
  shape D(μ_i)D(μ_o) is that of light multiply scattered in a half-space (for isotropic
  scatterers the absorptance 1 − ρ(μ) is proportional to Chandrasekhar's H(μ), the angular
  profile of the diffusely emerging light). This is sandlight's addition; the paper does not
  discuss energy conservation.

A guard keeps r_0 ≤ 1/max A (the measured sand's own albedo r_0 A(μ) ≤ 1, violated only by noise).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from sandlight.appearance.band_grid import BandGrid
from sandlight.errors import ParameterError

if TYPE_CHECKING:
    from sandlight.spatial.model import SpatialBRDF, SpatialModel

__all__ = ["COMBINATIONS", "Combination", "check_combination", "measured_reflectance"]

COMBINATIONS = ("energy", "product")


def check_combination(method: str) -> str:
    """``method`` if it is one of `COMBINATIONS`, else `ParameterError` naming ``combination``."""
    if method not in COMBINATIONS:
        raise ParameterError("combination", method, f"one of {COMBINATIONS}")
    return method


def measured_reflectance(spatial_model: SpatialModel, spatial: SpatialBRDF) -> float:
    """r_0: the spatial model's measured reflectance at normal incidence at the sample's mesh
    position (barycentric interpolation of the node values, dimensionless, at the model's
    measurement wavelength)."""
    return float(np.dot(spatial.weights, spatial_model.node_normal_reflectance_[spatial.nodes]))


@dataclass(frozen=True, eq=False)
class Combination:
    """f = a(λ) f̂ + b(λ) P(μ_i) P(μ_o) (module docstring).

    Attributes
    ----------
    method : {'energy', 'product'}
    reference_reflectance : float
        r_0 after the guard r_0 ≤ 1/max A.
    profile : numpy.ndarray, shape (n,)
        P = D/√N at the band grid's μ nodes, sr^-1/2 (zero for 'product').
    profile_albedo_nodes : numpy.ndarray, shape (n,)
        ∫ P(μ_i) P(μ_o) cos θ_o dω_o at the nodes (the diffuse term's albedo per unit b).
    """

    method: str
    reference_reflectance: float
    profile: np.ndarray
    profile_albedo_nodes: np.ndarray

    @classmethod
    def build(cls, method: str, band_grid: BandGrid, reflectance: float) -> Combination:
        """The combination ``method`` for the spatial part ``band_grid`` measured with reflectance
        r_0 = ``reflectance`` at normal incidence.

        Raises
        ------
        ParameterError
            ``method`` is not one of `COMBINATIONS`.
        """
        check_combination(method)
        r0 = float(min(reflectance, 1.0 / band_grid.albedo_nodes.max()))
        if method == "energy":
            d = np.clip(1.0 - r0 * band_grid.albedo_nodes, 0.0, None)
            norm = 2.0 * math.pi * float(d @ band_grid.mu_weights)
            profile = d / math.sqrt(norm) if norm > 0 else np.zeros_like(d)
        else:
            profile = np.zeros(len(band_grid.nodes))
        profile = np.ascontiguousarray(profile)
        # ∫ P(μ_i)P(μ_o) cos θ_o dω_o = P(μ_i) · 2π Σ c_q P_q.
        profile_albedo = profile * (2.0 * math.pi * float(profile @ band_grid.mu_weights))
        return cls(method, r0, profile, profile_albedo)

    def weights(self, r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Per-wavelength weights (a, b) of f = a f̂ + b P P for reflectances r (dimensionless)."""
        if self.method == "product":
            return r, np.zeros_like(r)
        r0 = self.reference_reflectance
        bright = r > r0
        a = np.where(bright, r0, r)
        b = np.where(bright, (r - r0) / (1.0 - r0) if r0 < 1 else 0.0, 0.0)
        return a, b

    def albedo_parts(self, band_grid: BandGrid, mu: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Albedo per unit weight of the two terms at incidence cosines μ (N,): A(μ) of f̂ and
        ∫ P(μ)P(μ_o) cos θ_o dω_o, each (N,); the albedo of f is a·A + b·(the second).

        Both are linear in the interpolant's μ_i weights, so their node values interpolate
        exactly. No horizon test: μ ≤ 0 gives the limit μ → 0⁺.
        """
        return band_grid.at_mu(band_grid.albedo_nodes, mu), band_grid.at_mu(self.profile_albedo_nodes, mu)
