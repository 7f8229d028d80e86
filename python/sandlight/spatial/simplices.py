"""Barycentric location of points among scattered nodes (paper eq. 6), in any coordinates.

`Mesh` locates samples by their mesh parameters with it; a `SpatialModel` that interpolates in
other coordinates (the log normal reflectance in place of the absorbers, docs/spatial-predictor.md,
"Interpolation coordinates") builds its own over the same nodes.

- **1-D**: the nodes sorted along the axis; the simplices are the segments between neighbours and
  the weights those of linear interpolation.
- **N-D**: the Delaunay triangulation (scipy.spatial.Delaunay, Qhull) of the nodes after mapping
  each coordinate's node range linearly onto [0, 1], so that units do not distort the
  triangulation. An affine map does not change barycentric weights, so the weights satisfy
  x = Σ α_i x_i in the coordinates' own units. On a regular grid Delaunay is not unique (four
  co-circular points per square); Qhull's deterministic choice is used.

Inside the nodes' convex hull the weights are non-negative and sum to 1, and at a node they are
exactly one-hot (the node is detected and snapped, not left to rounding).
"""

from __future__ import annotations

import functools

import numpy as np
from numpy.typing import ArrayLike

from sandlight.errors import ParameterError

__all__ = ["Simplices", "NODE_TOLERANCE"]

#: Distance (in the unit-box coordinates) within which a point counts as a node or as on the
#: hull: rounding of values read back from files, not a modelling tolerance.
NODE_TOLERANCE = 1e-12


class Simplices:
    """The simplices of ``nodes`` (n, d): distinct, finite, n ≥ d + 1 and, for d ≥ 2, not all in
    one hyperplane (refused with `ParameterError` naming ``nodes``)."""

    def __init__(self, nodes: ArrayLike) -> None:
        self.nodes = np.asarray(nodes, dtype=float)
        self.lower = self.nodes.min(axis=0)
        self.upper = self.nodes.max(axis=0)
        if self.nodes.shape[1] >= 2:
            self._delaunay  # noqa: B018 - build now: a degenerate node set is refused at construction

    @property
    def dimension(self) -> int:
        return self.nodes.shape[1]

    def unit(self, x: np.ndarray) -> np.ndarray:
        """Coordinates mapped so that the nodes span [0, 1] on every axis."""
        return (x - self.lower) / (self.upper - self.lower)

    @functools.cached_property
    def _delaunay(self):
        from scipy.spatial import Delaunay, QhullError

        try:
            return Delaunay(self.unit(self.nodes))
        except QhullError as exc:
            raise ParameterError(
                "nodes",
                f"{len(self.nodes)} nodes in {self.dimension}-D",
                f"nodes spanning all {self.dimension} dimensions (not all in one hyperplane): "
                f"{str(exc).splitlines()[0]}",
            ) from None

    def inside(self, x: ArrayLike) -> np.ndarray:
        """Whether each point (k, d) lies in the nodes' range (1-D) or convex hull, within
        `NODE_TOLERANCE`; NaN is outside. Boolean array (k,)."""
        x = np.asarray(x, dtype=float)
        finite = np.isfinite(x).all(axis=1)
        u = self.unit(np.where(finite[:, None], x, self.lower))
        if self.dimension == 1:
            return finite & (u[:, 0] >= -NODE_TOLERANCE) & (u[:, 0] <= 1.0 + NODE_TOLERANCE)
        return finite & (self._delaunay.find_simplex(u, tol=NODE_TOLERANCE) >= 0)

    def locate(self, x: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """Simplex vertices (k, d + 1) and barycentric weights (k, d + 1) of points (k, d), which
        must lie `inside` (the caller checks, and words its own error)."""
        x = np.asarray(x, dtype=float)
        idx, w = self._locate_1d(x[:, 0]) if self.dimension == 1 else self._locate_nd(x)
        # Snap to nodes: a point within rounding of one of its simplex's vertices gets weight 1
        # there, so that interpolation is exact at the nodes (not merely to 1e-16).
        u = self.unit(x)
        vert = self.unit(self.nodes)[idx]  # (k, d + 1, d)
        hit = np.all(np.abs(vert - u[:, None, :]) <= NODE_TOLERANCE, axis=2)
        rows = hit.any(axis=1)
        if rows.any():
            first = np.argmax(hit[rows], axis=1)
            w[rows] = 0.0
            w[np.flatnonzero(rows), first] = 1.0
        return idx, w

    def _locate_1d(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        order = np.argsort(self.nodes[:, 0])
        xs = self.nodes[order, 0]
        xc = np.clip(x, xs[0], xs[-1])
        j = np.clip(np.searchsorted(xs, xc, side="right") - 1, 0, len(xs) - 2)
        t = (xc - xs[j]) / (xs[j + 1] - xs[j])
        idx = np.stack([order[j], order[j + 1]], axis=1).astype(np.int64)
        w = np.stack([1.0 - t, t], axis=1)
        return idx, w

    def _locate_nd(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        tri = self._delaunay
        u = self.unit(x)
        simplex = tri.find_simplex(u, tol=NODE_TOLERANCE)
        d = self.dimension
        T = tri.transform[simplex]  # (k, d + 1, d): inverse affine map and offset
        b = np.einsum("kij,kj->ki", T[:, :d, :], u - T[:, d, :])
        w = np.concatenate([b, 1.0 - b.sum(axis=1, keepdims=True)], axis=1)
        # Points on a face give weights of -1e-16 by rounding: clip and renormalise.
        w = np.clip(w, 0.0, None)
        w /= w.sum(axis=1, keepdims=True)
        return tri.simplices[simplex].astype(np.int64), w
