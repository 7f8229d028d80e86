"""Mitsuba scene descriptions of sandlight's scenes: the desert and the drying beach (Python dicts).

Public objects
--------------
camera_sensor, ground_plane, directional_sun, sunsky, saturation_texture, terrain_mesh
    The pieces, from sandlight's `Camera`, sun direction, `MaterialMap` and terrain.
scene_dict
    The Mitsuba scene of one frame of a sandlight `Scene` (``desert-day``, ``beach-drying`` or a
    scene file): its camera, terrain, sand and sun position, under Mitsuba's ``sunsky``.
example_xml_path
    The shipped XML examples (``sandlight/data/mitsuba/``).

Coordinates are sandlight's (metres, x east, y north, z up), which Mitsuba's ``sunsky`` also
uses (its zenith is +z). What differs from sandlight's renderer (docs/mitsuba.md):

- the sky is Mitsuba's ``sunsky`` (Hošek–Wilkie sky and sun, spectral), not the Preetham sky of
  `sandlight.sky`; the sun direction is sandlight's (`Scene.sun_direction`) and the turbidity the
  scene's;
- the dune field is a triangle mesh of the heightfield's nodes (two triangles per cell, flat
  shading) over a square around the camera, and beyond it a plane at the field's lowest height,
  instead of bilinear patches repeated to the horizon;
- the beach's saturation map is a ``bitmap`` texture (bilinear, clamped at its border, as
  `MaterialMap.value_at`) on a 4 km plane;
- every scene has a far plane (`FAR_HALF_SIZE_M`) 1 cm below the ground, with the sand of the
  map's border value in the camera's heading.
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from sandlight.errors import ParameterError

if TYPE_CHECKING:
    from sandlight.render import Camera, HeightfieldTerrain, MaterialMap, Scene

__all__ = [
    "camera_sensor",
    "ground_plane",
    "directional_sun",
    "sunsky",
    "saturation_texture",
    "terrain_mesh",
    "scene_dict",
    "example_xml_path",
    "EXAMPLES",
    "GROUND_HALF_SIZE_M",
]

#: Half the side of the ground plane, metres (sandlight's renderer: the far field at 2 km).
GROUND_HALF_SIZE_M = 2000.0
#: Half the side of the far plane beyond it: rays heading 0.0006° below the horizon from 10 m
#: still meet ground (beyond a 2 km plane, the sky below the horizon would show as a black line).
FAR_HALF_SIZE_M = 1.0e6
#: The shipped XML examples.
EXAMPLES = ("desert.xml", "beach.xml")


def camera_sensor(mi: ModuleType, camera: Camera, spp: int, *, sampler: str = "independent") -> dict:
    """A ``perspective`` sensor with sandlight's pinhole camera (horizontal field of view, box filter)."""
    target = (camera.position + camera.forward).tolist()
    return {
        "type": "perspective",
        "fov": float(camera.fov_deg),
        "fov_axis": "x",
        "to_world": mi.ScalarTransform4f().look_at(origin=camera.position.tolist(), target=target, up=[0, 0, 1]),
        "film": {
            "type": "hdrfilm",
            "width": int(camera.width),
            "height": int(camera.height),
            "rfilter": {"type": "box"},
            "pixel_format": "rgb",
        },
        "sampler": {"type": sampler, "sample_count": int(spp)},
    }


def ground_plane(mi: ModuleType, bsdf: dict, *, height_m: float = 0.0, half_size_m: float = GROUND_HALF_SIZE_M) -> dict:
    """A horizontal ``rectangle`` (normal +z) of side 2·``half_size_m`` at ``height_m``."""
    to_world = mi.ScalarTransform4f().translate([0.0, 0.0, float(height_m)]) @ mi.ScalarTransform4f().scale(
        [half_size_m, half_size_m, 1.0]
    )
    return {"type": "rectangle", "to_world": to_world, "bsdf": bsdf}


