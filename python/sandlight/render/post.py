"""From spectral radiance to pictures: colour, exposure, texture transfer, grain, files, video.

**Colour.** A spectral image becomes CIE XYZ through the colour pipeline of
:mod:`sandlight.colour`: XYZ is linear in the spectrum, with the matrix whose row k is
``spectrum_to_xyz`` of the unit spectrum at band k (illuminant E, i.e. no illuminant: radiance is
already light; CIE 1964 10° observer as the paper). That matrix reproduces ``spectrum_to_xyz`` of
the full spectrum to within ΔE*ab 0.34 on sunlit sand and sky spectra (its PCHIP interpolation is
not exactly linear) and is some fifty times faster on a frame. Y = 1 for a spectrally flat radiance of
1 W m⁻² sr⁻¹ nm⁻¹. Then :func:`sandlight.colour.xyz_to_srgb` (``managed``: Bradford adaptation
from the equal-energy white to D65, IEC 61966-2-1 encoding; or the paper's ``paper`` mode).

**Exposure** divides XYZ by a white level: ``"auto"`` meters the incident light of each frame — a
white Lambertian horizontal surface under that sun and sky is shown as display white, so sand of
albedo 0.3 sits at 0.3 in linear light whatever the hour (like a photographer's incident-light
meter); ``"auto-sequence"`` uses the brightest frame's metering for all frames (dusk gets dark);
a number is the luminance in cd m⁻² shown as white. ``exposure_ev`` brightens by 2^EV. Above 0.8
of white, luminance is rolled off smoothly towards white (``highlights = "soft"``, the default)
or clipped (``"clip"``).

**Texture transfer** (paper §4.2.1): "The ground in the original image was isolated and blurred
heavily. The original image was then divided by the blurred image pixel by pixel, yielding a
quotient image. Each frame in the animation was then multiplied by the resulting quotient image."
We divide the photo's linear luminance by its Gaussian-blurred copy (σ = ``blur_px``; the blur is
normalised over the ground mask so the sky does not bleed in) and multiply each frame's XYZ, on
the ground pixels only (weighted by the renderer's ground coverage). Using luminance rather than
per-channel RGB keeps the simulated colour of the sand and transfers only the photo's texture.

**Grain** (the beach of §4.2.2): a fixed field of Gaussian noise (blurred over ``size_px``,
standard deviation ``amount``) multiplies the ground pixels, the same for every frame so that it
sticks to the (static-camera) ground.
"""

from __future__ import annotations

import functools
import os
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from sandlight.errors import ModelFileError, ParameterError

if TYPE_CHECKING:
    from sandlight.render.image import RenderedImage
    from sandlight.render.light import Lighting

__all__ = [
    "xyz_matrix",
    "spectral_to_xyz",
    "white_level",
    "to_srgb",
    "texture_quotient",
    "apply_quotient",
    "grain_field",
    "write_png",
    "write_netcdf",
    "write_video",
    "COLOUR_OBSERVER",
]

#: The observer of the paper's colour pipeline (§4.1.1).
COLOUR_OBSERVER = "CIE 1964 10 Degree Standard Observer"
#: Luminous efficacy K_m, lm W⁻¹ (SI definition of the candela).
K_M = 683.0


@functools.lru_cache(maxsize=8)
def _xyz_matrix(wavelengths: tuple[float, ...]) -> np.ndarray:
    from sandlight.colour import spectrum_to_xyz

    wl = np.array(wavelengths)
    m = spectrum_to_xyz(wl, np.eye(wl.size), illuminant="E", observer=COLOUR_OBSERVER)
    m.setflags(write=False)
    return m


def xyz_matrix(wavelength_nm: ArrayLike) -> np.ndarray:
    """(n_bands, 3) matrix taking band radiances to XYZ (Y = 1 for a flat unit spectrum)."""
    return _xyz_matrix(tuple(float(v) for v in np.asarray(wavelength_nm, dtype=float)))


def spectral_to_xyz(radiance: ArrayLike, wavelength_nm: ArrayLike) -> np.ndarray:
    """XYZ of spectral radiance (..., n_bands); see the module docstring for the scale."""
    return np.asarray(radiance, dtype=float) @ xyz_matrix(wavelength_nm)


