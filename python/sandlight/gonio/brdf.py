"""A measured BRDF: counts, reduced values, uncertainties, metadata and the continuous BRDF.

Public objects
--------------
MeasuredBRDF
    The result of the virtual goniophotometer (paper §3.2.1) with its continuous interpolant
    (paper §3.2.4).

The continuous BRDF
-------------------
The reduced values depend only on (incoming band, outgoing band, slice difference), so the
continuous BRDF is built on that grid. Write μ = cos θ and Δφ = φ_o − φ_i.

- **Nodes.** In μ, the cos θ of the patch centroids of each band, μ_b = (z0 + z1)/2, and μ = 1
  for the cap (its centroid is the pole); in Δφ, the centroid azimuth differences 2πk/L,
  k = 0 … L − 1 (L slices). The node value at (b_i, b_o, k) is the reduced value of the class of
  that triple; for the cap it does not depend on k.
- **Interpolation.** Trilinear: piecewise linear in μ_i and in μ_o, periodic piecewise linear in
  Δφ. Below the lowest node (μ < μ_B, the centroid of the lowest band, 0.017 at 31 × 30) the value
  is held constant down to the horizon.
- **Properties, by construction.** *Isotropic*: only Δφ enters. *Reciprocal*: the node values
  satisfy F[b, b', k] = F[b', b, −k], the same linear basis is used for μ_i and μ_o, and linear
  interpolation on the uniform periodic Δφ grid commutes with Δφ → −Δφ, so
  f(ω_i, ω_o) = f(ω_o, ω_i) up to rounding (no symmetrisation step is needed). *Continuous*: a
  tensor product of continuous interpolants; at the pole, the weight of the Δφ-dependent band
  nodes vanishes and the cap nodes do not depend on Δφ, so the value does not depend on the
  (undefined) azimuth there. *Exact at centroids*: f(u_i, u_j) equals the reduced value f[i, j]
  for every pair of patch centroids, up to the rounding of the azimuths (~1e-15 relative).
  *Non-negative*: linear weights are non-negative.
- The interpolant is C⁰, not smooth; it does not extrapolate a trend below the lowest band.
- Directions with z ≤ 0 (below or on the horizon) give 0: the BRDF of a reflecting surface is
  defined on the upper hemisphere only. A direction with a NaN component gives NaN.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from sandlight.errors import ParameterError
from sandlight.gonio.hemisphere import CollectorHemisphere
from sandlight.gonio.reduction import ReducedBRDF, check_sums, reduce_counts
from sandlight.gonio.symmetry import EquivalenceClasses, PatchClasses

__all__ = ["MeasuredBRDF", "band_grid", "band_grid_f", "interpolate_band_grid", "mu_bracket"]


def _version() -> str:
    import sandlight

    return sandlight.__version__


@dataclass(frozen=True, eq=False)
class MeasuredBRDF(PatchClasses):
    """BRDF of a sample measured by the virtual goniophotometer.

    Build it with `MeasuredBRDF.from_counts`; read it with `sandlight.gonio.io.read_netcdf`.

    Attributes
    ----------
    stacks, slices : int
        Geometry of the collector hemisphere (r = 1 + (stacks − 1)·slices patches).
    counts : numpy.ndarray of int64, shape (r, r)
        Raw counts n[i, j] (incoming patch i, outgoing patch j); for a run with shared paths
        (``squares`` not None) the weight sums Σ F of its trials, float64.
    absorbed, launched, lost : numpy.ndarray of int64, shape (r,)
        Raw per-incoming-patch counters; launched = escaped + absorbed + lost (absorbed and
        lost weight sums, float64, for a shared run; launched always counts trials).
    reduced : ReducedBRDF
        Unique values (normalised and absolute), standard errors, normal-incidence reflectance.
    sample : dict
        Parameters of the measured sample (JSON-serialisable).
    wavelength_nm : float or None
        Vacuum wavelength in nm, None if not monochromatic or not applicable.
    rays : int
        Number of trials of the run.
    seed : int or None
        Random seed of the run.
    sandlight_version : str
        Version of sandlight that produced the counts.
    reduction_method : {'average', 'pooled'}
        How the classes were estimated (`sandlight.gonio.reduction.reduce_counts`).
    squares : numpy.ndarray of float64, shape (r, r), or None
        Σ F² per cell of a run with shared paths (spectral path sharing, docs/transport.md),
        which the standard errors need; None for counts of independent trials.
    """

    stacks: int
    slices: int
    counts: np.ndarray
    absorbed: np.ndarray
    launched: np.ndarray
    lost: np.ndarray
    reduced: ReducedBRDF
    sample: dict = field(default_factory=dict)
    wavelength_nm: float | None = None
    rays: int = 0
    seed: int | None = None
    sandlight_version: str = field(default_factory=_version)
    reduction_method: str = "average"
    squares: np.ndarray | None = None

    @classmethod
    def from_counts(
        cls,
        counts: ArrayLike,
        absorbed: ArrayLike,
        launched: ArrayLike,
        lost: ArrayLike | None = None,
        *,
        stacks: int = 31,
        slices: int = 30,
        sample: dict | None = None,
        wavelength_nm: float | None = None,
        rays: int | None = None,
        seed: int | None = None,
        method: str = "average",
        squares: ArrayLike | None = None,
    ) -> MeasuredBRDF:
        """Reduce raw goniophotometer counts (paper §3.2.1) into a `MeasuredBRDF`.

        Parameters
        ----------
        counts : array_like of int, shape (r, r)
            n[i, j] from `BrdfTally.counts` (row-major incoming × outgoing).
        absorbed, launched : array_like of int, shape (r,)
            Per incoming patch: absorbed trials and all trials N_i.
        lost : array_like of int, shape (r,), optional
            Per incoming patch: trials stopped by the event cap or transmitted (default zeros).
        stacks, slices : int, default 31, 30
            Geometry of the collector hemisphere.
        sample : dict, optional
            Sample parameters; must be JSON-serialisable (they are stored as JSON).
        wavelength_nm : float, optional
            Wavelength in nm, > 0.
        rays : int, optional
            Number of trials; default Σ launched.
        seed : int, optional
            Random seed of the run.
        method : {'average', 'pooled'}, default 'average'
            Class estimator: the paper's average of values, or pooled counts
            (`sandlight.gonio.reduction.reduce_counts`).
        squares : array_like of float, shape (r, r), optional
            Σ F² per cell of a run with shared paths, whose counts, absorbed and lost are then
            weight sums (floats); None for counts of independent trials.

        Raises
        ------
        sandlight.errors.ParameterError
            On inconsistent counts or invalid metadata.
        """
        h = CollectorHemisphere(stacks, slices)
        if lost is None:
            lost = np.zeros(h.n_patches, dtype=np.int64)
        counts, absorbed, launched, lost, squares = check_sums(h, counts, absorbed, launched, lost, squares)
        sample = {} if sample is None else dict(sample)
        try:
            json.dumps(sample)
        except (TypeError, ValueError) as exc:
            raise ParameterError("sample", sample, f"must be JSON-serialisable ({exc})") from None
        if wavelength_nm is not None:
            try:
                wavelength_nm = float(wavelength_nm)
            except (TypeError, ValueError):
                raise ParameterError("wavelength_nm", wavelength_nm, "must be a positive number of nm") from None
            if not (math.isfinite(wavelength_nm) and wavelength_nm > 0):
                raise ParameterError("wavelength_nm", wavelength_nm, "must be a positive number of nm")
        rays = int(launched.sum()) if rays is None else rays
        if isinstance(rays, bool) or int(rays) != rays or rays < 0:
            raise ParameterError("rays", rays, "must be a non-negative integer")
        if seed is not None and (isinstance(seed, bool) or int(seed) != seed):
            raise ParameterError("seed", seed, "must be an integer or None")
        for a in (counts, absorbed, launched, lost, squares):
            if a is not None:
                a.setflags(write=False)
        return cls(
            stacks=h.stacks,
            slices=h.slices,
            counts=counts,
            absorbed=absorbed,
            launched=launched,
            lost=lost,
            reduced=reduce_counts(h, counts, absorbed, launched, lost, method=method, squares=squares),
            sample=sample,
            wavelength_nm=wavelength_nm,
            rays=int(rays),
            seed=None if seed is None else int(seed),
            reduction_method=method,
            squares=squares,
        )

    # Geometry and the full arrays -------------------------------------------------------------

    @property
    def unique_values(self) -> np.ndarray:
        """The m unique values of the normalised BRDF f̂, sr⁻¹ (the paper's linear array)."""
        return self.reduced.unique_values

    @property
    def unique_stderr(self) -> np.ndarray:
        """Standard errors of `unique_values`, sr⁻¹."""
        return self.reduced.unique_stderr

    @property
    def normal_reflectance(self) -> float:
        """Directional-hemispherical reflectance at normal incidence R (fraction)."""
        return self.reduced.normal_reflectance

    @property
    def values(self) -> np.ndarray:
        """Reduced BRDF f̂[i, j], normalised to unit reflectance at normal incidence, (r, r), sr⁻¹."""
        return self.classes.expand(self.reduced.unique_values)

    @property
    def stderr(self) -> np.ndarray:
        """Standard errors of `values`, (r, r), sr⁻¹."""
        return self.classes.expand(self.reduced.unique_stderr)

    @property
    def values_absolute(self) -> np.ndarray:
        """Symmetrised BRDF f̄[i, j] before normalisation, (r, r), sr⁻¹."""
        return self.classes.expand(self.reduced.unique_absolute)

    @property
    def stderr_absolute(self) -> np.ndarray:
        """Standard errors of `values_absolute`, (r, r), sr⁻¹."""
        return self.classes.expand(self.reduced.unique_absolute_stderr)

    # The continuous BRDF ----------------------------------------------------------------------

    def f(self, wi: ArrayLike, wo: ArrayLike, *, normalised: bool = False) -> np.ndarray:
        """Continuous BRDF f(ω_i, ω_o) by interpolation between patch centroids (paper §3.2.4).

        Parameters
        ----------
        wi, wo : array_like, shape (..., 3)
            Directions towards the light and towards the viewer, broadcast together; any
            positive length (they are normalised).
        normalised : bool, default False
            False: the absolute BRDF in sr⁻¹. True: the BRDF normalised to unit reflectance at
            normal incidence (the paper's spatial component, §3.3).

        Returns
        -------
        numpy.ndarray, shape (...)
            f in sr⁻¹; 0 where either direction has z ≤ 0; NaN where a direction has a NaN.

        Raises
        ------
        sandlight.errors.ParameterError
            If the last axis is not 3, or a direction is zero or infinite.

        Notes
        -----
        Trilinear in (cos θ_i, cos θ_o, φ_o − φ_i) on the band-centroid grid; isotropic,
        reciprocal, continuous and equal to the reduced values at the patch centroids by
        construction (module docstring).
        """
        unique = self.reduced.unique_values if normalised else self.reduced.unique_absolute
        return band_grid_f(self.hemisphere, unique, wi, wo)

    # Comparison -------------------------------------------------------------------------------

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, MeasuredBRDF):
            return NotImplemented
        arrays = ("counts", "absorbed", "launched", "lost")
        return (
            (self.stacks, self.slices, self.rays, self.seed, self.sandlight_version, self.reduction_method)
            == (other.stacks, other.slices, other.rays, other.seed, other.sandlight_version, other.reduction_method)
            and self.sample == other.sample
            and _same_float(self.wavelength_nm, other.wavelength_nm)
            and all(np.array_equal(getattr(self, a), getattr(other, a)) for a in arrays)
            and (self.squares is None) == (other.squares is None)
            and (self.squares is None or np.array_equal(self.squares, other.squares))
            and self.reduced.equals(other.reduced)
        )

    __hash__ = None

    def __repr__(self) -> str:
        wl = "None" if self.wavelength_nm is None else f"{self.wavelength_nm:g}"
        return (
            f"MeasuredBRDF(stacks={self.stacks}, slices={self.slices}, rays={self.rays}, "
            f"wavelength_nm={wl}, normal_reflectance={self.normal_reflectance:.4g})"
        )


