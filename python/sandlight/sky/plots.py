"""Pictures of the sky: fisheye views of the dome in sRGB.

Public objects
--------------
- :func:`fisheye_directions` : view directions of an equidistant fisheye image.
- :func:`sky_dome_xyz` : CIE XYZ (cd m⁻²) of the sky over a fisheye image.
- :func:`xyz_to_display_srgb` : exposure, clipping and sRGB encoding.
- :func:`plot_sky_dome` : one dome as a PNG, sun marked.
- :func:`plot_sky_day` : a strip of domes over a day as a PNG.

Projection and orientation
--------------------------
**Equidistant** fisheye (radius proportional to zenith angle: centre = zenith, rim = horizon), seen
**from below looking up**, as an all-sky camera shows it: north at the top, **east on the left**,
south at the bottom, west on the right. Compass letters are drawn on the rim.

Colour
------
The spectral sky radiance (380–780 nm, 5 nm) is integrated against the CIE 1931 2° colour-matching
functions (colour-science) with K_m = 683 lm W⁻¹, giving absolute XYZ in cd m⁻² (Y is the
luminance). Display: XYZ is divided by the exposure luminance (the luminance shown as display
white), converted to linear sRGB (IEC 61966-2-1, D65, no chromatic adaptation, so a bluish sky stays
bluish), clipped to [0, 1] and encoded with the sRGB transfer function. The sun's disc is not
drawn (it is not part of the sky radiance); a ring marks its position.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from sandlight.checks import check_allocation, check_real, check_real_array, check_whole_number
from sandlight.errors import ParameterError
from sandlight.io import write_atomically
from sandlight.sky import sun as _sun
from sandlight.sky.preetham import LUMINOUS_EFFICACY_LM_W, TURBIDITY_RANGE, PreethamSky

if TYPE_CHECKING:
    import datetime

    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["fisheye_directions", "sky_dome_xyz", "xyz_to_display_srgb", "plot_sky_dome", "plot_sky_day"]

# 380–780 nm at 5 nm: the visible range at the CMF table resolution used for the picture.
_PLOT_WAVELENGTHS_NM = np.arange(380.0, 781.0, 5.0)
# Rows of the fisheye evaluated at once; bounds the (pixels × wavelengths) temporary array.
_ROWS_PER_CHUNK = 64


def _check_size(size: int) -> int:
    return check_whole_number("size", size, 16, 4096, noun="a whole number of pixels")


def fisheye_directions(size: int) -> tuple[np.ndarray, np.ndarray]:
    """View directions of an equidistant, looking-up fisheye image of ``size`` × ``size`` pixels.

    Parameters
    ----------
    size : int
        Image width and height in pixels, in [16, 4096].

    Returns
    -------
    directions : numpy.ndarray, shape (size, size, 3)
        Unit vectors (x east, y north, z up) through the pixel centres; outside the disc they are
        set to the zenith and flagged by ``inside``.
    inside : numpy.ndarray of bool, shape (size, size)
        Pixels within the horizon circle.
    """
    size = _check_size(size)
    centres = (np.arange(size) + 0.5) / size * 2.0 - 1.0
    u, v = np.meshgrid(centres, -centres)  # u to the right, v up
    radius = np.hypot(u, v)
    inside = radius <= 1.0
    theta = np.where(inside, radius, 0.0) * (np.pi / 2.0)  # equidistant: r ∝ θ
    safe_radius = np.maximum(radius, 1e-12)
    # Looking up with north at the top puts east on the left: x_east = −u, y_north = v.
    directions = np.stack([np.sin(theta) * -u / safe_radius, np.sin(theta) * v / safe_radius, np.cos(theta)], axis=-1)
    return directions, inside


def _cmfs(wavelengths_nm: np.ndarray) -> np.ndarray:
    """CIE 1931 2° colour-matching functions at ``wavelengths_nm``, shape (n, 3)."""
    import colour

    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    return np.stack([np.interp(wavelengths_nm, cmfs.wavelengths, cmfs.values[:, i]) for i in range(3)], axis=-1)


def sky_dome_xyz(sky: PreethamSky, size: int = 512) -> tuple[np.ndarray, np.ndarray]:
    """Absolute CIE 1931 XYZ of the sky over an equidistant fisheye image.

    Parameters
    ----------
    sky : PreethamSky
    size : int
        Image size in pixels, in [16, 4096].

    Returns
    -------
    xyz : numpy.ndarray, shape (size, size, 3)
        Tristimulus values in cd m⁻² (0 outside the horizon circle).
    inside : numpy.ndarray of bool, shape (size, size)
    """
    if not isinstance(sky, PreethamSky):
        raise ParameterError("sky", sky, "a sandlight.sky.PreethamSky")
    directions, inside = fisheye_directions(size)
    wavelengths = _PLOT_WAVELENGTHS_NM
    weights = _cmfs(wavelengths) * (LUMINOUS_EFFICACY_LM_W * 5.0)  # 5 nm rectangle rule
    xyz = np.zeros(directions.shape)
    for start in range(0, directions.shape[0], _ROWS_PER_CHUNK):
        rows = slice(start, start + _ROWS_PER_CHUNK)
        radiance = sky.radiance(directions[rows], wavelengths)  # (rows, size, n)
        xyz[rows] = radiance @ weights
    xyz[~inside] = 0.0
    return xyz, inside


def xyz_to_display_srgb(xyz: np.ndarray, exposure_cd_m2: float | None) -> np.ndarray:
    """Display-encoded sRGB in [0, 1] from absolute XYZ.

    Parameters
    ----------
    xyz : array_like, shape (..., 3)
        CIE 1931 XYZ in cd m⁻².
    exposure_cd_m2 : float
        Luminance in cd m⁻² shown as display white (> 0).

    Returns
    -------
    numpy.ndarray, shape (..., 3)
        Non-linear sRGB values in [0, 1] (linear values clipped before encoding).
    """
    import colour

    exposure = check_real("exposure_cd_m2", exposure_cd_m2, 0.0, None, low_open=True)
    linear = colour.XYZ_to_RGB(
        np.asarray(xyz, dtype=np.float64) / exposure,
        colour.RGB_COLOURSPACES["sRGB"],
        chromatic_adaptation_transform=None,
        apply_cctf_encoding=False,
    )
    return colour.cctf_encoding(np.clip(linear, 0.0, 1.0), function="sRGB")


def _auto_exposure_cd_m2(xyz: np.ndarray, inside: np.ndarray) -> float:
    """Display white at twice the median sky luminance: the bulk of the dome sits mid-grey, the
    circumsolar region saturates, as in a photograph exposed for the sky."""
    return float(2.0 * np.median(xyz[..., 1][inside]))


def _save_figure_atomically(figure: Figure, path: Path) -> None:
    """Write the figure as PNG, atomically (sandlight.io)."""
    write_atomically(path, lambda tmp: figure.savefig(tmp, format="png"))


def _sun_marker_position(sky: PreethamSky, size: int) -> tuple[float, float]:
    """Pixel (column, row) of the sun in the fisheye image (continuous coordinates)."""
    zenith, azimuth = _sun.angles_from_direction(sky.sun_direction)
    radius = float(zenith) / (np.pi / 2.0)
    u = -radius * np.sin(float(azimuth))  # east on the left
    v = radius * np.cos(float(azimuth))  # north up
    return (u + 1.0) / 2.0 * size - 0.5, (1.0 - v) / 2.0 * size - 0.5


def _draw_dome(axes: Axes, image: np.ndarray, sky: PreethamSky | None, size: int, title: str) -> None:
    from matplotlib.patches import Circle

    axes.imshow(image, interpolation="nearest")
    axes.add_patch(Circle((size / 2 - 0.5, size / 2 - 0.5), size / 2, fill=False, edgecolor="0.5", linewidth=0.8))
    offset = size * 0.035
    for label, (column, row) in {
        "N": (size / 2, -offset),
        "S": (size / 2, size + offset),
        "E": (-offset, size / 2),
        "W": (size + offset, size / 2),
    }.items():
        axes.text(column - 0.5, row - 0.5, label, ha="center", va="center", fontsize=8, color="0.2")
    if sky is not None:
        column, row = _sun_marker_position(sky, size)
        axes.add_patch(Circle((column, row), size * 0.025, fill=False, edgecolor="yellow", linewidth=1.5))
        axes.add_patch(Circle((column, row), size * 0.035, fill=False, edgecolor="black", linewidth=0.8))
    axes.set_title(title, fontsize=9)
    axes.set_xlim(-offset * 2, size + offset * 2)
    axes.set_ylim(size + offset * 2, -offset * 2)
    axes.set_axis_off()


def _sky_title(sky: PreethamSky) -> str:
    zenith, azimuth = _sun.angles_from_direction(sky.sun_direction)
    return (
        f"T = {sky.turbidity:g}, sun elevation {90.0 - np.degrees(float(zenith)):.1f}°, "
        f"azimuth {np.degrees(float(azimuth)):.1f}°"
    )


def plot_sky_dome(
    sky: PreethamSky,
    path: str | os.PathLike,
    *,
    size: int = 512,
    exposure_cd_m2: float | None = None,
    title: str | None = None,
) -> Path:
    """Save a fisheye picture of the sky dome as a PNG.

    Equidistant projection seen from below (north up, east left); sun marked by a ring.

    Parameters
    ----------
    sky : PreethamSky
    path : str or os.PathLike
        Output PNG file; written atomically (temporary file, then rename). Parent directories
        are created.
    size : int, default 512
        Diameter of the dome in pixels, in [16, 4096].
    exposure_cd_m2 : float, optional
        Luminance (cd m⁻²) shown as display white. Default: twice the median sky luminance of the
        dome.
    title : str, optional
        Figure title; default states turbidity and sun elevation and azimuth.

    Returns
    -------
    pathlib.Path
        The written file.
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    size = _check_size(size)
    path = Path(path)
    xyz, inside = sky_dome_xyz(sky, size)
    exposure = _auto_exposure_cd_m2(xyz, inside) if exposure_cd_m2 is None else exposure_cd_m2
    rgb = xyz_to_display_srgb(xyz, exposure)
    image = np.concatenate([rgb, inside[..., np.newaxis].astype(np.float64)], axis=-1)
    inches = max(size / 100.0, 3.0)
    figure = plt.figure(figsize=(inches, inches * 1.08), dpi=100)
    try:
        axes = figure.add_axes((0.0, 0.0, 1.0, 0.93))
        _draw_dome(
            axes,
            image,
            sky,
            size,
            (title if title is not None else _sky_title(sky)) + f"\nexposure: white = {exposure / 1000.0:.3g} kcd/m²",
        )
        _save_figure_atomically(figure, path)
    finally:
        plt.close(figure)
    return path


