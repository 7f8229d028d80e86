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
tables"), and the sampler is the same blend of the levels' samplers (so its pdf stays exact).

Spectral weights. f = a(λ) f̂ + b(λ) P P with (a, b) the combination's weights of r(λ)
(`sandlight.appearance.combination`). r is kept on a regular 1 nm grid spanning the spectral
model's wavelengths (linear interpolation of its nodes, so the 1 nm grid reproduces
`SandAppearance.reflectance_at` exactly when the nodes are whole nanometres, as the shipped
400:700:20 are); outside that range r is held at its end values (Mitsuba samples 360–830 nm).
RGB variants use, per channel c, the weights a_c = Σ_λ w_c(λ) a(λ) with w the CIE 1931 2°
colour-matching functions under illuminant D65 taken to linear sRGB (Rec. 709 primaries) and
normalised so that a(λ) ≡ 1 gives (1, 1, 1): the linear-sRGB albedo colour of the spectral BRDF
under daylight, the convention of Mitsuba's own RGB reflectances. Mono variants use the
luminance row (Y) of the same map. Being linear in (a, b), the projection commutes with the
blend of levels and with the BRDF's angular part.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from sandlight.appearance import DEFENSIVE_COSINE_SHARE, SandAppearance
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
    """Flat arrays of K levels (module docstring); float64 here, float32 once uploaded.

    Attributes
    ----------
    levels : numpy.ndarray (K,)
        Values of the varied parameter at the levels (one level: its own value, or 0).
    nodes_ascending : numpy.ndarray (n,)
        μ of the band grid's nodes, ascending (shared by every level).
    slices : int
        Δφ nodes 2πk/L.
    grid : numpy.ndarray (K·n·n·L,)
        f̂ values, index ((k·n + q_i)·n + q_o)·L + j with q the node in the band grid's (decreasing) order.
    profile : numpy.ndarray (K·n,)
        P at the nodes, sr^-1/2.
    wavelength0_nm : float
        First wavelength of the 1 nm reflectance grid.
    reflectance : numpy.ndarray (K·M,)
        r(λ) on the 1 nm grid (M points), clipped to [0, 1] as `SandAppearance` does.
    reference_reflectance : numpy.ndarray (K,)
        r_0 of each level.
    product : bool
        True for the paper's 'product' combination (b = 0).
    rgb_a, rgb_b : numpy.ndarray (K, 3)
        The RGB variants' weights (`rgb_projection`).
    cell_z0, cell_z1, cell_phi0, cell_phi1, cell_projected : numpy.ndarray (R,)
        The sampler's outgoing cells (`sandlight.appearance.sampling.outgoing_cells`) and their
        projected solid angles, sr.
    band_z0 : numpy.ndarray (stacks,)
        Lower μ bound of each band (to locate a direction's cell).
    cdf : numpy.ndarray (K·n·R,)
        Running sums of the cell laws per level and μ node, float32-exact (last 1).
    pmf : numpy.ndarray (K·n·R,)
        Differences of `cdf` (the probabilities the float32 sampler realises, to ~10⁻⁷).
    last_cell : numpy.ndarray (K·n,), int
        Last cell of positive probability of each law.
    cosine_share : float
        ε of the defensive cosine mixture.
    """

    levels: np.ndarray
    nodes_ascending: np.ndarray
    slices: int
    grid: np.ndarray
    profile: np.ndarray
    wavelength0_nm: float
    reflectance: np.ndarray
    reference_reflectance: np.ndarray
    product: bool
    rgb_a: np.ndarray
    rgb_b: np.ndarray
    cell_z0: np.ndarray
    cell_z1: np.ndarray
    cell_phi0: np.ndarray
    cell_phi1: np.ndarray
    cell_projected: np.ndarray
    band_z0: np.ndarray
    cdf: np.ndarray
    pmf: np.ndarray
    last_cell: np.ndarray
    cosine_share: float

    @property
    def n_levels(self) -> int:
        return int(self.levels.size)

    @property
    def n_nodes(self) -> int:
        return int(self.nodes_ascending.size)

    @property
    def n_cells(self) -> int:
        return int(self.cell_z0.size)

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
            The appearances do not share the spatial model's nodes, wavelengths or combination.
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
        wl = first.wavelengths_nm
        fine = np.arange(np.floor(wl[0]), np.ceil(wl[-1]) + 1.0)
        proj = rgb_projection()
        rgb_a, rgb_b, refl = [], [], []
        for app in apps:
            refl.append(np.interp(fine, wl, app.normal_reflectance))
            # a, b on Mitsuba's whole range (r held outside the model's), projected to RGB.
            r_wide = np.interp(PROJECTION_WAVELENGTHS_NM, wl, app.normal_reflectance)
            a, b = app.combination_terms.weights(r_wide)
            rgb_a.append(proj @ a)
            rgb_b.append(proj @ b)
        sampling = [app.sampling_tables for app in apps]
        cdf = np.stack([s.cdf for s in sampling]).astype(np.float32)
        cdf[..., -1] = 1.0
        pmf = np.diff(cdf.astype(np.float64), axis=-1, prepend=0.0)
        positive = pmf > 0
        last = positive.shape[-1] - 1 - np.argmax(positive[..., ::-1], axis=-1)
        s0 = sampling[0]
        return cls(
            levels=levels,
            nodes_ascending=nodes[::-1].copy(),
            slices=first.band_grid.slices,
            grid=np.concatenate([app.band_grid.grid.ravel() for app in apps]),
            profile=np.concatenate([app.combination_terms.profile for app in apps]),
            wavelength0_nm=float(fine[0]),
            reflectance=np.concatenate(refl),
            reference_reflectance=np.array([app.reference_reflectance for app in apps]),
            product=first.combination == "product",
            rgb_a=np.array(rgb_a),
            rgb_b=np.array(rgb_b),
            cell_z0=s0.cell_z0,
            cell_z1=s0.cell_z1,
            cell_phi0=s0.cell_phi0,
            cell_phi1=s0.cell_phi1,
            cell_projected=s0.cell_projected,
            band_z0=s0.band_z0,
            cdf=cdf.ravel().astype(np.float64),
            pmf=pmf.ravel(),
            last_cell=last.ravel().astype(np.int64),
            cosine_share=DEFENSIVE_COSINE_SHARE,
        )
