"""Colourisation of a photograph of sand with a sample's colour (paper §4.1.1).

"The image was then colourized using the RGB triple. This was accomplished by computing the mean
RGB values for the original image. This mean was then subtracted from each pixel and the RGB
triple computed using the proposed framework was added." The paper did this on the encoded
(gamma-corrected) sRGB values; so does :func:`colourise` by default. ``linear=True`` does it on
linear-light values instead (image and target decoded with the IEC 61966-2-1 curve, shifted,
clipped, re-encoded), which keeps the shift physically additive in light but changes the contrast
of dark and bright grains differently. Either way the result is clipped to [0, 1] per channel.

Public objects
--------------
- :func:`default_texture_path`: the procedural sand texture shipped with sandlight.
- :func:`load_image`, :func:`save_image`: pillow I/O as encoded sRGB floats in [0, 1].
- :func:`colourise`: one photo, one sample (or one RGB triple).
- :func:`colourise_grid` → :class:`ColourisedGrid`: a Figure 6/7-style mosaic of one photo.
"""

from __future__ import annotations

import errno
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

import colour
from sandlight.checks import check_allocation
from sandlight.colour.provider import ReflectanceProvider
from sandlight.colour.sample_colour import sample_rgb
from sandlight.colour.spectrum import DEFAULT_ILLUMINANT, DEFAULT_OBSERVER, PREDICTOR_WAVELENGTHS_NM
from sandlight.colour.srgb import srgb_to_uint8
from sandlight.colour.swatches import GridAxis, framed_size_px, grid_samples, save_grid_png
from sandlight.errors import ModelFileError, ParameterError
from sandlight.io import open_image, write_atomically

__all__ = [
    "default_texture_path",
    "load_image",
    "save_image",
    "colourise",
    "ColourisedGrid",
    "colourise_grid",
]

# 16-bit greyscale modes pillow cannot convert to 8-bit RGB without clipping.
_SIXTEEN_BIT_MODES = ("I;16", "I;16B", "I;16L", "I")


def default_texture_path() -> Path:
    """Path of ``sandlight/data/textures/sand.png``, the project's own sand texture (CC0)."""
    return Path(__file__).resolve().parent.parent / "data" / "textures" / "sand.png"


#: Memory per pixel of reading an image (8-bit RGB from pillow, then float64), bytes.
LOAD_BYTES_PER_PIXEL = 32

#: Peak memory per pixel of the whole `colourise` command (read, shift, write), bytes: measured
#: with /usr/bin/time on a 3000² photo as 99 B/px shifting encoded values and 216 B/px in linear
#: light (the sRGB curve's temporaries), rounded up.
COLOURISE_BYTES_PER_PIXEL = {False: 110, True: 230}

#: Memory per pixel of a grid's mosaic (float64 RGB, 24 B) and of its labelled PNG (36 B), bytes.
MOSAIC_BYTES_PER_PIXEL = 60