#: Memory per dome pixel of a strip, bytes: the dome's XYZ (float64 × 3) and mask kept for the
#: shared exposure, the RGBA image matplotlib keeps (float64 × 4), the canvas (RGBA, 1.15 times
#: the panel) and the resampling temporaries: 1000 domes of 512² needed about 20 GiB.
_STRIP_BYTES_PER_PIXEL = 80


def plot_sky_day(
    latitude_deg: npt.ArrayLike,
    day_of_year: npt.ArrayLike | datetime.date,
    times_h: npt.ArrayLike,
    path: str | os.PathLike,
    *,
    turbidity: float = 3.0,
    longitude_deg: npt.ArrayLike | None = None,
    utc_offset_h: npt.ArrayLike | None = None,
    size: int = 256,
    exposure_cd_m2: float | None = None,
    columns: int = 6,
) -> Path:
    """Save a strip of fisheye sky domes over a day as one PNG.

    All domes share one exposure, so the dimming of the sky towards dawn and dusk shows. Times at
    which the sun is below the horizon get an empty panel saying so.

    Parameters
    ----------
    latitude_deg : float
        Latitude in degrees, north positive, in [−90, 90].
    day_of_year : int or datetime.date
        Day J in [1, 366], or a date.
    times_h : sequence of float
        Times of day in hours, each in [0, 24]: solar time, or clock time of the zone given by
        ``longitude_deg`` and ``utc_offset_h`` (see :func:`sandlight.sky.sun_position`).
    path : str or os.PathLike
        Output PNG file, written atomically.
    turbidity : float, default 3
        Turbidity T in [1.7, 10].
    longitude_deg, utc_offset_h : float, optional
        Give both to interpret ``times_h`` as clock time.
    size : int, default 256
        Diameter of each dome in pixels, in [16, 4096].
    exposure_cd_m2 : float, optional
        Luminance shown as display white for every dome. Default: twice the median sky luminance
        of the dome with the highest sun.
    columns : int, default 6
        Domes per row.

    Returns
    -------
    pathlib.Path
        The written file.
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    size = _check_size(size)
    times = check_real_array("times_h", times_h, 0.0, 24.0).reshape(-1)
    check_allocation("times_h", f"{times.size} domes of {size}² pixels", times.size * size**2 * _STRIP_BYTES_PER_PIXEL)
    check_whole_number("columns", columns, 1)
    latitude = check_real("latitude_deg", latitude_deg, -90.0, 90.0)
    turbidity = check_real("turbidity", turbidity, *TURBIDITY_RANGE)
    directions = _sun.sun_direction(
        latitude, day_of_year, times, longitude_deg=longitude_deg, utc_offset_h=utc_offset_h
    )
    if directions.shape != (times.size, 3):
        raise ParameterError("day_of_year", day_of_year, "a single day for the strip")
    skies = [PreethamSky(turbidity, d) if d[2] > 0.0 else None for d in directions]
    domes = [sky_dome_xyz(sky, size) if sky is not None else None for sky in skies]
    if exposure_cd_m2 is None:
        lit = [i for i, sky in enumerate(skies) if sky is not None]
        if lit:
            highest = max(lit, key=lambda i: skies[i].sun_direction[2])
            exposure = _auto_exposure_cd_m2(*domes[highest])
        else:
            exposure = 1.0  # nothing to expose: every panel is empty
    else:
        exposure = check_real("exposure_cd_m2", exposure_cd_m2, 0.0, None, low_open=True)

    columns = min(int(columns), times.size)
    rows = -(-times.size // columns)
    panel = max(size / 100.0, 2.0)
    figure, axes_grid = plt.subplots(
        rows,
        columns,
        dpi=100,
        squeeze=False,
        layout="constrained",
        figsize=(panel * columns, panel * rows * 1.15 + 0.3),
    )
    try:
        kind = "solar time" if longitude_deg is None else f"UTC{float(utc_offset_h):+g} h"
        for index, axes in enumerate(axes_grid.reshape(-1)):
            if index >= times.size:
                axes.set_axis_off()
                continue
            hours = int(times[index])
            minutes = int(round((times[index] - hours) * 60.0))
            if minutes == 60:
                hours, minutes = hours + 1, 0
            label = f"{hours:02d}:{minutes:02d}"
            sky = skies[index]
            if sky is None:
                _, inside = fisheye_directions(size)
                image = np.zeros((size, size, 4))
                image[..., :3] = 0.15  # a dark disc: no daylight sky
                image[..., 3] = inside
                _draw_dome(axes, image, None, size, f"{label}\nsun below horizon")
                continue
            xyz, inside = domes[index]
            rgb = xyz_to_display_srgb(xyz, exposure)
            image = np.concatenate([rgb, inside[..., np.newaxis].astype(np.float64)], axis=-1)
            elevation = 90.0 - np.degrees(sky.sun_zenith_rad)
            _draw_dome(axes, image, sky, size, f"{label}\nsun elevation {elevation:.1f}°")
        figure.suptitle(
            f"Preetham sky, T = {float(turbidity):g}, latitude {latitude:g}°, "
            f"day {_sun.day_array(day_of_year).item():g} ({kind}); "
            f"white = {exposure / 1000.0:.3g} kcd/m²",
            fontsize=10,
        )
        _save_figure_atomically(figure, Path(path))
    finally:
        plt.close(figure)
    return Path(path)
