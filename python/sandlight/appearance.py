"""The explicit spectral BRDF of a sand sample (paper §3.3): evaluation, sampling, albedo, tables.

`SandAppearance` combines the spectral predictor (directional-hemispherical reflectance at normal
incidence r(λ), `sandlight.predictor`) with the spatial predictor (the BRDF normalised to unit
reflectance at normal incidence, f̂, `sandlight.spatial`) into f(ω_i, ω_o, λ), in sr⁻¹, for
directions in the local frame (z = the surface normal; ω_i towards the light, ω_o towards the
viewer; any positive length).

The spatial part
----------------
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
   near-zero value undershoots) are set to 0; `n_negative_nodes` counts them.
4. **Normalisation of the continuous BRDF.** The measured values satisfy Σ_k ω_p(k) f̂[cap, k] = 1
   over patches; the piecewise-linear interpolant integrates to slightly different values. The
   grid is divided by the exact integral ∫ f̂(n, ω_o) cos θ_o dω_o of the interpolant, so that the
   continuous BRDF satisfies the paper's §3.3 normalisation exactly.

The combination
---------------
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

Sampling
--------
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

Table export
------------
`SandAppearance.to_table` writes f on a regular grid (format 'sandlight-brdf-table', described
in docs/spatial-predictor.md): variable ``f`` (wavelength, mu_i, mu_o, dphi) in sr⁻¹, coordinates
``wavelength`` (nm), ``mu_i`` and ``mu_o`` (cos θ, ascending, uniform, including 0 and 1) and
``dphi`` (rad, uniform on [0, π]). In μ_i and μ_o each value is the cos-weighted average of f
over the node's multilinear-interpolation hat, ∫ f h_q μ dμ / ∫ h_q μ dμ (exact Gauss quadrature
on the pieces where f is linear), so that interpolating the table conserves the energy of
features narrower than its spacing (the normal-incidence reflection of water); in Δφ values are
point samples. ``albedo`` holds the model's albedo averaged the same way.
"""

from __future__ import annotations

import json
import math
import warnings
from pathlib import Path

import numpy as np

from sandlight.errors import ParameterError

# The interpolant's linear weights in μ: (band a, band b, t), shared with the BRDF itself so that
# albedo, sampling tables and the BRDF bracket μ identically.
from sandlight.gonio.brdf import mu_bracket as _bracket

__all__ = [
    "SandAppearance",
    "TABLE_FORMAT",
    "TABLE_FORMAT_VERSION",
    "DEFENSIVE_COSINE_SHARE",
    "COMBINATIONS",
    "SAMPLING_METHODS",
]

TABLE_FORMAT = "sandlight-brdf-table"
TABLE_FORMAT_VERSION = 1
#: Share ε of cosine-weighted sampling mixed into the BRDF-following sampler (keeps pdf > 0
#: wherever cos θ_o > 0, and bounds the weight by π f / ε).
DEFENSIVE_COSINE_SHARE = 0.1
#: Midpoint-rule points per cell and axis for the sampling tables.
SAMPLING_SUBDIVISIONS = 4
COMBINATIONS = ("energy", "product")
SAMPLING_METHODS = ("brdf", "cosine")


