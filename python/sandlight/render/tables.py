"""Spectral BRDF tables as the renderer consumes them, and stacks of them for texture maps.

The renderer shades with *tables*, never with a model object: f(λ, μ_i, μ_o, Δφ) in sr⁻¹ on a
rectilinear grid, as in the 'sandlight-brdf-table' files that `SandAppearance.to_table` writes
(format, writer and reader: `sandlight.appearance.table_file`):

=============  ==============================  ============================================
name           dimensions / units              meaning
=============  ==============================  ============================================
``f``          (wavelength, mu_i, mu_o, dphi)  BRDF, sr⁻¹, ≥ 0
``wavelength`` nm, ascending                   wavelengths of the table
``mu_i``       cos θ_i, ascending, 0 … 1       cosine of the light's zenith angle
``mu_o``       cos θ_o, ascending, 0 … 1       cosine of the viewer's zenith angle
``dphi``       rad, ascending, 0 … π           φ_o − φ_i folded into [0, π]; 0 = backscatter
=============  ==============================  ============================================

A :class:`BrdfTable` holds one or more such tables on the same grid, the *levels* of a
one-parameter family (e.g. 16 degrees of saturation, ``level_name="saturation"``). A ground point
with parameter value v gets the linear blend of the two levels around v (the level coordinate is
``np.interp(v, level_values, range(n_levels))``). A file carries the level as an extra leading
dimension of ``f`` (any name, with a coordinate of the level values).

Constructors: :meth:`BrdfTable.lambertian` (f = a(λ)/π), :meth:`BrdfTable.oren_nayar` (an
analytic rough-diffuse BRDF with a backscatter lobe, for tests), :meth:`BrdfTable.from_function`
(tabulate any ``brdf(wi, wo, wavelengths_nm)`` on a grid), :meth:`BrdfTable.from_appearance`
(a ``SandAppearance`` exactly, on its own nodes), :meth:`BrdfTable.from_netcdf`,
:meth:`BrdfTable.stack`.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from sandlight.appearance import table_file
from sandlight.errors import ModelFileError, ParameterError

if TYPE_CHECKING:
    from sandlight.appearance import SandAppearance

__all__ = ["BrdfTable", "DEFAULT_MU", "DEFAULT_DPHI"]

#: Default μ grid of tabulated analytic BRDFs: denser towards grazing, where BRDFs change fast
#: (every 5° of zenith angle; rounding makes cos 90° exactly 0 rather than a second node at 6e-17).
DEFAULT_MU = np.unique(np.round(np.cos(np.radians(np.linspace(90.0, 0.0, 19))), 15))
#: Default Δφ grid: every 15°.
DEFAULT_DPHI = np.radians(np.arange(0.0, 180.1, 15.0))


def _axis(name: str, values: ArrayLike, lo: float, hi: float) -> np.ndarray:
    a = np.asarray(values, dtype=float)
    if a.ndim != 1 or a.size < 2 or not np.isfinite(a).all() or (np.diff(a) <= 0).any():
        raise ParameterError(name, values, "a strictly ascending 1-D array of at least 2 finite values")
    if abs(a[0] - lo) > 1e-9 or abs(a[-1] - hi) > 1e-9:
        raise ParameterError(name, f"[{a[0]:g} … {a[-1]:g}]", f"an axis from {lo:g} to {hi:g} inclusive")
    a = a.copy()
    a[0], a[-1] = lo, hi
    return a


@dataclass(frozen=True)
class BrdfTable:
    """A stack of spectral BRDF tables on one grid.

    Attributes
    ----------
    f : numpy.ndarray, shape (n_levels, n_wavelengths, n_mu_i, n_mu_o, n_dphi)
        BRDF values, sr⁻¹, finite and ≥ 0.
    wavelength_nm, mu_i, mu_o, dphi : numpy.ndarray
        Axes (nm; cosines in [0, 1] from 0 to 1; radians from 0 to π), strictly ascending.
    level_values : numpy.ndarray, shape (n_levels,)
        Parameter value of each level, strictly ascending (0 for a single table).
    level_name : str
        What the levels vary (``"saturation"``, ``"hematite_ratio"``, or ``"level"``).
    source : str
        Where the values come from (shown in output metadata).
    """

    f: np.ndarray
    wavelength_nm: np.ndarray
    mu_i: np.ndarray
    mu_o: np.ndarray
    dphi: np.ndarray
    level_values: np.ndarray
    level_name: str = "level"
    source: str = ""

    def __post_init__(self) -> None:
        wl = np.asarray(self.wavelength_nm, dtype=float)
        if wl.ndim != 1 or wl.size < 1 or not np.isfinite(wl).all() or (np.diff(wl) <= 0).any():
            raise ParameterError(
                "wavelength_nm", self.wavelength_nm, "a strictly ascending 1-D array of wavelengths in nm"
            )
        object.__setattr__(self, "wavelength_nm", wl)
        object.__setattr__(self, "mu_i", _axis("mu_i", self.mu_i, 0.0, 1.0))
        object.__setattr__(self, "mu_o", _axis("mu_o", self.mu_o, 0.0, 1.0))
        object.__setattr__(self, "dphi", _axis("dphi", self.dphi, 0.0, np.pi))
        f = np.asarray(self.f, dtype=float)
        if f.ndim == 4:
            f = f[np.newaxis]
        shape = (wl.size, self.mu_i.size, self.mu_o.size, self.dphi.size)
        if f.ndim != 5 or f.shape[1:] != shape:
            raise ParameterError(
                "f",
                f"array of shape {np.shape(self.f)}",
                f"shape (levels, {', '.join(map(str, shape))}) = (levels, wavelength, mu_i, mu_o, dphi)",
            )
        if not np.isfinite(f).all():
            raise ParameterError("f", "an array containing NaN or inf", "finite BRDF values in sr⁻¹")
        if (f < 0).any():
            raise ParameterError("f", float(f.min()), "BRDF values ≥ 0 sr⁻¹")
        levels = np.atleast_1d(np.asarray(self.level_values, dtype=float))
        if levels.shape != (f.shape[0],) or not np.isfinite(levels).all() or (np.diff(levels) <= 0).any():
            raise ParameterError(
                "level_values", self.level_values, f"{f.shape[0]} strictly ascending finite values, one per level"
            )
        object.__setattr__(self, "f", f)
        object.__setattr__(self, "level_values", levels)
        for a in (self.f, self.wavelength_nm, self.mu_i, self.mu_o, self.dphi, self.level_values):
            a.setflags(write=False)

    @property
    def n_levels(self) -> int:
        """Number of tables in the stack."""
        return self.f.shape[0]

    def __repr__(self) -> str:
        # Shapes and ranges, never the arrays (a table holds up to millions of values).
        levels = (
            f"{self.level_values[0]:g}"
            if self.n_levels == 1
            else (f"{self.level_values[0]:g}…{self.level_values[-1]:g}")
        )
        wl = self.wavelength_nm
        return (
            f"BrdfTable({self.n_levels} level{'s' if self.n_levels > 1 else ''} ({self.level_name} {levels}), "
            f"{wl.size} wavelength{'s' if wl.size > 1 else ''} {wl[0]:g}–{wl[-1]:g} nm, "
            f"mu_i × mu_o × dphi = {self.mu_i.size} × {self.mu_o.size} × {self.dphi.size}, "
            f"f in [{self.f.min():.4g}, {self.f.max():.4g}] sr⁻¹, source={self.source!r})"
        )

    # --- constructors --------------------------------------------------------------------------

    @classmethod
    def lambertian(
        cls,
        albedo: ArrayLike,
        wavelength_nm: ArrayLike,
        *,
        level_values: ArrayLike | None = None,
        level_name: str = "level",
        source: str = "Lambertian",
    ) -> BrdfTable:
        """f = a(λ)/π at every angle.

        Parameters
        ----------
        albedo : array_like, shape (n_wavelengths,) or (n_levels, n_wavelengths)
            Hemispherical albedo a in [0, 1] of each level at each wavelength.
        wavelength_nm : array_like
            Wavelengths, nm.
        level_values : array_like, optional
            One value per level (default 0, 1, 2, …).
        """
        wl = np.atleast_1d(np.asarray(wavelength_nm, dtype=float))
        a = np.asarray(albedo, dtype=float)
        if a.ndim == 0:
            a = np.full(wl.shape, float(a))
        a = np.atleast_2d(a)
        if a.shape[1] != wl.size or not np.isfinite(a).all() or (a < 0).any() or (a > 1).any():
            raise ParameterError("albedo", albedo, f"values in [0, 1], shape ({wl.size},) or (levels, {wl.size})")
        mu = np.array([0.0, 1.0])
        dphi = np.array([0.0, np.pi])
        f = np.broadcast_to((a / np.pi)[:, :, None, None, None], a.shape + (2, 2, 2)).copy()
        levels = np.arange(a.shape[0], dtype=float) if level_values is None else level_values
        return cls(f, wl, mu, mu, dphi, levels, level_name, source)

    @classmethod
    def oren_nayar(
        cls,
        albedo: ArrayLike,
        sigma_deg: float,
        wavelength_nm: ArrayLike,
        *,
        mu: ArrayLike = DEFAULT_MU,
        dphi: ArrayLike = DEFAULT_DPHI,
        max_theta_deg: float = 89.0,
    ) -> BrdfTable:
        """The qualitative Oren–Nayar (1994) model of a rough diffuse surface, tabulated.

        f = a/π · (A + B · max(0, cos Δφ) · sin α · tan β), α = max(θ_i, θ_o), β = min(θ_i, θ_o),
        A = 1 − 0.5 σ²/(σ² + 0.33), B = 0.45 σ²/(σ² + 0.09) (Oren & Nayar 1994, Eq. 30). It is
        reciprocal and brightest towards the light (Δφ = 0): a backscatter lobe like that of sand.
        tan β diverges when both directions graze; angles are capped at ``max_theta_deg``.

        Parameters
        ----------
        albedo : float or array_like, shape (n_wavelengths,)
            Albedo a(λ) in [0, 1].
        sigma_deg : float
            Slope roughness σ in [0, 60] degrees (0 is Lambertian).
        """
        if not (0.0 <= float(sigma_deg) <= 60.0):
            raise ParameterError("sigma_deg", sigma_deg, "a roughness in [0, 60] degrees")
        wl = np.atleast_1d(np.asarray(wavelength_nm, dtype=float))
        a = np.broadcast_to(np.asarray(albedo, dtype=float), wl.shape)
        if not np.isfinite(a).all() or (a < 0).any() or (a > 1).any():
            raise ParameterError("albedo", albedo, "values in [0, 1]")
        s2 = np.radians(float(sigma_deg)) ** 2
        big_a = 1.0 - 0.5 * s2 / (s2 + 0.33)
        big_b = 0.45 * s2 / (s2 + 0.09)
        mu = np.asarray(mu, dtype=float)
        dp = np.asarray(dphi, dtype=float)
        cap = np.radians(max_theta_deg)
        th = np.minimum(np.arccos(np.clip(mu, 0.0, 1.0)), cap)
        ti, to = np.meshgrid(th, th, indexing="ij")
        alpha, beta = np.maximum(ti, to), np.minimum(ti, to)
        shape = big_a + big_b * np.maximum(0.0, np.cos(dp))[None, None, :] * (np.sin(alpha) * np.tan(beta))[:, :, None]
        f = (a / np.pi)[:, None, None, None] * shape[None]
        return cls(f, wl, mu, mu, dp, [0.0], "level", f"Oren-Nayar sigma={float(sigma_deg):g} deg")

    @classmethod
    def from_function(
        cls,
        brdf: Callable,
        wavelength_nm: ArrayLike,
        *,
        mu: ArrayLike = DEFAULT_MU,
        dphi: ArrayLike = DEFAULT_DPHI,
        source: str = "",
        min_mu: float = 1e-3,
    ) -> BrdfTable:
        """Tabulate ``brdf(wi, wo, wavelengths_nm) -> (..., n_wavelengths)`` (directions in the
        local frame, z the normal, wi towards the light) on the grid. Nodes at μ = 0 are evaluated
        at μ = ``min_mu`` (a model may refuse exactly horizontal directions)."""
        wl = np.atleast_1d(np.asarray(wavelength_nm, dtype=float))
        mu = np.asarray(mu, dtype=float)
        dp = np.asarray(dphi, dtype=float)
        m = np.clip(mu, min_mu, 1.0)
        s = np.sqrt(1.0 - m * m)
        mi, mo, pp = np.meshgrid(np.arange(mu.size), np.arange(mu.size), np.arange(dp.size), indexing="ij")
        wi = np.stack([s[mi], np.zeros(mi.shape), m[mi]], axis=-1)
        wo = np.stack([s[mo] * np.cos(dp[pp]), s[mo] * np.sin(dp[pp]), m[mo]], axis=-1)
        values = np.asarray(brdf(wi.reshape(-1, 3), wo.reshape(-1, 3), wl), dtype=float)
        if values.shape != (wi.size // 3, wl.size):
            raise ParameterError(
                "brdf",
                f"a function returning shape {values.shape}",
                f"a function returning shape ({wi.size // 3}, {wl.size})",
            )
        f = np.moveaxis(values.reshape(mu.size, mu.size, dp.size, wl.size), -1, 0)
        return cls(
            np.maximum(f, 0.0), wl, mu, mu, dp, [0.0], "level", source or getattr(brdf, "__qualname__", "function")
        )

    @classmethod
    def from_appearance(
        cls,
        appearance: SandAppearance,
        wavelength_nm: ArrayLike,
        *,
        level_value: float = 0.0,
        level_name: str = "level",
    ) -> BrdfTable:
        """Tabulate a `sandlight.SandAppearance` exactly, on the nodes of its own interpolant.

        `SandAppearance.brdf` is trilinear in (μ_i, μ_o, Δφ) between its spatial model's nodes
        (band centroids plus the cap's step, held constant below the lowest centroid; even in Δφ
        with nodes every 2π/L), so a table with exactly those nodes (plus μ = 0, and Δφ = π when L
        is odd) reproduces it everywhere under the renderer's trilinear lookup: no resampling
        error, the wet sand's narrow mirror peaks keep their height, width and energy.
        Resampling it on another grid instead either spreads the peak (too much energy next to
        it) or misses it.

        Parameters
        ----------
        appearance : sandlight.SandAppearance
        wavelength_nm : array_like
            Wavelengths of the table, nm, within the appearance model's range.
        level_value : float
            Level value of this table (for `stack`).
        level_name : str
        """
        # The interpolant's μ nodes (descending, 1 first) and azimuth slices;
        # tests/render/test_render_appearance.py checks the reproduction.
        nodes = np.asarray(appearance.band_grid.nodes, dtype=float)
        slices = int(appearance.band_grid.slices)
        mu = np.unique(np.r_[0.0, nodes, 1.0])
        dphi = 2.0 * np.pi * np.arange(slices // 2 + 1) / slices
        dphi = np.r_[dphi[dphi < np.pi - 1e-9], np.pi]
        table = cls.from_function(
            appearance.brdf,
            wavelength_nm,
            mu=mu,
            dphi=dphi,
            min_mu=0.5 * float(nodes.min()),
            source=f"SandAppearance ({appearance.combination}), tabulated on its own nodes",
        )
        return cls(
            table.f,
            table.wavelength_nm,
            table.mu_i,
            table.mu_o,
            table.dphi,
            [float(level_value)],
            level_name,
            table.source,
        )

    @classmethod
    def stack(cls, tables: Sequence[BrdfTable], level_values: ArrayLike, level_name: str) -> BrdfTable:
        """One table per level (single-level tables on identical grids) → a stack."""
        tables = list(tables)
        if not tables:
            raise ParameterError("tables", tables, "at least one BrdfTable")
        first = tables[0]
        for k, t in enumerate(tables):
            if t.n_levels != 1:
                raise ParameterError(f"tables[{k}]", f"a stack of {t.n_levels} levels", "single-level tables")
            for axis in ("wavelength_nm", "mu_i", "mu_o", "dphi"):
                a, b = getattr(t, axis), getattr(first, axis)
                if a.shape != b.shape or not np.allclose(a, b):
                    raise ParameterError(f"tables[{k}].{axis}", a.tolist(), f"the same {axis} grid as tables[0]")
        f = np.concatenate([t.f for t in tables], axis=0)
        return cls(
            f,
            first.wavelength_nm,
            first.mu_i,
            first.mu_o,
            first.dphi,
            level_values,
            level_name,
            "; ".join(dict.fromkeys(t.source for t in tables)),
        )

    @classmethod
    def from_netcdf(cls, path: str | os.PathLike) -> BrdfTable:
        """Read a 'sandlight-brdf-table' file (`SandAppearance.to_table`, `to_netcdf`).

        The format, its version and its layout are checked by
        `sandlight.appearance.table_file.read_table`; a leading level dimension of ``f`` becomes
        the levels.

        Raises
        ------
        FileNotFoundError
            No such file.
        ModelFileError
            Not readable NetCDF (truncated, corrupt), not a sandlight BRDF table, a newer format
            version, variables or coordinates missing, or values a table cannot hold.
        """
        path = Path(path)
        ds = table_file.read_table(path)
        f = ds["f"]
        if f.ndim == 5:
            level_name = str(f.dims[0])
            levels = np.asarray(ds[level_name].values, dtype=float)
        else:
            level_name, levels = "level", np.array([0.0])
        try:
            return cls(
                np.asarray(f.values, dtype=float),
                ds["wavelength"].values,
                ds["mu_i"].values,
                ds["mu_o"].values,
                ds["dphi"].values,
                levels,
                level_name,
                str(ds.attrs.get("source", path.name)),
            )
        except ParameterError as exc:
            raise ModelFileError(f"{path}: {table_file.FORMAT_NAME} file with values out of range: {exc}") from exc

    # --- use -----------------------------------------------------------------------------------

    def to_netcdf(self, path: str | os.PathLike) -> Path:
        """Write the stack as a 'sandlight-brdf-table' file (the level as the leading dimension of
        ``f``) atomically; `from_netcdf` reads it back."""
        ds = table_file.table_dataset(
            self.f,
            self.wavelength_nm,
            self.mu_i,
            self.mu_o,
            self.dphi,
            level_name=self.level_name,
            level_values=self.level_values,
            interpolation=(
                "multilinear in (mu_i, mu_o, dphi) and linear between levels; values are the BRDF at the "
                "grid points (see source)"
            ),
            attrs={"source": self.source, "creator": "sandlight.render.BrdfTable"},
        )
        return table_file.write_table(ds, path)

    def level_coordinate(self, values: ArrayLike, name: str = "values") -> np.ndarray:
        """Fractional level index of parameter values (linear between the level values).

        Raises
        ------
        ParameterError
            A value outside [level_values[0], level_values[-1]] or not finite.
        """
        v = np.asarray(values, dtype=float)
        lo, hi = self.level_values[0], self.level_values[-1]
        if not np.isfinite(v).all() or (v < lo - 1e-9).any() or (v > hi + 1e-9).any():
            bad = v[~(np.isfinite(v) & (v >= lo - 1e-9) & (v <= hi + 1e-9))].ravel()[0]
            raise ParameterError(
                name, float(bad), f"{self.level_name} values within the levels' range [{lo:g}, {hi:g}]"
            )
        if self.n_levels == 1:
            return np.zeros(v.shape)
        return np.interp(v, self.level_values, np.arange(self.n_levels, dtype=float))

    def native_f(self, wavelength_nm: ArrayLike) -> np.ndarray:
        """float32 array (levels, mu_i, mu_o, dphi, bands) at the render wavelengths (linear in λ).

        Raises
        ------
        ParameterError
            A render wavelength outside the table's wavelength range.
        """
        wl = np.asarray(wavelength_nm, dtype=float)
        lo, hi = self.wavelength_nm[0], self.wavelength_nm[-1]
        if (wl < lo - 1e-6).any() or (wl > hi + 1e-6).any():
            raise ParameterError(
                "wavelength_nm", wl.tolist(), f"render wavelengths within the BRDF table's range [{lo:g}, {hi:g}] nm"
            )
        if self.wavelength_nm.size == 1:
            f = np.repeat(self.f, wl.size, axis=1)
        else:
            idx = np.clip(np.searchsorted(self.wavelength_nm, wl, side="right") - 1, 0, self.wavelength_nm.size - 2)
            t = np.clip(
                (wl - self.wavelength_nm[idx]) / (self.wavelength_nm[idx + 1] - self.wavelength_nm[idx]), 0.0, 1.0
            )
            f = (
                self.f[:, idx] * (1.0 - t)[None, :, None, None, None]
                + self.f[:, idx + 1] * t[None, :, None, None, None]
            )
        return np.ascontiguousarray(np.moveaxis(f, 1, -1), dtype=np.float32)

    def albedo(self, mu_i: float, level: int = 0) -> np.ndarray:
        """Directional-hemispherical reflectance ∫ f μ_o dω_o at cosine ``mu_i`` for each
        wavelength, by the trapezoid rule on the table grid (bilinear interpolation in μ_i)."""
        k = int(np.clip(np.searchsorted(self.mu_i, mu_i) - 1, 0, self.mu_i.size - 2))
        t = (mu_i - self.mu_i[k]) / (self.mu_i[k + 1] - self.mu_i[k])
        row = self.f[level, :, k] * (1 - t) + self.f[level, :, k + 1] * t  # (wl, mu_o, dphi)
        # ∫ over Δφ ∈ [0, π] counts both signs: factor 2.
        over_phi = 2.0 * np.trapezoid(row, self.dphi, axis=-1)
        return np.trapezoid(over_phi * self.mu_o[None, :], self.mu_o, axis=-1)
