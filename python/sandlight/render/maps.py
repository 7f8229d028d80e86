"""Texture maps over the ground: the per-point value of the parameter that selects the BRDF level
(degree of saturation on the beach, or any one mineralogical parameter).

A :class:`MaterialMap` holds values on a regular grid over the ground (node (i, j) at
(x₀ + i·dx, y₀ + j·dy)), interpolated bilinearly and extended from its border (or periodic). The
renderer receives it as level coordinates (:meth:`sandlight.render.BrdfTable.level_coordinate`).

:func:`waterline_map` builds the beach of the paper's §4.2.2: two waterlines drawn as Brownian
motion curves across a flat beach split it into three zones of different saturation that dry over
the day.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from sandlight.errors import ParameterError

if TYPE_CHECKING:
    from sandlight.render.tables import BrdfTable

__all__ = ["MaterialMap", "Waterlines", "waterline_map", "brownian_curve"]


@dataclass(frozen=True)
class MaterialMap:
    """Parameter values over the ground.

    Attributes
    ----------
    values : numpy.ndarray, shape (ny, nx)
        Values of the varied parameter (e.g. degree of saturation, a fraction).
    origin_m : (x0, y0)
    spacing_m : (dx, dy), > 0
    wrap : bool
        Periodic instead of clamped to the border.
    """

    values: np.ndarray
    origin_m: tuple[float, float] = (0.0, 0.0)
    spacing_m: tuple[float, float] = (1.0, 1.0)
    wrap: bool = False

    def __post_init__(self):
        v = np.atleast_2d(np.asarray(self.values, dtype=float))
        if v.ndim != 2 or not np.isfinite(v).all():
            raise ParameterError("values", f"array of shape {np.shape(self.values)}", "a finite 2-D array")
        spacing = tuple(float(s) for s in self.spacing_m)
        origin = tuple(float(o) for o in self.origin_m)
        if len(spacing) != 2 or not all(np.isfinite(s) and s > 0 for s in spacing):
            raise ParameterError("spacing_m", self.spacing_m, "two spacings (dx, dy) > 0 m")
        if len(origin) != 2 or not np.isfinite(origin).all():
            raise ParameterError("origin_m", self.origin_m, "two finite coordinates in metres")
        v.setflags(write=False)
        object.__setattr__(self, "values", v)
        object.__setattr__(self, "spacing_m", spacing)
        object.__setattr__(self, "origin_m", origin)

    @classmethod
    def uniform(cls, value: float) -> MaterialMap:
        return cls(np.array([[float(value)]]))

    @classmethod
    def from_image(
        cls, path: str | os.PathLike, *, extent_m: tuple[float, float, float, float], value_range: tuple[float, float]
    ) -> MaterialMap:
        """A grayscale image (black → value_range[0], white → value_range[1]) spread over
        ``extent_m`` = (x_min, y_min, x_max, y_max); the top image row is the north edge."""
        from sandlight.render.grayscale import read_grayscale

        a = read_grayscale(path, "map image")
        x0, y0, x1, y1 = (float(v) for v in extent_m)
        if not (x1 > x0 and y1 > y0):
            raise ParameterError("extent_m", extent_m, "(x_min, y_min, x_max, y_max) with max > min")
        lo, hi = (float(v) for v in value_range)
        ny, nx = a.shape
        values = lo + (hi - lo) * np.flipud(a)
        return cls(values, (x0, y0), ((x1 - x0) / max(nx - 1, 1), (y1 - y0) / max(ny - 1, 1)))

    def value_at(self, x: ArrayLike, y: ArrayLike) -> np.ndarray:
        """Bilinear value at ground points (as the renderer interpolates level coordinates)."""
        v = self.values
        ny, nx = v.shape
        fx = (np.asarray(x, dtype=float) - self.origin_m[0]) / self.spacing_m[0]
        fy = (np.asarray(y, dtype=float) - self.origin_m[1]) / self.spacing_m[1]
        if not self.wrap:
            fx, fy = np.clip(fx, 0, nx - 1), np.clip(fy, 0, ny - 1)
        i, j = np.floor(fx).astype(np.int64), np.floor(fy).astype(np.int64)
        u, w = fx - i, fy - j

        def at(ii: np.ndarray, jj: np.ndarray) -> np.ndarray:
            if self.wrap:
                return v[jj % ny, ii % nx]
            return v[np.clip(jj, 0, ny - 1), np.clip(ii, 0, nx - 1)]

        return (1 - w) * ((1 - u) * at(i, j) + u * at(i + 1, j)) + w * ((1 - u) * at(i, j + 1) + u * at(i + 1, j + 1))

    def native_args(self, table: BrdfTable) -> dict:
        """Arguments of the native scene: level coordinates of ``table`` (a BrdfTable)."""
        level = table.level_coordinate(self.values, name="material map").astype(np.float32)
        return {
            "material": np.ascontiguousarray(level),
            "material_origin": list(self.origin_m),
            "material_spacing": list(self.spacing_m),
            "material_wrap": bool(self.wrap),
        }


def brownian_curve(n: int, step_sd: float, rng: np.random.Generator) -> np.ndarray:
    """A Brownian motion sampled at n points: cumulative sums of N(0, step_sd²) increments, mean
    removed (a discrete Wiener process, the Brownian-motion curve of §4.2.2)."""
    walk = np.concatenate([[0.0], np.cumsum(rng.normal(0.0, step_sd, n - 1))])
    return walk - walk.mean()


@dataclass(frozen=True)
class Waterlines:
    """Two waterlines across a flat beach (the paper's §4.2.2) and the saturation they imply.

    The shore runs along x; the sea is towards −y. Waterline k lies at y = ``offsets_m[k]`` plus a
    Brownian motion curve in x whose increments have standard deviation
    ``roughness_m_per_sqrt_m``·√Δx. They split the beach into three zones — seaward of the first
    line, between the lines, landward of the second — with degree of saturation
    ``start`` at the first frame and ``end`` at the last (linear in the time of day: the sand
    dries); zone boundaries are blurred over ``edge_m`` (capillary fringe).

    Attributes
    ----------
    extent_m : (x_min, y_min, x_max, y_max)
    resolution_m : float
        Grid spacing of the map.
    offsets_m : (y_1, y_2), y_1 < y_2
    roughness_m_per_sqrt_m : float
    edge_m : float
    start, end : (s_sea, s_middle, s_land)
        Degrees of saturation in [0, 1].
    seed : int
    """

    extent_m: tuple[float, float, float, float] = (-60.0, -30.0, 60.0, 40.0)
    resolution_m: float = 0.1
    offsets_m: tuple[float, float] = (2.0, 9.0)
    roughness_m_per_sqrt_m: float = 0.25
    edge_m: float = 0.6
    start: tuple[float, float, float] = (1.0, 0.8, 0.35)
    end: tuple[float, float, float] = (0.9, 0.25, 0.02)
    seed: int = 0

    def __post_init__(self):
        x0, y0, x1, y1 = (float(v) for v in self.extent_m)
        if not (x1 > x0 and y1 > y0 and np.isfinite([x0, y0, x1, y1]).all()):
            raise ParameterError("extent_m", self.extent_m, "(x_min, y_min, x_max, y_max) with max > min")
        if not (
            self.resolution_m > 0 and (x1 - x0) / self.resolution_m <= 8192 and (y1 - y0) / self.resolution_m <= 8192
        ):
            raise ParameterError(
                "resolution_m", self.resolution_m, "a spacing > 0 m giving at most 8192 nodes per side"
            )
        a, b = (float(v) for v in self.offsets_m)
        if not a < b:
            raise ParameterError("offsets_m", self.offsets_m, "(y_1, y_2) with y_1 < y_2 (the first line is seaward)")
        if not self.roughness_m_per_sqrt_m >= 0:
            raise ParameterError("roughness_m_per_sqrt_m", self.roughness_m_per_sqrt_m, "a value ≥ 0")
        if not self.edge_m > 0:
            raise ParameterError("edge_m", self.edge_m, "a width > 0 m")
        for name in ("start", "end"):
            v = np.asarray(getattr(self, name), dtype=float)
            if v.shape != (3,) or not np.isfinite(v).all() or (v < 0).any() or (v > 1).any():
                raise ParameterError(
                    name, getattr(self, name), "three degrees of saturation in [0, 1] (sea, middle, land)"
                )

    def curves(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """x nodes and the y of both waterlines there (fixed by the seed, the same every frame)."""
        x0, _, x1, _ = self.extent_m
        x = np.arange(x0, x1 + 0.5 * self.resolution_m, self.resolution_m)
        rng = np.random.default_rng(self.seed)
        step = self.roughness_m_per_sqrt_m * np.sqrt(self.resolution_m)
        return (
            x,
            self.offsets_m[0] + brownian_curve(x.size, step, rng),
            self.offsets_m[1] + brownian_curve(x.size, step, rng),
        )

    def map(self, day_fraction: float) -> MaterialMap:
        """Saturation map at ``day_fraction`` ∈ [0, 1] of the drying (0 = first frame)."""
        if not 0.0 <= day_fraction <= 1.0:
            raise ParameterError("day_fraction", day_fraction, "a fraction in [0, 1]")
        x, line1, line2 = self.curves()
        _, y0, _, y1 = self.extent_m
        y = np.arange(y0, y1 + 0.5 * self.resolution_m, self.resolution_m)
        s = (1.0 - day_fraction) * np.asarray(self.start, float) + day_fraction * np.asarray(self.end, float)
        # Smooth steps across each line: 0 seaward, 1 landward (logistic over edge_m).
        past1 = 0.5 * (1.0 + np.tanh((y[:, None] - line1[None, :]) / (0.5 * self.edge_m)))
        past2 = 0.5 * (1.0 + np.tanh((y[:, None] - line2[None, :]) / (0.5 * self.edge_m)))
        values = s[0] + (s[1] - s[0]) * past1 + (s[2] - s[1]) * past2
        return MaterialMap(
            np.clip(values, 0.0, 1.0), (float(x[0]), float(y[0])), (self.resolution_m, self.resolution_m)
        )


def waterline_map(day_fraction: float, **kwargs) -> MaterialMap:
    """Shorthand for ``Waterlines(**kwargs).map(day_fraction)``."""
    return Waterlines(**kwargs).map(day_fraction)