def directional_sun(mi: ModuleType, direction: ArrayLike, irradiance: float) -> dict:
    """A ``directional`` emitter: light from unit ``direction`` (towards the sun) with normal
    irradiance ``irradiance`` (W m⁻² nm⁻¹, per channel in RGB variants)."""
    d = np.asarray(direction, dtype=float)
    return {"type": "directional", "direction": (-d / np.linalg.norm(d)).tolist(), "irradiance": float(irradiance)}


def sunsky(sun_direction: ArrayLike, turbidity: float) -> dict:
    """Mitsuba's ``sunsky`` emitter for a sun direction (x east, y north, z up) and turbidity."""
    return {"type": "sunsky", "sun_direction": np.asarray(sun_direction, dtype=float).tolist(), "turbidity": turbidity}


def saturation_texture(mi: ModuleType, material: MaterialMap, half_size_m: float = GROUND_HALF_SIZE_M) -> dict:
    """A ``bitmap`` texture of a `MaterialMap` for `ground_plane`'s uv (raw values, bilinear,
    clamped), placed so that its node (i, j) lies at origin + (i·dx, j·dy)."""
    values = np.asarray(material.values, dtype=np.float32)
    ny, nx = values.shape
    (x0, y0), (dx, dy) = material.origin_m, material.spacing_m
    # Rectangle uv = ((x/h + 1)/2, (y/h + 1)/2); bitmap pixel centres at ((i + ½)/nx, (j + ½)/ny).
    sx, sy = 2.0 * half_size_m / (nx * dx), 2.0 * half_size_m / (ny * dy)
    tx, ty = (-half_size_m - x0 + 0.5 * dx) / (nx * dx), (-half_size_m - y0 + 0.5 * dy) / (ny * dy)
    to_uv = mi.ScalarTransform4f().translate([tx, ty, 0.0]) @ mi.ScalarTransform4f().scale([sx, sy, 1.0])
    return {
        "type": "bitmap",
        "data": mi.TensorXf(values[:, :, None]),
        "raw": True,
        "filter_type": "bilinear",
        "wrap_mode": "clamp",
        "to_uv": to_uv,
    }


def terrain_mesh(
    mi: ModuleType, terrain: HeightfieldTerrain, centre_m: ArrayLike, half_size_m: float, bsdf: dict, stride: int = 1
) -> object:
    """A triangle mesh of ``terrain``'s nodes within ``half_size_m`` of ``centre_m`` (x, y),
    every ``stride``-th node, periodic terrains repeated; two triangles per cell."""
    if not (isinstance(stride, int) and stride >= 1):
        raise ParameterError("stride", stride, "a whole number ≥ 1")
    (x0, y0), (dx, dy) = terrain.origin_m, terrain.spacing_m
    cx, cy = (float(v) for v in np.asarray(centre_m, dtype=float)[:2])
    i = np.arange(np.floor((cx - half_size_m - x0) / dx), np.ceil((cx + half_size_m - x0) / dx) + 1, stride)
    j = np.arange(np.floor((cy - half_size_m - y0) / dy), np.ceil((cy + half_size_m - y0) / dy) + 1, stride)
    xs, ys = x0 + i * dx, y0 + j * dy
    X, Y = np.meshgrid(xs, ys)
    Z = terrain.height_at(X, Y)
    ny, nx = X.shape
    positions = np.stack([X.ravel(), Y.ravel(), Z.ravel()]).astype(np.float32)
    q = (np.arange(ny - 1)[:, None] * nx + np.arange(nx - 1)[None, :]).ravel()
    faces = np.concatenate([np.stack([q, q + 1, q + nx + 1]), np.stack([q, q + nx + 1, q + nx])], axis=1)
    props = mi.Properties()
    props["bsdf"] = mi.load_dict(bsdf)
    mesh = mi.Mesh("terrain", positions.shape[1], faces.shape[1], props=props, has_vertex_normals=False)
    params = mi.traverse(mesh)
    params["vertex_positions"] = mi.Float(positions.T.ravel())
    params["faces"] = mi.UInt32(faces.T.ravel().astype(np.uint32))
    params.update()
    return mesh


