"""Swatch grids: the colour of sand as two parameters vary (paper Figures 6 and 7).

Public objects
--------------
- :class:`GridAxis`: a parameter name and its values.
- :func:`parse_grid_spec`: ``"iron_oxide=0.001:0.05:8"`` → :class:`GridAxis`.
- :func:`grid_samples`: the samples of a grid, row by row.
- :func:`swatch_grid` → :class:`SwatchGrid`, which renders a labelled PNG (matplotlib).
- :func:`figure6`, :func:`figure7`: the paper's two grids.
- :func:`save_grid_png`: the labelled-grid renderer, also used for colourised mosaics.

Orientation: the x parameter increases to the right and the y parameter **downward** (first value
in the top row), as in the paper's Figures 6 and 7.
"""

from __future__ import annotations

import os
import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from sandlight.checks import check_allocation
from sandlight.colour.provider import ReflectanceProvider
from sandlight.colour.sample_colour import sample_xyz
from sandlight.colour.spectrum import DEFAULT_ILLUMINANT, DEFAULT_OBSERVER, PREDICTOR_WAVELENGTHS_NM
from sandlight.colour.srgb import xyz_to_lab, xyz_to_srgb
from sandlight.errors import ParameterError, SandlightError
from sandlight.io import write_atomically

__all__ = [
    "GridAxis",
    "MAX_AXIS_COUNT",
    "parse_grid_spec",
    "grid_samples",
    "SwatchGrid",
    "swatch_grid",
    "default_sample",
    "figure6",
    "figure7",
    "save_grid_png",
    "framed_size_px",
]

# More cells than this per axis cannot be told apart in a figure and only cost predictor calls.
MAX_AXIS_COUNT = 64

_SPEC_SYNTAX = (
    "NAME=start:stop:count with count an integer in 1–"
    f"{MAX_AXIS_COUNT} (inclusive endpoints), e.g. iron_oxide=0.001:0.05:8"
)
_SPEC_RE = re.compile(r"^\s*([A-Za-z_][A-Za-z0-9_]*)\s*=\s*([^:]+):([^:]+):([^:]+?)\s*$")

# Layout of a labelled grid, in pixels at 100 dpi: room for tick labels and axis labels.
_DPI = 100
_MARGIN_LEFT_PX, _MARGIN_RIGHT_PX = 130, 30
_MARGIN_BOTTOM_PX, _MARGIN_TOP_PX = 100, 50
_DEFAULT_CELL_PX = 96


class GridAxis(NamedTuple):
    """One axis of a grid: a ``SandSample`` parameter name and the values it takes."""

    name: str
    values: NDArray[np.float64]


def parse_grid_spec(text: str) -> GridAxis:
    """Parse the CLI grid syntax ``NAME=start:stop:count`` (count values, endpoints included).

    Parameters
    ----------
    text
        e.g. ``"iron_oxide=0.001:0.05:8"`` or ``"saturation=0:1:5"``. With count 1, start and
        stop must be equal.

    Returns
    -------
    GridAxis
        The name and ``numpy.linspace(start, stop, count)``.

    Raises
    ------
    ParameterError
        The text does not follow the syntax; the message quotes the offending text.
    """
    match = _SPEC_RE.match(text) if isinstance(text, str) else None
    if match is None:
        raise ParameterError("grid spec", text, _SPEC_SYNTAX)
    name, start_text, stop_text, count_text = match.groups()
    try:
        start, stop = float(start_text), float(stop_text)
    except ValueError:
        raise ParameterError("grid spec", text, f"numeric start and stop; {_SPEC_SYNTAX}") from None
    try:
        count = int(count_text)
    except ValueError:
        raise ParameterError("grid spec", text, _SPEC_SYNTAX) from None
    if not (np.isfinite(start) and np.isfinite(stop)):
        raise ParameterError("grid spec", text, f"finite start and stop; {_SPEC_SYNTAX}")
    if not 1 <= count <= MAX_AXIS_COUNT:
        raise ParameterError("grid spec", text, _SPEC_SYNTAX)
    if count == 1 and start != stop:
        raise ParameterError("grid spec", text, "count 1 only with start equal to stop")
    return GridAxis(name, np.linspace(start, stop, count))