def load_image(path: str | os.PathLike, *, bytes_per_pixel: float = LOAD_BYTES_PER_PIXEL) -> NDArray[np.float64]:
    """Read an image file as encoded sRGB in [0, 1].

    Parameters
    ----------
    path
        Any format pillow reads (PNG, JPEG, TIFF, ...). Alpha is ignored; greyscale is
        replicated to three channels; 16-bit greyscale is scaled by 1/65535.
    bytes_per_pixel
        Memory the caller's work needs per pixel (default: reading alone). An image whose
        pixels times this exceed `sandlight.checks.MAX_ALLOCATION_BYTES` is refused before
        it is decoded (`sandlight.io.open_image`).

    Returns
    -------
    numpy.ndarray, shape (H, W, 3)
        Encoded sRGB values in [0, 1] (the file's values are taken to be sRGB).

    Raises
    ------
    FileNotFoundError
        No file at ``path`` (the message names it).
    ModelFileError
        The file exists but is not a readable image (the message names it).
    ParameterError
        The image is too large for the memory limit (the message gives both figures).
    """

    p = Path(path)
    if not p.exists():
        raise FileNotFoundError(errno.ENOENT, "Image file not found", str(p))
    if not p.is_file():
        raise ModelFileError(f"Cannot read image {str(p)!r}: not a regular file.")
    try:
        with open_image(p, "image", bytes_per_pixel=bytes_per_pixel) as im:
            im.load()
            if im.mode in _SIXTEEN_BIT_MODES:
                grey = np.asarray(im, dtype=float) / 65535.0
                return np.repeat(np.clip(grey, 0.0, 1.0)[..., None], 3, axis=-1)
            return np.asarray(im.convert("RGB"), dtype=float) / 255.0
    except (OSError, ValueError, SyntaxError) as exc:
        if isinstance(exc, ParameterError):
            raise
        # Pillow reports unknown formats as UnidentifiedImageError (an OSError), truncated files
        # as OSError, and some corrupt headers as ValueError or SyntaxError.
        raise ModelFileError(f"Cannot read image {str(p)!r}: {exc}") from exc


def image_format(path: str | os.PathLike) -> str:
    """The pillow format name that the suffix of ``path`` says (e.g. "PNG" for .png, "JPEG" for .jpg).

    Raises
    ------
    ParameterError
        Pillow cannot write a format of that suffix.
    """
    from PIL import Image

    p = Path(path)
    fmt = Image.registered_extensions().get(p.suffix.lower())
    if fmt is None or fmt not in Image.SAVE:
        raise ParameterError(
            "output", str(p), "a file name ending in .png, .jpg, .tif or another extension pillow can write"
        )
    return fmt


def save_image(path: str | os.PathLike, rgb: ArrayLike) -> Path:
    """Write encoded sRGB in [0, 1] as an 8-bit image, atomically; format from the extension.

    Parameters
    ----------
    path
        Output path ending in an extension pillow can write (.png, .jpg, .tif, ...).
    rgb
        Encoded sRGB, shape (H, W, 3), clipped to [0, 1] and rounded to 8 bits.

    Returns
    -------
    pathlib.Path
        The written path.
    """
    from PIL import Image

    p = Path(path)
    fmt = image_format(p)
    arr = np.asarray(rgb)
    if arr.ndim != 3 or arr.shape[-1] != 3:
        raise ParameterError("rgb", f"array of shape {arr.shape}", "shape (H, W, 3)")
    image = Image.fromarray(srgb_to_uint8(arr), mode="RGB")
    return write_atomically(p, lambda tmp: image.save(tmp, format=fmt), make_dirs=False)


def _validated_image(image: ArrayLike) -> NDArray[np.float64]:
    arr = np.asarray(image)
    if arr.ndim != 3 or arr.shape[-1] != 3 or arr.shape[0] == 0 or arr.shape[1] == 0:
        raise ParameterError(
            "image", f"array of shape {arr.shape}", "shape (H, W, 3), encoded sRGB floats in [0, 1] or uint8"
        )
    if arr.dtype == np.uint8:
        return arr.astype(float) / 255.0
    arr = arr.astype(float)
    if not np.all(np.isfinite(arr)) or arr.min() < 0.0 or arr.max() > 1.0:
        raise ParameterError(
            "image", "an array with values outside [0, 1] or NaN", "encoded sRGB floats in [0, 1] (or a uint8 array)"
        )
    return arr


def _target_rgb(sample_or_rgb: Any, **colour_kwargs: Any) -> NDArray[np.float64]:
    """The colour to impose: an explicit RGB triple, or the sRGB of a sample."""
    if isinstance(sample_or_rgb, (np.ndarray, list, tuple)):
        try:
            rgb = np.asarray(sample_or_rgb, dtype=float)
        except (TypeError, ValueError):
            rgb = None
        if rgb is None or rgb.shape != (3,) or not np.all((rgb >= 0.0) & (rgb <= 1.0)):
            raise ParameterError("sample_or_rgb", sample_or_rgb, "a sand sample, or an encoded sRGB triple in [0, 1]")
        return rgb
    return sample_rgb(sample_or_rgb, **colour_kwargs)


