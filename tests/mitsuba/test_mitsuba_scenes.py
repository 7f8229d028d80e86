"""The Mitsuba scenes of sandlight's scenes: texture placement, the XML examples, the CLI path."""

from __future__ import annotations

import numpy as np
import pytest

from sandlight.mitsuba.scenes import EXAMPLES, GROUND_HALF_SIZE_M, example_xml_path, saturation_texture
from sandlight.render import MaterialMap

pytestmark = pytest.mark.filterwarnings("ignore::sandlight.spatial.model.SpatialApproximationWarning")


def test_saturation_texture_puts_the_map_where_sandlight_does(rgb):
    mi = rgb
    import drjit as dr

    rng = np.random.default_rng(7)
    material = MaterialMap(rng.random((7, 11)), origin_m=(-3.0, 2.0), spacing_m=(0.5, 0.25))
    texture = mi.load_dict(saturation_texture(mi, material))
    x = rng.uniform(-5.0, 4.0, 2000)  # inside and outside the map (clamped there)
    y = rng.uniform(1.0, 4.5, 2000)
    si = dr.zeros(mi.SurfaceInteraction3f, x.size)
    h = GROUND_HALF_SIZE_M
    # The rectangle's uv (tests/mitsuba: rectangle uv = ((x/h + 1)/2, (y/h + 1)/2)).
    si.uv = mi.Point2f(((x / h + 1) / 2).astype(np.float32), ((y / h + 1) / 2).astype(np.float32))
    np.testing.assert_allclose(np.array(texture.eval_1(si)), material.value_at(x, y), atol=2e-3)


def test_rectangle_uv_is_as_assumed(rgb):
    mi = rgb
    scene = mi.load_dict(
        {
            "type": "scene",
            "g": {"type": "rectangle", "to_world": mi.ScalarTransform4f().scale([GROUND_HALF_SIZE_M] * 3)},
        }
    )
    x, y = np.array([-1500.0, 700.0]), np.array([300.0, -1900.0])
    ray = mi.Ray3f(mi.Point3f(x.astype(np.float32), y.astype(np.float32), [1.0, 1.0]), mi.Vector3f(0, 0, -1))
    uv = np.array(scene.ray_intersect(ray).uv)
    h = GROUND_HALF_SIZE_M
    np.testing.assert_allclose(uv, [(x / h + 1) / 2, (y / h + 1) / 2], atol=1e-6)


@pytest.mark.parametrize("name", EXAMPLES)
def test_xml_examples_render(spectral, name):
    mi = spectral
    scene = mi.load_file(str(example_xml_path(name)))
    image = np.array(mi.render(scene, spp=1))
    assert image.shape == (180, 320, 3)
    assert np.isfinite(image).all()
    # Spectral → linear sRGB leaves saturated oranges slightly out of gamut (small negatives).
    assert image.min() > -0.1 * image.max()
    # Sky above (bluish at midday), sand below (reddish) in both scenes.
    sky, sand = image[:10].mean(axis=(0, 1)), image[-60:].mean(axis=(0, 1))
    assert sky[2] > sky[0] and sand[0] > sand[2] and sand[0] > 0.05


def test_render_command_with_mitsuba(spectral, tmp_path):
    from typer.testing import CliRunner

    from sandlight.cli import app

    args = ["render", "beach-drying", "-o", str(tmp_path), "--width", "16", "--height", "9", "--spp", "2"]
    result = CliRunner().invoke(app, args + ["--frames", "2", "--renderer", "mitsuba", "--no-progress"])
    assert result.exit_code == 0, result.output
    assert sorted(p.name for p in tmp_path.glob("frame_*.png")) == ["frame_0000.png", "frame_0001.png"]
    bad = CliRunner().invoke(app, args + ["--renderer", "povray"])
    assert bad.exit_code == 2 and "--renderer" in bad.output
