"""Rendering one spectral image: the native path tracer driven in batches of rows.

Each native call renders a block of rows with the GIL released; between calls Python handles
signals, so Ctrl-C stops a render within about a quarter of a second (``KeyboardInterrupt``,
nothing written). Sample k of pixel p has its own counter-based random stream, so the image does
not depend on the batch sizes or the number of threads.
"""

from __future__ import annotations

import contextlib
import signal
import threading
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from sandlight.checks import check_choice, check_whole_number
from sandlight.errors import ParameterError
from sandlight.progress import progress_bar
from sandlight.render.camera import Camera
from sandlight.render.light import Lighting
from sandlight.render.maps import MaterialMap
from sandlight.render.tables import BrdfTable
from sandlight.render.terrain import HeightfieldTerrain, PlaneTerrain

if TYPE_CHECKING:
    from types import FrameType

    from sandlight._native import RenderScene

__all__ = ["RenderSettings", "RenderedImage", "render_image", "native_scene", "interrupt_requests"]

ESTIMATORS = ("mis", "brdf", "light")
SAMPLINGS = ("table", "cosine")
HEURISTICS = ("power", "balance")
TARGET_BATCH_SECONDS = 0.25


@dataclass(frozen=True)
class RenderSettings:
    """How to estimate the image.

    Attributes
    ----------
    spp : int
        Samples per pixel, ≥ 1.
    seed : int
        Master seed in [0, 2⁶⁴).
    estimator : {"mis", "brdf", "light"}
        Light and BRDF sampling combined by multiple importance sampling, BRDF sampling alone,
        or light sampling alone.
    sampling : {"table", "cosine"}
        BRDF sampling that follows the table, or cosine-weighted (the paper's choice).
    heuristic : {"power", "balance"}
        MIS weights (Veach 1997).
    max_bounces : int
        Ground interactions per path, ≥ 1 (1: direct light only, exact for a plane).
    threads : int or None
        Worker threads (None: all cores). Images do not depend on it.
    """

    spp: int = 16
    seed: int = 0
    estimator: str = "mis"
    sampling: str = "table"
    heuristic: str = "power"
    max_bounces: int = 1
    threads: int | None = None

    def __post_init__(self) -> None:
        check_whole_number("spp", self.spp, 1, 1 << 20)
        check_whole_number("seed", self.seed, 0, (1 << 64) - 1)
        check_whole_number("max_bounces", self.max_bounces, 1, 64)
        if self.threads is not None:
            check_whole_number("threads", self.threads, 1, 1024)
        for name, options in (("estimator", ESTIMATORS), ("sampling", SAMPLINGS), ("heuristic", HEURISTICS)):
            check_choice(name, getattr(self, name), options)


@dataclass(frozen=True)
class RenderedImage:
    """A linear spectral image.

    Attributes
    ----------
    radiance : numpy.ndarray, float32, shape (height, width, n_bands)
        Mean spectral radiance, W m⁻² sr⁻¹ nm⁻¹.
    coverage : numpy.ndarray, float32, shape (height, width)
        Fraction of each pixel's samples that saw the ground (1) rather than the sky (0).
    wavelength_nm : numpy.ndarray, shape (n_bands,)
    spp : int
    elapsed_s : float
        Wall time of the native rendering.
    metadata : dict
        Scene facts written with the image (sun elevation, BRDF source, …).
    """

    radiance: np.ndarray
    coverage: np.ndarray
    wavelength_nm: np.ndarray
    spp: int
    elapsed_s: float
    metadata: dict = field(default_factory=dict)


