"""Grayscale images as data (height fields, saturation or mineralogy maps)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

#: Memory per pixel of reading one (the decoded pixels, up to 8 B; float64 copies of up to four
#: channels, the luminance and the scaled result), bytes: a 30000² heightfield is refused
#: before it is decoded.
BYTES_PER_PIXEL = 64


def read_grayscale(path: str | os.PathLike, what: str) -> np.ndarray:
    """The image at ``path`` as floats in [0, 1], top row first.

    8- and 16-bit images are scaled by their full range (other types by their maximum); colour
    images become their Rec. 709 luminance (alpha ignored). ``what`` names the image in errors.
    """
    from PIL import UnidentifiedImageError

    from sandlight.errors import ModelFileError
    from sandlight.io import open_image

    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{what} {str(path)!r} does not exist")
    try:
        with open_image(path, what, bytes_per_pixel=BYTES_PER_PIXEL) as im:
            raw = np.asarray(im)
    except (UnidentifiedImageError, OSError) as exc:
        raise ModelFileError(f"{path}: not a readable image ({exc})") from exc
    a = raw.astype(float)
    if a.ndim == 3:
        a = a[..., :3] @ np.array([0.2126, 0.7152, 0.0722]) if a.shape[2] >= 3 else a[..., 0]
    full = 65535.0 if raw.dtype == np.uint16 else (255.0 if raw.dtype == np.uint8 else max(a.max(), 1.0))
    return a / full