@functools.lru_cache(maxsize=1)
def _luminance_per_y() -> float:
    """cd m⁻² per unit of our Y: K_m Σ ȳ₁₀(λ) Δλ over the 1 nm CMF grid (the E normalisation)."""
    import colour

    return K_M * float(colour.MSDS_CMFS[COLOUR_OBSERVER].values[:, 1].sum())


def white_level(exposure: str | float, lighting: Lighting, wavelength_nm: ArrayLike) -> float:
    """The Y shown as display white for an exposure setting (module docstring)."""
    if isinstance(exposure, str):
        if exposure != "auto":
            raise ParameterError("exposure", exposure, "'auto', 'auto-sequence' or a luminance in cd/m² > 0")
        white = lighting.horizontal_irradiance() / np.pi
        return float(spectral_to_xyz(white, wavelength_nm)[1])
    value = float(exposure)
    if not (value > 0 and np.isfinite(value)):
        raise ParameterError("exposure", exposure, "'auto', 'auto-sequence' or a luminance in cd/m² > 0")
    return value / _luminance_per_y()


#: Highlight handling: "clip" (as sandlight.colour does) or "soft" (roll-off above SOFT_KNEE).
HIGHLIGHTS = ("soft", "clip")
SOFT_KNEE = 0.8


def soft_highlights(y: np.ndarray, knee: float = SOFT_KNEE) -> np.ndarray:
    """Luminance roll-off: identity up to ``knee``, then knee + (1 − knee)(1 − e^(−(Y − knee)/(1 − knee))),
    which is continuous with slope 1 at the knee and approaches 1 (display white) smoothly."""
    y = np.asarray(y, dtype=float)
    over = np.maximum(y - knee, 0.0)
    return np.where(y <= knee, y, knee + (1.0 - knee) * (1.0 - np.exp(-over / (1.0 - knee))))


def to_srgb(
    xyz: ArrayLike, white_y: float, *, exposure_ev: float = 0.0, mode: str = "managed", highlights: str = "soft"
) -> np.ndarray:
    """Encoded sRGB in [0, 1] of XYZ scaled so that Y = ``white_y`` is display white.

    With ``highlights="soft"`` luminances above 0.8 of white are compressed towards white
    (:func:`soft_highlights`, chromaticity kept) instead of clipped, so a bright sky at dawn keeps
    its gradient; everything darker is unchanged.
    """
    from sandlight.colour import xyz_to_srgb

    if highlights not in HIGHLIGHTS:
        raise ParameterError("highlights", highlights, "one of " + ", ".join(repr(h) for h in HIGHLIGHTS))
    scale = 2.0 ** float(exposure_ev) / max(float(white_y), 1e-300)
    scaled = np.asarray(xyz, dtype=float) * scale
    if highlights == "soft":
        y = scaled[..., 1]
        factor = np.where(y > SOFT_KNEE, soft_highlights(y) / np.maximum(y, 1e-300), 1.0)
        scaled = scaled * factor[..., None]
    return xyz_to_srgb(scaled, mode, illuminant="E", observer=COLOUR_OBSERVER)


def _gaussian(image: np.ndarray, sigma: float) -> np.ndarray:
    from scipy.ndimage import gaussian_filter

    return gaussian_filter(image, sigma, mode="reflect")


