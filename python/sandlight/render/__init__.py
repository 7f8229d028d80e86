"""Spectral rendering of sandy landscapes under daylight (paper §4.2); see ``docs/rendering.md``.

The hot loop (path tracing with multiple importance sampling over terrain, sky and sun) is in
Rust (``crates/sandlight-core/src/render``); this package describes scenes, prepares the arrays the
renderer consumes, and turns spectral images into pictures and videos.

- :mod:`~sandlight.render.tables`: :class:`BrdfTable`, spectral BRDF tables and stacks of them.
- :mod:`~sandlight.render.standin`: Lambertian tables with the engine's spectra (``brdf =
  "standin"``, an option for comparison; the scenes shade with ``SandAppearance``).
- :mod:`~sandlight.render.terrain`: :class:`PlaneTerrain`, :class:`HeightfieldTerrain`,
  :func:`dune_field`, :func:`heightfield_from_image`.
- :mod:`~sandlight.render.maps`: :class:`MaterialMap`, :class:`Waterlines`.
- :mod:`~sandlight.render.light`: :class:`Lighting` (sky texture and sun).
- :mod:`~sandlight.render.camera`: :class:`Camera`.
- :mod:`~sandlight.render.image`: :func:`render_image`, :class:`RenderSettings`.
- :mod:`~sandlight.render.post`: colour, exposure, texture transfer, grain, files, video.
- :mod:`~sandlight.render.scene`: :class:`Scene` (TOML scene files).
- :mod:`~sandlight.render.animation`: :func:`render_scene` (frames and MP4).

>>> import numpy as np
>>> from sandlight.render import BrdfTable
>>> BrdfTable.lambertian(np.full(16, 0.4), np.arange(400, 701, 20)).albedo(0.5).round(3)[:3]
array([0.4, 0.4, 0.4])
"""

from sandlight.render.animation import SceneRun, render_scene
from sandlight.render.camera import Camera
from sandlight.render.image import RenderedImage, RenderSettings, render_image
from sandlight.render.light import Lighting
from sandlight.render.maps import MaterialMap, Waterlines
from sandlight.render.scene import Scene, shipped_scenes
from sandlight.render.tables import BrdfTable
from sandlight.render.terrain import (
    HeightfieldTerrain,
    PlaneTerrain,
    dune_field,
    heightfield_from_array,
    heightfield_from_image,
)

__all__ = [
    "BrdfTable",
    "Camera",
    "HeightfieldTerrain",
    "Lighting",
    "MaterialMap",
    "PlaneTerrain",
    "RenderSettings",
    "RenderedImage",
    "Scene",
    "SceneRun",
    "Waterlines",
    "dune_field",
    "heightfield_from_array",
    "heightfield_from_image",
    "render_image",
    "render_scene",
    "shipped_scenes",
]
