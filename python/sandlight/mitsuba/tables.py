"""The arrays the Mitsuba plugin evaluates and samples: one or more `SandAppearance` levels, flat.

Public objects
--------------
PluginTables
    Every level's band grid f̂, diffuse profile P, reflectance r(λ), r_0 and sampling laws, on
    the shared μ nodes, as flat float arrays (NumPy; `sandlight.mitsuba.bsdf` uploads them).
rgb_projection
    The matrix that turns a spectral weight on a 1 nm grid into linear sRGB (the RGB variants'
    conversion).

A *level* is the `SandAppearance` of one value of the parameter a texture varies (16
saturations for the drying beach); an untextured plugin has one level. Between two levels the
plugin blends the BRDFs linearly, as sandlight's renderer does (docs/rendering.md, "BRDF
tables"). A level holds S *shapes* (`SandAppearance.shapes`: one, or for the dune family the
shapes at the anchors of the sand's reflectance, `sandlight.appearance.shapes`); levels with fewer
shapes than the most are padded with shapes of zero weight (anchor +∞). The spectral variants
blend a level's shapes per wavelength as `ShapeSeries.weights` does: linear in log r between the
two anchors around log r(λ), each shape combined with r by its own r_0, and inside the anchors'
range the product r f̂. `ShapeSeries` falls back to the shapes' own combinations where that
product's albedo would exceed 1; the tables refuse an appearance for which that can happen
anywhere between two anchors (checked on 257 points per bracket), so the plugin needs no
fallback.

Sampling tables. f is linear in the given direction's μ between its two nodes (and in the
level), so at the reference spectrum — the mean over the model's wavelengths of the weights,
(ā_s, b̄_s) of every shape s, as `SandAppearance`'s sampler uses — f_ref is the trilinear
interpolant of one *reference grid* per level, H_k[q_i, q_o, j] = Σ_s ā_s F_{k,s}[q_i, q_o, j] +
b̄_s P_{k,s}[q_i] P_{k,s}[q_o] (the product of two interpolated profiles is the bilinear
interpolant of their node products), and a blend Σ_c w_c h_c of at most four *rows* c (level k ×
given-side node q), each row h_{k,q}(μ, Δφ) = H_k[q, ·, ·] bilinear in (μ, Δφ) on every *cell*
between consecutive sampled-side nodes (μ below the lowest node: the held value) and Δφ nodes.
A row's cell weight is its exact integral
W = ∫∫ h μ dμ dΔφ = (ΔΔφ/2)[(h₀₀ + h₀₁) Δμ(2μ₀ + μ₁)/6 + (h₁₀ + h₁₁) Δμ(μ₀ + 2μ₁)/6], and the row's
albedo A = Σ W (= Σ_s ā_s A_f̂s(node) + b̄_s A_PPs(node), the albedo at the reference spectrum).
The sampler (`sandlight.mitsuba.bsdf`) picks row c with probability w_c A_c / Σ w A, a cell by
W / A, then Δφ from the cell's linear marginal and μ from the conditional (linear × μ), both
exactly, so that pdf = f_ref cos θ / Σ_c w_c A_c: proportional to the BRDF at the reference
spectrum, as sandlight's renderer samples its tables (docs/rendering.md, "Sampling that follows
the table, exactly"), with no defensive cosine share (f = 0 wherever f_ref = 0).

Spectral weights. f = Σ_s a_s(λ) f̂_s + b_s(λ) P_s P_s with (a_s, b_s) the shapes' weights of
r(λ) (`sandlight.appearance.shapes`; one shape: the combination's,
`sandlight.appearance.combination`). r is kept on a regular 1 nm grid spanning the spectral
model's wavelengths (linear interpolation of its nodes, so the 1 nm grid reproduces
`SandAppearance.reflectance_at` exactly when the nodes are whole nanometres, as the shipped
400:700:20 are); outside that range r is held at its end values (Mitsuba samples 360–830 nm).
RGB variants use, per channel c and shape, the weights a_c = Σ_λ w_c(λ) a(λ) with w the CIE
1931 2° colour-matching functions under illuminant D65 taken to linear sRGB (Rec. 709 primaries) and
normalised so that a(λ) ≡ 1 gives (1, 1, 1): the linear-sRGB albedo colour of the spectral BRDF
under daylight, the convention of Mitsuba's own RGB reflectances. Mono variants use the
luminance row (Y) of the same map. Being linear in (a, b), the projection commutes with the
blend of levels and with the BRDF's angular part.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from sandlight.appearance import SandAppearance
from sandlight.errors import ParameterError

__all__ = ["PluginTables", "rgb_projection", "PROJECTION_WAVELENGTHS_NM"]

#: The 1 nm grid of the RGB projection: Mitsuba's spectral range.
PROJECTION_WAVELENGTHS_NM = np.arange(360.0, 831.0)


@functools.cache
def rgb_projection() -> np.ndarray:
    """Matrix (3, 471): linear sRGB of a reflectance spectrum on `PROJECTION_WAVELENGTHS_NM`.

    Rows: R, G, B; row sums 1 (a white reflectance maps to (1, 1, 1)). CIE 1931 2° observer,
    illuminant D65 (both from colour-science, interpolated to 1 nm), IEC 61966-2-1 XYZ → linear
    sRGB matrix.
    """
    import colour

    wl = PROJECTION_WAVELENGTHS_NM
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    xyz_bar = np.stack([np.interp(wl, cmfs.wavelengths, cmfs.values[:, i]) for i in range(3)])
    d65 = colour.SDS_ILLUMINANTS["D65"]
    e = np.interp(wl, d65.wavelengths, d65.values)
    weights = xyz_bar * e[None, :]  # (3, W): XYZ of a reflectance under D65, up to a constant
    m = np.asarray(colour.RGB_COLOURSPACES["sRGB"].matrix_XYZ_to_RGB, dtype=float)
    rgb = m @ weights
    return rgb / rgb.sum(axis=1, keepdims=True)


@dataclass(frozen=True, eq=False)
class PluginTables:
    """Flat arrays of K levels of S shapes (module docstring); float64 here, float32 once uploaded.

    Attributes
    ----------
    levels : numpy.ndarray (K,)
        Values of the varied parameter at the levels (one level: its own value, or 0).
    nodes_ascending : numpy.ndarray (n,)
        μ of the band grid's nodes, ascending (shared by every level).
    slices : int
        Δφ nodes 2πk/L.
    shapes : int
        S, the shapes of a level (the most of any level; the others padded).
    grid : numpy.ndarray (K·S·n·n·L,)
        f̂ values, index (((k·S + s)·n + q_i)·n + q_o)·L + j with q the node in the band grid's
        (decreasing) order.
    profile : numpy.ndarray (K·S·n,)
        P at the nodes, sr^-1/2.
    log_anchor : numpy.ndarray (K·S,)
        log of each shape's reflectance, ascending within a level (+∞ for padding; 0 for a
        level of one shape).
    anchor_range : numpy.ndarray (K·2,)
        The first and last finite ``log_anchor`` of each level.
    wavelength0_nm : float
        First wavelength of the 1 nm reflectance grid.
    reflectance : numpy.ndarray (K·M,)
        r(λ) on the 1 nm grid (M points), clipped to [0, 1] as `SandAppearance` does.
    reference_reflectance : numpy.ndarray (K·S,)
        r_0 of each shape (1 for padding).
    product : bool
        True for the paper's 'product' combination (b = 0).
    rgb_a, rgb_b : numpy.ndarray (K·S, 3)
        The RGB variants' weights of every shape (`rgb_projection`).
    reference_grid : numpy.ndarray (K·n·n·L,)
        H_k, the BRDF at the reference spectrum on the nodes (module docstring).
    row_cdf : numpy.ndarray (K·n·n·L,)
        Running sums of W / A over the cells (m, j) of each row (k, q), float32-exact (last 1);
        cell index m·L + j, m the sampled-side μ interval (0: [0, lowest node]).
    row_albedo : numpy.ndarray (K·n,)
        A of each row, dimensionless.
    last_cell : numpy.ndarray (K·n,), int
        Last cell of positive weight of each row.
    """

    levels: np.ndarray
    nodes_ascending: np.ndarray
    slices: int
    shapes: int
    grid: np.ndarray
    profile: np.ndarray
    log_anchor: np.ndarray
    anchor_range: np.ndarray
    wavelength0_nm: float
    reflectance: np.ndarray
    reference_reflectance: np.ndarray
    product: bool
    rgb_a: np.ndarray
    rgb_b: np.ndarray
    reference_grid: np.ndarray
    row_cdf: np.ndarray
    row_albedo: np.ndarray
    last_cell: np.ndarray

    @property
    def n_levels(self) -> int:
        return int(self.levels.size)

    @property
    def n_nodes(self) -> int:
        return int(self.nodes_ascending.size)

    @property
    def n_cells(self) -> int:
        """Cells of a row: n μ intervals × L Δφ intervals."""
        return self.n_nodes * self.slices

    @property
    def n_wavelengths(self) -> int:
        """Points M of the 1 nm reflectance grid."""
        return self.reflectance.size // self.n_levels

    @classmethod
    def build(cls, appearances: Sequence[SandAppearance], levels: Sequence[float] | None = None) -> PluginTables:
        """Tables of the appearances (one per level, in increasing level order).

        Raises
        ------
        ParameterError
            The appearances do not share the spatial model's nodes, wavelengths or combination, or
            the shapes of one would need `ShapeSeries.weights`' energy fallback (`_check_product_blend`).
        """
        apps = list(appearances)
        levels = np.zeros(1) if levels is None else np.asarray(levels, dtype=float)
        first = apps[0]
        nodes = first.band_grid.nodes
        for app in apps[1:]:
            same = (
                app.band_grid.grid.shape == first.band_grid.grid.shape
                and np.array_equal(app.band_grid.nodes, nodes)
                and np.array_equal(app.wavelengths_nm, first.wavelengths_nm)
                and app.combination == first.combination
            )
            if not same:
                raise ParameterError(
                    "levels", repr(app), "appearances of one spatial model, spectral model and combination"
                )
        for app in apps:
            _check_product_blend(app)
        n_shapes = max(len(app.shapes.shapes) for app in apps)
        wl = first.wavelengths_nm
        fine = np.arange(np.floor(wl[0]), np.ceil(wl[-1]) + 1.0)
        proj = rgb_projection()
        grid, profile, log_anchor, ranges, r0, rgb_a, rgb_b, refl, ref_grids = [], [], [], [], [], [], [], [], []
        for app in apps:
            shapes = list(app.shapes.shapes)
            refl.append(np.interp(fine, wl, app.normal_reflectance))
            # a, b on Mitsuba's whole range (r held outside the model's), projected to RGB.
            r_wide = np.interp(PROJECTION_WAVELENGTHS_NM, wl, app.normal_reflectance)
            a_wide, b_wide = app.shapes.weights(r_wide)
            a_ref, b_ref = app.reference_weights
            ref = np.zeros_like(first.band_grid.grid)
            for i, shape in enumerate(shapes):
                p = shape.combination.profile
                ref += a_ref[i] * shape.band_grid.grid + b_ref[i] * p[:, None, None] * p[None, :, None]
            ref_grids.append(ref)
            pad = n_shapes - len(shapes)
            grid += [sh.band_grid.grid.ravel() for sh in shapes] + [np.zeros(first.band_grid.grid.size)] * pad
            profile += [sh.combination.profile for sh in shapes] + [np.zeros(nodes.size)] * pad
            logs = [math.log(sh.reflectance) for sh in shapes] if len(shapes) > 1 else [0.0]
            log_anchor += logs + [math.inf] * pad
            ranges.append((logs[0], logs[-1]))
            r0 += [sh.combination.reference_reflectance for sh in shapes] + [1.0] * pad
            rgb_a += [proj @ a_wide[:, i] for i in range(len(shapes))] + [np.zeros(3)] * pad
            rgb_b += [proj @ b_wide[:, i] for i in range(len(shapes))] + [np.zeros(3)] * pad
        rows = np.stack([_row_cells(ref, nodes) for ref in ref_grids])  # (K, n, n·L)
        albedo = rows.sum(axis=-1)
        with np.errstate(invalid="ignore", divide="ignore"):
            cdf = np.where(albedo[..., None] > 0, np.cumsum(rows, axis=-1) / albedo[..., None], 1.0)
        cdf = cdf.astype(np.float32)
        cdf[..., -1] = 1.0
        positive = np.diff(cdf.astype(np.float64), axis=-1, prepend=0.0) > 0
        last = positive.shape[-1] - 1 - np.argmax(positive[..., ::-1], axis=-1)
        return cls(
            levels=levels,
            nodes_ascending=nodes[::-1].copy(),
            slices=first.band_grid.slices,
            shapes=n_shapes,
            grid=np.concatenate(grid),
            profile=np.concatenate(profile),
            log_anchor=np.array(log_anchor),
            anchor_range=np.array(ranges).ravel(),
            wavelength0_nm=float(fine[0]),
            reflectance=np.concatenate(refl),
            reference_reflectance=np.array(r0),
            product=first.combination == "product",
            rgb_a=np.array(rgb_a),
            rgb_b=np.array(rgb_b),
            reference_grid=np.concatenate([g.ravel() for g in ref_grids]),
            row_cdf=cdf.ravel().astype(np.float64),
            row_albedo=albedo.ravel(),
            last_cell=last.ravel().astype(np.int64),
        )


#: Points per bracket between two anchors at which `_check_product_blend` tests the product.
PRODUCT_CHECK_POINTS = 257


def _check_product_blend(app: SandAppearance) -> None:
    """Refuse (`ParameterError` naming ``appearances``) an appearance whose blended shapes would,
    somewhere between two anchors, need `ShapeSeries.weights`' fallback from the product (its
    albedo r Σ w_s A_s(μ) above 1), which the plugin does not implement."""
    x = np.log(app.shapes.reflectances)
    if x.size < 2:
        return
    # PRODUCT_CHECK_POINTS per bracket, without the range's two ends (outside the product's rule).
    r = np.exp(np.concatenate([np.linspace(x[j], x[j + 1], PRODUCT_CHECK_POINTS) for j in range(x.size - 1)]))[1:-1]
    if not app.shapes.product(r).all():
        raise ParameterError(
            "appearances",
            repr(app),
            "appearances whose shapes blend as a product between their anchors (albedo ≤ 1); "
            "use SandAppearance(..., shape='fixed') for this sand",
        )


def _row_cells(reference: np.ndarray, nodes: np.ndarray) -> np.ndarray:
    """W of every cell of every row of one level (module docstring), shape (n, n·L).

    ``reference`` H[q_i, q_o, j], the level's reference grid, in the band grid's (decreasing)
    node order; rows are the given side's nodes q, cells (m, j) with m the sampled side's μ
    interval in ascending order (0: [0, lowest node], the held value; m ≥ 1: [asc[m − 1], asc[m]]).
    """
    n, _, L = reference.shape
    asc = nodes[::-1]
    h = reference[:, ::-1, :]  # h[q, i, j]: the row function at ascending node i and Δφ node j
    i0 = np.r_[0, np.arange(n - 1)]
    i1 = np.arange(n)
    mu0 = np.r_[0.0, asc[:-1]]
    mu1 = asc
    dmu = mu1 - mu0
    c_a = dmu * (2 * mu0 + mu1) / 6.0  # ∫ (1 − s) μ dμ over the interval
    c_b = dmu * (mu0 + 2 * mu1) / 6.0  # ∫ s μ dμ
    j1 = (np.arange(L) + 1) % L
    low = h[:, i0, :] + h[:, i0][:, :, j1]
    high = h[:, i1, :] + h[:, i1][:, :, j1]
    w = (np.pi / L) * (low * c_a[None, :, None] + high * c_b[None, :, None])  # Δφ/2 = π/L
    return w.reshape(n, n * L)