def _mu_integral_weights(band_cos_theta: np.ndarray) -> np.ndarray:
    """c_q = ∫_0^1 μ φ_q(μ) dμ for the piecewise-linear basis φ_q on the nodes (band order).

    The basis is the one of the interpolant: hat functions on the ascending nodes a_0 < … < a_{n−1}
    = 1, with φ_0 = 1 on [0, a_0] (values held below the lowest node). So ∫ μ g(μ) dμ = Σ c_q g_q
    exactly for the interpolant g; Σ c_q = 1/2.
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


def _directions(name: str, w) -> np.ndarray:
    d = np.asarray(w, dtype=float)
    if d.ndim == 1:
        d = d[None, :]
    if d.ndim != 2 or d.shape[1] != 3:
        raise ParameterError(name, f"an array of shape {np.shape(w)}", "must have shape (N, 3) or (3,)")
    return d


def _resolve_sample(sample):
    from sandlight.sample import SandSample

    if isinstance(sample, SandSample):
        return sample
    if isinstance(sample, str):
        return SandSample.preset(sample)
    if isinstance(sample, dict):
        return SandSample.from_dict(sample)
    raise ParameterError("sample", type(sample).__name__, "a SandSample, a preset name or a dict of parameters")


def _resolve_spectral(model, sample) -> tuple[np.ndarray, np.ndarray, str, str | None]:
    """Wavelengths, reflectance, a description of the model and its engine memory (None: unknown,
    e.g. for a callable)."""
    from sandlight.predictor.spectral import SpectralModel

    if model is None:
        from sandlight.predictor import default_model

        model = default_model()
    if isinstance(model, (str, Path)):
        model = SpectralModel.load(model)
    if hasattr(model, "predict") and hasattr(model, "wavelengths_"):
        wl, r = np.asarray(model.wavelengths_, dtype=float), np.asarray(model.predict([sample]), dtype=float)[0]
        source = f"{type(model).__name__} ({len(wl)} wavelengths)"
    elif callable(model):
        wl, r = (np.asarray(x, dtype=float) for x in model(sample))
        source = getattr(model, "__qualname__", repr(model))
    else:
        raise ParameterError(
            "spectral_model",
            type(model).__name__,
            "None (the shipped model), a SpectralModel, a model file, or a callable "
            "sample -> (wavelengths_nm, reflectance)",
        )
    if (
        wl.ndim != 1
        or wl.shape != r.shape
        or wl.size < 1
        or not (np.isfinite(wl).all() and np.isfinite(r).all())
        or np.any(np.diff(wl) <= 0)
    ):
        raise ParameterError(
            "spectral_model",
            f"wavelengths of shape {wl.shape}, reflectance of shape {r.shape}",
            "increasing finite wavelengths (nm) and one finite reflectance per wavelength",
        )
    return wl, r, source, getattr(model, "memory_", None)


def _resolve_spatial(model):
    from sandlight.spatial.model import SpatialModel, default_model

    if model is None:
        return default_model()
    if isinstance(model, (str, Path)):
        return SpatialModel.load(model)
    if isinstance(model, SpatialModel):
        return model
    raise ParameterError(
        "spatial_model", type(model).__name__, "None (the shipped model), a SpatialModel or a model file"
    )


class SandAppearance:
    """Spectral BRDF of a sand sample: spectral × spatial predictor (paper §3.3).

    Parameters
    ----------
    sample : SandSample, str or dict
        The sample (or a preset name).
    spectral_model : SpectralModel, path, callable or None
        Source of r(λ), the directional-hemispherical reflectance at normal incidence. None: the
        shipped model (`sandlight.predictor.default_model`); a callable
        ``sample -> (wavelengths_nm, reflectance)`` is accepted.
    spatial_model : SpatialModel, path or None
        Source of the normalised BRDF. None: the shipped beach-scene model
        (`sandlight.spatial.default_model`).
    combination : {'energy', 'product'}
        How r(λ) and f̂ combine (module docstring); 'product' is the paper's formula.
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
    reference_reflectance : float
        r_0 of the spatial measurements at the sample's mesh position.
    n_negative_nodes : int
        Node values of the spatial grid set to 0.
    spatial : sandlight.spatial.SpatialBRDF
        The spatial model's prediction (before the three steps of the module docstring).
    spectral_memory : str or None
        Engine path memory the spectral model was trained with (None for a callable). A warning
        is issued when it differs from the spatial model's ``memory_``.

    Examples
    --------
    >>> app = SandAppearance("wet-beach")                                   # doctest: +SKIP
    >>> f = app.brdf([[0, 0, 1]], [[0.5, 0, 0.866]])                        # (1, 16), sr⁻¹
    """

    def __init__(
        self, sample, spectral_model=None, spatial_model=None, *, combination: str = "energy", fixed: str = "warn"
    ):
        from sandlight import _native

        if combination not in COMBINATIONS:
            raise ParameterError("combination", combination, f"one of {COMBINATIONS}")
        self.sand_sample = _resolve_sample(sample)
        self.combination = combination
        wl, r, self.spectral_source, self.spectral_memory = _resolve_spectral(spectral_model, self.sand_sample)
        self.wavelengths_nm = wl
        self.normal_reflectance = np.clip(r, 0.0, 1.0)
        model = _resolve_spatial(spatial_model)
        if self.spectral_memory is not None and self.spectral_memory != model.memory_:
            warnings.warn(
                f"the spectral model was trained with engine memory {self.spectral_memory!r}, the spatial "
                f"model with {model.memory_!r}: the appearance combines two transport models "
                f"(docs/geometry.md)",
                UserWarning,
                stacklevel=2,
            )
        self.spatial_model = model
        self.spatial = model.brdf(self.sand_sample, fixed=fixed)
        h = self.spatial.hemisphere
        self._stacks, self._slices = h.stacks, h.slices
        # Step 1 of the module docstring: the cap's step. Nodes in μ (decreasing): the pole and the
        # cap's lower edge z_c with the cap's values, just below z_c and at the band centroids
        # with the bands' values.
        band_nodes = h.band_cos_theta
        z_cap = float(h.bounds[h.cap, 0])
        below = z_cap - 1e-6 * (z_cap - band_nodes[1])
        self._nodes = np.ascontiguousarray(np.r_[1.0, z_cap, below, band_nodes[1:]])
        node_band = np.r_[0, 0, 1, np.arange(1, self._stacks)]
        self._mu_weights = _mu_integral_weights(self._nodes)

        # Steps 2–4 of the module docstring.
        grid = self.spatial.grid()
        k = np.arange(self._slices)
        grid = 0.5 * (grid + grid[:, :, (-k) % self._slices])
        self.n_negative_nodes = int((grid < 0).sum())
        grid = np.maximum(grid, 0.0)[np.ix_(node_band, node_band)]
        # A[b] = ∫ f̂ cos θ_o dω_o for incidence at node b: exact for the interpolant, whose Δφ
        # integral is (2π/L) Σ_k F and whose μ_o integral is Σ c_q (_mu_integral_weights).
        albedo_nodes = (grid.sum(axis=2) * (2.0 * math.pi / self._slices)) @ self._mu_weights
        if not albedo_nodes[0] > 0:
            raise ParameterError(
                "spatial_model",
                "a BRDF that reflects nothing at normal incidence",
                "a spatial model with positive normalised values",
            )
        grid /= albedo_nodes[0]
        self._albedo_nodes = albedo_nodes / albedo_nodes[0]  # A at the nodes; A(1) = 1
        self._grid = np.ascontiguousarray(grid)

        r0 = float(np.dot(self.spatial.weights, model.node_normal_reflectance_[self.spatial.nodes]))
        self.reference_reflectance = float(min(r0, 1.0 / self._albedo_nodes.max()))
        if combination == "energy":
            d = np.clip(1.0 - self.reference_reflectance * self._albedo_nodes, 0.0, None)
            norm = 2.0 * math.pi * float(d @ self._mu_weights)
            profile = d / math.sqrt(norm) if norm > 0 else np.zeros_like(d)
        else:
            profile = np.zeros(len(self._nodes))
        self._profile = np.ascontiguousarray(profile)
        # ∫ P(μ_i)P(μ_o) cos θ_o dω_o = P(μ_i) · 2π Σ c_q P_q.
        self._profile_albedo_nodes = profile * (2.0 * math.pi * float(profile @ self._mu_weights))
        self._native = _native.BandGridBrdf(self._grid, self._nodes, self._profile)
        self._build_sampling_tables()

    # ---- spectra -----------------------------------------------------------------------------
    def _weights(self, r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Per-wavelength weights (a, b) of f = a f̂ + b P P for reflectances r."""
        if self.combination == "product":
            return r, np.zeros_like(r)
        r0 = self.reference_reflectance
        bright = r > r0
        a = np.where(bright, r0, r)
        b = np.where(bright, (r - r0) / (1.0 - r0) if r0 < 1 else 0.0, 0.0)
        return a, b

    def reflectance_at(self, wavelengths_nm=None) -> np.ndarray:
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
    def brdf(self, wi, wo, wavelengths_nm=None, *, threads: int | None = None) -> np.ndarray:
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
        a, b = self._weights(self.reflectance_at(wavelengths_nm))
        return self._native.evaluate(
            np.ascontiguousarray(wi),
            np.ascontiguousarray(wo),
            np.ascontiguousarray(a),
            np.ascontiguousarray(b),
            threads,
        )

    def albedo(self, wi, wavelengths_nm=None) -> np.ndarray:
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

    def _albedo_mu(self, mu: np.ndarray, wavelengths_nm) -> np.ndarray:
        """Albedo (N, W) at incidence cosines μ (no horizon test: μ ≤ 0 gives the limit μ → 0⁺).

        A(μ) and the diffuse term's albedo are linear in the interpolant's μ_i weights, so their
        node values interpolate exactly.
        """
        b0, b1, t = _bracket(self._nodes, mu)
        spatial = (1 - t) * self._albedo_nodes[b0] + t * self._albedo_nodes[b1]
        diffuse = (1 - t) * self._profile_albedo_nodes[b0] + t * self._profile_albedo_nodes[b1]
        a, b = self._weights(self.reflectance_at(wavelengths_nm))
        return spatial[:, None] * a[None, :] + diffuse[:, None] * b[None, :]

    # ---- sampling ----------------------------------------------------------------------------
    def _cells(self):
        """Bounds of the outgoing cells in the frame of the incident azimuth: z0, z1 (μ) and the
        Δφ range, one row per cell in patch order (cap, then band by band)."""
        h = self.spatial.hemisphere
        z0, z1 = h.bounds[:, 0], h.bounds[:, 1]
        step = 2.0 * math.pi / self._slices
        centre = h.slice * step
        phi0 = np.where(h.band == 0, 0.0, centre - step / 2)
        phi1 = np.where(h.band == 0, 2.0 * math.pi, centre + step / 2)
        return z0, z1, phi0, phi1

    def _build_sampling_tables(self):
        z0, z1, phi0, phi1 = self._cells()
        r = z0.size
        n = SAMPLING_SUBDIVISIONS
        s = (np.arange(n) + 0.5) / n
        mu = z0[:, None, None] + (z1 - z0)[:, None, None] * s[None, :, None]  # (r, n, 1)
        dphi = phi0[:, None, None] + (phi1 - phi0)[:, None, None] * s[None, None, :]  # (r, 1, n)
        mu, dphi = np.broadcast_arrays(mu, dphi)
        a_ref, b_ref = (float(np.mean(x)) for x in self._weights(self.normal_reflectance))
        solid = (z1 - z0) * (phi1 - phi0)
        pmf = np.empty((len(self._nodes), r))
        for b, mu_i in enumerate(self._nodes):
            g, pp = self._native.evaluate_mu(np.full(mu.size, mu_i), mu.ravel(), dphi.ravel())
            f = (a_ref * g + b_ref * pp).reshape(mu.shape)
            w = (f * mu).mean(axis=(1, 2)) * solid  # ∫_cell f cos θ_o dω_o (midpoint rule)
            total = w.sum()
            pmf[b] = w / total if total > 0 else solid / solid.sum()  # (cosine-like fallback for a black BRDF)
        self._cell_z0, self._cell_z1, self._cell_phi0, self._cell_phi1 = z0, z1, phi0, phi1
        self._cell_projected = 0.5 * (z1**2 - z0**2) * (phi1 - phi0)  # W_cell = ∫ cos θ dω
        self._pmf = pmf
        cdf = np.cumsum(pmf, axis=1)
        cdf /= cdf[:, -1:]
        self._cdf = cdf
        # Lower bounds of the bands in μ (band order), for locating the cell of a direction.
        first = np.concatenate([[0], 1 + self._slices * np.arange(self._stacks - 1)])
        self._band_z0 = z0[first]

    def _cell_of(self, mu_o: np.ndarray, dphi: np.ndarray) -> np.ndarray:
        band = np.sum(self._band_z0[None, :] > mu_o[:, None], axis=1)  # bands wholly above μ_o
        band = np.minimum(band, self._stacks - 1)
        k = (
            np.floor(np.mod(dphi, 2.0 * math.pi) * (self._slices / (2.0 * math.pi)) + 0.5).astype(np.int64)
            % self._slices
        )
        return np.where(band == 0, 0, 1 + (band - 1) * self._slices + k)

    def _frame(self, wi, wo):
        wi, wo = _directions("wi", wi), _directions("wo", wo)
        ni, no = np.linalg.norm(wi, axis=1), np.linalg.norm(wo, axis=1)
        for name, w, nrm in (("wi", wi, ni), ("wo", wo, no)):
            bad = ~((nrm > 0) & np.isfinite(nrm))
            if bad.any():
                raise ParameterError(name, w[bad][0].tolist(), "non-zero finite directions")
        return wi / ni[:, None], wo / no[:, None]

    def pdf(self, wi, wo, method: str = "brdf") -> np.ndarray:
        """Density of `sample`'s outgoing directions with respect to solid angle, sr⁻¹.

        Parameters
        ----------
        wi, wo : array_like, shape (N, 3)
        method : {'brdf', 'cosine'}

        Returns
        -------
        numpy.ndarray, shape (N,)
            0 where ω_o has z ≤ 0.
        """
        if method not in SAMPLING_METHODS:
            raise ParameterError("method", method, f"one of {SAMPLING_METHODS}")
        wi, wo = self._frame(wi, wo)
        if wi.shape[0] != wo.shape[0]:
            wi, wo = np.broadcast_arrays(wi, wo)
        mu_o = wo[:, 2]
        cosine = np.clip(mu_o, 0.0, None) / math.pi
        if method == "cosine":
            return cosine
        b0, b1, t = _bracket(self._nodes, wi[:, 2])
        dphi = np.arctan2(wo[:, 1], wo[:, 0]) - np.arctan2(wi[:, 1], wi[:, 0])
        cell = self._cell_of(mu_o, dphi)
        tab = ((1 - t) * self._pmf[b0, cell] + t * self._pmf[b1, cell]) * mu_o / self._cell_projected[cell]
        eps = DEFENSIVE_COSINE_SHARE
        return np.where(mu_o > 0, eps * cosine + (1 - eps) * tab, 0.0)

    def sample(self, wi, u1, u2, wavelength_nm=None, method: str = "brdf"):
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
            Follow the tabulated BRDF (module docstring) or the paper's cosine sampling.

        Returns
        -------
        wo : numpy.ndarray, shape (N, 3)
            Unit outgoing directions (z > 0).
        weight : numpy.ndarray, shape (N,) for a scalar wavelength, else (N, W)
            f(ω_i, ω_o, λ) cos θ_o / pdf (0 for incoming directions below the horizon).
        pdf : numpy.ndarray, shape (N,)
            pdf(ω_i, ω_o) with respect to solid angle, sr⁻¹.
        """
        if method not in SAMPLING_METHODS:
            raise ParameterError("method", method, f"one of {SAMPLING_METHODS}")
        wi = _directions("wi", wi)
        n = wi.shape[0]
        u1, u2 = (np.broadcast_to(np.asarray(u, dtype=float), (n,)) for u in (u1, u2))
        for name, u in (("u1", u1), ("u2", u2)):
            if not ((u >= 0) & (u < 1)).all():
                raise ParameterError(name, float(u[~((u >= 0) & (u < 1))][0]), "uniform numbers in [0, 1)")
        wi_unit, _ = self._frame(wi, np.broadcast_to([0.0, 0.0, 1.0], wi.shape))
        phi_i = np.arctan2(wi_unit[:, 1], wi_unit[:, 0])
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
            b0, b1, t = _bracket(self._nodes, wi_unit[t_rows, 2])
            first = v < (1 - t)
            row = np.where(first, b0, b1)
            with np.errstate(divide="ignore", invalid="ignore"):
                v = np.where(first, v / (1 - t), (v - (1 - t)) / t)
            v = np.clip(v, 0.0, np.nextafter(1.0, 0.0))
            cell = np.empty(v.size, dtype=np.int64)
            for b in np.unique(row):
                m = row == b
                cdf = self._cdf[b]
                j = np.searchsorted(cdf, v[m], side="right")
                cell[m] = np.minimum(j, np.flatnonzero(self._pmf[b] > 0)[-1])
            lo = np.where(cell > 0, self._cdf[row, np.maximum(cell - 1, 0)], 0.0)
            width = self._cdf[row, cell] - lo
            with np.errstate(divide="ignore", invalid="ignore"):
                within = np.clip(np.where(width > 0, (v - lo) / width, 0.5), 0.0, 1.0)
            z0, z1 = self._cell_z0[cell], self._cell_z1[cell]
            mu_o[t_rows] = np.sqrt(z0**2 + within * (z1**2 - z0**2))  # density ∝ μ within the cell
            ph0, ph1 = self._cell_phi0[cell], self._cell_phi1[cell]
            phi_o[t_rows] = phi_i[t_rows] + ph0 + u2[t_rows] * (ph1 - ph0)
        mu_o = np.clip(mu_o, np.finfo(float).tiny, 1.0)
        sin_o = np.sqrt(np.maximum(0.0, 1.0 - mu_o**2))
        wo = np.stack([sin_o * np.cos(phi_o), sin_o * np.sin(phi_o), mu_o], axis=1)
        pdf = self.pdf(wi, wo, method)
        scalar = wavelength_nm is not None and np.ndim(wavelength_nm) == 0
        f = self.brdf(wi, wo, None if wavelength_nm is None else np.atleast_1d(wavelength_nm))
        with np.errstate(divide="ignore", invalid="ignore"):
            weight = np.where(pdf[:, None] > 0, f * mu_o[:, None] / pdf[:, None], 0.0)
        return wo, (weight[:, 0] if scalar else weight), pdf

    # ---- regular-grid table -----------------------------------------------------------------
    def table(self, n_mu: int = 32, n_dphi: int = 32, wavelengths_nm=None):
        """The BRDF on a regular grid as an ``xarray.Dataset`` (the layout of `to_table`).

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
            ``f`` (wavelength, mu_i, mu_o, dphi) in sr⁻¹ (hat averages in μ, module docstring),
            ``albedo`` (wavelength, mu_i), ``normal_reflectance`` (wavelength), with units and
            the format attributes.
        """
        import xarray as xr

        import sandlight

        for name, v in (("n_mu", n_mu), ("n_dphi", n_dphi)):
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not 2 <= v <= 4096:
                raise ParameterError(name, v, "an integer in [2, 4096]")
        wl = self.wavelengths_nm if wavelengths_nm is None else np.atleast_1d(np.asarray(wavelengths_nm, dtype=float))
        a, b = self._weights(self.reflectance_at(wl))
        mu = np.linspace(0.0, 1.0, int(n_mu))
        dphi = np.linspace(0.0, math.pi, int(n_dphi))
        # Table values in μ are cos-weighted averages over each table node's interpolation hat
        # (module docstring), by Gauss quadrature on the pieces where the model is linear.
        x, W = self._hat_quadrature(mu)  # points (P,), weights (n_mu, P) normalised per node
        XI, XO, DP = np.meshgrid(x, x, dphi, indexing="ij")
        g, pp = self._native.evaluate_mu(XI.ravel(), XO.ravel(), DP.ravel())
        shape = XI.shape
        g = np.einsum("ix,xyk,jy->ijk", W, g.reshape(shape), W, optimize=True)
        pp = np.einsum("ix,xyk,jy->ijk", W, pp.reshape(shape), W, optimize=True)
        f = a[:, None, None, None] * g[None] + b[:, None, None, None] * pp[None]
        # The model is reciprocal; averaging with the transpose removes the rounding (~1e-16) of the
        # summation order, so that readers may rely on exact symmetry.
        f = 0.5 * (f + f.transpose(0, 2, 1, 3))
        albedo = W @ self._albedo_mu(x, wl)  # the same averages of the model's albedo
        attrs = {
            "title": "Spectral BRDF of a sand sample (sandlight)",
            "format": TABLE_FORMAT,
            "format_version": TABLE_FORMAT_VERSION,
            "sandlight_version": sandlight.__version__,
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
            "conventions": (
                "local frame: z = surface normal; mu = cos(zenith angle); dphi = |phi_o - phi_i| in [0, pi]; "
                "wi points towards the light, wo towards the viewer; f in sr-1 with "
                "L_o = integral of f L_i cos(theta_i) d(omega_i)"
            ),
            "interpolation": (
                "multilinear in (mu_i, mu_o, dphi); f is reciprocal (f[:, i, j, k] == f[:, j, i, k]) "
                "and even in dphi; in mu_i and mu_o each value is the cos-weighted average of the "
                "model over the node's interpolation hat (energy-conserving), in dphi a point sample"
            ),
        }
        ds = xr.Dataset(
            {
                "f": (
                    ("wavelength", "mu_i", "mu_o", "dphi"),
                    f,
                    {"units": "sr-1", "long_name": "bidirectional reflectance distribution function"},
                ),
                "albedo": (
                    ("wavelength", "mu_i"),
                    albedo.T,
                    {"units": "1", "long_name": "directional-hemispherical reflectance of the continuous model"},
                ),
                "normal_reflectance": (
                    ("wavelength",),
                    self.reflectance_at(wl),
                    {
                        "units": "1",
                        "long_name": "directional-hemispherical reflectance at normal incidence (spectral predictor)",
                    },
                ),
            },
            coords={
                "wavelength": ("wavelength", wl, {"units": "nm"}),
                "mu_i": ("mu_i", mu, {"units": "1", "long_name": "cosine of the incident zenith angle"}),
                "mu_o": ("mu_o", mu, {"units": "1", "long_name": "cosine of the outgoing zenith angle"}),
                "dphi": ("dphi", dphi, {"units": "rad", "long_name": "azimuth difference |phi_o - phi_i|"}),
            },
            attrs=attrs,
        )
        return ds

    def _hat_quadrature(self, mu: np.ndarray):
        """Quadrature of ∫ g(μ) h_q(μ) μ dμ / ∫ h_q(μ) μ dμ for the hats h_q of the table nodes μ.

        Each hat's support is cut at the model's μ nodes, where the model is linear between
        cuts, and integrated by 2-point Gauss–Legendre, exact for the cubic g·h_q·μ.

        Returns
        -------
        points : ndarray (P,)
        weights : ndarray (n_mu, P)
            Row q sums to 1 (normalised by ∫ h_q μ dμ).
        """
        cuts = np.unique(np.r_[self._nodes, mu])
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

    def to_table(self, path, n_mu: int = 32, n_dphi: int = 32, wavelengths_nm=None) -> Path:
        """Write the BRDF on a regular grid to NetCDF (format 'sandlight-brdf-table', atomic).

        See `table` for the parameters and docs/spatial-predictor.md for the layout. Returns the
        path written.
        """
        from sandlight.io import atomic_path

        ds = self.table(n_mu, n_dphi, wavelengths_nm)
        path = Path(path)
        with atomic_path(path) as tmp:
            ds.to_netcdf(tmp, engine="h5netcdf", encoding={"f": {"zlib": True, "complevel": 4}})
        return path

    def __repr__(self) -> str:
        return (
            f"SandAppearance({len(self.wavelengths_nm)} wavelengths {self.wavelengths_nm[0]:g}–"
            f"{self.wavelengths_nm[-1]:g} nm, combination={self.combination!r}, r_0={self.reference_reflectance:.4f})"
        )
