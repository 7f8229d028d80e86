"""`SandAppearance`: the explicit spectral BRDF of a sand sample (paper §3.3), evaluated.

The class holds the parts built in the package's other modules — the band grid of the spatial
part (`band_grid`), the spectral × spatial combination (`combination`), the sampling tables
(`sampling`) — and the native evaluator of f; its methods check their arguments and delegate.
"""

from __future__ import annotations

import json
import math
import os
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from sandlight.appearance import table_file
from sandlight.appearance.band_grid import hat_quadrature
from sandlight.appearance.combination import Combination, check_combination
from sandlight.appearance.sampling import SamplingTables, check_sampling_method
from sandlight.appearance.shapes import SHAPES, Shape, ShapeSeries
from sandlight.appearance.sources import resolve_sample, resolve_spatial, resolve_spectral
from sandlight.checks import check_allocation, check_choice
from sandlight.errors import ParameterError

if TYPE_CHECKING:
    import xarray as xr

    from sandlight.predictor.spectral import SpectralModel
    from sandlight.sample import SandSample
    from sandlight.spatial.model import SpatialModel

__all__ = ["SandAppearance"]

#: How `SandAppearance.table` makes its values (the file's ``interpolation`` attribute).
TABLE_INTERPOLATION = (
    "multilinear in (mu_i, mu_o, dphi); f is reciprocal (f[:, i, j, k] == f[:, j, i, k]) "
    "and even in dphi; in mu_i and mu_o each value is the cos-weighted average of the "
    "model over the node's interpolation hat (energy-conserving), in dphi a point sample"
)


def _directions(name: str, w: ArrayLike) -> np.ndarray:
    d = np.asarray(w, dtype=float)
    if d.ndim == 1:
        d = d[None, :]
    if d.ndim != 2 or d.shape[1] != 3:
        raise ParameterError(name, f"an array of shape {np.shape(w)}", "must have shape (N, 3) or (3,)")
    return d