def texture_quotient(
    photo: ArrayLike,
    *,
    blur_px: float = 25.0,
    ground_mask: ArrayLike | None = None,
    limits: tuple[float, float] = (0.25, 4.0),
) -> np.ndarray:
    """Quotient image of §4.2.1: photo luminance over its heavily blurred copy.

    Parameters
    ----------
    photo : array_like, shape (h, w, 3) or (h, w)
        Encoded sRGB in [0, 1] (as :func:`sandlight.colour.load_image` returns).
    blur_px : float
        Standard deviation of the Gaussian blur, pixels (> 0).
    ground_mask : array_like of bool or float, shape (h, w), optional
        Where the photo shows ground (default: everywhere); elsewhere the quotient is 1.
    limits : (low, high)
        The quotient is clipped to this range (very dark pores would otherwise blacken a frame).

    Returns
    -------
    numpy.ndarray, shape (h, w)
        Mean ≈ 1 over the ground.
    """
    p = np.asarray(photo, dtype=float)
    if p.ndim == 3:
        import colour

        linear = colour.models.eotf_sRGB(np.clip(p[..., :3], 0.0, 1.0))
        lum = linear @ np.array([0.2126, 0.7152, 0.0722])
    elif p.ndim == 2:
        lum = p
    else:
        raise ParameterError("photo", f"array of shape {p.shape}", "an image of shape (h, w, 3) or (h, w)")
    if not (blur_px > 0 and np.isfinite(blur_px)):
        raise ParameterError("blur_px", blur_px, "a blur radius > 0 pixels")
    mask = np.ones(lum.shape) if ground_mask is None else np.asarray(ground_mask, dtype=float)
    if mask.shape != lum.shape:
        raise ParameterError("ground_mask", f"array of shape {mask.shape}", f"the photo's shape {lum.shape}")
    # Normalised convolution: the blur averages ground pixels only.
    blurred = _gaussian(lum * mask, blur_px) / np.maximum(_gaussian(mask, blur_px), 1e-6)
    q = np.where(mask > 0.5, lum / np.maximum(blurred, 1e-6), 1.0)
    return np.clip(q, *limits)


