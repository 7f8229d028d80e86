"""The spatial predictor: the normalised BRDF of a sample from its mesh position (paper §3.2).

Given the BRDFs measured at the nodes x_i of a `Mesh` (each reduced, normalised to unit
reflectance at normal incidence and compressed to the m unique values of its classes of
isotropy and reciprocity, paper §3.2.1):

1. **PCA (§3.2.2).** The n compressed BRDFs f_i (rows of an n × m matrix) are centred on their
   mean f̄, each value is divided by a scale s_j, and the result is decomposed by SVD. The
   paper's PCA is unscaled (``scaling="none"``). sandlight's engine, however, gives sand whose
   pores reach the surface filled with water flat mirror-like water surfaces (docs/transport.md),
   and their specular reflection puts a few values near the grazing mirror direction at up to
   10⁵ sr⁻¹ against a median of 0.3 sr⁻¹: unscaled, the variance is all in those few values and
   the first component describes only them. The default ``scaling="relative"`` divides by the
   mean BRDF (s_j = |f̄_j|), so that the PCA sees relative changes of every value alike;
   ``"noise"`` divides by each value's RMS standard error (noise-whitened PCA). Either way the
   scale floors at 10⁻³ of its median. The first ℓ principal directions v_1 … v_ℓ (rows of
   ``components_``) are kept, ℓ the smallest number whose cumulative *signal* variance reaches
   ``variance_threshold``: the Monte Carlo noise variance of each direction, Σ_j σ_j²/(n − 1)
   from the measured standard errors (m ≫ n: noise spreads evenly over the n − 1 directions the
   nodes span), is subtracted first, so that noise does not inflate ℓ. Node scores
   f̃_i = V_ℓ ((f_i − f̄)/s).
2. **Interpolation (§3.2.3, eqs. 6–7).** A new sample's mesh coordinates x are written as an
   affine combination x = Σ α_i x_i of the vertices of the simplex holding it (`Mesh.locate`)
   and its scores are f̃ = Σ α_i f̃_i. Exact at the nodes. With ``absorbers`` the location runs
   in other coordinates (sandlight's departure, docs/spatial-predictor.md, "Interpolation
   coordinates"): those parameters are replaced by log r₀, the sample's normal-incidence
   reflectance at the model's wavelength, since the BRDF's shape follows the albedo, which is far
   from linear in them; ``log_parameters`` are located in their logarithm.
3. **Reconstruction (§3.2.2 eq. 5, §3.2.4).** f = f̄ + s ⊙ (V_ℓᵀ f̃) (the paper's eq. 5 leaves the
   mean implicit), expanded to the r × r patch pairs and interpolated continuously over the
   hemisphere by the goniophotometer's interpolant (`sandlight.gonio.brdf.band_grid_f`).

Every node BRDF satisfies Σ_k ω_p(k) f[cap, k] = 1; this linear constraint holds for the mean
and vanishes on the centred (and scaled) data, hence on the principal directions, so every
reconstruction is normalised too (to rounding).

Public objects
--------------
SpatialModel
    The estimator (scikit-learn conventions: hyper-parameters in ``__init__``, learned attributes
    ending in ``_``), with ``fit``, ``scores``, ``predict``, ``brdf``, ``save`` and ``load``.
SpatialBRDF
    A predicted normalised BRDF: unique values, full array and the continuous f(ω_i, ω_o).
SpatialApproximationWarning
    A sample differs from the mesh's base sample in a parameter the mesh does not vary.
default_model, default_model_path
    The model shipped in the package (``sandlight/data/models/spatial-beach.npz``).
"""

from __future__ import annotations

import functools
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from numbers import Integral, Real
from pathlib import Path
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from sandlight.checks import Interval, Names, StrOptions
from sandlight.errors import ModelFileError, ParameterError
from sandlight.gonio.brdf import MeasuredBRDF, band_grid, band_grid_f
from sandlight.gonio.hemisphere import CollectorHemisphere
from sandlight.gonio.symmetry import EquivalenceClasses, PatchClasses
from sandlight.predictor.estimator import Estimator
from sandlight.predictor.model_file import ModelFileFormat, jsonable
from sandlight.predictor.pca import n_components_for, principal_directions, signal_variance_ratio, variance_ratio
from sandlight.sample import PARAMETERS
from sandlight.spatial.mesh import Mesh
from sandlight.spatial.simplices import Simplices

