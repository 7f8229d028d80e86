"""Scene files: the shipped scenes parse; bad values are refused with messages naming the key."""

import copy
import tomllib

import numpy as np
import pytest

from sandlight.errors import ModelFileError, ParameterError
from sandlight.render.scene import Scene, scene_path, shipped_scenes


def shipped(name):
    return tomllib.loads(scene_path(name).read_text())


def test_shipped_scenes_parse_and_describe_the_paper_animations():
    assert {"desert-day", "beach-drying"} <= set(shipped_scenes())
    desert = Scene.load("desert-day")
    times = desert.times_h()
    assert times[-1] - times[0] == pytest.approx(12.0)  # the sun crosses the sky over 12 hours
    elevations = [90 - np.degrees(np.arccos(desert.sun_direction(t)[2])) for t in (times[0], times[-1])]
    assert all(2.0 <= e <= 10.0 for e in elevations)  # a few degrees above the horizon at the ends
    beach = Scene.load("beach-drying")
    assert beach.vary == "saturation" and beach.levels.size == 16
    assert beach.wavelength_nm.size == 16 and beach.grain is not None
    wet = beach.build_material(0.0).values.mean()
    dry = beach.build_material(1.0).values.mean()
    assert dry < wet  # the beach dries over the day


def with_change(doc, table, key, value):
    d = copy.deepcopy(doc)
    node = d
    for part in table.split("."):
        node = node.setdefault(part, {})
    if value is None:
        node.pop(key, None)
    else:
        node[key] = value
    return d


@pytest.mark.parametrize(
    "table,key,value,message",
    [
        ("camera", "fov_deg", 200.0, "camera.fov_deg"),
        ("camera", "fov_deg", "wide", "camera.fov_deg"),
        ("camera", "zoom", 2.0, "camera.zoom"),
        ("output", "width", 0, "output.width"),
        ("output", "width", 12.5, "output.width"),
        ("output", "exposure", "bright", "output.exposure"),
        ("output", "exposure", -3.0, "output.exposure"),
        ("output", "linear", True, "output.linear"),
        ("sun", "turbidity", 0.5, "sun.turbidity"),
        ("sun", "latitude_deg", 95.0, "sun.latitude_deg"),
        ("sun", "latitude_deg", None, "sun.latitude_deg"),
        ("sun", "start_h", 3.0, "sun.start_h"),  # before sunrise
        ("sun", "end_h", 5.0, "sun.end_h"),
        ("sun", "longitude_deg", 10.0, "sun.longitude_deg"),  # without utc_offset_h
        ("render", "spp", 0, "render.spp"),
        ("render", "estimator", "bdpt", "render.estimator"),
        ("render", "bands", "700:400:20", "render.bands"),
        ("render", "bands", [450.0, 550.0], "render.bands"),
        ("terrain", "type", "mountain", "terrain.type"),
        ("terrain", "cells", 1000, "terrain.cells"),
        ("terrain", "ripple_wavelength_m", 0.1, "terrain.ripple_wavelength_m"),
        ("sand", "preset", "moon-dust", "sand.preset"),
        ("sand", "brdf", "fancy", "sand.brdf"),
        ("sand", "vary", "colour", "sand.vary"),
        ("post.texture", "strength", -1.0, "post.texture.strength"),
        ("post.texture", "photo", "no/such/photo.png", "post.texture.photo"),
    ],
)
def test_bad_values_in_the_desert_scene_are_refused_with_the_key_named(table, key, value, message):
    doc = with_change(shipped("desert-day"), table, key, value)
    with pytest.raises(ParameterError) as info:
        Scene.from_dict(doc, source="test.toml")
    text = str(info.value)
    assert message in text and "test.toml" in text


@pytest.mark.parametrize(
    "table,key,value,message",
    [
        ("sand", "levels", 1, "sand.levels"),
        ("sand", "levels", [0.0, 0.5, 0.4], "sand.levels"),
        ("sand", "range", [0.0, 2.0], "sand.levels"),  # saturation above 1
        ("sand.map", "type", "spots", "sand.map.type"),
        ("sand.map", "start", [1.0, 0.5], "sand.map.start"),
        ("sand.map", "end", [1.0, 0.5, 1.5], "sand.map.end"),
        ("sand.map", "offsets_m", [9.0, 2.0], "sand.map.offsets_m"),
        ("post.grain", "amount", 2.0, "post.grain.amount"),
    ],
)
def test_bad_values_in_the_beach_scene_are_refused_with_the_key_named(table, key, value, message):
    doc = with_change(shipped("beach-drying"), table, key, value)
    with pytest.raises(ParameterError, match=message.replace(".", r"\.")):
        Scene.from_dict(doc, source="beach.toml")


