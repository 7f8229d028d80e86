"""The same flat scene (camera, sun, sky) in sandlight's renderer and in Mitsuba agrees.

Lighting is spectrally flat (a uniform sky of 0.2 and a sun of normal irradiance 1, both per nm
and per channel), so every renderer's radiance is linear in the sand's weights a(λ), b(λ) with
wavelength-independent coefficients: sandlight's spectral image, rendered at the spectral model's
nodes plus the wavelengths where r(λ) crosses r_0 (the kinks of a and b), interpolates exactly to
1 nm and projects to the plugin's RGB (`sandlight.mitsuba.tables.rgb_projection`). Mitsuba renders
in llvm_ad_rgb with the `directional` sun (sandlight's is a disc of 6.8e-5 sr: on a plane the
difference is of order 10⁻⁵). The image is cut into 2 × 4 regions; the standard error of each
region's mean comes from K = 16 independent renders per renderer (seeds 100–115), SE =
√(s_a²/K + s_b²/K) with s the sample standard deviations of the K region means.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from sandlight.appearance import SandAppearance
from sandlight.mitsuba.scenes import camera_sensor, directional_sun, ground_plane
from sandlight.mitsuba.tables import PROJECTION_WAVELENGTHS_NM, rgb_projection
from sandlight.render import BrdfTable, Camera, Lighting, PlaneTerrain, RenderSettings, render_image
from sandlight.sample import SandSample

W, H, SPP, K = 48, 32, 16, 16
SKY, SUN_E = 0.2, 1.0


def kink_bands(app):
    wl, r, r0 = app.wavelengths_nm, app.normal_reflectance, app.reference_reflectance
    crossings = [
        wl[i] + (r0 - r[i]) / (r[i + 1] - r[i]) * (wl[i + 1] - wl[i])
        for i in range(wl.size - 1)
        if (r[i] - r0) * (r[i + 1] - r0) < 0
    ]
    return np.unique(np.r_[wl, crossings])


def regions(images):  # (K, H, W, 3) -> (K, 2, 4, 3)
    return images.reshape(images.shape[0], 2, H // 2, 4, W // 4, 3).mean(axis=(2, 4))


@pytest.mark.parametrize("saturation", [0.0, 1.0])
def test_sandlight_and_mitsuba_agree_per_region(rgb, saturation):
    mi = rgb
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        app = SandAppearance(SandSample(saturation=saturation))
    bands = kink_bands(app)
    camera = Camera.heading([0.0, 0.0, 2.0], 0.0, -25.0, 50.0, W, H)
    el, az = math.radians(30.0), math.radians(160.0)  # the sun behind the camera, to the right
    sun = np.array([math.cos(el) * math.sin(az), math.cos(el) * math.cos(az), math.sin(el)])
    light = Lighting.uniform(SKY, bands, sun_direction=sun, sun_irradiance=SUN_E)
    table = BrdfTable.from_appearance(app, bands)
    projection = rgb_projection()
    ours = []
    for k in range(K):
        radiance = render_image(
            camera, PlaneTerrain(0.0), table, light, settings=RenderSettings(spp=SPP, seed=100 + k, threads=1)
        ).radiance.reshape(-1, bands.size)
        fine = np.array([np.interp(PROJECTION_WAVELENGTHS_NM, bands, row) for row in radiance])
        ours.append((fine @ projection.T).reshape(H, W, 3))
    scene = mi.load_dict(
        {
            "type": "scene",
            "integrator": {"type": "path", "max_depth": 2},
            "sensor": camera_sensor(mi, camera, SPP),
            "ground": ground_plane(mi, {"type": "sand", "saturation": saturation}),
            "sky": {"type": "constant", "radiance": {"type": "rgb", "value": [SKY] * 3}},
            "sun": directional_sun(mi, sun, SUN_E),
        }
    )
    theirs = [np.array(mi.render(scene, seed=100 + k)) for k in range(K)]
    a, b = regions(np.array(ours)), regions(np.array(theirs))
    diff = a.mean(axis=0) - b.mean(axis=0)
    se = np.sqrt(a.var(axis=0, ddof=1) / K + b.var(axis=0, ddof=1) / K)
    print(f"saturation {saturation}: R per region sandlight {a.mean(0)[..., 0].round(4).tolist()}")
    print(f"  mitsuba {b.mean(0)[..., 0].round(4).tolist()}; |diff|/SE max {np.abs(diff / se).max():.2f}")
    assert (np.abs(diff) < 3 * se).all(), diff / se
    assert (se < 0.02 * b.mean(axis=0)).all()  # the comparison has power: SE below 2 %