def band_grid(hemisphere: CollectorHemisphere, unique_values: ArrayLike) -> np.ndarray:
    """Node values F[b_i, b_o, k] of the continuous BRDF (module docstring) from unique values.

    Parameters
    ----------
    hemisphere : CollectorHemisphere
        The collector hemisphere (stacks, slices).
    unique_values : array_like, shape (m,)
        One value per class of isotropy and reciprocity (`EquivalenceClasses`), sr⁻¹.

    Returns
    -------
    numpy.ndarray, shape (stacks, stacks, slices)
        F[b_i, b_o, k]: the value of the class of (incoming band b_i, outgoing band b_o, slice
        difference k); band 0 is the cap.
    """
    classes = EquivalenceClasses(hemisphere)
    u = np.asarray(unique_values, dtype=float)
    if u.shape != (classes.n_classes,):
        raise ParameterError("unique_values", f"an array of shape {u.shape}", f"must have shape ({classes.n_classes},)")
    return u[classes.table]


def mu_bracket(nodes_desc: np.ndarray, mu: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The interpolant's linear weights in μ on decreasing nodes (`interpolate_band_grid`).

    Parameters
    ----------
    nodes_desc : numpy.ndarray, shape (n,)
        μ = cos θ of the nodes, strictly decreasing, n ≥ 2 (e.g. ``band_cos_theta``).
    mu : numpy.ndarray
        Cosines to bracket, any shape (NaN is treated as 0).

    Returns
    -------
    a, b : numpy.ndarray of int
        Node indices (into ``nodes_desc``) on either side of each μ.
    t : numpy.ndarray of float
        Weight in [0, 1]: the interpolant is (1 − t)·F[a] + t·F[b]. μ below the last node is held
        at the last node; μ above the first node (only rounding above 1) at the first.
    """
    asc = nodes_desc[::-1]
    n = asc.size
    m = np.clip(np.nan_to_num(mu), asc[0], asc[-1])
    j = np.clip(np.searchsorted(asc, m, side="right") - 1, 0, n - 2)  # asc[j] ≤ μ < asc[j + 1]
    t = (m - asc[j]) / (asc[j + 1] - asc[j])
    # Back to the decreasing (band) index: ascending index q is band n − 1 − q.
    return n - 1 - j, n - 2 - j, t


def interpolate_band_grid(
    grid: ArrayLike, band_cos_theta: ArrayLike, mu_i: ArrayLike, mu_o: ArrayLike, dphi: ArrayLike
) -> np.ndarray:
    """The continuous BRDF's interpolant on the band grid (module docstring), in (μ_i, μ_o, Δφ).

    Parameters
    ----------
    grid : array_like, shape (stacks, stacks, slices)
        Node values F[b_i, b_o, k] (`band_grid`).
    band_cos_theta : array_like, shape (stacks,)
        μ of the nodes, decreasing (``CollectorHemisphere.band_cos_theta``).
    mu_i, mu_o : array_like
        cos θ of the incoming and outgoing directions; values below the lowest node (down to 0
        and below) take the lowest node's value, values above 1 the cap's.
    dphi : array_like
        φ_o − φ_i in radians, any real (periodic).

    Returns
    -------
    numpy.ndarray
        Trilinear interpolant, broadcast shape of the inputs. No horizon test: μ ≤ 0 gives the
        limit μ → 0⁺ (callers working with directions set those to 0).
    """
    grid = np.asarray(grid, dtype=float)
    nodes = np.asarray(band_cos_theta, dtype=float)
    mu_i, mu_o, dphi = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (mu_i, mu_o, dphi)))
    shape = mu_i.shape
    slices = grid.shape[2]
    bi0, bi1, ti = mu_bracket(nodes, mu_i.ravel())
    bo0, bo1, to = mu_bracket(nodes, mu_o.ravel())
    # (NaN rows are computed on 0 by the callers, which set them to NaN at the end.)
    x = np.mod(np.nan_to_num(dphi.ravel()) * (slices / (2.0 * math.pi)), slices)
    k0 = np.floor(x)
    tk = x - k0
    k0 = k0.astype(np.int64) % slices  # x can round up to exactly `slices`
    k1 = (k0 + 1) % slices

    value = np.zeros(mu_i.size)
    for b_in, w_in in ((bi0, 1.0 - ti), (bi1, ti)):
        for b_out, w_out in ((bo0, 1.0 - to), (bo1, to)):
            for k, w_k in ((k0, 1.0 - tk), (k1, tk)):
                value += w_in * w_out * w_k * grid[b_in, b_out, k]
    return value.reshape(shape)


def band_grid_f(hemisphere: CollectorHemisphere, unique_values: ArrayLike, wi: ArrayLike, wo: ArrayLike) -> np.ndarray:
    """Continuous BRDF f(ω_i, ω_o) from the m unique values of a BRDF (paper §3.2.4).

    This is `MeasuredBRDF.f` for any unique values (e.g. a BRDF reconstructed by the spatial
    predictor): trilinear in (cos θ_i, cos θ_o, φ_o − φ_i) on the band-centroid grid.

    Parameters
    ----------
    hemisphere : CollectorHemisphere
    unique_values : array_like, shape (m,)
        sr⁻¹.
    wi, wo : array_like, shape (..., 3)
        Directions (any positive length), broadcast together.

    Returns
    -------
    numpy.ndarray, shape (...)
        f in sr⁻¹; 0 where either direction has z ≤ 0; NaN where a direction has a NaN.
    """
    wi = _unit("wi", wi)
    wo = _unit("wo", wo)
    shape = np.broadcast_shapes(wi.shape, wo.shape)[:-1]
    wi = np.broadcast_to(wi, shape + (3,)).reshape(-1, 3)
    wo = np.broadcast_to(wo, shape + (3,)).reshape(-1, 3)
    dphi = np.arctan2(wo[:, 1], wo[:, 0]) - np.arctan2(wi[:, 1], wi[:, 0])
    value = interpolate_band_grid(
        band_grid(hemisphere, unique_values),
        hemisphere.band_cos_theta,
        np.nan_to_num(wi[:, 2]),
        np.nan_to_num(wo[:, 2]),
        dphi,
    )
    above = (wi[:, 2] > 0) & (wo[:, 2] > 0)
    value = np.where(above, value, 0.0)
    nan = np.isnan(wi).any(axis=1) | np.isnan(wo).any(axis=1)
    return np.where(nan, np.nan, value).reshape(shape)


def _same_float(a: float | None, b: float | None) -> bool:
    return (a is None and b is None) or (a is not None and b is not None and float(a) == float(b))


def _unit(name: str, w: ArrayLike) -> np.ndarray:
    d = np.asarray(w, dtype=float)
    if d.ndim == 0 or d.shape[-1] != 3:
        raise ParameterError(name, f"an array of shape {d.shape}", "must have shape (..., 3)")
    norm = np.linalg.norm(d, axis=-1, keepdims=True)
    bad = ~np.isnan(norm) & ~((norm > 0) & np.isfinite(norm))
    if bad.any():
        raise ParameterError(name, d[bad[..., 0]][0].tolist(), "directions must be non-zero and finite")
    return d / norm