def _as_axis(axis: GridAxis | tuple[str, ArrayLike] | str, which: str) -> GridAxis:
    if isinstance(axis, str):
        return parse_grid_spec(axis)
    allowed = f"a (name, values) pair with 1–{MAX_AXIS_COUNT} finite values, or a spec string {_SPEC_SYNTAX}"
    try:
        name, values = axis
        arr = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(which, axis, allowed) from None
    if (
        not isinstance(name, str)
        or not name.isidentifier()
        or arr.ndim != 1
        or not 1 <= arr.size <= MAX_AXIS_COUNT
        or not np.all(np.isfinite(arr))
    ):
        raise ParameterError(which, axis, allowed)
    return GridAxis(name, arr)


def grid_samples(
    base_sample: Any, x: GridAxis | tuple[str, ArrayLike] | str, y: GridAxis | tuple[str, ArrayLike] | str
) -> tuple[GridAxis, GridAxis, list[Any]]:
    """The samples of a grid: ``base_sample.replace(x=x_i, y=y_j)`` row by row.

    Parameters
    ----------
    base_sample
        Any object with ``replace(**changes)`` returning a modified copy (``SandSample``).
    x, y
        Axes as :class:`GridAxis`, ``(name, values)`` or a spec string.

    Returns
    -------
    (x, y, samples)
        The normalised axes and the ``len(y) * len(x)`` samples, y-major (row j, column i at
        index ``j * len(x) + i``).
    """
    x_axis, y_axis = _as_axis(x, "x"), _as_axis(y, "y")
    if x_axis.name == y_axis.name:
        raise ParameterError("y", y_axis.name, f"a parameter other than x ({x_axis.name})")
    if not callable(getattr(base_sample, "replace", None)):
        raise ParameterError("base_sample", base_sample, "a sample with a replace(**changes) method, e.g. a SandSample")
    samples = [
        base_sample.replace(**{x_axis.name: float(xv), y_axis.name: float(yv)})
        for yv in y_axis.values
        for xv in x_axis.values
    ]
    return x_axis, y_axis, samples


#: Memory matplotlib needs per pixel of a grid PNG: the Agg canvas (RGBA, 4 bytes) and the
#: image resampled to it in float64 RGBA (32 bytes). 20000 × 20000 px would need 13 GiB.
_BYTES_PER_PIXEL = 36


def framed_size_px(width_px: int, height_px: int) -> tuple[int, int]:
    """Size of a labelled grid PNG that shows ``width_px × height_px`` of content at 1:1."""
    return (width_px + _MARGIN_LEFT_PX + _MARGIN_RIGHT_PX, height_px + _MARGIN_BOTTOM_PX + _MARGIN_TOP_PX)


def _validated_size(size_px: tuple[int, int], n_x: int, n_y: int) -> tuple[int, int]:
    min_w = _MARGIN_LEFT_PX + _MARGIN_RIGHT_PX + n_x
    min_h = _MARGIN_BOTTOM_PX + _MARGIN_TOP_PX + n_y
    try:
        width, height = (int(v) for v in size_px)
    except (TypeError, ValueError):
        raise ParameterError("size_px", size_px, "a (width, height) pair of integers") from None
    if width < min_w or height < min_h or width > 20000 or height > 20000:
        raise ParameterError(
            "size_px", size_px, f"width {min_w}–20000 and height {min_h}–20000 pixels for a {n_x}×{n_y} grid"
        )
    check_allocation("size_px", size_px, width * height * _BYTES_PER_PIXEL)
    return width, height