def test_a_map_without_a_varied_parameter_is_refused():
    doc = shipped("desert-day")
    doc["sand"]["map"] = {"type": "uniform", "value": 0.2}
    with pytest.raises(ParameterError, match="sand.map"):
        Scene.from_dict(doc)


def test_unknown_tables_and_missing_files(tmp_path):
    doc = shipped("desert-day")
    doc["lights"] = {"lamp": 1}
    with pytest.raises(ParameterError, match="lights"):
        Scene.from_dict(doc)
    with pytest.raises(FileNotFoundError, match="desert-day"):
        Scene.load(tmp_path / "nothing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[output\nwidth = 3")
    with pytest.raises(ModelFileError, match="bad.toml"):
        Scene.load(bad)


def test_overrides_are_validated():
    scene = Scene.load("beach-drying")
    small = scene.with_overrides(width=32, height=18, frames=2, spp=2)
    assert (small.width, small.height, small.frames, small.settings.spp) == (32, 18, 2, 2)
    with pytest.raises(ParameterError, match="width"):
        scene.with_overrides(width=0)
    with pytest.raises(ParameterError, match="spp"):
        scene.with_overrides(spp=-1)
    with pytest.raises(ParameterError, match="linear"):
        scene.with_overrides(write_linear="exr")


def test_relative_paths_are_read_from_the_scene_folder(tmp_path):
    from PIL import Image

    ramp = (np.linspace(0, 255, 32)[None, :] * np.ones((16, 1))).astype(np.uint8)
    Image.fromarray(ramp).save(tmp_path / "hills.png")
    doc = shipped("desert-day")
    doc["terrain"] = {"type": "image", "path": "hills.png", "size_m": [64.0, 32.0], "height_range_m": [0.0, 4.0]}
    (tmp_path / "scene.toml").write_text("")
    scene = Scene.from_dict(doc, source=str(tmp_path / "scene.toml"), base_dir=tmp_path)
    terrain = scene.build_terrain()
    # West edge black (0 m), east edge white (4 m).
    assert terrain.height_at(-31.9, 0.0) == pytest.approx(0.0, abs=0.02)
    assert terrain.height_at(31.9, 0.0) == pytest.approx(4.0, abs=0.02)


def test_brdf_sources_appearance_and_netcdf_tables(tmp_path):
    from sandlight.appearance import SandAppearance

    beach = shipped("beach-drying")
    beach["render"]["bands"] = "400:700:100"
    doc = copy.deepcopy(beach)
    assert doc["sand"]["brdf"] == "appearance"
    scene = Scene.from_dict(doc)
    with pytest.warns(UserWarning):  # the spatial mesh varies saturation only (SpatialApproximationWarning)
        table = scene.build_table()
    assert table.n_levels == 16 and table.level_name == "saturation"
    # Level k is SandAppearance of the sample at saturation k/15 (same nodes as the model).
    with pytest.warns(UserWarning):
        wet = SandAppearance(scene.sample.replace(saturation=1.0))
    wi, wo = np.array([[0.6, 0.0, 0.8]]), np.array([[-0.3, 0.1, 0.95]])
    mu_i, mu_o = wi[0, 2], wo[0, 2] / np.linalg.norm(wo)
    dphi = abs(np.arctan2(wo[0, 1], wo[0, 0]))
    from scipy.interpolate import RegularGridInterpolator  # the renderer's trilinear lookup

    got = [
        RegularGridInterpolator((table.mu_i, table.mu_o, table.dphi), table.f[15, b])([mu_i, mu_o, dphi])[0]
        for b in range(table.wavelength_nm.size)
    ]
    np.testing.assert_allclose(got, wet.brdf(wi, wo, table.wavelength_nm)[0], rtol=1e-6)
    # A NetCDF stack whose levels match the scene's.
    path = table.to_netcdf(tmp_path / "beach.nc")
    doc["sand"]["brdf"] = "beach.nc"
    loaded = Scene.from_dict(doc, base_dir=tmp_path).build_table()
    np.testing.assert_allclose(loaded.f, table.f)
    doc["sand"]["levels"] = 8
    with pytest.raises(ParameterError, match="sand.levels"):
        Scene.from_dict(doc, base_dir=tmp_path).build_table()
    assert path.exists()
