"""Scene files: a whole animation described in TOML that a user can read and edit.

Every table and key is listed in ``docs/rendering.md``; the shipped scenes
(``sandlight/data/scenes/desert-day.toml``, ``beach-drying.toml``) are commented examples. A
:class:`Scene` is parsed and validated completely before anything is rendered: a bad value
raises :class:`~sandlight.errors.ParameterError` naming the key (``camera.fov_deg``), the value,
what is allowed and the file; unknown keys are refused.

Tables: ``[output]`` (size, frames, exposure, files), ``[sun]`` (place, date, hours, turbidity),
``[camera]``, ``[terrain]`` (plane / dunes / image), ``[sand]`` (sample, BRDF source, the
parameter varied per point and its levels), ``[sand.map]`` (uniform / image / waterlines),
``[render]`` (samples, estimator, bands), ``[post]`` (texture transfer, grain).
"""

from __future__ import annotations

import dataclasses
import math
import os
import tomllib
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from sandlight.checks import CONTROL_CHARACTERS, Table, check_choice, check_printable, check_whole_number
from sandlight.errors import ModelFileError, ParameterError
from sandlight.render.camera import Camera
from sandlight.render.image import ESTIMATORS, HEURISTICS, SAMPLINGS, RenderSettings
from sandlight.render.light import DEFAULT_SKY_RESOLUTION, Lighting
from sandlight.render.maps import MaterialMap, Waterlines
from sandlight.render.post import HIGHLIGHTS
from sandlight.render.tables import BrdfTable
from sandlight.render.terrain import HeightfieldTerrain, PlaneTerrain, dune_field, heightfield_from_image

if TYPE_CHECKING:
    from sandlight.sample import SandSample

__all__ = ["Scene", "shipped_scenes", "scene_path"]

EXPOSURES = ("auto", "auto-sequence")
COLOUR_MODES = ("managed", "paper")
BRDF_SOURCES = ("standin", "appearance")
#: What the per-frame NetCDF holds: spectral radiance and XYZ, XYZ only, or no file.
LINEAR_OUTPUTS = ("spectral", "xyz", "none")


def shipped_scenes() -> tuple[str, ...]:
    """Names of the scene files shipped in ``sandlight/data/scenes``."""
    folder = resources.files("sandlight") / "data" / "scenes"
    return tuple(sorted(p.name.removesuffix(".toml") for p in folder.iterdir() if p.name.endswith(".toml")))


def scene_path(name_or_path: str | os.PathLike) -> Path:
    """A shipped scene's file for its name, else the given path.

    Raises
    ------
    FileNotFoundError
        Neither a shipped scene name nor an existing file; the message lists the shipped names.
    """
    text = str(name_or_path)
    if text in shipped_scenes():
        return Path(str(resources.files("sandlight") / "data" / "scenes" / f"{text}.toml"))
    path = Path(text)
    if path.is_file():
        return path
    raise FileNotFoundError(
        f"no scene {text!r}: give a TOML file or one of the shipped scenes ({', '.join(shipped_scenes())})"
    )


def _bands(t: Table) -> np.ndarray:
    value = t.raw("bands", "400:700:20")
    name = t.name("bands")
    allowed = (
        "'start:stop:step' in nm (e.g. '400:700:20') or a list of wavelengths, "
        "1–32 bands within [380, 780] nm, covering 400–700"
    )
    if isinstance(value, str):
        try:
            start, stop, step = (float(v) for v in value.split(":"))
            if not step > 0 or stop < start:
                raise ValueError
            wl = start + step * np.arange(int(math.floor((stop - start) / step + 1e-9)) + 1)
        except ValueError:
            raise t.error(name, value, allowed) from None
    elif isinstance(value, list) and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value):
        wl = np.array(value, dtype=float)
    else:
        raise t.error(name, value, allowed)
    if (
        not (1 <= wl.size <= 32)
        or (np.diff(wl) <= 0).any()
        or wl[0] < 380
        or wl[-1] > 780
        or wl[0] > 400
        or wl[-1] < 700
    ):
        raise t.error(name, value, allowed)
    return wl