def save_grid_png(
    path: str | os.PathLike,
    image: ArrayLike,
    x: GridAxis,
    y: GridAxis,
    *,
    size_px: tuple[int, int] | None = None,
    cell_text: Sequence[Sequence[str]] | None = None,
    title: str | None = None,
) -> Path:
    """Write a labelled grid image as PNG: ticks at cell centres, parameter names on the axes.

    Parameters
    ----------
    path
        Output PNG path (written atomically).
    image
        Encoded sRGB in [0, 1], shape (H, W, 3), made of ``len(y)`` rows × ``len(x)`` columns of
        equal cells: one pixel per cell for swatches, one tile per cell for mosaics.
    x, y
        The grid's axes; y is drawn increasing downward.
    size_px
        (width, height) of the PNG in pixels; default: 96 px per cell plus margins.
    cell_text
        Optional text per cell, ``cell_text[j][i]`` for row j, column i.
    title
        Optional title above the grid.

    Returns
    -------
    pathlib.Path
        The written path.
    """
    from matplotlib.figure import Figure

    img = np.clip(np.asarray(image, dtype=float), 0.0, 1.0)
    n_x, n_y = len(x.values), len(y.values)
    if size_px is None:
        size_px = framed_size_px(_DEFAULT_CELL_PX * n_x, _DEFAULT_CELL_PX * n_y)
    width, height = _validated_size(size_px, n_x, n_y)

    fig = Figure(figsize=(width / _DPI, height / _DPI), dpi=_DPI)
    grid_w = width - _MARGIN_LEFT_PX - _MARGIN_RIGHT_PX
    grid_h = height - _MARGIN_BOTTOM_PX - _MARGIN_TOP_PX
    ax = fig.add_axes((_MARGIN_LEFT_PX / width, _MARGIN_BOTTOM_PX / height, grid_w / width, grid_h / height))
    # extent puts cell (j, i) centred on (i, j); origin "upper" puts row 0 (first y) at the top.
    ax.imshow(img, interpolation="nearest", aspect="auto", origin="upper", extent=(-0.5, n_x - 0.5, n_y - 0.5, -0.5))
    ax.set_xticks(
        range(n_x), [f"{v:.4g}" for v in x.values], rotation=45 if n_x > 8 else 0, ha="right" if n_x > 8 else "center"
    )
    ax.set_yticks(range(n_y), [f"{v:.4g}" for v in y.values])
    ax.set_xlabel(x.name)
    ax.set_ylabel(y.name)
    if title:
        ax.set_title(title)
    if cell_text is not None:
        cell_w, cell_h = grid_w / n_x, grid_h / n_y
        # Three short lines must fit a cell: points = pixels · 72 / dpi.
        fontsize = max(4.0, min(11.0, 0.16 * cell_h * 72 / _DPI, 0.12 * cell_w * 72 / _DPI))
        for j in range(n_y):
            for i in range(n_x):
                cy, cx = (int((j + 0.5) * img.shape[0] / n_y), int((i + 0.5) * img.shape[1] / n_x))
                luminance = float(np.mean(img[cy, cx]))
                ax.text(
                    i,
                    j,
                    cell_text[j][i],
                    ha="center",
                    va="center",
                    fontsize=fontsize,
                    color="black" if luminance > 0.5 else "white",
                )
    return write_atomically(path, lambda tmp: fig.savefig(tmp, format="png", dpi=_DPI), make_dirs=False)


@dataclass(frozen=True)
class SwatchGrid:
    """Colours of a grid of samples; row j is ``y.values[j]``, column i is ``x.values[i]``.

    Attributes
    ----------
    x, y
        The axes.
    mode
        sRGB mode used for ``rgb`` (``"managed"`` or ``"paper"``).
    xyz, rgb, lab
        CIE XYZ (Y = 1 for white), encoded sRGB in [0, 1] and CIELAB, each (len(y), len(x), 3).
    out_of_gamut
        (len(y), len(x)) booleans: the sRGB of that cell was clipped.
    """

    x: GridAxis
    y: GridAxis
    mode: str
    xyz: NDArray[np.float64]
    rgb: NDArray[np.float64]
    lab: NDArray[np.float64]
    out_of_gamut: NDArray[np.bool_]

    def save_png(
        self,
        path: str | os.PathLike,
        *,
        size_px: tuple[int, int] | None = None,
        show_lab: bool = False,
        title: str | None = None,
    ) -> Path:
        """Render the grid to a PNG with labelled axes and tick values.

        Parameters
        ----------
        path
            Output PNG path (written atomically).
        size_px
            (width, height) in pixels; default 96 px per cell plus margins.
        show_lab
            Print L*, a*, b* in each cell.
        title
            Title above the grid.
        """
        text = None
        if show_lab:
            text = [[f"L* {L:.1f}\na* {a:.1f}\nb* {b:.1f}" for L, a, b in row] for row in self.lab]
        return save_grid_png(path, self.rgb, self.x, self.y, size_px=size_px, cell_text=text, title=title)