def native_scene(
    camera: Camera,
    terrain: PlaneTerrain | HeightfieldTerrain,
    table: BrdfTable,
    lighting: Lighting,
    material: MaterialMap | None = None,
    settings: RenderSettings = RenderSettings(),
) -> RenderScene:
    """The native ``RenderScene`` for these objects (validated, arrays converted)."""
    from sandlight._native import RenderScene

    if not isinstance(camera, Camera):
        raise ParameterError("camera", camera, "a sandlight.render.Camera")
    if not isinstance(terrain, (PlaneTerrain, HeightfieldTerrain)):
        raise ParameterError("terrain", terrain, "a PlaneTerrain or HeightfieldTerrain")
    if not isinstance(table, BrdfTable):
        raise ParameterError("table", table, "a sandlight.render.BrdfTable")
    if not isinstance(lighting, Lighting):
        raise ParameterError("lighting", lighting, "a sandlight.render.Lighting")
    wl = lighting.wavelength_nm
    if wl.size > 32:
        raise ParameterError("wavelength_nm", f"{wl.size} bands", "at most 32 render bands")
    args = {
        **camera.native_args(),
        **terrain.native_args(),
        "sky_radiance": lighting.sky_radiance,
        "sun_direction": lighting.sun_direction.tolist(),
        "sun_solid_angle_sr": lighting.sun_solid_angle_sr,
        "sun_radiance": lighting.sun_radiance.tolist(),
        "brdf": table.native_f(wl),
        "mu_i": table.mu_i.tolist(),
        "mu_o": table.mu_o.tolist(),
        "dphi": table.dphi.tolist(),
        "estimator": settings.estimator,
        "sampling": settings.sampling,
        "heuristic": settings.heuristic,
        "max_bounces": settings.max_bounces,
    }
    if material is not None:
        if not isinstance(material, MaterialMap):
            raise ParameterError("material", material, "a sandlight.render.MaterialMap or None")
        args.update(material.native_args(table))
    elif table.n_levels > 1:
        raise ParameterError("material", None, f"a MaterialMap choosing among the table's {table.n_levels} levels")
    return RenderScene(**args)


@contextlib.contextmanager
def interrupt_requests() -> Iterator[list[bool]]:
    """Catch Ctrl-C as a flag checked between row batches (a context manager yielding
    ``[interrupted]``; also used by :mod:`sandlight.render.animation` between frames).

    Python's default handler raises ``KeyboardInterrupt`` wherever the interpreter happens to
    be, and one raised inside a garbage-collection callback is printed and dropped: a single
    Ctrl-C could be lost. The flag is honoured at the next batch boundary instead. Outside the
    main thread no handler can be installed and the flag stays False.
    """
    flag = [False]
    if threading.current_thread() is not threading.main_thread():
        yield flag
        return

    def handler(signum: int, frame: FrameType | None):
        flag[0] = True

    previous = signal.signal(signal.SIGINT, handler)
    try:
        yield flag
    finally:
        signal.signal(signal.SIGINT, previous)


def render_image(
    camera: Camera,
    terrain: PlaneTerrain | HeightfieldTerrain,
    table: BrdfTable,
    lighting: Lighting,
    material: MaterialMap | None = None,
    settings: RenderSettings = RenderSettings(),
    *,
    frame: int = 0,
    on_rows: Callable[[int], None] | None = None,
    progress: bool = False,
) -> RenderedImage:
    """Render one spectral image.

    Parameters
    ----------
    camera, terrain, table, lighting, material
        The scene (``material`` selects the table level per ground point; required when the
        table has several levels).
    settings : RenderSettings
    frame : int
        Frame number: frames of one animation get decorrelated random streams.
    on_rows : callable, optional
        Called with the number of rows finished after each batch (for an outer progress bar).
    progress : bool
        Show a progress bar of its own.

    Returns
    -------
    RenderedImage
    """
    check_whole_number("frame", frame, 0)
    scene = native_scene(camera, terrain, table, lighting, material, settings)
    h, w, nb = camera.height, camera.width, lighting.wavelength_nm.size
    radiance = np.empty((h, w, nb), dtype=np.float32)
    coverage = np.empty((h, w), dtype=np.float32)
    start = time.perf_counter()
    with (
        progress_bar("rendering", h, unit="rows", enabled=progress) as bar,
        interrupt_requests() as interrupted,
    ):
        row, batch = 0, 1
        while row < h:
            if interrupted[0]:
                raise KeyboardInterrupt
            n = min(batch, h - row)
            t0 = time.perf_counter()
            rad, cov = scene.render_rows(row, n, settings.spp, settings.seed, frame, settings.threads)
            radiance[row : row + n] = rad
            coverage[row : row + n] = cov
            row += n
            dt = time.perf_counter() - t0
            # Aim for a fixed wall time per call (Ctrl-C latency), growing at most 4× at a time.
            batch = int(max(1, min(4 * n, n * TARGET_BATCH_SECONDS / max(dt, 1e-6))))
            if on_rows is not None:
                on_rows(n)
            bar.advance(n)
        if interrupted[0]:
            raise KeyboardInterrupt
    return RenderedImage(
        radiance,
        coverage,
        lighting.wavelength_nm.copy(),
        settings.spp,
        time.perf_counter() - start,
        {
            "sun_elevation_deg": lighting.sun_elevation_deg,
            "brdf_source": table.source,
            "estimator": settings.estimator,
            "sampling": settings.sampling,
            "max_bounces": settings.max_bounces,
            "seed": settings.seed,
            "frame": int(frame),
        },
    )
