"""Rendering a scene file to frames and a video (the paper's §4.2 animations).

For each frame: the sun for its time of day, the sky texture, the material map for its point of
the day (the beach dries), the spectral render, then colour, texture transfer and grain. Frames
are written as they finish (``frame_0000.png``, and ``frame_0000.nc`` with the linear spectral
image); the MP4 is encoded at the end. Ctrl-C stops within a batch of rows: finished frames stay,
the frame in progress and the video are not written.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from sandlight.checks import check_allocation
from sandlight.errors import ParameterError
from sandlight.progress import progress_bar
from sandlight.render import post
from sandlight.render.image import interrupt_requests, render_image
from sandlight.render.scene import Scene

if TYPE_CHECKING:
    from sandlight.progress import ProgressBar
    from sandlight.render.camera import Camera
    from sandlight.render.tables import BrdfTable
    from sandlight.render.terrain import HeightfieldTerrain, PlaneTerrain

__all__ = ["render_scene", "SceneRun", "frame_bytes"]

#: Memory per pixel of one frame besides its spectral radiance (float32 per band): coverage
#: (float32), XYZ, the shown XYZ and the sRGB (float64 × 3 each), texture and grain quotients
#: (float64), the 8-bit PNG, bytes.
_FRAME_BYTES_PER_PIXEL = 4 + 3 * 24 + 16 + 3


def frame_bytes(scene: Scene) -> int:
    """Estimated memory of one frame's arrays, bytes: checked before anything is rendered, since
    a size inside the allowed 1–16384 pixels can still need more than a machine has (16384² at
    16 bands needs about 40 GiB)."""
    return scene.width * scene.height * (4 * scene.wavelength_nm.size + _FRAME_BYTES_PER_PIXEL)


@dataclass
class SceneRun:
    """What a scene render produced."""

    scene: Scene
    pngs: list[Path] = field(default_factory=list)
    netcdfs: list[Path] = field(default_factory=list)
    video: Path | None = None
    render_seconds: list[float] = field(default_factory=list)
    elapsed_s: float = 0.0


def _texture(scene: Scene, height: int, width: int) -> np.ndarray | None:
    t = scene.texture
    if t is None:
        return None
    from sandlight.colour import default_texture_path, load_image

    photo = load_image(default_texture_path() if t["photo"] == "builtin:sand" else t["photo"])
    mask = None
    if t["ground_mask"] is not None:
        m = load_image(t["ground_mask"])
        mask = (m.mean(axis=-1) if m.ndim == 3 else m) > 0.5
        if mask.shape != photo.shape[:2]:
            raise ParameterError(
                "post.texture.ground_mask",
                t["ground_mask"],
                f"an image of the photo's size {photo.shape[1]}×{photo.shape[0]}",
            )
    q = post.texture_quotient(photo, blur_px=t["blur_px"], ground_mask=mask)
    if t["scale"] != 1.0:
        q = post.fit_to(q, max(1, round(q.shape[0] * t["scale"])), max(1, round(q.shape[1] * t["scale"])), "stretch")
    return post.fit_to(q, height, width, t["fit"])


def render_scene(
    scene: Scene,
    out_dir: str | os.PathLike[str],
    *,
    video: str | os.PathLike[str] | None = None,
    progress: bool = True,
    log: Callable[[str], object] | None = None,
) -> SceneRun:
    """Render every frame of ``scene`` into ``out_dir`` (created if needed) and optionally an MP4.

    Parameters
    ----------
    scene : Scene
    out_dir : path-like
        Folder for ``frame_NNNN.png`` and, unless ``scene.write_linear`` is ``"none"``,
        ``frame_NNNN.nc`` (linear XYZ, and the spectral radiance when it is ``"spectral"``).
    video : path-like, optional
        MP4 file to encode from the frames (its folder is created if needed).
    progress : bool
        Show a progress bar over all frames.
    log : callable, optional
        Receives one line of text per finished frame.

    Returns
    -------
    SceneRun
    """
    check_allocation("width × height", f"{scene.width}×{scene.height} pixels", frame_bytes(scene))
    start = time.perf_counter()
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    if video is not None:
        if Path(video).suffix.lower() != ".mp4":
            raise ParameterError("video", str(video), "a file name ending in .mp4")
        Path(video).parent.mkdir(parents=True, exist_ok=True)
    terrain = scene.build_terrain()
    camera = scene.build_camera(terrain)
    table = scene.build_table(progress=progress)
    wl = scene.wavelength_nm
    quotient = _texture(scene, scene.height, scene.width)
    grain = None
    if scene.grain is not None:
        grain = post.grain_field(
            scene.height,
            scene.width,
            amount=scene.grain["amount"],
            size_px=scene.grain["size_px"],
            seed=scene.grain["seed"],
        )
    fixed_white = None
    if scene.exposure == "auto-sequence":
        fixed_white = max(post.white_level("auto", scene.build_lighting(t), wl) for t in scene.times_h())
    elif not isinstance(scene.exposure, str):
        fixed_white = post.white_level(scene.exposure, None, wl)

    run = SceneRun(scene)
    with (
        progress_bar(scene.name, scene.frames * scene.height, unit="rows", enabled=progress) as bar,
        interrupt_requests() as interrupted,
    ):
        _render_frames(scene, out, run, camera, terrain, table, quotient, grain, fixed_white, bar, interrupted, log)
    if video is not None:
        run.video = post.write_video(video, run.pngs, scene.fps)
    run.elapsed_s = time.perf_counter() - start
    return run


def _render_frames(
    scene: Scene,
    out: Path,
    run: SceneRun,
    camera: Camera,
    terrain: PlaneTerrain | HeightfieldTerrain,
    table: BrdfTable,
    quotient: np.ndarray | None,
    grain: np.ndarray | None,
    fixed_white: float | None,
    bar: ProgressBar,
    interrupted: list[bool],
    log: Callable[[str], object] | None,
) -> None:
    """The frame loop of :func:`render_scene`; a Ctrl-C between frames is honoured before the next."""
    wl = scene.wavelength_nm
    for k, (t, frac) in enumerate(zip(scene.times_h(), scene.day_fractions())):
        if interrupted[0]:
            raise KeyboardInterrupt
        lighting = scene.build_lighting(t)
        material = scene.build_material(float(frac))
        bar.advance(
            0,
            description=f"{scene.name}: frame {k + 1}/{scene.frames}, "
            f"{int(t):02d}:{int(round(t % 1 * 60)) % 60:02d}, sun {lighting.sun_elevation_deg:.1f}°",
        )
        image = render_image(
            camera,
            terrain,
            table,
            lighting,
            material,
            scene.settings,
            frame=k,
            on_rows=bar.advance,
        )
        xyz = post.spectral_to_xyz(image.radiance, wl)
        shown = xyz
        if quotient is not None:
            shown = post.apply_quotient(shown, quotient, image.coverage, scene.texture["strength"])
        if grain is not None:
            shown = post.apply_quotient(shown, grain, image.coverage)
        white = fixed_white if fixed_white is not None else post.white_level("auto", lighting, wl)
        rgb = post.to_srgb(
            shown, white, exposure_ev=scene.exposure_ev, mode=scene.colour_mode, highlights=scene.highlights
        )
        png = post.write_png(out / f"frame_{k:04d}.png", rgb)
        run.pngs.append(png)
        if scene.write_linear != "none":
            attrs = {
                "scene": scene.name,
                "time_h": float(t),
                "day_fraction": float(frac),
                "sun_direction": str(np.round(lighting.sun_direction, 6).tolist()),
                "white_Y": float(white),
                "exposure_ev": scene.exposure_ev,
            }
            run.netcdfs.append(
                post.write_netcdf(
                    out / f"frame_{k:04d}.nc", image, xyz, attrs, spectral=scene.write_linear == "spectral"
                )
            )
        run.render_seconds.append(image.elapsed_s)
        if log is not None:
            log(
                f"frame {k + 1}/{scene.frames}: {t:5.2f} h, sun {lighting.sun_elevation_deg:5.1f}°, "
                f"{image.elapsed_s:.1f} s → {png}"
            )
    if interrupted[0]:
        raise KeyboardInterrupt