@dataclass(frozen=True)
class SunSpec:
    latitude_deg: float
    day_of_year: int
    start_h: float
    end_h: float
    turbidity: float
    longitude_deg: float | None = None
    utc_offset_h: float | None = None
    min_elevation_deg: float = 1.0


@dataclass(frozen=True)
class TerrainSpec:
    kind: str
    params: dict


@dataclass(frozen=True)
class MapSpec:
    kind: str
    params: dict


@dataclass(frozen=True)
class Scene:
    """A parsed, validated scene file (see the module docstring and ``docs/rendering.md``)."""

    name: str
    description: str
    source: str
    width: int
    height: int
    frames: int
    fps: float
    exposure: str | float
    exposure_ev: float
    colour_mode: str
    highlights: str
    write_linear: str
    sun: SunSpec
    camera: dict
    terrain: TerrainSpec
    sample: Any
    preset: str | None
    brdf: str
    vary: str | None
    levels: np.ndarray
    standin_rays: int
    material: MapSpec
    settings: RenderSettings
    wavelength_nm: np.ndarray
    sky_resolution: tuple[int, int]
    texture: dict | None
    grain: dict | None
    base_dir: Path = field(default=Path("."))

    # --- reading ------------------------------------------------------------------------------

    @classmethod
    def load(cls, name_or_path: str | os.PathLike) -> Scene:
        """Parse a scene file (or a shipped scene by name).

        Raises
        ------
        FileNotFoundError
            No such scene.
        ModelFileError
            The file is not valid TOML.
        ParameterError
            A bad or unknown key (the message names it and the file).
        """
        path = scene_path(name_or_path)
        try:
            doc = tomllib.loads(path.read_text(encoding="utf-8"))
        except (UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
            raise ModelFileError(f"{path}: not a valid TOML scene file: {exc}") from exc
        return cls.from_dict(doc, source=str(path), base_dir=path.parent)

    @classmethod
    def from_dict(cls, doc: dict, *, source: str = "", base_dir: Path | str = ".") -> Scene:
        """Parse a scene from the dict of a TOML document (see :meth:`load`)."""
        from sandlight.sample import SandSample
        from sandlight.sky import sun_position

        root = Table(doc, "", source)
        scene_t = root.table("scene")
        # The name is shown in the progress bar: no terminal control characters in it.
        default_name = CONTROL_CHARACTERS.sub("", Path(source).stem) if source else "scene"
        name = check_printable(scene_t.name("name"), scene_t.string("name", default_name or "scene"))
        description = scene_t.raw("description", "")
        if not isinstance(description, str):
            raise scene_t.error("scene.description", description, "a string")
        scene_t.finish()

        out = root.table("output")
        width = out.integer("width", 640, 1, 16384)
        height = out.integer("height", 360, 1, 16384)
        frames = out.integer("frames", 1, 1, 100000)
        fps = out.number("fps", 12.0, 0.0, 240.0, lo_open=True)
        exposure_raw = out.raw("exposure", "auto")
        if isinstance(exposure_raw, str):
            if exposure_raw not in EXPOSURES:
                raise out.error("output.exposure", exposure_raw, "'auto', 'auto-sequence' or a luminance in cd/m² > 0")
            exposure: str | float = exposure_raw
        else:
            exposure = out.number("exposure", None, 0.0, None, lo_open=True)
        exposure_ev = out.number("exposure_ev", 0.0, -20.0, 20.0)
        colour_mode = out.choice("colour_mode", COLOUR_MODES, "managed")
        highlights = out.choice("highlights", HIGHLIGHTS, "soft")
        write_linear = out.choice("linear", LINEAR_OUTPUTS, "spectral")
        out.finish()

        sun_t = root.table("sun")
        sun = SunSpec(
            latitude_deg=sun_t.number("latitude_deg", None, -90.0, 90.0),
            day_of_year=sun_t.integer("day_of_year", None, 1, 366),
            start_h=sun_t.number("start_h", None, 0.0, 24.0),
            end_h=sun_t.number("end_h", None, 0.0, 24.0),
            turbidity=sun_t.number("turbidity", 3.0, 1.7, 10.0),
            longitude_deg=sun_t.number("longitude_deg", None, -180.0, 180.0)
            if sun_t.has("longitude_deg")
            else sun_t.raw("longitude_deg"),
            utc_offset_h=sun_t.number("utc_offset_h", None, -12.0, 14.0)
            if sun_t.has("utc_offset_h")
            else sun_t.raw("utc_offset_h"),
            min_elevation_deg=sun_t.number("min_elevation_deg", 1.0, 0.0, 89.0, lo_open=True),
        )
        if (sun.longitude_deg is None) != (sun.utc_offset_h is None):
            raise sun_t.error(
                "sun.longitude_deg",
                sun.longitude_deg,
                "given together with sun.utc_offset_h (clock time), or both omitted (solar time)",
            )
        if frames > 1 and not sun.end_h > sun.start_h:
            raise sun_t.error("sun.end_h", sun.end_h, f"a time after sun.start_h = {sun.start_h:g} h for an animation")
        sun_t.finish()
        times = np.linspace(sun.start_h, sun.end_h, frames) if frames > 1 else np.array([sun.start_h])
        zenith, _ = sun_position(
            sun.latitude_deg, sun.day_of_year, times, longitude_deg=sun.longitude_deg, utc_offset_h=sun.utc_offset_h
        )
        elevation = 90.0 - np.degrees(np.atleast_1d(zenith))
        if (elevation < sun.min_elevation_deg).any():
            k = int(np.argmin(elevation))
            key = "sun.start_h" if k < frames / 2 else "sun.end_h"
            raise sun_t.error(
                key,
                float(times[k]),
                f"times when the sun is at least {sun.min_elevation_deg:g}° above the "
                f"horizon (it is at {elevation[k]:.1f}° at {times[k]:.2f} h on day {sun.day_of_year} at latitude "
                f"{sun.latitude_deg:g}°)",
            )

        cam = root.table("camera")
        position = cam.vector("position", (2, 3), [0.0, 0.0])
        camera = {
            "position": position,
            "height_m": cam.number("height_m", 1.7, 0.0, None, lo_open=True),
            "fov_deg": cam.number("fov_deg", 60.0, 0.0, 170.0, lo_open=True, hi_open=True),
        }
        if cam.has("look_at"):
            camera["look_at"] = cam.vector("look_at", 3)
            if cam.has("heading_deg") or cam.has("pitch_deg"):
                raise cam.error(
                    "camera.look_at", camera["look_at"].tolist(), "either look_at or heading_deg/pitch_deg, not both"
                )
        else:
            camera["heading_deg"] = cam.number("heading_deg", 0.0, -360.0, 360.0)
            camera["pitch_deg"] = cam.number("pitch_deg", -10.0, -89.0, 89.0)
        cam.finish()

        terrain = _parse_terrain(root.table("terrain"), Path(base_dir))

        sand = root.table("sand")
        if sand.has("sample_file") and sand.has("preset"):
            raise sand.error(
                "sand.sample_file", sand.raw("sample_file"), "either sand.preset or sand.sample_file, not both"
            )
        if sand.has("sample_file"):
            preset = None
            sample = SandSample.from_file(_resolve(sand.string("sample_file"), base_dir))
        else:
            preset = sand.string("preset", "yellow-dune")
            try:
                sample = SandSample.preset(preset)
            except ParameterError as exc:
                raise sand.error("sand.preset", preset, exc.allowed) from None
        brdf = sand.string("brdf", "appearance")
        if brdf not in BRDF_SOURCES and not brdf.endswith(".nc"):
            raise sand.error("sand.brdf", brdf, "'standin', 'appearance' or the path of a NetCDF BRDF table (*.nc)")
        vary = sand.raw("vary")
        if vary is not None:
            try:
                parameter = SandSample.parameter(vary)
            except ParameterError as exc:
                raise sand.error("sand.vary", vary, exc.allowed) from None
            if parameter.kind != "float":
                raise sand.error("sand.vary", vary, "a numeric sample parameter")
            raw_levels = sand.raw("levels", 16)
            if isinstance(raw_levels, list):
                levels = sand.vector("levels", len(raw_levels))
            else:
                n = sand.integer("levels", 16, 2, 64)
                lo, hi = sand.vector("range", 2, [0.0, 1.0])
                if not hi > lo:
                    raise sand.error("sand.range", [lo, hi], "(low, high) with high > low")
                levels = np.linspace(lo, hi, n)
            if levels.size < 2 or (np.diff(levels) <= 0).any():
                raise sand.error("sand.levels", levels.tolist(), "at least 2 strictly ascending values")
            for v in levels:
                try:
                    parameter.check(float(v))
                except ParameterError as exc:
                    raise sand.error("sand.levels", float(v), f"values of {vary}: {exc.allowed}") from None
        else:
            levels = np.array([0.0])
        standin_rays = sand.integer("standin_rays", 5000, 100, 10**8)
        material = _parse_map(sand.table("map"), vary, levels, Path(base_dir))
        sand.finish()

        ren = root.table("render")
        settings = RenderSettings(
            spp=ren.integer("spp", 16, 1, 1 << 20),
            seed=ren.integer("seed", 0, 0, (1 << 63) - 1),
            estimator=ren.choice("estimator", ESTIMATORS, "mis"),
            sampling=ren.choice("sampling", SAMPLINGS, "table"),
            heuristic=ren.choice("heuristic", HEURISTICS, "power"),
            max_bounces=ren.integer("max_bounces", 1, 1, 64),
        )
        wavelength_nm = _bands(ren)
        sky_res = ren.vector("sky_resolution", 2, list(DEFAULT_SKY_RESOLUTION), 2, 4096)
        if sky_res[1] < 4 or (sky_res != np.round(sky_res)).any():
            raise ren.error("render.sky_resolution", sky_res.tolist(), "two whole numbers [n_theta ≥ 2, n_phi ≥ 4]")
        ren.finish()

        post = root.table("post")
        texture = _parse_texture(post.table("texture"), Path(base_dir))
        grain_t = post.table("grain")
        grain = None
        if grain_t.data:
            grain = {
                "amount": grain_t.number("amount", 0.06, 0.0, 1.0),
                "size_px": grain_t.number("size_px", 0.7, 0.0, 20.0),
                "seed": grain_t.integer("seed", 0, 0, (1 << 63) - 1),
            }
        grain_t.finish()
        post.finish()
        root.finish()
        return cls(
            name=name,
            description=description,
            source=source,
            width=width,
            height=height,
            frames=frames,
            fps=fps,
            exposure=exposure,
            exposure_ev=exposure_ev,
            colour_mode=colour_mode,
            highlights=highlights,
            write_linear=write_linear,
            sun=sun,
            camera=camera,
            terrain=terrain,
            sample=sample,
            preset=preset,
            brdf=brdf,
            vary=vary,
            levels=levels,
            standin_rays=standin_rays,
            material=material,
            settings=settings,
            wavelength_nm=wavelength_nm,
            sky_resolution=(int(sky_res[0]), int(sky_res[1])),
            texture=texture,
            grain=grain,
            base_dir=Path(base_dir),
        )

    def with_overrides(self, **changes) -> Scene:
        """A copy with command-line overrides applied (width, height, frames, spp, seed, threads,
        write_linear); values are validated like the file's."""
        changes = {k: v for k, v in changes.items() if v is not None}
        settings_keys = {"spp", "seed", "threads"}
        settings = dataclasses.replace(
            self.settings, **{k: changes.pop(k) for k in list(changes) if k in settings_keys}
        )
        for key, lo, hi in (("width", 1, 16384), ("height", 1, 16384), ("frames", 1, 100000)):
            if key in changes:
                check_whole_number(key, changes[key], lo, hi)
        if "write_linear" in changes:
            check_choice("linear", changes["write_linear"], LINEAR_OUTPUTS)
        unknown = set(changes) - {"width", "height", "frames", "write_linear"}
        if unknown:
            raise ParameterError(
                "override", sorted(unknown)[0], "one of width, height, frames, spp, seed, threads, write_linear"
            )
        scene = dataclasses.replace(self, settings=settings, **changes)
        if scene.frames > 1 and not scene.sun.end_h > scene.sun.start_h:
            raise ParameterError("frames", scene.frames, "1, since the scene's sun.end_h is not after sun.start_h")
        return scene

    # --- building -----------------------------------------------------------------------------

    def times_h(self) -> np.ndarray:
        """Time of day of each frame, hours (evenly spaced from start_h to end_h)."""
        if self.frames == 1:
            return np.array([self.sun.start_h])
        return np.linspace(self.sun.start_h, self.sun.end_h, self.frames)

    def day_fractions(self) -> np.ndarray:
        """Progress through the day of each frame, in [0, 1]."""
        return np.linspace(0.0, 1.0, self.frames) if self.frames > 1 else np.zeros(1)

    def build_terrain(self) -> PlaneTerrain | HeightfieldTerrain:
        kind, p = self.terrain.kind, self.terrain.params
        if kind == "plane":
            return PlaneTerrain(p["height_m"])
        if kind == "dunes":
            return dune_field(**p)
        return heightfield_from_image(**p)

    def build_camera(self, terrain: PlaneTerrain | HeightfieldTerrain) -> Camera:
        c = self.camera
        pos = c["position"]
        if pos.size == 2:
            pos = np.array([pos[0], pos[1], float(terrain.height_at(pos[0], pos[1])) + c["height_m"]])
        if "look_at" in c:
            return Camera.look_at(pos, c["look_at"], c["fov_deg"], self.width, self.height)
        return Camera.heading(pos, c["heading_deg"], c["pitch_deg"], c["fov_deg"], self.width, self.height)

    def build_table(self, progress: bool = False) -> BrdfTable:
        """The BRDF stack: tabulated SandAppearance, the Lambertian stand-in (sandlight.render.standin), or a file."""
        if self.brdf == "standin":
            from sandlight.render.standin import standin_table

            return standin_table(
                self.sample,
                self.wavelength_nm,
                preset=self.preset,
                vary=self.vary,
                level_values=self.levels,
                rays=self.standin_rays,
                progress=progress,
            )
        if self.brdf == "appearance":
            return _appearance_table(self.sample, self.vary, self.levels, self.wavelength_nm)
        table = BrdfTable.from_netcdf(_resolve(self.brdf, self.base_dir))
        if self.vary is not None and (
            table.n_levels != self.levels.size or not np.allclose(table.level_values, self.levels)
        ):
            raise ParameterError(
                "sand.levels",
                self.levels.tolist(),
                f"the levels of the table {self.brdf} ({table.level_name} = {table.level_values.tolist()})",
            )
        return table

    def build_material(self, day_fraction: float) -> MaterialMap | None:
        kind, p = self.material.kind, self.material.params
        if self.vary is None:
            return None
        if kind == "uniform":
            return MaterialMap.uniform(p["value"])
        if kind == "image":
            return MaterialMap.from_image(p["path"], extent_m=p["extent_m"], value_range=p["value_range"])
        return Waterlines(**p).map(day_fraction)

    def sun_direction(self, time_h: float) -> np.ndarray:
        from sandlight.sky import sun_direction

        return sun_direction(
            self.sun.latitude_deg,
            self.sun.day_of_year,
            float(time_h),
            longitude_deg=self.sun.longitude_deg,
            utc_offset_h=self.sun.utc_offset_h,
        )

    def build_lighting(self, time_h: float) -> Lighting:
        return Lighting.preetham(
            self.sun.turbidity, self.sun_direction(time_h), self.wavelength_nm, resolution=self.sky_resolution
        )


def _resolve(path: str, base_dir: str | os.PathLike) -> Path:
    p = Path(path).expanduser()
    return p if p.is_absolute() else Path(base_dir) / p


def _parse_terrain(t: Table, base_dir: Path) -> TerrainSpec:
    kind = t.choice("type", ("plane", "dunes", "image"), "plane")
    if kind == "plane":
        spec = TerrainSpec(kind, {"height_m": t.number("height_m", 0.0)})
    elif kind == "dunes":
        cells = t.integer("cells", 1024, 16, 4096)
        if cells & (cells - 1):
            raise t.error("terrain.cells", cells, "a power of two in [16, 4096]")
        spec = TerrainSpec(
            kind,
            {
                "size_m": t.number("size_m", 204.8, 0.0, None, lo_open=True),
                "cells": cells,
                "dune_height_m": t.number("dune_height_m", 6.0, 0.0),
                "dune_wavelength_m": t.number("dune_wavelength_m", 60.0, 0.0, None, lo_open=True),
                "wind_azimuth_deg": t.number("wind_azimuth_deg", 80.0, -360.0, 360.0),
                "lee_fraction": t.number("lee_fraction", 0.25, 0.1, 0.5),
                "sinuosity_m": t.number("sinuosity_m", 6.0, 0.0),
                "ripple_wavelength_m": t.number("ripple_wavelength_m", 0.8, 0.0, None, lo_open=True),
                "ripple_height_m": t.number("ripple_height_m", 0.03, 0.0),
                "roughness_m": t.number("roughness_m", 0.4, 0.0),
                "seed": t.integer("seed", 0, 0, (1 << 63) - 1),
                "far_m": t.number("far_m", 2000.0, 0.0, None, lo_open=True),
            },
        )
        spacing = spec.params["size_m"] / cells
        if spec.params["ripple_height_m"] > 0 and spec.params["ripple_wavelength_m"] < 3 * spacing:
            raise t.error(
                "terrain.ripple_wavelength_m",
                spec.params["ripple_wavelength_m"],
                f"at least 3 grid cells ({3 * spacing:g} m for size_m/cells); raise cells or set ripple_height_m = 0",
            )
    else:
        path = _resolve(t.string("path"), base_dir)
        if not path.is_file():
            raise t.error("terrain.path", str(path), "an existing grayscale image file")
        hr = t.vector("height_range_m", 2)
        if hr[1] < hr[0]:
            raise t.error("terrain.height_range_m", hr.tolist(), "(low, high) with high ≥ low")
        size = t.vector("size_m", 2, None, 0.0)
        if (size <= 0).any():
            raise t.error("terrain.size_m", size.tolist(), "(width, depth) > 0 m")
        spec = TerrainSpec(
            kind,
            {
                "path": path,
                "size_m": tuple(size),
                "height_range_m": tuple(hr),
                "origin_m": tuple(t.vector("origin_m", 2)) if t.has("origin_m") else None,
                "wrap": t.boolean("wrap", False),
                "outside_m": t.number("outside_m") if t.has("outside_m") else None,
                "far_m": t.number("far_m", 2000.0, 0.0, None, lo_open=True),
            },
        )
    t.finish()
    return spec


def _parse_map(t: Table, vary: str | None, levels: np.ndarray, base_dir: Path) -> MapSpec:
    lo, hi = float(levels[0]), float(levels[-1])
    if vary is None:
        if t.data:
            raise t.error("sand.map", t.data, "no map unless sand.vary names the parameter it maps")
        return MapSpec("none", {})
    kind = t.choice("type", ("uniform", "image", "waterlines"), "uniform")
    if kind == "uniform":
        spec = MapSpec(kind, {"value": t.number("value", lo, lo, hi)})
    elif kind == "image":
        path = _resolve(t.string("path"), base_dir)
        if not path.is_file():
            raise t.error("sand.map.path", str(path), "an existing grayscale image file")
        extent = t.vector("extent_m", 4)
        if not (extent[2] > extent[0] and extent[3] > extent[1]):
            raise t.error("sand.map.extent_m", extent.tolist(), "(x_min, y_min, x_max, y_max) with max > min")
        spec = MapSpec(
            kind,
            {
                "path": path,
                "extent_m": tuple(extent),
                "value_range": tuple(t.vector("value_range", 2, [lo, hi], lo, hi)),
            },
        )
    else:
        if vary != "saturation":
            raise t.error(
                "sand.map.type",
                kind,
                "'uniform' or 'image' (waterlines map the degree of saturation: set sand.vary = 'saturation')",
            )
        params = {
            "extent_m": tuple(t.vector("extent_m", 4, [-60.0, -30.0, 60.0, 40.0])),
            "resolution_m": t.number("resolution_m", 0.1, 0.0, None, lo_open=True),
            "offsets_m": tuple(t.vector("offsets_m", 2, [2.0, 9.0])),
            "roughness_m_per_sqrt_m": t.number("roughness_m_per_sqrt_m", 0.25, 0.0),
            "edge_m": t.number("edge_m", 0.6, 0.0, None, lo_open=True),
            "start": tuple(t.vector("start", 3, [1.0, 0.8, 0.35], lo, hi)),
            "end": tuple(t.vector("end", 3, [0.9, 0.25, 0.02], lo, hi)),
            "seed": t.integer("seed", 0, 0, (1 << 63) - 1),
        }
        try:
            Waterlines(**params)
        except ParameterError as exc:
            raise t.error(f"sand.map.{exc.name}", exc.value, exc.allowed) from None
        spec = MapSpec(kind, params)
    t.finish()
    return spec


def _parse_texture(t: Table, base_dir: Path) -> dict | None:
    if not t.data:
        return None
    photo = t.string("photo", "builtin:sand")
    if photo != "builtin:sand":
        path = _resolve(photo, base_dir)
        if not path.is_file():
            raise t.error("post.texture.photo", photo, "'builtin:sand' or an existing image file")
        photo = str(path)
    mask = t.raw("ground_mask")
    if mask is not None:
        mpath = _resolve(t.string("ground_mask"), base_dir)
        if not mpath.is_file():
            raise t.error("post.texture.ground_mask", mask, "an existing black/white image (white = ground)")
        mask = str(mpath)
    spec = {
        "photo": photo,
        "ground_mask": mask,
        "blur_px": t.number("blur_px", 25.0, 0.0, 10000.0, lo_open=True),
        "strength": t.number("strength", 1.0, 0.0, 4.0),
        "fit": t.choice("fit", ("tile", "stretch"), "tile"),
        "scale": t.number("scale", 1.0, 0.01, 100.0),
    }
    t.finish()
    return spec


def _appearance_table(sample: SandSample, vary: str | None, levels: np.ndarray, wavelength_nm: np.ndarray) -> BrdfTable:
    """`SandAppearance` of the sample (of each level's sample when ``vary`` is set, all with the
    one shipped spatial model that covers every level), tabulated exactly on its own nodes
    (`BrdfTable.from_appearance`) and stacked."""
    from sandlight.appearance import SandAppearance
    from sandlight.spatial import model_for

    samples = [sample if vary is None else sample.replace(**{vary: float(v)}) for v in levels]
    spatial = model_for(samples)  # one spatial model for every level: no jump between them
    tables = [BrdfTable.from_appearance(SandAppearance(s, spatial_model=spatial), wavelength_nm) for s in samples]
    return BrdfTable.stack(tables, levels if vary else [0.0], vary or "level")