__all__ = [
    "SpatialModel",
    "SpatialBRDF",
    "SpatialApproximationWarning",
    "default_model",
    "default_model_path",
    "MODEL_FORMAT",
    "MODEL_FORMAT_VERSION",
]

_ARRAYS = (
    "mean",
    "components",
    "scale",
    "explained_variance_ratio",
    "node_coordinates",
    "node_scores",
    "node_normal_reflectance",
)
MODEL_FILE = ModelFileFormat(
    "sandlight-spatial-model", 1, "spatial model", _ARRAYS, optional=("signal_variance_ratio",), compressed=True
)
MODEL_FORMAT, MODEL_FORMAT_VERSION = MODEL_FILE.name, MODEL_FILE.version
FIXED_POLICIES = ("warn", "ignore", "error")
SCALINGS = ("relative", "none", "noise")
#: Reflectances, log-uniform over a sample's range, at which `SpatialModel.reflectance_anchors`
#: compares the interpolation between anchors with the model's own prediction.
ANCHOR_POINTS = 129
#: Default largest error of that interpolation: 0.2 % of the mean BRDF (RMS over the unique
#: values), a twentieth of the 5 % held-out target of every shipped model (the blended BRDF
#: then stays within 0.7 % of the shape at r(λ) over direction pairs: tests/appearance).
ANCHOR_TOLERANCE = 0.002
#: Names a mesh may vary (float parameters of SandSample).
_FLOAT_PARAMETERS = tuple(p.name for p in PARAMETERS if p.kind == "float")


class SpatialApproximationWarning(UserWarning):
    """A sample differs from the spatial model's base sample in a parameter the mesh does not
    vary: its BRDF shape is taken at its mesh coordinates with the base's other parameters (the
    paper's assumption for its beach scene, §4.2.2)."""


@dataclass(frozen=True, eq=False)
class SpatialBRDF(PatchClasses):
    """A BRDF normalised to unit reflectance at normal incidence, predicted by a `SpatialModel`.

    Attributes
    ----------
    stacks, slices : int
        Collector hemisphere of the model.
    unique_values : numpy.ndarray, shape (m,)
        The m unique values f̂ in sr⁻¹ (read-only).
    coordinates : numpy.ndarray, shape (d,)
        Mesh coordinates of the sample.
    nodes, weights : numpy.ndarray, shape (d + 1,)
        The simplex's node indices and barycentric weights (eq. 6).
    sample : dict
        The sample's parameters (empty when predicted from coordinates).
    """

    stacks: int
    slices: int
    unique_values: np.ndarray
    coordinates: np.ndarray
    nodes: np.ndarray
    weights: np.ndarray
    sample: dict = field(default_factory=dict)

    @property
    def values(self) -> np.ndarray:
        """f̂[i, j] for every (incoming, outgoing) patch pair, (r, r), sr⁻¹."""
        return self.classes.expand(self.unique_values)

    def grid(self) -> np.ndarray:
        """Node values F[b_i, b_o, k] of the continuous BRDF, (stacks, stacks, slices), sr⁻¹."""
        return band_grid(self.hemisphere, self.unique_values)

    def f(self, wi: ArrayLike, wo: ArrayLike) -> np.ndarray:
        """Continuous normalised BRDF f̂(ω_i, ω_o) in sr⁻¹ (`sandlight.gonio.brdf.band_grid_f`).

        Parameters
        ----------
        wi, wo : array_like, shape (..., 3)
            Directions towards the light and the viewer (local frame, z = normal).
        """
        return band_grid_f(self.hemisphere, self.unique_values, wi, wo)


