"""Terrain: the paper's flat plane, heightfields from images or arrays, procedural dune fields.

Coordinates are metres, x east, y north, z up. A heightfield holds node heights on a regular grid
(row j at y₀ + j·dy, column i at x₀ + i·dx); the renderer joins them by bilinear patches. Outside
its grid a heightfield either repeats (``wrap=True``: periodic dune fields tile to the horizon) or
continues as the plane z = ``outside_m``. Beyond ``far_m`` from a ray's origin the renderer takes
the ground as a plane at the mean height (distant relief is smaller than a pixel).
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from sandlight.errors import ParameterError

__all__ = ["PlaneTerrain", "HeightfieldTerrain", "dune_field", "heightfield_from_image"]


@dataclass(frozen=True)
class PlaneTerrain:
    """The flat ground z = ``height_m`` (the paper's desert and beach)."""

    height_m: float = 0.0

    def __post_init__(self):
        if not np.isfinite(self.height_m):
            raise ParameterError("height_m", self.height_m, "a finite height in metres")

    def height_at(self, x: ArrayLike, y: ArrayLike) -> np.ndarray:
        return np.full(np.broadcast(np.asarray(x), np.asarray(y)).shape, float(self.height_m))

    def native_args(self) -> dict:
        return {"terrain": "plane", "plane_z": float(self.height_m)}


@dataclass(frozen=True)
class HeightfieldTerrain:
    """Node heights on a regular grid, joined by bilinear patches.

    Attributes
    ----------
    heights_m : numpy.ndarray, shape (ny, nx)
        Heights in metres (row j at y₀ + j·dy).
    origin_m : tuple of float
        (x₀, y₀), metres.
    spacing_m : tuple of float
        (dx, dy) > 0, metres.
    wrap : bool
        Periodic continuation (period nx·dx by ny·dy) instead of a surrounding plane.
    outside_m : float
        Height of the plane around a non-periodic grid.
    far_m : float
        Distance beyond which the ground is taken as flat (> 0).
    """

    heights_m: np.ndarray
    origin_m: tuple[float, float] = (0.0, 0.0)
    spacing_m: tuple[float, float] = (1.0, 1.0)
    wrap: bool = False
    outside_m: float = 0.0
    far_m: float = 2000.0

    def __post_init__(self):
        h = np.ascontiguousarray(self.heights_m, dtype=np.float32)
        if h.ndim != 2 or min(h.shape) < 2:
            raise ParameterError(
                "heights_m", f"array of shape {np.shape(self.heights_m)}", "a 2-D array of at least 2 × 2 heights"
            )
        if not np.isfinite(h).all():
            raise ParameterError("heights_m", "an array containing NaN or inf", "finite heights in metres")
        origin = tuple(float(v) for v in self.origin_m)
        spacing = tuple(float(v) for v in self.spacing_m)
        if len(origin) != 2 or not np.isfinite(origin).all():
            raise ParameterError("origin_m", self.origin_m, "two finite coordinates (x0, y0) in metres")
        if len(spacing) != 2 or not all(np.isfinite(s) and s > 0 for s in spacing):
            raise ParameterError("spacing_m", self.spacing_m, "two spacings (dx, dy) > 0 m")
        if not np.isfinite(self.outside_m):
            raise ParameterError("outside_m", self.outside_m, "a finite height in metres")
        if not (self.far_m > 0 and np.isfinite(self.far_m)):
            raise ParameterError("far_m", self.far_m, "a distance > 0 m")
        h.setflags(write=False)
        object.__setattr__(self, "heights_m", h)
        object.__setattr__(self, "origin_m", origin)
        object.__setattr__(self, "spacing_m", spacing)

    @property
    def size_m(self) -> tuple[float, float]:
        """Extent (width, depth) in metres: the period when wrapping, else the span of the nodes."""
        ny, nx = self.heights_m.shape
        k = 0 if self.wrap else 1
        return ((nx - k) * self.spacing_m[0], (ny - k) * self.spacing_m[1])

    def height_at(self, x: ArrayLike, y: ArrayLike) -> np.ndarray:
        """Height of the bilinear surface at (x, y), as the renderer sees it."""
        h = self.heights_m.astype(float)
        ny, nx = h.shape
        fx = (np.asarray(x, dtype=float) - self.origin_m[0]) / self.spacing_m[0]
        fy = (np.asarray(y, dtype=float) - self.origin_m[1]) / self.spacing_m[1]
        i, j = np.floor(fx).astype(np.int64), np.floor(fy).astype(np.int64)
        u, v = fx - i, fy - j

        def node(ii: np.ndarray, jj: np.ndarray) -> np.ndarray:
            if self.wrap:
                return h[jj % ny, ii % nx]
            inside = (ii >= 0) & (ii < nx) & (jj >= 0) & (jj < ny)
            return np.where(inside, h[np.clip(jj, 0, ny - 1), np.clip(ii, 0, nx - 1)], self.outside_m)

        return (1 - v) * ((1 - u) * node(i, j) + u * node(i + 1, j)) + v * (
            (1 - u) * node(i, j + 1) + u * node(i + 1, j + 1)
        )

    def native_args(self) -> dict:
        return {
            "terrain": "heightfield",
            "heights": self.heights_m,
            "origin": list(self.origin_m),
            "spacing": list(self.spacing_m),
            "wrap": bool(self.wrap),
            "outside": float(self.outside_m),
            "far_m": float(self.far_m),
        }


def _periodic_wave(n_cycles_x: int, n_cycles_y: int, x: np.ndarray, y: np.ndarray, size: float) -> np.ndarray:
    """Phase (in cycles) of a plane wave with a whole number of cycles across the tile."""
    return (n_cycles_x * x + n_cycles_y * y) / size


def _wave_numbers(wavelength_m: float, azimuth_deg: float, size_m: float) -> tuple[int, int]:
    """Whole cycle counts (m, n) over the tile closest to a wave of given wavelength travelling
    towards ``azimuth_deg`` (from north, clockwise), so the field stays periodic."""
    a = np.radians(azimuth_deg)
    k = size_m / wavelength_m
    m, n = int(round(k * np.sin(a))), int(round(k * np.cos(a)))
    if m == 0 and n == 0:
        n = 1
    return m, n


def _periodic_noise(shape: tuple[int, int], correlation_cells: float, rng: np.random.Generator) -> np.ndarray:
    """Gaussian random field with unit variance, periodic (filtered in Fourier space)."""
    ny, nx = shape
    white = rng.standard_normal(shape)
    kx = np.fft.fftfreq(nx)[None, :]
    ky = np.fft.fftfreq(ny)[:, None]
    # Gaussian filter of standard deviation `correlation_cells`: exp(−2π²σ²k²).
    spectrum = np.fft.fft2(white) * np.exp(-2.0 * np.pi**2 * correlation_cells**2 * (kx**2 + ky**2))
    field = np.real(np.fft.ifft2(spectrum))
    return (field - field.mean()) / max(field.std(), 1e-12)


def dune_field(
    *,
    size_m: float = 204.8,
    cells: int = 1024,
    dune_height_m: float = 6.0,
    dune_wavelength_m: float = 60.0,
    wind_azimuth_deg: float = 80.0,
    lee_fraction: float = 0.25,
    sinuosity_m: float = 6.0,
    ripple_wavelength_m: float = 0.8,
    ripple_height_m: float = 0.03,
    roughness_m: float = 0.4,
    seed: int = 0,
    far_m: float = 2000.0,
) -> HeightfieldTerrain:
    """A periodic field of transverse dunes with wind ripples (procedural).

    Dune profile along the wind: a sin² rise over the stoss (windward) side and a cos² fall over
    the steeper lee side (fraction ``lee_fraction`` of the wavelength), so with the defaults the
    stoss slopes reach ≈ 12° and the lee faces ≈ 32°, near the angle of repose of dry sand
    (≈ 30–34°). Crests meander by ``sinuosity_m``; a second, oblique and lower dune train and a
    periodic random field of ``roughness_m`` break the regularity. Ripples run across the wind
    with wavelength ``ripple_wavelength_m`` (wind ripples are 0.05–0.2 m in nature; the default
    is a little longer so that a 0.2 m grid resolves them) and fade out on lee faces, where
    avalanching erases them. Every component has a whole number of cycles across the tile, so the
    field wraps without seams.

    Parameters
    ----------
    size_m : float
        Side of the square tile, metres (> 0).
    cells : int
        Grid nodes per side, a power of two in [16, 4096].
    dune_height_m, dune_wavelength_m : float
        Height (crest over trough) and spacing of the main dunes, metres.
    wind_azimuth_deg : float
        Direction the wind blows *towards*, degrees from north clockwise.
    lee_fraction : float
        Share of a wavelength taken by the lee side, in [0.1, 0.5].
    sinuosity_m, ripple_wavelength_m, ripple_height_m, roughness_m : float
        Crest meander amplitude, ripple spacing and height, random relief (standard deviation).
    seed : int
        Seed of the random components.

    Returns
    -------
    HeightfieldTerrain
        Periodic (``wrap=True``), lowest point at z = 0.
    """
    for name, value, lo in (
        ("size_m", size_m, 0.0),
        ("dune_wavelength_m", dune_wavelength_m, 0.0),
        ("ripple_wavelength_m", ripple_wavelength_m, 0.0),
    ):
        if not (np.isfinite(value) and value > lo):
            raise ParameterError(name, value, "a length > 0 m")
    for name, value in (
        ("dune_height_m", dune_height_m),
        ("sinuosity_m", sinuosity_m),
        ("ripple_height_m", ripple_height_m),
        ("roughness_m", roughness_m),
    ):
        if not (np.isfinite(value) and value >= 0):
            raise ParameterError(name, value, "a length ≥ 0 m")
    if not (isinstance(cells, (int, np.integer)) and 16 <= cells <= 4096 and cells & (cells - 1) == 0):
        raise ParameterError("cells", cells, "a power of two in [16, 4096]")
    if not 0.1 <= lee_fraction <= 0.5:
        raise ParameterError("lee_fraction", lee_fraction, "a fraction in [0.1, 0.5]")
    spacing = size_m / cells
    if ripple_height_m > 0 and ripple_wavelength_m < 3.0 * spacing:
        raise ParameterError(
            "ripple_wavelength_m",
            ripple_wavelength_m,
            f"at least 3 grid cells ({3 * spacing:g} m at size_m/cells = {spacing:g} m); "
            f"increase cells or set ripple_height_m = 0",
        )
    rng = np.random.default_rng(seed)
    coords = np.arange(cells) * spacing
    x, y = np.meshgrid(coords, coords)

    def profile(phase: np.ndarray) -> np.ndarray:
        # One cycle per unit phase: sin² rise over the stoss side, cos² fall over the lee side.
        t = np.mod(phase, 1.0)
        stoss = 1.0 - lee_fraction
        return np.where(
            t < stoss, np.sin(0.5 * np.pi * t / stoss) ** 2, np.cos(0.5 * np.pi * (t - stoss) / lee_fraction) ** 2
        )

    m, n = _wave_numbers(dune_wavelength_m, wind_azimuth_deg, size_m)
    # Crest meander: a wave along the crest (perpendicular wave vector, about three dune
    # wavelengths long), whole cycles across the tile.
    ma, na = _wave_numbers(3.0 * dune_wavelength_m, wind_azimuth_deg + 90.0, size_m)
    along = _periodic_wave(ma, na, x, y, size_m)
    meander = sinuosity_m / dune_wavelength_m * np.sin(2 * np.pi * along + rng.uniform(0, 2 * np.pi))
    noise = _periodic_noise(x.shape, dune_wavelength_m / spacing / 3.0, rng)
    phase = _periodic_wave(m, n, x, y, size_m) + meander + 0.08 * noise
    main = profile(phase)
    m2, n2 = _wave_numbers(dune_wavelength_m * 0.55, wind_azimuth_deg + 35.0, size_m)
    secondary = profile(_periodic_wave(m2, n2, x, y, size_m) + 0.1 * noise)
    h = dune_height_m * (0.8 * main + 0.2 * secondary)
    h += roughness_m * _periodic_noise(x.shape, 8.0 / spacing, rng)
    if ripple_height_m > 0:
        mr, nr = _wave_numbers(ripple_wavelength_m, wind_azimuth_deg, size_m)
        ripple_noise = _periodic_noise(x.shape, 2.0 / spacing, rng)
        ripples = np.sin(2 * np.pi * (_periodic_wave(mr, nr, x, y, size_m) + 0.6 * ripple_noise))
        # No ripples on avalanche faces: fade with the local slope (gradient of the dunes).
        gy, gx = np.gradient(h, spacing)
        slope = np.hypot(gx, gy)
        ripples *= np.clip(1.0 - (slope - 0.25) / 0.2, 0.0, 1.0)
        h += 0.5 * ripple_height_m * ripples
    h -= h.min()
    return HeightfieldTerrain(h, (0.0, 0.0), (spacing, spacing), wrap=True, outside_m=0.0, far_m=far_m)


def heightfield_from_image(
    path: str | os.PathLike,
    *,
    size_m: tuple[float, float],
    height_range_m: tuple[float, float],
    origin_m: tuple[float, float] | None = None,
    wrap: bool = False,
    outside_m: float | None = None,
    far_m: float = 2000.0,
) -> HeightfieldTerrain:
    """Heightfield from a grayscale image (black = lowest, white = highest; 8 or 16 bit).

    Parameters
    ----------
    path : path-like
        Image file (PNG, TIFF, …); colour images are converted to luminance.
    size_m : (width, depth)
        Extent covered by the image, metres; the top row of the image is the north edge.
    height_range_m : (low, high)
        Heights of black and white, metres.
    origin_m : (x0, y0), optional
        South-west corner; default centres the image on the origin.
    wrap : bool
        Tile the image periodically instead of surrounding it by a plane.
    outside_m : float, optional
        Height of the surrounding plane (default: the mean height of the image border).
    """
    from sandlight.render.grayscale import read_grayscale

    a = read_grayscale(path, "heightfield image")
    return heightfield_from_array(
        np.flipud(a),
        size_m=size_m,
        height_range_m=height_range_m,
        origin_m=origin_m,
        wrap=wrap,
        outside_m=outside_m,
        far_m=far_m,
    )


def heightfield_from_array(
    values: ArrayLike,
    *,
    size_m: tuple[float, float],
    height_range_m: tuple[float, float],
    origin_m: tuple[float, float] | None = None,
    wrap: bool = False,
    outside_m: float | None = None,
    far_m: float = 2000.0,
) -> HeightfieldTerrain:
    """Heightfield from an array of values in [0, 1] (row 0 = south edge), scaled to
    ``height_range_m``; see :func:`heightfield_from_image` for the other parameters."""
    a = np.asarray(values, dtype=float)
    if a.ndim != 2 or min(a.shape) < 2:
        raise ParameterError("heightfield", f"array of shape {a.shape}", "a 2-D array of at least 2 × 2 values")
    if not np.isfinite(a).all() or a.min() < 0 or a.max() > 1:
        raise ParameterError("heightfield", "values outside [0, 1]", "values in [0, 1] (scaled to height_range_m)")
    w, d = (float(v) for v in size_m)
    if not (w > 0 and d > 0 and np.isfinite(w) and np.isfinite(d)):
        raise ParameterError("size_m", size_m, "a width and depth > 0 m")
    lo, hi = (float(v) for v in height_range_m)
    if not (np.isfinite(lo) and np.isfinite(hi) and hi >= lo):
        raise ParameterError("height_range_m", height_range_m, "(low, high) in metres with high ≥ low")
    ny, nx = a.shape
    k = 0 if wrap else 1
    spacing = (w / (nx - k), d / (ny - k))
    h = lo + (hi - lo) * a
    origin = (-0.5 * w, -0.5 * d) if origin_m is None else tuple(float(v) for v in origin_m)
    if outside_m is None:
        border = np.concatenate([h[0], h[-1], h[:, 0], h[:, -1]])
        outside_m = float(border.mean())
    return HeightfieldTerrain(h, origin, spacing, wrap=wrap, outside_m=outside_m, far_m=far_m)
