"""The paper's two animations rendered through Mitsuba (``sandlight render … --renderer mitsuba``).

For each frame of a sandlight `Scene`: the Mitsuba scene of `sandlight.mitsuba.scenes.scene_dict`
(the frame's sun under ``sunsky``, the frame's saturation map), rendered in a spectral variant to
linear sRGB, exposed like sandlight's ``exposure = "auto"`` (display white = the luminance of a
white Lambertian horizontal surface under that sky, E_h/π, measured with `METER_SPP` samples),
highlights rolled off as ``highlights = "soft"``, written as ``frame_NNNN.png``; the MP4 at the
end. The texture transfer and grain post-processes and the linear NetCDF of sandlight's renderer
are not applied (docs/mitsuba.md).
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable
from pathlib import Path
from types import ModuleType

import numpy as np

from sandlight.mitsuba.scenes import scene_dict
from sandlight.render import SceneRun, post
from sandlight.render.scene import Scene

__all__ = ["render_scene_mitsuba", "white_luminance", "tonemap", "METER_SPP", "DEFAULT_VARIANT"]

METER_SPP = 1 << 14
DEFAULT_VARIANT = "llvm_ad_spectral"
#: Linear-sRGB luminance weights (IEC 61966-2-1).
_LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def white_luminance(mi: ModuleType, sky: dict) -> float:
    """E_h/π in linear-sRGB luminance units: the radiance of a white Lambertian horizontal disc
    under ``sky`` (a ``radiancemeter`` looking down at it; the path integrator samples the sun)."""
    meter = mi.load_dict(
        {
            "type": "scene",
            "integrator": {"type": "path", "max_depth": 2},
            "sky": sky,
            "white": {"type": "disk", "bsdf": {"type": "diffuse", "reflectance": 1.0}},
            "meter": {
                "type": "radiancemeter",
                "origin": [0.0, 0.0, 1.0],
                "direction": [0.0, 0.0, -1.0],
                "film": {"type": "hdrfilm", "width": 1, "height": 1, "rfilter": {"type": "box"}},
                "sampler": {"type": "independent", "sample_count": METER_SPP},
            },
        }
    )
    radiance = np.array(mi.render(meter)).reshape(-1)[:3]
    return float(_LUMINANCE @ radiance)


def tonemap(rgb_linear: np.ndarray, white: float, exposure_ev: float = 0.0) -> np.ndarray:
    """Encoded sRGB in [0, 1]: linear sRGB scaled so that luminance ``white`` is display white,
    luminances above 0.8 of white rolled off (`sandlight.render.post.soft_highlights`)."""
    import colour

    scaled = np.asarray(rgb_linear, dtype=float) * (2.0**exposure_ev / max(white, 1e-300))
    y = scaled @ _LUMINANCE
    factor = np.where(y > post.SOFT_KNEE, post.soft_highlights(y) / np.maximum(y, 1e-300), 1.0)
    return np.clip(colour.cctf_encoding(np.clip(scaled * factor[..., None], 0.0, 1.0), function="sRGB"), 0.0, 1.0)


def render_scene_mitsuba(
    scene: Scene,
    out_dir: str | os.PathLike[str],
    *,
    video: str | os.PathLike[str] | None = None,
    variant: str = DEFAULT_VARIANT,
    log: Callable[[str], object] | None = None,
) -> SceneRun:
    """Render every frame of ``scene`` through Mitsuba into ``out_dir`` (created) and optionally an MP4.

    Uses the scene's size, frames, spp and seed (frame k: seed + k) and ``render.max_bounces``.

    Raises
    ------
    ParameterError
        A scene the Mitsuba path does not support (`scene_dict`), or a bad ``variant``.
    """
    from sandlight.mitsuba import load_mitsuba

    start = time.perf_counter()
    mi = load_mitsuba(variant)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    run = SceneRun(scene)
    mesh = None
    for k, t in enumerate(scene.times_h()):
        description = scene_dict(mi, scene, k, terrain=mesh)
        mesh = description.get("terrain")  # the dune mesh is built once
        t0 = time.perf_counter()
        image = np.array(mi.render(mi.load_dict(description), seed=scene.settings.seed + k))
        seconds = time.perf_counter() - t0
        white = white_luminance(mi, description["sky"])
        png = post.write_png(out / f"frame_{k:04d}.png", tonemap(image[..., :3], white, scene.exposure_ev))
        run.pngs.append(png)
        run.render_seconds.append(seconds)
        if log is not None:
            log(f"frame {k + 1}/{scene.frames}: {t:5.2f} h, Mitsuba {variant} {seconds:.1f} s → {png}")
    if video is not None:
        run.video = post.write_video(video, run.pngs, scene.fps)
    run.elapsed_s = time.perf_counter() - start
    return run