class SpatialModel(Estimator):
    """Normalised-BRDF predictor over a mesh of sample parameters (paper §3.2).

    Parameters
    ----------
    n_components : int, optional
        ℓ, the principal components kept. Default: the smallest ℓ whose cumulative signal
        variance reaches ``variance_threshold`` (paper's beach scene: 3).
    variance_threshold : float
        In (0, 1]; used when ``n_components`` is None.
    scaling : {'relative', 'none', 'noise'}
        What each unique value is divided by before the PCA: the mean node BRDF (relative
        deviations; default), nothing (the paper), or its RMS standard error over the nodes
        (noise-whitened). See the module docstring.
    absorbers : sequence of str
        Mesh parameters that change the BRDF's shape through the sample's albedo alone (e.g.
        iron_oxide, hematite_ratio). The interpolation (eq. 6) then runs in other coordinates:
        these parameters are replaced by one, log r₀, the logarithm of the sample's reflectance
        at normal incidence at the model's wavelength (a node's from its measurement; a new
        sample's as given, else from the shipped spectral predictor). Empty (default): the
        paper's interpolation in the mesh parameters. docs/spatial-predictor.md, "Interpolation
        coordinates".
    log_parameters : sequence of str
        Mesh parameters (not absorbers) interpolated in their logarithm (e.g. grain_size, whose
        effects scale with ln d); positive at every node.

    Attributes
    ----------
    mesh_ : Mesh
        Nodes, mesh parameters and the base sample.
    interpolation_ : Simplices or None
        The nodes in the interpolation coordinates when they are not the mesh's (``absorbers``
        or ``log_parameters`` given), else None.
    stacks_, slices_ : int
        Collector hemisphere of the measurements (m unique values).
    wavelength_nm_ : float or None
        Wavelength of the measurements (the spatial component is assumed independent of it,
        as in the paper's beach scene).
    n_components_ : int
        ℓ.
    mean_ : ndarray (m,)
        Mean node BRDF f̄, sr⁻¹.
    components_ : ndarray (ℓ, m)
        Principal directions times the scale, sr⁻¹ per unit score: f = f̄ + f̃ · components_.
    scale_ : ndarray (m,)
        Scale of each value in the PCA (ones for ``scaling='none'``); components_ / scale_ has
        orthonormal rows.
    explained_variance_ratio_ : ndarray (min(n, m),)
        Share of the nodes' variance along every principal direction.
    signal_variance_ratio_ : ndarray (min(n, m),) or None
        The same after subtracting the Monte Carlo noise variance (when the BRDFs carried
        standard errors); ℓ is chosen on these. Saved in files when present.
    node_scores_ : ndarray (n, ℓ)
        f̃_i of every node.
    node_normal_reflectance_ : ndarray (n,)
        Directional-hemispherical reflectance at normal incidence of every node measurement.
    reconstruction_rms_ : float
        RMS over nodes and unique values of (rank-ℓ reconstruction − measurement) / scale_
        (a fraction of the mean BRDF for 'relative', sr⁻¹ for 'none').
    node_noise_rms_ : float or None
        RMS of the measurements' standard errors / scale_: the reconstruction error expected
        from noise alone when ℓ captures all the signal.
    training_set_ : dict
        How the node BRDFs were measured (rays, seed, wavelength, method, times ...), as given.
    memory_ : str
        Path memory of the engine that measured the nodes (from ``training_set_``): 'none', the
        classic model, unless the training set records another.
    holdout_scores_ : dict or None
        Held-out comparison attached by `sandlight.spatial.training.evaluate`.
    """

    _parameter_constraints: ClassVar[dict[str, list]] = {
        "n_components": [None, Interval(Integral, 1, None)],
        "variance_threshold": [Interval(Real, 0, 1, closed="right")],
        "scaling": [StrOptions(SCALINGS)],
        "absorbers": [Names(_FLOAT_PARAMETERS)],
        "log_parameters": [Names(_FLOAT_PARAMETERS)],
    }
    _model_file = MODEL_FILE

    def __init__(
        self,
        n_components: int | None = None,
        variance_threshold: float = 0.999,
        scaling: str = "relative",
        absorbers: Sequence[str] = (),
        log_parameters: Sequence[str] = (),
    ) -> None:
        self.n_components = n_components
        self.variance_threshold = variance_threshold
        self.scaling = scaling
        self.absorbers = absorbers
        self.log_parameters = log_parameters

    # ---- interpolation coordinates -----------------------------------------------------------
    def _interpolation_simplices(self, mesh: Mesh, node_reflectance: np.ndarray) -> Simplices | None:
        """The nodes in the interpolation coordinates (None: the mesh's own), checked."""
        if not self.absorbers and not self.log_parameters:
            return None
        for name, values in (("absorbers", self.absorbers), ("log_parameters", self.log_parameters)):
            alien = [p for p in values if p not in mesh.parameters]
            if alien:
                raise ParameterError(name, alien[0], f"a parameter the mesh varies: {mesh.parameters}")
        both = set(self.absorbers) & set(self.log_parameters)
        if both:
            raise ParameterError("log_parameters", sorted(both)[0], "a mesh parameter that is not an absorber")
        if self.absorbers and not (np.isfinite(node_reflectance).all() and (node_reflectance > 0).all()):
            raise ParameterError("absorbers", tuple(self.absorbers), "nodes with a positive normal reflectance")
        for p in self.log_parameters:
            if (mesh.nodes[:, mesh.parameters.index(p)] <= 0).any():
                raise ParameterError("log_parameters", p, "a parameter positive at every node")
        return Simplices(self._interpolation_coordinates(mesh.parameters, mesh.nodes, node_reflectance))

    def _interpolation_coordinates(
        self, parameters: Sequence[str], x: np.ndarray, reflectance: np.ndarray | None
    ) -> np.ndarray:
        """Mesh coordinates (k, d) of ``parameters`` and normal reflectances (k,) → the
        interpolation coordinates (k, d'): log r₀ first when there are absorbers."""
        columns = [np.log(reflectance)] if self.absorbers else []
        for j, p in enumerate(parameters):
            if p not in self.absorbers:
                columns.append(np.log(x[:, j]) if p in self.log_parameters else x[:, j])
        return np.stack(columns, axis=1)

    def _scale(self, mean: np.ndarray, stderr: np.ndarray | None) -> np.ndarray:
        """Per-value scale of the PCA (module docstring), floored at 10⁻³ of its median."""
        if self.scaling == "none":
            return np.ones_like(mean)
        if self.scaling == "relative":
            raw = np.abs(mean)
        else:
            if stderr is None:
                raise ParameterError("scaling", "noise", "measurements with finite standard errors")
            raw = np.sqrt(np.mean(stderr**2, axis=0))
        floor = 1e-3 * float(np.median(raw))
        return np.maximum(raw, floor if floor > 0 else 1.0)

    @property
    def n_classes_(self) -> int:
        """m, the number of unique values."""
        return self.mean_.shape[0]

    # ---- fitting -----------------------------------------------------------------------------
    def fit(self, brdfs: Sequence[MeasuredBRDF], mesh: Mesh, *, training_set: Mapping | None = None) -> SpatialModel:
        """Fit the PCA basis to the node BRDFs.

        Parameters
        ----------
        brdfs : sequence of MeasuredBRDF
            One measurement per node of ``mesh``, in node order, on one collector hemisphere.
        mesh : Mesh
        training_set : mapping, optional
            Description of the measurements (kept in ``training_set_`` and in saved files).

        Returns
        -------
        self
        """
        self.validate_params()
        if not isinstance(mesh, Mesh):
            raise ParameterError("mesh", type(mesh).__name__, "a sandlight.spatial.Mesh")
        brdfs = list(brdfs)
        if len(brdfs) != mesh.n_nodes or not all(isinstance(b, MeasuredBRDF) for b in brdfs):
            raise ParameterError("brdfs", f"{len(brdfs)} objects", f"one MeasuredBRDF per mesh node ({mesh.n_nodes})")
        geometry = {(b.stacks, b.slices) for b in brdfs}
        if len(geometry) != 1:
            raise ParameterError("brdfs", sorted(geometry), "measurements on one collector hemisphere (stacks, slices)")
        wavelengths = {b.wavelength_nm for b in brdfs}
        if len(wavelengths) != 1:
            raise ParameterError("brdfs", sorted(wavelengths, key=str), "measurements at one wavelength")
        X = np.stack([b.unique_values for b in brdfs])
        S = np.stack([b.unique_stderr for b in brdfs])
        bad = ~np.isfinite(X).all(axis=1)
        if bad.any():
            raise ParameterError(
                "brdfs",
                f"node {int(np.argmax(bad))} has undefined values (a class saw no incidence or R = 0)",
                "finite normalised BRDFs: measure with more rays",
            )
        stderr = S if np.isfinite(S).all() else None
        n, m = X.shape

        # PCA (§3.2.2) by SVD of the centred node BRDFs, each value divided by its scale (see the
        # module docstring): rows of vt are the principal directions in the scaled space.
        mean = X.mean(axis=0)
        scale = self._scale(mean, stderr)
        G = (X - mean) / scale
        variance, vt = principal_directions(G)
        ratio = variance_ratio(variance)
        signal_ratio = None if stderr is None else signal_variance_ratio(variance, _noise_floor(stderr / scale))
        rank = max(n - 1, 1)  # centred data have rank ≤ n − 1
        if self.n_components is None:
            chosen = ratio if signal_ratio is None else signal_ratio
            k = n_components_for(chosen, self.variance_threshold, rank)
        else:
            k = int(self.n_components)
            if k > rank:
                raise ParameterError("n_components", k, f"<= n_nodes − 1 = {rank}")
        directions = vt[:k]
        scores = G @ directions.T  # f̃_i
        components = directions * scale  # f = f̄ + f̃ (V_ℓ ⊙ scale): eq. 5 with the mean and the scale
        recon = mean + scores @ components

        self.mesh_ = mesh
        self.stacks_, self.slices_ = next(iter(geometry))
        wl = next(iter(wavelengths))
        self.wavelength_nm_ = None if wl is None else float(wl)
        self.n_components_ = k
        self.mean_ = mean
        self.components_ = components
        self.explained_variance_ratio_ = ratio
        self.signal_variance_ratio_ = signal_ratio
        self.node_scores_ = scores
        self.node_normal_reflectance_ = np.array([b.normal_reflectance for b in brdfs])
        self.interpolation_ = self._interpolation_simplices(mesh, self.node_normal_reflectance_)
        self.scale_ = scale
        self.reconstruction_rms_ = float(np.sqrt(np.mean(((recon - X) / scale) ** 2)))
        self.node_noise_rms_ = None if stderr is None else float(np.sqrt(np.mean((stderr / scale) ** 2)))
        self.training_set_ = jsonable(dict(training_set or {}))
        self.holdout_scores_ = None
        return self

    # ---- prediction --------------------------------------------------------------------------
    def _locate(
        self, samples: Any, fixed: str, normal_reflectance: ArrayLike | None = None
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, list | None]:
        if fixed not in FIXED_POLICIES:
            raise ParameterError("fixed", fixed, f"one of {FIXED_POLICIES}")
        from sandlight.sample import SandSample

        many = (
            samples
            if isinstance(samples, Sequence)
            and not isinstance(samples, str)
            and samples
            and isinstance(samples[0], (SandSample, Mapping))
            else None
        )
        if isinstance(samples, (SandSample, Mapping)):
            many = [samples]
        if many is not None and fixed != "ignore":
            for s in many:
                diff = self.mesh_.differing_parameters(s)
                if diff:
                    text = ", ".join(f"{k} = {a!r} (base {b!r})" for k, a, b in ((k, *v) for k, v in diff.items()))
                    message = (
                        f"the spatial model's mesh varies only {', '.join(self.mesh_.parameters)}; this sample "
                        f"differs from its base sample in {text}"
                    )
                    if fixed == "error":
                        name = next(iter(diff))
                        raise ParameterError(
                            name,
                            diff[name][0],
                            f"{diff[name][1]!r}, the value of the spatial model's "
                            f"base sample (pass fixed='warn' or 'ignore' to accept the approximation)",
                        )
                    warnings.warn(
                        message + ": its BRDF shape is taken at its mesh coordinates with the base's other parameters",
                        SpatialApproximationWarning,
                        stacklevel=3,
                    )
        if self.interpolation_ is None:
            x = self.mesh_.coordinates(samples)
            idx, w = self.mesh_.locate(x)
        else:  # inside the mesh, then located among the nodes in the interpolation coordinates
            x = self.mesh_.checked_coordinates(samples)
            r0 = self._normal_reflectance(many, x, normal_reflectance) if self.absorbers else None
            z = self._into_hull(self._interpolation_coordinates(self.mesh_.parameters, x, r0))
            idx, w = self.interpolation_.locate(z)
        return x, idx, w, many

    def _normal_reflectance(self, many: list | None, x: np.ndarray, given: ArrayLike | None) -> np.ndarray:
        """r₀ of each sample at the model's wavelength: ``given``, else the shipped spectral
        predictor's for the samples themselves (or, for bare coordinates, for the mesh's sample
        there)."""
        if given is not None:
            r0 = np.broadcast_to(np.asarray(given, dtype=float), (x.shape[0],))
            if not (np.isfinite(r0).all() and (r0 > 0).all() and (r0 <= 1).all()):
                raise ParameterError("normal_reflectance", given, "reflectances in (0, 1], one per sample")
            return r0
        from sandlight.predictor.prediction import predict

        samples = many if many is not None else [self.mesh_.sample_dict(row) for row in x]
        r0 = predict(samples, [self.r0_wavelength_nm])["reflectance"].values.reshape(len(samples))
        return np.clip(r0, 1e-6, 1.0)

    def _into_hull(self, z: np.ndarray) -> np.ndarray:
        """Points outside the interpolation nodes' hull moved onto it, along the line to the
        nodes' centroid (bisection): a sample inside the mesh whose predicted r₀ lies a little
        beyond the nodes' takes the shape at the nearest r₀ the nodes span."""
        outside = ~self.interpolation_.inside(z)
        if not outside.any():
            return z
        z = z.copy()
        centre = self.interpolation_.nodes.mean(axis=0)
        for i in np.flatnonzero(outside):
            lo, hi = 0.0, 1.0  # fraction of the way from the centre to z: lo inside, hi outside
            for _ in range(60):
                mid = 0.5 * (lo + hi)
                lo, hi = (
                    (mid, hi) if self.interpolation_.inside((centre + mid * (z[i] - centre))[None])[0] else (lo, mid)
                )
            z[i] = centre + lo * (z[i] - centre)
        return z

    def scores(self, samples: Any, *, fixed: str = "warn", normal_reflectance: ArrayLike | None = None) -> np.ndarray:
        """Principal components f̃ = Σ α_i f̃_i of samples (paper eqs. 6–7).

        Parameters
        ----------
        samples : SandSample, dict, sequence of them, or array_like (k, d)
            Samples, or mesh coordinates in the order ``mesh_.parameters``.
        fixed : {'warn', 'ignore', 'error'}
            What to do when a sample differs from the mesh's base sample in a parameter the mesh
            does not vary (`SpatialApproximationWarning`, nothing, or `ParameterError`).
        normal_reflectance : float or array_like (k,), optional
            r₀ of the samples at the model's wavelength, for a model with ``absorbers`` (None:
            the shipped spectral predictor's); ignored otherwise.

        Returns
        -------
        numpy.ndarray, shape (k, ℓ)

        Raises
        ------
        ParameterError
            A sample outside the mesh.
        """
        self.check_is_fitted()
        _, idx, w, _ = self._locate(samples, fixed, normal_reflectance)
        return np.einsum("kv,kvl->kl", w, self.node_scores_[idx])

    def predict(self, samples: Any, *, fixed: str = "warn", normal_reflectance: ArrayLike | None = None) -> np.ndarray:
        """Normalised BRDFs f = f̄ + s ⊙ V_ℓᵀ f̃ as unique values (paper eq. 5), shape (k, m), sr⁻¹.

        Parameters are those of `scores`.
        """
        scores = self.scores(samples, fixed=fixed, normal_reflectance=normal_reflectance)
        return self.mean_ + scores @ self.components_

    def brdf(self, sample: Any, *, fixed: str = "warn", normal_reflectance: float | None = None) -> SpatialBRDF:
        """The predicted BRDF of one sample (or one point of mesh coordinates) as a `SpatialBRDF`
        (``normal_reflectance`` as in `scores`)."""
        self.check_is_fitted()
        x, idx, w, many = self._locate(sample, fixed, normal_reflectance)
        if x.shape[0] != 1:
            raise ParameterError("sample", f"{x.shape[0]} samples", "one sample (use predict for many)")
        unique = self.mean_ + np.einsum("v,vl->l", w[0], self.node_scores_[idx[0]]) @ self.components_
        unique.setflags(write=False)
        sample_dict = {}
        if many is not None:
            s = many[0]
            sample_dict = s.to_dict() if hasattr(s, "to_dict") else dict(s)
        return SpatialBRDF(self.stacks_, self.slices_, unique, x[0], idx[0], w[0], sample_dict)

    def reflectance_anchors(
        self, sample: Any, low: float, high: float, *, tolerance: float = ANCHOR_TOLERANCE
    ) -> np.ndarray:
        """Normal reflectances r_1 < … < r_K over [low, high] between which the prediction for
        ``sample`` may be interpolated linearly in log r₀ (a model with ``absorbers`` only).

        The range is first clipped to the nodes' r₀. The model's own prediction is piecewise
        linear in log r₀ (barycentric weights within each simplex; the hull projection bends it
        outside), so its breaks are where anchors are needed: along `ANCHOR_POINTS` reflectances
        log-uniform over the range, anchors are placed greedily, each as far from the last as
        keeps the linear interpolation between them within ``tolerance`` of the prediction at
        every point in between. The error is measured as ``reconstruction_rms_`` is (RMS over
        the unique values of the difference divided by ``scale_``: for 'relative' scaling a
        fraction of the mean BRDF); since ``components_ / scale_`` has orthonormal rows, it is
        the norm of the scores' difference over √m.

        Parameters
        ----------
        sample : SandSample or dict
            Located as by `brdf`, with ``fixed='ignore'`` (call `brdf` first for the warning).
        low, high : float
            The sample's reflectance range, in (0, 1].
        tolerance : float
            Largest interpolation error between anchors (default `ANCHOR_TOLERANCE`).

        Returns
        -------
        numpy.ndarray (K,)
            Ascending; one value when the clipped range is a point.

        Raises
        ------
        ParameterError
            A model without absorbers, or a range outside (0, 1] or with ``low > high``.
        """
        self.check_is_fitted()
        if not self.absorbers:
            raise ParameterError("spatial_model", "a model without absorbers", "a model that interpolates in log r₀")
        if not (0 < low <= high <= 1):
            raise ParameterError("low, high", (low, high), "reflectances with 0 < low ≤ high ≤ 1")
        nodes = self.node_normal_reflectance_
        lo, hi = np.log(np.clip([low, high], nodes.min(), nodes.max()))
        if hi - lo < 1e-12:
            return np.array([float(np.exp(lo))])
        x = np.linspace(lo, hi, ANCHOR_POINTS)
        scores = self.scores([sample] * x.size, fixed="ignore", normal_reflectance=np.exp(x))
        limit = tolerance * np.sqrt(self.n_classes_)

        def linear(i: int, j: int) -> bool:
            t = (x[i + 1 : j] - x[i]) / (x[j] - x[i])
            between = scores[i] + t[:, None] * (scores[j] - scores[i])
            return bool((np.linalg.norm(between - scores[i + 1 : j], axis=1) <= limit).all())

        anchors, i = [0], 0
        while i < x.size - 1:
            j = i + 1
            while j + 1 < x.size and linear(i, j + 1):
                j += 1
            anchors.append(j)
            i = j
        return np.exp(x[anchors])

    @property
    def r0_wavelength_nm(self) -> float:
        """Wavelength (nm) of the r₀ coordinate: the measurements' (550 nm, the paper's, for a
        model file that does not record it)."""
        return 550.0 if self.wavelength_nm_ is None else self.wavelength_nm_

    # ---- persistence -------------------------------------------------------------------------
    @property
    def memory_(self) -> str:
        return self.training_set_.get("memory", "none")

    def _metadata(self) -> dict:
        return {
            "params": self.get_params(),
            "mesh": {"parameters": list(self.mesh_.parameters), "base": self.mesh_.base},
            "stacks": self.stacks_,
            "slices": self.slices_,
            "wavelength_nm": self.wavelength_nm_,
            "n_components": self.n_components_,
            "reconstruction_rms": self.reconstruction_rms_,
            "node_noise_rms": self.node_noise_rms_,
            "training_set": self.training_set_,
            "holdout_scores": self.holdout_scores_,
            "units": {
                "mean": "sr-1",
                "components": "sr-1 per unit score",
                "scale": "sr-1 (relative, none) or as stderr",
                "node_coordinates": "units of the mesh parameters (SandSample)",
                "node_normal_reflectance": "1",
            },
        }

    def _arrays(self) -> dict[str, np.ndarray]:
        arrays = {
            "mean": self.mean_,
            "components": self.components_,
            "scale": self.scale_,
            "explained_variance_ratio": self.explained_variance_ratio_,
            "node_coordinates": self.mesh_.nodes,
            "node_scores": self.node_scores_,
            "node_normal_reflectance": self.node_normal_reflectance_,
        }
        if self.signal_variance_ratio_ is not None:
            arrays["signal_variance_ratio"] = self.signal_variance_ratio_
        return arrays

    @classmethod
    def _from_parts(cls, meta: Mapping, data: Mapping[str, np.ndarray], path: Path) -> SpatialModel:
        model = cls._params_from_file(meta["params"])
        stacks, slices = int(meta["stacks"]), int(meta["slices"])
        m = EquivalenceClasses(CollectorHemisphere(stacks, slices)).n_classes
        mesh = Mesh(tuple(meta["mesh"]["parameters"]), data["node_coordinates"], meta["mesh"]["base"])
        n, d, k = mesh.n_nodes, mesh.dimension, int(meta["n_components"])
        expected = {
            "mean": (m,),
            "components": (k, m),
            "scale": (m,),
            "node_coordinates": (n, d),
            "node_scores": (n, k),
            "node_normal_reflectance": (n,),
        }
        for name, shape in expected.items():
            if data[name].shape != shape:
                raise ValueError(f"array {name!r} has shape {data[name].shape}, expected {shape}")
        for name in (*_ARRAYS, "signal_variance_ratio"):
            if name not in data:
                continue
            if data[name].dtype.kind != "f":
                raise ValueError(f"array {name!r} has dtype {data[name].dtype}")
            if not np.isfinite(data[name]).all():
                raise ValueError(f"array {name!r} holds NaN or inf")
        model.mesh_ = mesh
        model.stacks_, model.slices_ = stacks, slices
        wl = meta.get("wavelength_nm")
        model.wavelength_nm_ = None if wl is None else float(wl)
        model.n_components_ = k
        model.mean_ = data["mean"]
        model.components_ = data["components"]
        model.scale_ = data["scale"]
        model.explained_variance_ratio_ = data["explained_variance_ratio"]
        model.signal_variance_ratio_ = data.get("signal_variance_ratio")
        model.node_scores_ = data["node_scores"]
        model.node_normal_reflectance_ = data["node_normal_reflectance"]
        model.interpolation_ = model._interpolation_simplices(mesh, model.node_normal_reflectance_)
        model.reconstruction_rms_ = meta.get("reconstruction_rms")
        model.node_noise_rms_ = meta.get("node_noise_rms")
        model.training_set_ = meta.get("training_set") or {}
        model.holdout_scores_ = meta.get("holdout_scores")
        return model


