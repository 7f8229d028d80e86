"""The preview: a small rendered view of the sand under the Preetham sky, refined progressively.

The sample's `SandAppearance` is tabulated (`sandlight.render.BrdfTable.from_appearance`) and
rendered by sandlight's spectral path tracer (`sandlight.render.render_image`, 16 bands
400–700 nm) on a flat patch or the procedural dune field (`sandlight.render.dune_field`), lit
by the Preetham et al. (1999) sky and sun for a latitude, day of year and local solar time
(`sandlight.sky.sun_direction`). The image is shown as `sandlight.render.post` shows frames:
XYZ, auto exposure (the white of a Lambertian white patch under the same light), soft
highlights, sRGB.

Refinement: pass k adds ``spp_k`` samples per pixel (1, 3, 12, 48, …, doubling the total four
times each pass, up to ``spp``) with its own seed, and the image shown is the sample-weighted
mean of the passes so far, so each streamed image is an unbiased estimate with more samples
than the last. The first pass (1 sample per pixel) is what the page shows first.
"""

from __future__ import annotations

import base64
import functools
import io
from collections.abc import Callable
from typing import Any

import numpy as np
from PIL import Image

from sandlight.checks import check_choice, check_whole_number
from sandlight.errors import ParameterError
from sandlight.render import post
from sandlight.render.camera import Camera
from sandlight.render.image import RenderSettings, render_image
from sandlight.render.light import Lighting
from sandlight.render.tables import BrdfTable
from sandlight.render.terrain import PlaneTerrain, dune_field
from sandlight.sample import SandSample
from sandlight.sky import sun_direction
from sandlight.web.brdf_maps import appearance_of
from sandlight.web.jobs import Job, JobContext
from sandlight.web.limits import Limits
from sandlight.web.requests import number_in

__all__ = ["PREVIEW_OPTIONS", "preview_work", "dune_tile", "warm_up"]

#: The options of a preview request with their defaults (the page's controls).
PREVIEW_OPTIONS: dict[str, Any] = {
    "terrain": "flat",
    "latitude_deg": 25.0,
    "day_of_year": 110,
    "time_h": 10.0,
    "width": 160,
    "height": 96,
    "spp": 64,
}
TERRAINS = ("flat", "dunes")
#: Clear desert air (the desert-day scene's turbidity).
TURBIDITY = 3.0
#: The sun must be this far above the horizon, degrees.
MIN_ELEVATION_DEG = 2.0
#: The 16 bands of the spectral predictor, nm.
BANDS_NM = np.arange(400.0, 701.0, 20.0)


@functools.cache
def dune_tile() -> Any:
    """The preview's dune field (built once, about a second; the app builds it at start-up)."""
    # A coarser tile than the desert-day scene's (256 cells of 0.8 m): a preview is small, and
    # wind ripples (0.8 m) would need a finer grid than the preview's pixels can show.
    return dune_field(size_m=204.8, cells=256, ripple_height_m=0.0, seed=1)


def warm_up() -> None:
    """Build what every first preview needs (the dune tile, the spatial model, the sky and sun
    tables) with a tiny render of the default sample, so that the first image of the first
    preview comes as fast as the later ones (the app runs this at start-up)."""
    work = preview_work(SandSample(), {"width": 8, "height": 8, "spp": 1, "terrain": "dunes"}, Limits())
    work(JobContext(Job("warm-up", "preview", "server")))


def _camera(terrain: str, width: int, height: int) -> tuple[Any, Camera]:
    if terrain == "flat":
        return PlaneTerrain(0.0), Camera.heading([0.0, 0.0, 1.7], 20.0, -25.0, 60.0, width, height)
    ground = dune_tile()
    position = [30.0, 10.0, float(ground.height_at(30.0, 10.0)) + 10.0]
    return ground, Camera.heading(position, 20.0, -9.0, 60.0, width, height)


def _passes(spp: int) -> list[int]:
    """Samples per pixel added by each pass: 1, 3, 12, 48, … (total ×4 per pass) up to ``spp``."""
    added, total = [], 0
    while total < spp:
        step = min(max(1, 3 * total), spp - total)
        added.append(step)
        total += step
    return added


def _png_data_url(rgb: np.ndarray) -> str:
    buffer = io.BytesIO()
    Image.fromarray(np.clip(np.round(rgb * 255.0), 0, 255).astype(np.uint8)).save(buffer, format="PNG")
    return "data:image/png;base64," + base64.b64encode(buffer.getvalue()).decode("ascii")


def preview_work(sample: SandSample, body: dict[str, Any], limits: Limits) -> Callable[[JobContext], dict[str, Any]]:
    """The job's work for a preview request, checked now (before the job is queued).

    Raises
    ------
    ParameterError
        An option out of its range, an image larger than `Limits.max_preview_px`, or a time when
        the sun is less than 2° above the horizon.
    """
    terrain = check_choice("terrain", body.get("terrain", PREVIEW_OPTIONS["terrain"]), TERRAINS)
    latitude = number_in(body, "latitude_deg", PREVIEW_OPTIONS["latitude_deg"], -90.0, 90.0)
    day = check_whole_number("day_of_year", body.get("day_of_year", PREVIEW_OPTIONS["day_of_year"]), 1, 366)
    time_h = number_in(body, "time_h", PREVIEW_OPTIONS["time_h"], 0.0, 24.0)
    side = limits.max_preview_px
    width = check_whole_number("width", body.get("width", PREVIEW_OPTIONS["width"]), 8, side, noun="pixels")
    height = check_whole_number("height", body.get("height", PREVIEW_OPTIONS["height"]), 8, side, noun="pixels")
    spp = check_whole_number("spp", body.get("spp", PREVIEW_OPTIONS["spp"]), 1, 1024)
    sun = sun_direction(latitude, day, time_h)
    elevation = float(np.degrees(np.arcsin(np.clip(sun[2], -1.0, 1.0))))
    if elevation < MIN_ELEVATION_DEG:
        raise ParameterError(
            "time_h",
            time_h,
            f"a time when the sun is at least {MIN_ELEVATION_DEG:g}° above the horizon (it is at "
            f"{elevation:.1f}° on day {day} at latitude {latitude:g}°)",
        )

    def work(context: JobContext) -> dict[str, Any]:
        table = BrdfTable.from_appearance(appearance_of(sample)[0], BANDS_NM)
        ground, camera = _camera(terrain, width, height)
        lighting = Lighting.preetham(TURBIDITY, sun, BANDS_NM)
        white = post.white_level("auto", lighting, BANDS_NM)
        mean, total = None, 0
        for k, added in enumerate(_passes(spp)):
            settings = RenderSettings(spp=added, seed=k)
            image = render_image(camera, ground, table, lighting, settings=settings, on_rows=lambda n: context.check())
            radiance = image.radiance.astype(float)
            mean = radiance if mean is None else (mean * total + radiance * added) / (total + added)
            total += added
            context.report(total, spp, f"{total} of {spp} samples per pixel")
            context.image(_png_data_url(post.to_srgb(post.spectral_to_xyz(mean, BANDS_NM), white)))
        return {"width": width, "height": height, "spp": total, "sun_elevation_deg": elevation, "terrain": terrain}

    return work