def _shift(image: NDArray, target: NDArray, linear: bool) -> NDArray:
    """§4.1.1: pixel − mean(image) + target, per channel, clipped to [0, 1]."""
    if not linear:
        return np.clip(image - image.mean(axis=(0, 1)) + target, 0.0, 1.0)
    with colour.utilities.domain_range_scale("reference"):
        img_lin = colour.models.eotf_sRGB(image)
        target_lin = colour.models.eotf_sRGB(target)
        shifted = np.clip(img_lin - img_lin.mean(axis=(0, 1)) + target_lin, 0.0, 1.0)
        return np.asarray(colour.models.eotf_inverse_sRGB(shifted), dtype=float)


def colourise(
    image: ArrayLike,
    sample_or_rgb: Any,
    *,
    linear: bool = False,
    mode: str = "managed",
    reflectance: ReflectanceProvider | None = None,
    wavelengths_nm: ArrayLike = PREDICTOR_WAVELENGTHS_NM,
    illuminant: str = DEFAULT_ILLUMINANT,
    observer: str = DEFAULT_OBSERVER,
) -> NDArray[np.float64]:
    """Give a photo of sand the colour of a sample (paper §4.1.1).

    Parameters
    ----------
    image
        Encoded sRGB, shape (H, W, 3): floats in [0, 1] or uint8.
    sample_or_rgb
        A sand sample (its colour comes from :func:`~sandlight.colour.sample_rgb`) or an
        encoded sRGB triple in [0, 1].
    linear
        False (the paper): shift the encoded values. True: shift in linear light.
    mode, reflectance, wavelengths_nm, illuminant, observer
        How the sample's colour is computed; see :func:`~sandlight.colour.sample_rgb`.

    Returns
    -------
    numpy.ndarray, shape (H, W, 3)
        Encoded sRGB in [0, 1]. Its mean equals the target colour wherever no pixel was clipped.
    """
    img = _validated_image(image)
    target = _target_rgb(
        sample_or_rgb,
        mode=mode,
        reflectance=reflectance,
        wavelengths_nm=wavelengths_nm,
        illuminant=illuminant,
        observer=observer,
    )
    return _shift(img, target, linear)


def _tile_size(tile_px: Any) -> tuple[int, int]:
    """``tile_px`` checked: (width, height) in 1–4096 pixels."""
    try:
        width, height = (int(v) for v in tile_px)
    except (TypeError, ValueError):
        raise ParameterError("tile_px", tile_px, "a (width, height) pair of integers") from None
    if not (1 <= width <= 4096 and 1 <= height <= 4096):
        raise ParameterError("tile_px", tile_px, "width and height in 1–4096 pixels")
    return width, height


def _resized(image: NDArray, tile_px: tuple[int, int] | None) -> NDArray:
    if tile_px is None:
        return image
    from PIL import Image

    width, height = _tile_size(tile_px)
    # Per-channel float resampling keeps the values exact enough for the mean shift.
    channels = [
        np.asarray(
            Image.fromarray(image[..., c].astype(np.float32), mode="F").resize(
                (width, height), Image.Resampling.LANCZOS
            ),
            dtype=float,
        )
        for c in range(3)
    ]
    return np.clip(np.stack(channels, axis=-1), 0.0, 1.0)