def _unit_pairs(wi: ArrayLike, wo: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    wi, wo = _directions("wi", wi), _directions("wo", wo)
    ni, no = np.linalg.norm(wi, axis=1), np.linalg.norm(wo, axis=1)
    for name, w, nrm in (("wi", wi, ni), ("wo", wo, no)):
        bad = ~((nrm > 0) & np.isfinite(nrm))
        if bad.any():
            raise ParameterError(name, w[bad][0].tolist(), "non-zero finite directions")
    return wi / ni[:, None], wo / no[:, None]


class SandAppearance:
    """Spectral BRDF of a sand sample: spectral × spatial predictor (paper §3.3).

    f(ω_i, ω_o, λ) in sr⁻¹ for directions in the local frame (z = the surface normal; ω_i towards
    the light, ω_o towards the viewer; any positive length).

    Parameters
    ----------
    sample : SandSample, str or dict
        The sample (or a preset name).
    spectral_model : SpectralModel, path, callable or None
        Source of r(λ), the directional-hemispherical reflectance at normal incidence. None: the
        shipped model (`sandlight.predictor.default_model`); a callable
        ``sample -> (wavelengths_nm, reflectance)`` is accepted.
    spatial_model : SpatialModel, path or None
        Source of the normalised BRDF. None: the shipped model that covers the sample
        (`sandlight.spatial.model_for`: the family whose mesh holds it and whose base it differs
        from least; the paper's beach-scene model for the default mineralogy).
    combination : {'energy', 'product'}
        How r(λ) and f̂ combine (`sandlight.appearance.combination`); 'product' is the paper's
        formula.
    shape : {'reflectance', 'fixed'}
        'reflectance' (default): at every wavelength the shape the spatial model gives at the
        sand's reflectance there, for a model that interpolates in log r₀ (the dune family);
        'fixed': one shape, at the model's measurement wavelength, at every wavelength (the
        paper's assumption; also what models without absorbers give).
        `sandlight.appearance.shapes`.
    fixed : {'warn', 'ignore', 'error'}
        What to do when the sample differs from the spatial mesh's base sample in a parameter
        the mesh does not vary (`SpatialModel.scores`).

    Attributes
    ----------
    sand_sample : SandSample
        The sample.
    wavelengths_nm : ndarray (W,)
        Wavelengths of the spectral model, nm (the default for every method).
    normal_reflectance : ndarray (W,)
        r(λ), clipped to [0, 1].
    shapes : sandlight.appearance.shapes.ShapeSeries
        The spatial shapes the BRDF blends per wavelength (one unless ``shape='reflectance'``
        with a model that interpolates in log r₀).
    reference_weights : tuple of numpy.ndarray (K,)
        (ā, b̄): each shape's weights of the reference spectrum, the mean over ``wavelengths_nm``
        of the per-wavelength weights; the ``'brdf'`` sampler and `reference_brdf` follow f with
        them.
    reference_reflectance : float
        r_0 of the spatial measurements at the sample's mesh position, for the shape at the
        spatial model's wavelength (this and the next three describe that shape, the one
        ``shape='fixed'`` applies everywhere).
    n_negative_nodes : int
        Node values of that spatial grid set to 0.
    spatial : sandlight.spatial.SpatialBRDF
        The spatial model's prediction (before the steps of `sandlight.appearance.band_grid`).
    band_grid : sandlight.appearance.band_grid.BandGrid
        The spatial part's nodes in μ and values, as the BRDF interpolates them.
    spectral_memory : str or None
        Engine path memory the spectral model was trained with (None for a callable). A warning
        is issued when it differs from the spatial model's ``memory_``.

    Examples
    --------
    >>> app = SandAppearance("wet-beach")                                   # doctest: +SKIP
    >>> f = app.brdf([[0, 0, 1]], [[0.5, 0, 0.866]])                        # (1, 16), sr⁻¹
    """

    def __init__(
        self,
        sample: SandSample | str | dict,
        spectral_model: SpectralModel | str | Path | Callable | None = None,
        spatial_model: SpatialModel | str | Path | None = None,
        *,
        combination: str = "energy",
        shape: str = "reflectance",
        fixed: str = "warn",
    ) -> None:
        from sandlight import _native

        self.combination = check_combination(combination)
        check_choice("shape", shape, SHAPES)
        self.sand_sample = resolve_sample(sample)
        wl, r, self.spectral_source, self.spectral_memory = resolve_spectral(spectral_model, self.sand_sample)
        self.wavelengths_nm = wl
        self.normal_reflectance = np.clip(r, 0.0, 1.0)
        model = resolve_spatial(spatial_model, self.sand_sample)
        if self.spectral_memory is not None and self.spectral_memory != model.memory_:
            warnings.warn(
                f"the spectral model was trained with engine memory {self.spectral_memory!r}, the spatial "
                f"model with {model.memory_!r}: the appearance combines two transport models "
                f"(docs/geometry.md)",
                UserWarning,
                stacklevel=2,
            )
        self.spatial_model = model
        # A model that interpolates in log r₀ takes the sample's r₀ from this spectral source.
        r0 = float(np.interp(model.r0_wavelength_nm, wl, self.normal_reflectance))
        at_r0 = Shape.predict(model, self.sand_sample, r0, combination, fixed)
        self.spatial = at_r0.spatial
        self.band_grid = at_r0.band_grid
        self.n_negative_nodes = self.band_grid.n_negative_nodes
        self._combination = at_r0.combination
        self.reference_reflectance = self._combination.reference_reflectance
        self.shapes = ShapeSeries.build(shape, model, self.sand_sample, at_r0, self.normal_reflectance, combination)
        # One native evaluator: a stacked grid of the K shapes on the same nodes (a plain one for K = 1).
        shapes = self.shapes.shapes
        self._stacked = len(shapes) > 1
        grids = np.stack([s.band_grid.grid for s in shapes])
        profiles = np.stack([s.combination.profile for s in shapes])
        self._evaluator = _native.BandGridBrdf(
            grids if self._stacked else grids[0], self.band_grid.nodes, profiles if self._stacked else profiles[0]
        )
        # The sampling tables follow f at the reference spectrum: the mean of the per-wavelength weights.
        self.reference_weights = tuple(x.mean(axis=0) for x in self.shapes.weights(self.normal_reflectance))
        self._sampling = SamplingTables.build(
            self.band_grid, lambda *mu: self._evaluate_mu(mu, *self.reference_weights)[..., 0]
        )

    def _layers_mu(self, *mu: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(f̂_k, P_k P_k) of every shape at points (μ_i, μ_o, Δφ) (each (P,)): two (P, K) arrays."""
        g, pp = self._evaluator.evaluate_mu(*mu)
        return g.reshape(g.shape[0], -1), pp.reshape(pp.shape[0], -1)

    def _evaluate_mu(self, mu: tuple[np.ndarray, ...], a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """f (P, W) at points (μ_i, μ_o, Δφ) (each (P,)) for shape weights a, b ((W, K) or (K,))."""
        a, b = np.atleast_2d(a), np.atleast_2d(b)
        g, pp = self._layers_mu(*mu)
        out = np.zeros((mu[0].size, a.shape[0]))
        for k in range(g.shape[1]):
            out += g[:, k, None] * a[None, :, k] + pp[:, k, None] * b[None, :, k]
        return out

    # ---- parts, for renderers that re-implement the evaluation (sandlight.mitsuba) --------------
    @property
    def combination_terms(self) -> Combination:
        """The combination f = a(λ) f̂ + b(λ) P(μ_i) P(μ_o): r_0, the profile P at the band grid's
        nodes and the weights (a, b) of a reflectance (`sandlight.appearance.combination`)."""
        return self._combination

    # ---- spectra -----------------------------------------------------------------------------
    def reflectance_at(self, wavelengths_nm: ArrayLike | None = None) -> np.ndarray:
        """r(λ) at the given wavelengths (nm), linear between the spectral model's wavelengths.

        Raises
        ------
        ParameterError
            A wavelength outside the spectral model's range.
        """
        if wavelengths_nm is None:
            return self.normal_reflectance.copy()
        wl = np.atleast_1d(np.asarray(wavelengths_nm, dtype=float))
        lo, hi = self.wavelengths_nm[0], self.wavelengths_nm[-1]
        bad = ~((wl >= lo) & (wl <= hi))
        if wl.ndim != 1 or bad.any():
            value = wl[bad][0] if wl.ndim == 1 and bad.any() else wavelengths_nm
            raise ParameterError(
                "wavelengths_nm",
                value if np.ndim(value) else float(value),
                f"wavelengths in [{lo:g}, {hi:g}] nm, the spectral model's range",
            )
        return np.interp(wl, self.wavelengths_nm, self.normal_reflectance)

    # ---- evaluation --------------------------------------------------------------------------
    def brdf(
        self, wi: ArrayLike, wo: ArrayLike, wavelengths_nm: ArrayLike | None = None, *, threads: int | None = None
    ) -> np.ndarray:
        """The spectral BRDF f(ω_i, ω_o, λ) in sr⁻¹.

        Parameters
        ----------
        wi, wo : array_like, shape (N, 3) or (3,)
            Directions towards the light and the viewer (local frame, z = normal; any positive
            length); a single direction is paired with every row of the other.
        wavelengths_nm : array_like (W,), optional
            Default: the spectral model's wavelengths.
        threads : int, optional
            Threads for very large batches (default: the calling thread only).

        Returns
        -------
        numpy.ndarray, shape (N, W)
            0 where either direction has z ≤ 0; NaN where one has a NaN component.

        Raises
        ------
        ParameterError
            Wrong shapes, a zero or infinite direction, or a wavelength outside the model's range.
        """
        wi, wo = _directions("wi", wi), _directions("wo", wo)
        if wi.shape[0] != wo.shape[0]:
            if wi.shape[0] == 1:
                wi = np.broadcast_to(wi, wo.shape)
            elif wo.shape[0] == 1:
                wo = np.broadcast_to(wo, wi.shape)
            else:
                raise ParameterError("wo", f"{wo.shape[0]} rows", f"as many rows as wi ({wi.shape[0]}) or one")
        a, b = self.shapes.weights(self.reflectance_at(wavelengths_nm))
        if not self._stacked:
            a, b = a[:, 0], b[:, 0]
        return self._evaluator.evaluate(
            np.ascontiguousarray(wi),
            np.ascontiguousarray(wo),
            np.ascontiguousarray(a),
            np.ascontiguousarray(b),
            threads,
        )

    def albedo(self, wi: ArrayLike, wavelengths_nm: ArrayLike | None = None) -> np.ndarray:
        """Directional-hemispherical reflectance ∫ f(ω_i, ω_o, λ) cos θ_o dω_o, exact for the model.

        Parameters
        ----------
        wi : array_like, shape (N, 3) or (3,)
        wavelengths_nm : array_like (W,), optional

        Returns
        -------
        numpy.ndarray, shape (N, W)
            0 for directions with z ≤ 0.
        """
        wi = _directions("wi", wi)
        norm = np.linalg.norm(wi, axis=1)
        if not ((norm > 0) & np.isfinite(norm)).all():
            raise ParameterError("wi", wi[~((norm > 0) & np.isfinite(norm))][0].tolist(), "non-zero finite directions")
        mu = wi[:, 2] / norm
        return np.where((mu > 0)[:, None], self._albedo_mu(mu, wavelengths_nm), 0.0)

    def _albedo_mu(self, mu: np.ndarray, wavelengths_nm: np.ndarray | None) -> np.ndarray:
        return self.shapes.albedo(mu, self.reflectance_at(wavelengths_nm))

    def reference_brdf(self, wi: ArrayLike, wo: ArrayLike) -> np.ndarray:
        """The BRDF at the reference spectrum, sr⁻¹: f with the mean over the spectral model's
        wavelengths of the per-wavelength weights, which the ``'brdf'`` sampler's tables follow
        (`sandlight.appearance.sampling`; renderers that sample in proportion to it, such as the
        Mitsuba plugin, need it). wi, wo: (N, 3) or (3,) as in `brdf`; returns (N,), 0 where
        either direction has z ≤ 0."""
        wi, wo = _unit_pairs(wi, wo)
        if wi.shape[0] != wo.shape[0]:
            wi, wo = np.broadcast_arrays(wi, wo)
        dphi = np.arctan2(wo[:, 1], wo[:, 0]) - np.arctan2(wi[:, 1], wi[:, 0])
        f = self._evaluate_mu((wi[:, 2].copy(), wo[:, 2].copy(), dphi), *self.reference_weights)[:, 0]
        return np.where((wi[:, 2] > 0) & (wo[:, 2] > 0), f, 0.0)

    # ---- sampling ----------------------------------------------------------------------------
    def pdf(self, wi: ArrayLike, wo: ArrayLike, method: str = "brdf") -> np.ndarray:
        """Density of `sample`'s outgoing directions with respect to solid angle, sr⁻¹.

        Parameters
        ----------
        wi, wo : array_like, shape (N, 3)
        method : {'brdf', 'cosine'}
            `sandlight.appearance.sampling` describes both.

        Returns
        -------
        numpy.ndarray, shape (N,)
            0 where ω_o has z ≤ 0.
        """
        check_sampling_method(method)
        wi, wo = _unit_pairs(wi, wo)
        if wi.shape[0] != wo.shape[0]:
            wi, wo = np.broadcast_arrays(wi, wo)
        return self._sampling.pdf(wi, wo, method)

    def sample(
        self,
        wi: ArrayLike,
        u1: ArrayLike,
        u2: ArrayLike,
        wavelength_nm: ArrayLike | None = None,
        method: str = "brdf",
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Draw outgoing directions for incoming ones (importance sampling of f cos θ_o).

        Parameters
        ----------
        wi : array_like, shape (N, 3)
            Directions towards the light (local frame).
        u1, u2 : array_like, shape (N,)
            Uniform numbers in [0, 1).
        wavelength_nm : float or array_like (W,), optional
            Wavelength(s) of the weights (default: the spectral model's).
        method : {'brdf', 'cosine'}
            Follow the tabulated BRDF or the paper's cosine sampling (`sandlight.appearance.sampling`).

        Returns
        -------
        wo : numpy.ndarray, shape (N, 3)
            Unit outgoing directions (z > 0).
        weight : numpy.ndarray, shape (N,) for a scalar wavelength, else (N, W)
            f(ω_i, ω_o, λ) cos θ_o / pdf (0 for incoming directions below the horizon).
        pdf : numpy.ndarray, shape (N,)
            pdf(ω_i, ω_o) with respect to solid angle, sr⁻¹.
        """
        check_sampling_method(method)
        wi = _directions("wi", wi)
        n = wi.shape[0]
        u1, u2 = (np.broadcast_to(np.asarray(u, dtype=float), (n,)) for u in (u1, u2))
        for name, u in (("u1", u1), ("u2", u2)):
            if not ((u >= 0) & (u < 1)).all():
                raise ParameterError(name, float(u[~((u >= 0) & (u < 1))][0]), "uniform numbers in [0, 1)")
        wi_unit, _ = _unit_pairs(wi, np.broadcast_to([0.0, 0.0, 1.0], wi.shape))
        wo = self._sampling.sample(wi_unit, u1, u2, method)
        pdf = self.pdf(wi, wo, method)
        scalar = wavelength_nm is not None and np.ndim(wavelength_nm) == 0
        f = self.brdf(wi, wo, None if wavelength_nm is None else np.atleast_1d(wavelength_nm))
        with np.errstate(divide="ignore", invalid="ignore"):
            weight = np.where(pdf[:, None] > 0, f * wo[:, 2:3] / pdf[:, None], 0.0)
        return wo, (weight[:, 0] if scalar else weight), pdf

    # ---- regular-grid table -----------------------------------------------------------------
    def table(self, n_mu: int = 32, n_dphi: int = 32, wavelengths_nm: ArrayLike | None = None) -> xr.Dataset:
        """The BRDF on a regular grid as an ``xarray.Dataset`` (format 'sandlight-brdf-table').

        In μ_i and μ_o each value is the cos-weighted average of f over the node's
        multilinear-interpolation hat, ∫ f h_q μ dμ / ∫ h_q μ dμ (exact Gauss quadrature on the
        pieces where f is linear, `hat_quadrature`), so that interpolating the table conserves
        the energy of features narrower than its spacing (the normal-incidence reflection of
        water); in Δφ values are point samples. docs/spatial-predictor.md describes the layout.

        Parameters
        ----------
        n_mu : int
            Points in μ_i and in μ_o, uniform on [0, 1] (≥ 2).
        n_dphi : int
            Points in Δφ, uniform on [0, π] (≥ 2).
        wavelengths_nm : array_like, optional
            Default: the spectral model's wavelengths.

        Returns
        -------
        xarray.Dataset
            ``f`` (wavelength, mu_i, mu_o, dphi) in sr⁻¹, ``albedo`` (wavelength, mu_i) (the
            model's albedo averaged as f is), ``normal_reflectance`` (wavelength), with units and
            the format attributes (`sandlight.appearance.table_file`).
        """
        for name, v in (("n_mu", n_mu), ("n_dphi", n_dphi)):
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not 2 <= v <= 4096:
                raise ParameterError(name, v, "an integer in [2, 4096]")
        wl = self.wavelengths_nm if wavelengths_nm is None else np.atleast_1d(np.asarray(wavelengths_nm, dtype=float))
        a, b = self.shapes.weights(self.reflectance_at(wl))
        mu = np.linspace(0.0, 1.0, int(n_mu))
        dphi = np.linspace(0.0, math.pi, int(n_dphi))
        x, W = hat_quadrature(self.band_grid.nodes, mu)  # points (P,), weights (n_mu, P) normalised per node
        # float64 arrays: about 8 over the quadrature points (the meshgrids, g, pp and their
        # temporaries) and 3 over the table (f, its transpose average, the file's copy).
        need = 8 * (8 * x.size**2 * int(n_dphi) + 3 * wl.size * int(n_mu) ** 2 * int(n_dphi))
        need += 8 * 2 * (len(self.shapes.shapes) - 1) * x.size**2 * int(n_dphi)  # the other shapes' g, pp
        check_allocation("n_mu, n_dphi", (int(n_mu), int(n_dphi)), need)
        XI, XO, DP = np.meshgrid(x, x, dphi, indexing="ij")
        f = np.zeros((wl.size, int(n_mu), int(n_mu), int(n_dphi)))
        layers = self._layers_mu(XI.ravel(), XO.ravel(), DP.ravel())
        for k in range(layers[0].shape[1]):
            g, pp = (np.einsum("ix,xyk,jy->ijk", W, v[:, k].reshape(XI.shape), W, optimize=True) for v in layers)
            f += a[:, k, None, None, None] * g[None] + b[:, k, None, None, None] * pp[None]
        # The model is reciprocal; averaging with the transpose removes the rounding (~1e-16) of the
        # summation order, so that readers may rely on exact symmetry.
        f = 0.5 * (f + f.transpose(0, 2, 1, 3))
        albedo = W @ self._albedo_mu(x, wl)  # the same averages of the model's albedo
        provenance = {
            "sample": json.dumps(self.sand_sample.to_dict(), sort_keys=True),
            "combination": self.combination,
            "spectral_source": self.spectral_source,
            "engine_memory": json.dumps(
                {"spectral": self.spectral_memory or "unknown", "spatial": self.spatial_model.memory_}
            ),
            "spatial_mesh": json.dumps(
                {
                    "parameters": list(self.spatial_model.mesh_.parameters),
                    "coordinates": self.spatial.coordinates.tolist(),
                }
            ),
            "spatial_wavelength_nm": -1.0
            if self.spatial_model.wavelength_nm_ is None
            else self.spatial_model.wavelength_nm_,
            "reference_reflectance": self.reference_reflectance,
            "shape": self.shapes.method,
            "shape_reflectances": json.dumps(self.shapes.reflectances.tolist()),
        }
        return table_file.table_dataset(
            f,
            wl,
            mu,
            mu,
            dphi,
            interpolation=TABLE_INTERPOLATION,
            title="Spectral BRDF of a sand sample (sandlight)",
            attrs=provenance,
            albedo=albedo.T,
            normal_reflectance=self.reflectance_at(wl),
        )

    def to_table(
        self,
        path: str | os.PathLike,
        n_mu: int = 32,
        n_dphi: int = 32,
        wavelengths_nm: ArrayLike | None = None,
    ) -> Path:
        """Write the BRDF on a regular grid to NetCDF (format 'sandlight-brdf-table', atomically).

        See `table` for the parameters and docs/spatial-predictor.md for the layout; read it back
        with `sandlight.appearance.table_file.read_table` or `sandlight.render.BrdfTable.from_netcdf`.
        Returns the path written.
        """
        return table_file.write_table(self.table(n_mu, n_dphi, wavelengths_nm), path)

    def __repr__(self) -> str:
        return (
            f"SandAppearance({len(self.wavelengths_nm)} wavelengths {self.wavelengths_nm[0]:g}–"
            f"{self.wavelengths_nm[-1]:g} nm, combination={self.combination!r}, r_0={self.reference_reflectance:.4f}, "
            f"shape={self.shapes.method!r} ({len(self.shapes.shapes)} shapes), "
            f"spatial mesh over {', '.join(self.spatial_model.mesh_.parameters)})"
        )