def _noise_floor(stderr: np.ndarray) -> float:
    """Monte Carlo noise variance along each principal direction of the node BRDFs.

    With n node BRDFs of m ≫ n unique values each, independent noise of variances σ_j² does not
    favour any direction of the (n − 1)-dimensional space the centred nodes span: each principal
    direction picks up ≈ Σ_j σ_j² / (n − 1) of noise variance (the centred noise matrix E has
    E Eᵀ ≈ Σ_j σ_j² (I − 11ᵀ/n) when m ≫ n). σ_j² is the mean squared standard error of value j
    over the nodes.
    """
    return float(np.sum(np.mean(stderr**2, axis=0))) / max(stderr.shape[0] - 1, 1)


# ---- the shipped model -------------------------------------------------------------------------
def default_model_path() -> Path:
    """Where the shipped default spatial model lives in the installed package."""
    from importlib.resources import files

    return Path(str(files("sandlight") / "data" / "models" / "spatial-beach.npz"))


@functools.lru_cache(maxsize=1)
def default_model() -> SpatialModel:
    """The spatial model shipped with sandlight: 16 saturations 0–1 at the default mineralogy,
    measured at 550 nm (loaded once, then cached).

    Raises
    ------
    ModelFileError
        The package has no default model (a source checkout before
        ``scripts/data/train_default_spatial.py`` was run).
    """
    path = default_model_path()
    if not path.is_file():
        raise ModelFileError(
            f"the default spatial model is not installed (expected at {path}); train it with "
            f"scripts/data/train_default_spatial.py, or pass a model file"
        )
    return SpatialModel.load(path)
