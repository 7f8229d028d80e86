"""The mesh of the spatial predictor: nodes over a chosen subset of the sample parameters
(paper §3.2, §3.2.3).

Public objects
--------------
Mesh
    Nodes x_1 … x_n over d chosen `SandSample` parameters (the *mesh parameters*), the fixed
    values of all the others (the *base* sample), and the affine (barycentric) combination
    x = Σ α_i x_i of any point inside the mesh (paper eq. 6).

Simplices
---------
Segments in 1-D, the Delaunay triangulation of the nodes in N-D, each parameter's node range
mapped onto [0, 1] (`sandlight.spatial.simplices`).

Properties (tested): the weights are non-negative and sum to 1 inside the mesh; at a node the
weight is exactly 1 on that node (the node is detected and snapped, not left to rounding); a point
outside the mesh's convex hull raises `ParameterError` naming the parameters, the point and the
node ranges.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from sandlight.errors import ParameterError
from sandlight.spatial.simplices import Simplices

if TYPE_CHECKING:
    from sandlight.sample import SandSample

__all__ = ["Mesh"]


def _float_parameters() -> dict:
    from sandlight.sample import PARAMETERS

    return {p.name: p for p in PARAMETERS if p.kind == "float"}


def _base_dict(base: SandSample | str | Mapping | None) -> dict:
    from sandlight.sample import SandSample

    if base is None:
        return SandSample().to_dict()
    if isinstance(base, str):
        return SandSample.preset(base).to_dict()
    if isinstance(base, SandSample):
        return base.to_dict()
    if isinstance(base, Mapping):
        return SandSample.from_dict(base).to_dict()
    raise ParameterError("base", type(base).__name__, "a SandSample, a preset name or a dict of parameters")


@dataclass(frozen=True, eq=False)
class Mesh:
    """Nodes over a subset of the sample parameters.

    Parameters
    ----------
    parameters : sequence of str
        The d mesh parameters: float parameters of `SandSample` (e.g. ``("saturation",)``).
    nodes : array_like, shape (n, d)
        Node coordinates in the parameters' units, distinct; n ≥ d + 1 and, for d ≥ 2, not all
        in one hyperplane.
    base : SandSample, str, dict or None
        The sample that gives every other parameter (default: ``SandSample()``, the default
        mineralogy). If the mesh varies ``silt`` or ``clay`` but not ``sand``, each node's sand
        is 1 − silt − clay.

    Examples
    --------
    >>> mesh = Mesh.grid(saturation=np.linspace(0, 1, 16))     # the paper's beach scene
    >>> mesh.n_nodes, mesh.parameters
    (16, ('saturation',))
    >>> idx, w = mesh.locate([[0.5]])
    >>> w.sum()
    1.0
    """

    parameters: tuple
    nodes: np.ndarray
    base: dict = field(default=None)

    def __post_init__(self):
        params = tuple(str(p) for p in (self.parameters if not isinstance(self.parameters, str) else [self.parameters]))
        known = _float_parameters()
        if not params:
            raise ParameterError("parameters", params, "at least one float parameter of SandSample")
        for p in params:
            if p not in known:
                raise ParameterError("parameters", p, f"float parameters of SandSample: {sorted(known)}")
        if len(set(params)) != len(params):
            raise ParameterError("parameters", params, "distinct names")
        nodes = np.array(self.nodes, dtype=float)
        if nodes.ndim == 1 and len(params) == 1:
            nodes = nodes[:, None]
        d = len(params)
        if nodes.ndim != 2 or nodes.shape[1] != d:
            raise ParameterError(
                "nodes", f"an array of shape {nodes.shape}", f"must have shape (n, {d}), one column per parameter"
            )
        if not np.isfinite(nodes).all():
            raise ParameterError("nodes", nodes[~np.isfinite(nodes).all(axis=1)][0].tolist(), "finite coordinates")
        if nodes.shape[0] < d + 1:
            raise ParameterError(
                "nodes", f"{nodes.shape[0]} nodes", f"at least d + 1 = {d + 1} nodes for {d} parameter(s)"
            )
        if len(np.unique(nodes, axis=0)) != len(nodes):
            raise ParameterError("nodes", "duplicate nodes", "distinct nodes")
        for j, p in enumerate(params):
            spec = known[p]
            col = nodes[:, j]
            low_ok = col > spec.low if spec.low_open else col >= spec.low
            if not (low_ok & (col <= spec.high)).all():
                bad = col[~(low_ok & (col <= spec.high))][0]
                raise ParameterError(p, float(bad), f"node values inside the parameter's domain: {spec.allowed}")
        nodes.setflags(write=False)
        object.__setattr__(self, "parameters", params)
        object.__setattr__(self, "nodes", nodes)
        base = _base_dict(self.base)
        object.__setattr__(self, "base", base)
        self._simplices  # noqa: B018 - build now: a degenerate node set is refused at construction
        self.samples()  # every node must be a valid SandSample

    # ---- construction ----------------------------------------------------------------------
    @classmethod
    def grid(cls, base: SandSample | str | Mapping | None = None, **axes: ArrayLike) -> Mesh:
        """A mesh on the Cartesian product of per-parameter node values.

        Parameters
        ----------
        base : SandSample, str, dict or None
            Sample giving the other parameters (default ``SandSample()``).
        **axes : sequence of float
            Node values of each mesh parameter, e.g. ``saturation=np.linspace(0, 1, 16)``.
        """
        if not axes:
            raise ParameterError("axes", {}, "at least one parameter=values")
        names = list(axes)
        values = []
        for name in names:
            v = np.atleast_1d(np.asarray(axes[name], dtype=float))
            if v.ndim != 1 or v.size < 2:
                raise ParameterError(name, axes[name], "at least two node values")
            values.append(v)
        mesh = np.stack([g.ravel() for g in np.meshgrid(*values, indexing="ij")], axis=1)
        return cls(tuple(names), mesh, base)

    @classmethod
    def beach(cls, n: int = 16, base: SandSample | str | Mapping | None = None) -> Mesh:
        """The paper's beach-scene mesh: ``n`` degrees of saturation evenly spaced over [0, 1]."""
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 2:
            raise ParameterError("n", n, "an integer >= 2")
        return cls.grid(base, saturation=np.linspace(0.0, 1.0, int(n)))

    # ---- properties ------------------------------------------------------------------------
    @property
    def n_nodes(self) -> int:
        return self.nodes.shape[0]

    @property
    def dimension(self) -> int:
        return self.nodes.shape[1]

    @property
    def lower(self) -> np.ndarray:
        return self.nodes.min(axis=0)

    @property
    def upper(self) -> np.ndarray:
        return self.nodes.max(axis=0)

    def _ranges(self) -> str:
        return ", ".join(f"{p} in [{lo:g}, {hi:g}]" for p, lo, hi in zip(self.parameters, self.lower, self.upper))

    def sample_dict(self, point: ArrayLike) -> dict:
        """Parameters of the sample at ``point`` (d,): the base with the mesh parameters set."""
        values = dict(self.base)
        values.update({p: float(v) for p, v in zip(self.parameters, np.asarray(point, dtype=float))})
        if {"silt", "clay"} & set(self.parameters) and "sand" not in self.parameters:
            values["sand"] = 1.0 - values["silt"] - values["clay"]
        return values

    def samples(self) -> list:
        """The node samples (`SandSample`), in node order."""
        from sandlight.sample import SandSample

        return [SandSample.from_dict(self.sample_dict(x)) for x in self.nodes]

    def coordinates(self, samples: SandSample | Mapping | Sequence | ArrayLike) -> np.ndarray:
        """Mesh coordinates (k, d) of samples.

        Parameters
        ----------
        samples : SandSample, dict, or a sequence of them, or array_like (k, d) / (d,)
            Samples (their mesh parameters are read) or coordinates directly.
        """
        from sandlight.sample import SandSample

        if isinstance(samples, (SandSample, Mapping)):
            samples = [samples]
        if isinstance(samples, Sequence) and samples and isinstance(samples[0], (SandSample, Mapping)):
            rows = []
            for s in samples:
                d = s.to_dict() if isinstance(s, SandSample) else s
                missing = [p for p in self.parameters if p not in d]
                if missing:
                    raise ParameterError(missing[0], None, f"a value for every mesh parameter {self.parameters}")
                rows.append([float(d[p]) for p in self.parameters])
            return np.array(rows, dtype=float)
        x = np.asarray(samples, dtype=float)
        if x.ndim == 1 and x.shape[0] == self.dimension:
            x = x[None, :]
        if x.ndim != 2 or x.shape[1] != self.dimension:
            raise ParameterError(
                "points", f"an array of shape {x.shape}", f"shape (k, {self.dimension}) in the order {self.parameters}"
            )
        return x

    def differing_parameters(self, sample: SandSample | Mapping) -> dict:
        """Parameters (other than the mesh's) in which ``sample`` differs from the base, as
        ``{name: (sample value, base value)}``."""
        from sandlight.sample import SandSample

        d = sample.to_dict() if isinstance(sample, SandSample) else dict(sample)
        out = {}
        derived = {"sand"} if {"silt", "clay"} & set(self.parameters) else set()
        for k, v in self.base.items():
            if k in self.parameters or k in derived or k not in d:
                continue
            w = d[k]
            same = (
                (v == w)
                if isinstance(v, str) or isinstance(w, str)
                else ((math.isinf(v) and v == w) or math.isclose(float(v), float(w), rel_tol=1e-9, abs_tol=1e-12))
            )
            if not same:
                out[k] = (w, v)
        return out

    # ---- barycentric location --------------------------------------------------------------
    @functools.cached_property
    def _simplices(self) -> Simplices:
        return Simplices(self.nodes)

    def contains(self, points: SandSample | Mapping | Sequence | ArrayLike) -> np.ndarray:
        """Whether each point (samples or coordinates, see `coordinates`) lies in the mesh: in
        its range (1-D) or in the convex hull of its nodes, within `locate`'s tolerance.
        Returns a boolean array (k,); NaN coordinates are outside."""
        return self._simplices.inside(self.coordinates(points))

    def locate(self, points: SandSample | Mapping | Sequence | ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """Simplex vertices and barycentric weights of points inside the mesh (paper eq. 6).

        Parameters
        ----------
        points : array_like, shape (k, d), or samples (see `coordinates`)

        Returns
        -------
        indices : numpy.ndarray of int64, shape (k, d + 1)
            Node indices of the simplex holding each point.
        weights : numpy.ndarray, shape (k, d + 1)
            α ≥ 0 with Σ α = 1 and Σ α_i x_i = x; exactly one-hot at a node.

        Raises
        ------
        ParameterError
            A point outside the mesh (its convex hull), or NaN.
        """
        return self._simplices.locate(self.checked_coordinates(points))

    def checked_coordinates(self, points: SandSample | Mapping | Sequence | ArrayLike) -> np.ndarray:
        """`coordinates` of points that must lie in the mesh, shape (k, d).

        Raises
        ------
        ParameterError
            A point outside the mesh (its convex hull), or NaN.
        """
        x = self.coordinates(points)
        if not np.isfinite(x).all():
            raise ParameterError(",".join(self.parameters), x[~np.isfinite(x).all(axis=1)][0].tolist(), "finite values")
        outside = ~self._simplices.inside(x)
        if outside.any():
            raise self._outside(x[np.argmax(outside)])
        return x

    def _outside(self, x_row: ArrayLike) -> ParameterError:
        point = dict(zip(self.parameters, (float(v) for v in x_row)))
        name = self.parameters[0] if self.dimension == 1 else ", ".join(self.parameters)
        value = point[name] if self.dimension == 1 else point
        return ParameterError(
            name,
            value,
            f"a point inside the spatial model's mesh ({self._ranges()}"
            f"{'' if self.dimension == 1 else ', within the convex hull of the nodes'})",
        )

    # ---- (de)serialisation -----------------------------------------------------------------
    def to_dict(self) -> dict:
        """JSON-able description (parameters, nodes, base)."""
        return {"parameters": list(self.parameters), "nodes": self.nodes.tolist(), "base": dict(self.base)}

    @classmethod
    def from_dict(cls, d: Mapping) -> Mesh:
        return cls(tuple(d["parameters"]), np.asarray(d["nodes"], dtype=float), d["base"])

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Mesh):
            return NotImplemented
        return (
            self.parameters == other.parameters and np.array_equal(self.nodes, other.nodes) and self.base == other.base
        )

    __hash__ = None

    def __repr__(self) -> str:
        return f"Mesh({self.n_nodes} nodes over {', '.join(self.parameters)}: {self._ranges()})"
