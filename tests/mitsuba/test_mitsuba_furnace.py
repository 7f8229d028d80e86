"""White furnace: a plane of sand under a uniform unit sky renders to its directional albedo."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from sandlight.appearance import SandAppearance
from sandlight.mitsuba.tables import PROJECTION_WAVELENGTHS_NM, rgb_projection
from sandlight.sample import SandSample

pytestmark = pytest.mark.filterwarnings("ignore::sandlight.spatial.model.SpatialApproximationWarning")

SIZE, SPP = 32, 64


def furnace_scene(mi, view_deg, bsdf):
    # An orthographic camera: every pixel sees the plane from the same direction.
    th = math.radians(view_deg)
    origin = [0.0, -10.0 * math.sin(th), 10.0 * math.cos(th)]
    up = [0.0, 1.0, 0.0] if view_deg < 1.0 else [0.0, 0.0, 1.0]
    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 2},
        "sensor": {
            "type": "orthographic",
            "to_world": mi.ScalarTransform4f().look_at(origin=origin, target=[0, 0, 0], up=up),
            "film": {"type": "hdrfilm", "width": SIZE, "height": SIZE, "rfilter": {"type": "box"}},
            "sampler": {"type": "independent", "sample_count": SPP},
        },
        "ground": {
            "type": "rectangle",
            "to_world": mi.ScalarTransform4f().scale([50.0, 50.0, 1.0]),
            "bsdf": bsdf,
        },
        "sky": {"type": "constant", "radiance": {"type": "rgb", "value": [1.0, 1.0, 1.0]}},
    }


@pytest.mark.parametrize("view_deg", [0.0, 60.0, 80.0])
@pytest.mark.parametrize("saturation", [0.0, 1.0])
def test_furnace_gives_the_directional_albedo(rgb, saturation, view_deg):
    mi = rgb
    image = np.array(
        mi.render(mi.load_dict(furnace_scene(mi, view_deg, {"type": "sand", "saturation": saturation})), seed=1)
    )
    pixels = image.reshape(-1, 3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        app = SandAppearance(SandSample(saturation=saturation))
    th = math.radians(view_deg)
    fine = np.arange(400.0, 701.0)
    albedo = app.albedo([math.sin(th), 0.0, math.cos(th)], fine)[0]
    expected = rgb_projection() @ np.interp(PROJECTION_WAVELENGTHS_NM, fine, albedo)
    # Pixels are independent estimates (their own samples): SE of the image mean from their spread.
    mean, se = pixels.mean(axis=0), pixels.std(axis=0, ddof=1) / math.sqrt(len(pixels))
    print(f"furnace saturation {saturation} view {view_deg}: mean {mean}, albedo {expected}, SE {se}")
    assert (np.abs(mean - expected) < 4 * se).all(), (mean, expected, se)
    assert (se < 0.01 * expected).all()  # a test with power: the noise is far below the albedo
