"""The BRDF's shape over wavelength: one spatial shape, or the shape at the sand's reflectance.

Public objects
--------------
SHAPES
    The names accepted: ``"reflectance"`` (default) and ``"fixed"`` (the paper's assumption).
Shape
    One spatial shape: the spatial model's prediction at one normal reflectance, its band grid
    and its combination with r(λ).
ShapeSeries
    The shapes of an appearance and the per-wavelength weights that blend them.

- ``shape="fixed"``: the paper's §4.2.2 assumption ("the spatial distribution of the BRDF did
  not vary with wavelength"): one shape, the spatial model's at the sample's reflectance at the
  model's measurement wavelength, applied at every wavelength.
- ``shape="reflectance"``: a sand's BRDF shape follows its brightness (for one particle
  geometry, the angular distribution of multiply scattered light is set by the single-scattering
  albedo, of which the normal reflectance r is a monotone function; measured over 350–2500 nm in
  docs/spatial-predictor.md, "How wrong is one shape over 350–2500 nm?"). A spatial model that
  interpolates in log r₀ (``absorbers``: the dune family) is therefore asked for the shape at the
  sand's own r(λ) at every wavelength: f(λ) = r(λ) f̂(r(λ)) (with the energy combination applied
  per shape). Its prediction is piecewise linear in log r₀, so the appearance holds the shapes at
  a few anchors r_1 < … < r_K (`SpatialModel.reflectance_anchors`, from the range of the
  spectral source's r(λ) clipped to the nodes' r₀) and blends the two that bracket log r(λ):

      f̂(r) = (1 − t) f̂_k + t f̂_{k+1},   t = (log r − log r_k)/(log r_{k+1} − log r_k).

  Inside the anchors' range that is the shape of a sand as bright as r, so it is applied as the
  product, f = r f̂(r): the energy combination's diffuse term exists for a shape measured on a
  darker sand. Beyond the range (r below the darkest or above the brightest node, where the shape
  is held at the end anchor) the end shape is combined with r by its own r_0, as a single shape
  is (above the brightest node, `"energy"` adds the diffuse term). At normal incidence the albedo
  is r(λ) either way. The product's albedo r Σ_k w_k A_k(μ) could exceed 1 only where r is close
  to 1/max A; wherever it would, the wavelength takes the blend of the two shapes' own
  combinations instead, f = (1 − t)[a_k f̂_k + b_k P_k P_k] + t[a_{k+1} f̂_{k+1} + b_{k+1} P_{k+1}
  P_{k+1}], each term with albedo r at normal incidence and at most 1 elsewhere. A model without
  absorbers (the beach and wet families: in wet sand the shape is not a function of r₀ alone) has
  one shape either way, combined as before.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from sandlight.appearance.band_grid import BandGrid
from sandlight.appearance.combination import Combination, measured_reflectance
from sandlight.checks import check_choice

if TYPE_CHECKING:
    from sandlight.spatial.model import SpatialBRDF, SpatialModel

__all__ = ["SHAPES", "Shape", "ShapeSeries"]

SHAPES = ("reflectance", "fixed")


@dataclass(frozen=True, eq=False)
class Shape:
    """The spatial model's shape at one normal reflectance, ready to combine with r(λ).

    Attributes
    ----------
    reflectance : float
        r at which the spatial model was asked (its r₀ coordinate; the sample's r at the model's
        wavelength for the fixed shape), dimensionless.
    spatial : SpatialBRDF
        The prediction.
    band_grid : BandGrid
        Its nodes as the BRDF interpolates them.
    combination : Combination
        Its combination with r(λ) (r_0 of the measurements at this position).
    """

    reflectance: float
    spatial: SpatialBRDF
    band_grid: BandGrid
    combination: Combination

    @classmethod
    def predict(cls, model: SpatialModel, sample: Any, reflectance: float, combination: str, fixed: str) -> Shape:
        """The shape of ``sample`` at normal reflectance ``reflectance`` (`SpatialModel.brdf`)."""
        spatial = model.brdf(sample, fixed=fixed, normal_reflectance=max(reflectance, 1e-6))
        grid = BandGrid.from_spatial(spatial)
        terms = Combination.build(combination, grid, measured_reflectance(model, spatial))
        return cls(reflectance, spatial, grid, terms)


@dataclass(frozen=True, eq=False)
class ShapeSeries:
    """Shapes at ascending reflectances and their blend per wavelength (module docstring).

    Attributes
    ----------
    method : {'reflectance', 'fixed'}
    shapes : tuple of Shape
        Ascending in ``reflectance``; one for 'fixed' and for models without absorbers.
    """

    method: str
    shapes: tuple[Shape, ...]

    @classmethod
    def build(
        cls,
        method: str,
        model: SpatialModel,
        sample: Any,
        fixed_shape: Shape,
        reflectance: np.ndarray,
        combination: str,
    ) -> ShapeSeries:
        """The series for ``sample`` whose spectral source gives the reflectances ``reflectance``
        (W,); ``fixed_shape`` is its shape at the model's wavelength (reused when one suffices)."""
        check_choice("shape", method, SHAPES)
        if method == "fixed" or not model.absorbers:
            return cls(method, (fixed_shape,))
        r = np.clip(reflectance, 1e-6, 1.0)
        anchors = model.reflectance_anchors(sample, float(r.min()), float(r.max()))
        shapes = tuple(Shape.predict(model, sample, float(a), combination, "ignore") for a in anchors)
        return cls(method, shapes)

    @property
    def reflectances(self) -> np.ndarray:
        """The shapes' reflectances (K,)."""
        return np.array([s.reflectance for s in self.shapes])

    def blend(self, r: np.ndarray) -> np.ndarray:
        """Blend weights (W, K) of the shapes for reflectances r (W,): linear in log r between the
        bracketing anchors, held beyond them; rows sum to 1."""
        r = np.asarray(r, dtype=float)
        k = len(self.shapes)
        weights = np.zeros((r.size, k))
        if k == 1:
            weights[:, 0] = 1.0
            return weights
        x = np.log(self.reflectances)
        u = np.clip(np.log(np.clip(r, 1e-300, None)), x[0], x[-1])
        j = np.clip(np.searchsorted(x, u, side="right") - 1, 0, k - 2)
        t = (u - x[j]) / (x[j + 1] - x[j])
        rows = np.arange(r.size)
        weights[rows, j] = 1.0 - t
        weights[rows, j + 1] += t
        return weights

    def weights(self, r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Weights (a, b), each (W, K), of f = Σ_k a_k f̂_k + b_k P_k P_k for reflectances r (W,)
        (the module docstring's rule: the product inside the anchors' range where it conserves
        energy, each shape's own combination elsewhere)."""
        r = np.asarray(r, dtype=float)
        blend = self.blend(r)
        a = np.empty_like(blend)
        b = np.empty_like(blend)
        for k, shape in enumerate(self.shapes):
            ak, bk = shape.combination.weights(r)
            a[:, k] = blend[:, k] * ak
            b[:, k] = blend[:, k] * bk
        product = self._product(r, blend)
        a[product] = blend[product] * r[product, None]
        b[product] = 0.0
        return a, b

    def product(self, r: np.ndarray) -> np.ndarray:
        """Which reflectances r (W,) take the blend as the product r f̂ (bool, W): inside the
        anchors' range, where its albedo r Σ_k w_k A_k(μ) stays at most 1 (module docstring)."""
        r = np.asarray(r, dtype=float)
        return self._product(r, self.blend(r))

    def _product(self, r: np.ndarray, blend: np.ndarray) -> np.ndarray:
        """`product` for reflectances r (W,) whose blend weights (W, K) are known."""
        if len(self.shapes) == 1:
            return np.zeros(r.shape, dtype=bool)
        ends = self.reflectances[[0, -1]]
        albedo_nodes = np.stack([s.band_grid.albedo_nodes for s in self.shapes])  # (K, n)
        # The blend's albedo is linear in μ between the nodes: its largest value is at a node.
        return (r > ends[0]) & (r < ends[1]) & (r * (blend @ albedo_nodes).max(axis=1) <= 1.0)

    def albedo(self, mu: np.ndarray, r: np.ndarray) -> np.ndarray:
        """Albedo (N, W) at incidence cosines μ (N,) for reflectances r (W,), exact for the model."""
        a, b = self.weights(r)
        out = np.zeros((np.size(mu), np.size(r)))
        for k, shape in enumerate(self.shapes):
            spatial, diffuse = shape.combination.albedo_parts(shape.band_grid, mu)
            out += spatial[:, None] * a[None, :, k] + diffuse[:, None] * b[None, :, k]
        return out