def scene_dict(
    mi: ModuleType,
    scene: Scene,
    frame: int = 0,
    *,
    mesh_half_size_m: float = 150.0,
    mesh_stride: int = 2,
    max_depth: int | None = None,
    terrain: object | None = None,
) -> dict:
    """The Mitsuba scene of frame ``frame`` of a sandlight `Scene` (module docstring).

    The sand is the scene's sample; with ``sand.vary`` (the beach's saturation) the plugin gets
    the frame's texture map and the scene's levels. Integrator: ``path`` with the scene's
    ``render.max_bounces`` ground interactions (``max_depth`` = bounces + 1) unless given.
    ``terrain``: a mesh of `terrain_mesh` to reuse (the dune field is the same in every frame).

    Raises
    ------
    ParameterError
        ``frame`` outside the scene's frames, or a scene whose BRDF is not ``"appearance"``.
    """
    if not (isinstance(frame, int) and 0 <= frame < scene.frames):
        raise ParameterError("frame", frame, f"a frame number in [0, {scene.frames - 1}]")
    if scene.brdf != "appearance":
        raise ParameterError("sand.brdf", scene.brdf, "'appearance' (the Mitsuba plugin is SandAppearance)")
    ground = scene.build_terrain()
    camera = scene.build_camera(ground)
    bsdf: dict = {"type": "sand", **_sample_parameters(scene)}
    material = scene.build_material(float(scene.day_fractions()[frame]))
    if scene.vary is not None:
        bsdf[scene.vary] = saturation_texture(mi, material)
        bsdf["levels"] = int(scene.levels.size)
        bsdf["level_min"], bsdf["level_max"] = float(scene.levels[0]), float(scene.levels[-1])
    time_h = float(scene.times_h()[frame])
    out = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": int(max_depth or scene.settings.max_bounces + 1)},
        "sensor": camera_sensor(mi, camera, scene.settings.spp),
        "sky": sunsky(scene.sun_direction(time_h), scene.sun.turbidity),
    }
    far_bsdf = dict(bsdf)
    if scene.vary is not None:  # beyond the map: its border value in the camera's heading
        ahead = camera.position[:2] + 1e7 * camera.forward[:2]
        far_bsdf[scene.vary] = float(material.value_at(ahead[0], ahead[1]))
        for name in ("levels", "level_min", "level_max"):
            far_bsdf.pop(name)
    if scene.terrain.kind == "plane":
        out["ground"] = ground_plane(mi, bsdf, height_m=float(ground.height_m))
        low = float(ground.height_m)
    else:
        out["terrain"] = terrain or terrain_mesh(mi, ground, camera.position, mesh_half_size_m, bsdf, mesh_stride)
        low = float(np.min(ground.heights_m))
    out["far"] = ground_plane(mi, far_bsdf, height_m=low - 0.01, half_size_m=FAR_HALF_SIZE_M)
    return out


def _sample_parameters(scene: Scene) -> dict:
    """The plugin parameters of the scene's sample: its preset (if any) and the parameters in
    which the sample differs from it (the varied one left to the texture)."""
    from sandlight.sample import SandSample

    base = SandSample.preset(scene.preset) if scene.preset else SandSample()
    out = {"preset": scene.preset} if scene.preset else {}
    for name, value in scene.sample.to_dict().items():
        if name != scene.vary and value != getattr(base, name):
            out[name] = float(value) if isinstance(value, (int, float)) else value
    return out


def example_xml_path(name: str) -> Path:
    """Path of a shipped XML example (`EXAMPLES`)."""
    if name not in EXAMPLES:
        raise ParameterError("name", name, f"one of {EXAMPLES}")
    return Path(str(resources.files("sandlight") / "data" / "mitsuba" / name))