@dataclass(frozen=True)
class ColourisedGrid:
    """A photo colourised for every cell of a grid; row j is ``y.values[j]``.

    Attributes
    ----------
    x, y
        The axes (x to the right, y downward).
    rgb
        Target sRGB of each cell, (len(y), len(x), 3).
    mosaic
        The tiles side by side, separated by ``gap_px`` white pixels, (H, W, 3) in [0, 1].
    """

    x: GridAxis
    y: GridAxis
    rgb: NDArray[np.float64]
    mosaic: NDArray[np.float64]

    def save_png(
        self,
        path: str | os.PathLike,
        *,
        labels: bool = True,
        size_px: tuple[int, int] | None = None,
        title: str | None = None,
    ) -> Path:
        """Write the mosaic: with ``labels``, framed by axes with parameter names and values
        (default size shows the mosaic at 1:1 plus margins); without, the bare mosaic."""
        if not labels:
            return save_image(path, self.mosaic)
        if size_px is None:
            size_px = framed_size_px(self.mosaic.shape[1], self.mosaic.shape[0])
        return save_grid_png(path, self.mosaic, self.x, self.y, size_px=size_px, title=title)


def colourise_grid(
    image: ArrayLike,
    base_sample: Any,
    x: Any,
    y: Any,
    *,
    tile_px: tuple[int, int] | None = None,
    gap_px: int = 4,
    linear: bool = False,
    mode: str = "managed",
    reflectance: ReflectanceProvider | None = None,
    wavelengths_nm: ArrayLike = PREDICTOR_WAVELENGTHS_NM,
    illuminant: str = DEFAULT_ILLUMINANT,
    observer: str = DEFAULT_OBSERVER,
) -> ColourisedGrid:
    """One photo colourised over a grid of two parameters (paper Figures 6 and 7).

    Parameters
    ----------
    image
        Encoded sRGB photo, (H, W, 3), floats in [0, 1] or uint8.
    base_sample
        The sample the other parameters come from (anything with ``replace(**changes)``).
    x, y
        Axes as ``(name, values)``, :class:`~sandlight.colour.swatches.GridAxis` or spec
        strings ``"name=a:b:n"``.
    tile_px
        (width, height) each tile is resampled to (Lanczos); default: the photo's own size.
    gap_px
        White pixels between tiles, 0–64.
    linear, mode, reflectance, wavelengths_nm, illuminant, observer
        See :func:`colourise`. All cells are computed in one provider call.

    Returns
    -------
    ColourisedGrid
        Mosaic of height ``n_y·h + (n_y − 1)·gap_px`` and width ``n_x·w + (n_x − 1)·gap_px``.
    """
    if not isinstance(gap_px, (int, np.integer)) or not 0 <= gap_px <= 64:
        raise ParameterError("gap_px", gap_px, "an integer in 0–64")
    x_axis, y_axis, samples = grid_samples(base_sample, x, y)
    n_x, n_y = len(x_axis.values), len(y_axis.values)
    img = _validated_image(image)
    h, w = img.shape[:2] if tile_px is None else _tile_size(tile_px)[::-1]
    mosaic_px = (n_y * h + (n_y - 1) * gap_px) * (n_x * w + (n_x - 1) * gap_px)
    check_allocation(
        "tile_px" if tile_px is not None else "image",
        f"{n_x}×{n_y} tiles of {w}×{h} pixels",
        mosaic_px * MOSAIC_BYTES_PER_PIXEL,
    )
    img = _resized(img, tile_px)
    rgb = sample_rgb(
        samples,
        mode=mode,
        reflectance=reflectance,
        wavelengths_nm=wavelengths_nm,
        illuminant=illuminant,
        observer=observer,
    ).reshape(n_y, n_x, 3)
    mosaic = np.ones((n_y * h + (n_y - 1) * gap_px, n_x * w + (n_x - 1) * gap_px, 3))
    for j in range(n_y):
        for i in range(n_x):
            top, left = j * (h + gap_px), i * (w + gap_px)
            mosaic[top : top + h, left : left + w] = _shift(img, rgb[j, i], linear)
    return ColourisedGrid(x_axis, y_axis, rgb, mosaic)