def fit_to(image: np.ndarray, height: int, width: int, fit: str) -> np.ndarray:
    """Resize a 2-D array to (height, width): ``"stretch"`` (bilinear) or ``"tile"`` (repeat)."""
    if fit == "tile":
        reps = (-(-height // image.shape[0]), -(-width // image.shape[1]))
        return np.tile(image, reps)[:height, :width]
    if fit == "stretch":
        from scipy.ndimage import zoom

        return zoom(image, (height / image.shape[0], width / image.shape[1]), order=1, mode="nearest")[:height, :width]
    raise ParameterError("fit", fit, "'tile' or 'stretch'")


def apply_quotient(xyz: np.ndarray, quotient: np.ndarray, coverage: np.ndarray, strength: float = 1.0) -> np.ndarray:
    """Multiply the ground pixels of an XYZ image by quotient^strength (weighted by coverage)."""
    factor = 1.0 + np.asarray(coverage, dtype=float) * (np.power(quotient, strength) - 1.0)
    return xyz * factor[..., None]


def grain_field(height: int, width: int, *, amount: float, size_px: float = 0.7, seed: int = 0) -> np.ndarray:
    """Multiplicative grain: 1 + Gaussian noise of standard deviation ``amount``, blurred over
    ``size_px`` pixels (then rescaled to that standard deviation), clipped to ≥ 0."""
    if not (0.0 <= amount <= 1.0):
        raise ParameterError("grain.amount", amount, "a standard deviation in [0, 1]")
    if not (size_px >= 0 and np.isfinite(size_px)):
        raise ParameterError("grain.size_px", size_px, "a blur ≥ 0 pixels")
    noise = np.random.default_rng(seed).standard_normal((height, width))
    if size_px > 0:
        noise = _gaussian(noise, size_px)
    noise /= max(noise.std(), 1e-12)
    return np.maximum(1.0 + amount * noise, 0.0)


def write_png(path: str | os.PathLike, rgb: np.ndarray) -> Path:
    """Write encoded sRGB in [0, 1] as an 8-bit PNG, atomically."""
    from PIL import Image

    from sandlight.colour import srgb_to_uint8
    from sandlight.io import write_atomically

    data = srgb_to_uint8(rgb)
    return write_atomically(path, lambda tmp: Image.fromarray(data, "RGB").save(tmp, format="PNG"))


def write_netcdf(
    path: str | os.PathLike,
    image: RenderedImage,
    xyz: np.ndarray | None = None,
    attrs: dict | None = None,
    *,
    spectral: bool = True,
) -> Path:
    """Write a :class:`~sandlight.render.image.RenderedImage` as compressed NetCDF, atomically:
    ground coverage, the linear spectral radiance (unless ``spectral=False``) and XYZ if given."""
    if not spectral and xyz is None:
        raise ParameterError("xyz", None, "an XYZ image when the spectral radiance is not written")
    import xarray as xr

    from sandlight.io import WAVELENGTH_ATTRS, cf_attributes, write_atomically

    h, w, _ = image.radiance.shape
    data = {
        "coverage": (("y", "x"), image.coverage, {"units": "1", "long_name": "fraction of samples that saw the ground"})
    }
    if spectral:
        data["radiance"] = (
            ("y", "x", "wavelength"),
            image.radiance,
            {"units": "W m-2 sr-1 nm-1", "long_name": "mean spectral radiance (row 0 = top of the image)"},
        )
    if xyz is not None:
        data["XYZ"] = (
            ("y", "x", "channel"),
            xyz.astype(np.float32),
            {
                "units": "W m-2 sr-1 nm-1",
                "long_name": "CIE XYZ (1964 10 deg observer, Y = 1 for a flat unit spectrum), before exposure",
            },
        )
    meta = {
        k: (v if isinstance(v, (int, float, str)) else str(v)) for k, v in {**image.metadata, **(attrs or {})}.items()
    }
    coords = {
        "y": ("y", np.arange(h), {"units": "1", "long_name": "pixel row (0 = top)"}),
        "x": ("x", np.arange(w), {"units": "1", "long_name": "pixel column (0 = left)"}),
    }
    if spectral:
        coords["wavelength"] = ("wavelength", image.wavelength_nm, WAVELENGTH_ATTRS)
    if xyz is not None:
        coords["channel"] = ("channel", ["X", "Y", "Z"], {"long_name": "CIE tristimulus channel"})
    attrs = {**cf_attributes("Rendered frame (sandlight)", "sandlight.render"), "creator": "sandlight.render"}
    ds = xr.Dataset(data, coords=coords, attrs={**attrs, "spp": image.spp, **meta})
    encoding = {name: {"compression": "gzip", "compression_opts": 4} for name in data}
    return write_atomically(path, lambda tmp: ds.to_netcdf(tmp, engine="h5netcdf", encoding=encoding))


def write_video(path: str | os.PathLike, frames: list[Path], fps: float) -> Path:
    """Encode PNG frames as an H.264 MP4 (imageio-ffmpeg), atomically."""
    import imageio_ffmpeg
    from PIL import Image

    from sandlight.io import write_atomically

    if not frames:
        raise ParameterError("frames", frames, "at least one frame")
    if not (fps > 0 and np.isfinite(fps)):
        raise ParameterError("fps", fps, "a frame rate > 0")

    target = Path(path)
    if target.suffix.lower() != ".mp4":
        raise ParameterError("video", str(path), "a file name ending in .mp4")

    def write(tmp: Path) -> None:
        images = [np.asarray(Image.open(f).convert("RGB")) for f in frames]
        h, w = images[0].shape[:2]
        # libx264 with yuv420p needs even sizes: pad by repeating the last row/column.
        pad = ((0, h % 2), (0, w % 2), (0, 0))
        # The temporary name does not end in .mp4, so the container is named for ffmpeg.
        writer = imageio_ffmpeg.write_frames(
            str(tmp),
            (w + w % 2, h + h % 2),
            fps=fps,
            codec="libx264",
            pix_fmt_out="yuv420p",
            macro_block_size=1,
            ffmpeg_log_level="error",
            output_params=["-f", "mp4"],
        )
        try:
            writer.send(None)  # start ffmpeg
            for img in images:
                if img.shape[:2] != (h, w):
                    raise ParameterError(
                        "frames", f"an image of {img.shape[1]}×{img.shape[0]} px", f"frames of one size ({w}×{h})"
                    )
                writer.send(np.ascontiguousarray(np.pad(img, pad, mode="edge")))
            writer.close()
        except (OSError, RuntimeError) as exc:
            raise ModelFileError(f"could not encode {path} with ffmpeg: {exc}") from exc
        finally:
            writer.close()

    return write_atomically(target, write)