def swatch_grid(
    base_sample: Any,
    x: GridAxis | tuple[str, ArrayLike] | str,
    y: GridAxis | tuple[str, ArrayLike] | str,
    *,
    mode: str = "managed",
    reflectance: ReflectanceProvider | None = None,
    wavelengths_nm: ArrayLike = PREDICTOR_WAVELENGTHS_NM,
    illuminant: str = DEFAULT_ILLUMINANT,
    observer: str = DEFAULT_OBSERVER,
) -> SwatchGrid:
    """Colours of ``base_sample`` as two of its parameters vary over a grid.

    Parameters
    ----------
    base_sample
        The sample the other parameters come from (anything with ``replace(**changes)``).
    x, y
        Axes as ``(name, values)``, :class:`GridAxis` or spec strings ``"name=a:b:n"``; x
        increases to the right, y downward.
    mode
        sRGB mode, ``"managed"`` or ``"paper"``.
    reflectance, wavelengths_nm, illuminant, observer
        See :func:`sandlight.colour.sample_xyz`. All cells are computed in one provider call.

    Returns
    -------
    SwatchGrid
        The colours; call :meth:`SwatchGrid.save_png` for the figure.

    Examples
    --------
    >>> grid = swatch_grid(SandSample(), ("iron_oxide", [0.001, 0.01, 0.05]),
    ...                    ("hematite_ratio", [0, 0.5, 1]))              # doctest: +SKIP
    >>> grid.save_png("grid.png", show_lab=True)                          # doctest: +SKIP
    """
    x_axis, y_axis, samples = grid_samples(base_sample, x, y)
    shape = (len(y_axis.values), len(x_axis.values), 3)
    xyz = sample_xyz(
        samples, reflectance=reflectance, wavelengths_nm=wavelengths_nm, illuminant=illuminant, observer=observer
    )
    rgb, gamut = xyz_to_srgb(xyz, mode, illuminant=illuminant, observer=observer, return_out_of_gamut=True)
    lab = xyz_to_lab(xyz, illuminant=illuminant, observer=observer)
    return SwatchGrid(
        x_axis, y_axis, mode, xyz.reshape(shape), rgb.reshape(shape), lab.reshape(shape), gamut.reshape(shape[:2])
    )


def default_sample() -> Any:
    """``SandSample()`` with its documented defaults.

    Raises
    ------
    SandlightError
        ``sandlight.sample`` cannot be imported.
    """
    try:
        from sandlight.sample import SandSample
    except ImportError as exc:
        raise SandlightError(
            f"sandlight.sample.SandSample is not available ({exc}); pass a base sample explicitly."
        ) from exc
    return SandSample()


def figure6(base_sample: Any = None, *, n_x: int = 8, n_y: int = 6, **kwargs: Any) -> SwatchGrid:
    """Paper Figure 6: iron oxide 0.001 → 0.05 (right) × hematite ratio 0 → 1 (downward).

    Parameters
    ----------
    base_sample
        Sample the other parameters come from; default ``SandSample()``.
    n_x, n_y
        Number of iron-oxide and hematite-ratio values (endpoints included).
    **kwargs
        Passed to :func:`swatch_grid` (``mode``, ``reflectance``, ...).
    """
    base = default_sample() if base_sample is None else base_sample
    return swatch_grid(
        base, ("iron_oxide", np.linspace(0.001, 0.05, n_x)), ("hematite_ratio", np.linspace(0.0, 1.0, n_y)), **kwargs
    )


def figure7(base_sample: Any = None, *, n_x: int = 6, n_y: int = 5, **kwargs: Any) -> SwatchGrid:
    """Paper Figure 7: hematite ratio 0 → 1 (right) × degree of saturation 0 → 1 (downward).

    Parameters
    ----------
    base_sample
        Sample the other parameters come from; default ``SandSample()``.
    n_x, n_y
        Number of hematite-ratio and saturation values (endpoints included).
    **kwargs
        Passed to :func:`swatch_grid` (``mode``, ``reflectance``, ...).
    """
    base = default_sample() if base_sample is None else base_sample
    return swatch_grid(
        base, ("hematite_ratio", np.linspace(0.0, 1.0, n_x)), ("saturation", np.linspace(0.0, 1.0, n_y)), **kwargs
    )
