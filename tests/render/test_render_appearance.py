"""The renderer with the paper's BRDF (SandAppearance): exact tabulation, and unbiased, low-noise
estimates on saturated sand, whose mirror reflection peaks at 10³–10⁴ sr⁻¹ near grazing."""

import warnings

import numpy as np
import pytest
from scipy.interpolate import RegularGridInterpolator

from sandlight.render import BrdfTable, Camera, Lighting, PlaneTerrain, RenderSettings, render_image

WL = np.arange(400.0, 701.0, 50.0)


@pytest.fixture(scope="module")
def wet():
    """SandAppearance of the saturated beach sand and its table."""
    from sandlight.appearance import SandAppearance
    from sandlight.sample import SandSample

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the spatial mesh varies saturation only
        app = SandAppearance(SandSample.preset("wet-beach").replace(saturation=1.0))
    return app, BrdfTable.from_appearance(app, WL)


def directions(mu, dphi):
    s = np.sqrt(1.0 - mu**2)
    return np.stack([s * np.cos(dphi), s * np.sin(dphi), mu], axis=-1)


def test_the_table_reproduces_the_model_under_trilinear_lookup(wet):
    app, table = wet
    rng = np.random.default_rng(4)
    n = 4000
    mu_i, mu_o, dphi = rng.uniform(0, 1, n), rng.uniform(0, 1, n), rng.uniform(0, np.pi, n)
    # A quarter near the grazing mirror direction, where the peak is.
    k = n // 4
    mu_i[:k] = rng.uniform(0.0, 0.1, k)
    mu_o[:k] = mu_i[:k] + rng.uniform(-0.01, 0.01, k)
    mu_o = np.clip(mu_o, 1e-4, 1.0)
    dphi[:k] = np.pi - rng.uniform(0.0, 0.3, k)
    expected = app.brdf(directions(mu_i, 0.0 * mu_i), directions(mu_o, dphi), WL)
    points = np.stack([mu_i, mu_o, dphi], axis=1)
    got = np.stack(
        [RegularGridInterpolator((table.mu_i, table.mu_o, table.dphi), table.f[0, b])(points) for b in range(WL.size)],
        axis=1,
    )
    np.testing.assert_allclose(got, expected, rtol=1e-6, atol=1e-9)
    assert expected.max() > 1000.0  # the mirror peak is in the test


def grazing_camera(pitch_deg):
    # 0.5° per pixel: the albedo hardly changes across a pixel's footprint.
    return Camera.heading([0.0, 0.0, 1.0], 0.0, pitch_deg, 4.0, 8, 4)


@pytest.mark.parametrize("pitch_deg", [-3.0, -12.0])
def test_saturated_plane_under_a_unit_sky_gives_the_albedo_without_fireflies(wet, pitch_deg):
    # L(ω_o) = ∫ f(ω_i, ω_o) cos θ_i dω_i = albedo(μ_o) (f reciprocal). At 3° below the horizon
    # the mirror reflection carries most of it: the BRDF sampler must follow the peak closely,
    # or the per-pixel error at 64 samples is tens of per cent.
    app, table = wet
    cam = grazing_camera(pitch_deg)
    mu_o = -cam.directions()[..., 2]
    expected = app.albedo(directions(mu_o.ravel(), 0.0 * mu_o.ravel()), WL).reshape(mu_o.shape + (WL.size,))
    # The sampler follows the band mean of f: its error is what sampling controls (single bands
    # add the spectral difference between the grey mirror and the yellow diffuse part).
    for estimator, spp, limit in (("brdf", 64, 0.04), ("mis", 256, 0.1)):
        img = render_image(
            cam, PlaneTerrain(), table, Lighting.uniform(1.0, WL), settings=RenderSettings(spp=spp, estimator=estimator)
        )
        assert (img.coverage == 1).all()
        rel = img.radiance.mean(axis=-1) / expected.mean(axis=-1) - 1.0
        assert abs(rel.mean()) < 0.015, (estimator, rel.mean())
        assert np.abs(rel).max() < limit, (estimator, np.abs(rel).max())
        np.testing.assert_allclose(img.radiance.mean(axis=(0, 1)), expected.mean(axis=(0, 1)), rtol=0.03)
    if pitch_deg == -3.0:
        assert expected.mean() > 0.5  # mostly the mirror reflection (the sand's own albedo is ≈ 0.1)


def test_sun_in_the_mirror_direction_of_saturated_sand(wet):
    # Sun only: L = E f(ω_sun, ω_o) cos θ_sun, the glint of wet sand, from the sun's light sample.
    # The sun is 6° in azimuth from the mirror image of the view ray of pixel (1, 4), where f is
    # linear in Δφ (at the mirror azimuth it has a kink, and averaging over the pixel and the
    # solar disc would lower it by 1–2 %).
    app, table = wet
    cam = grazing_camera(-8.0)
    d = cam.directions()[1, 4]
    c, s = np.cos(np.radians(6.0)), np.sin(np.radians(6.0))
    sun = np.array([c * d[0] - s * d[1], s * d[0] + c * d[1], -d[2]])
    e = np.linspace(1.0, 2.0, WL.size)
    lighting = Lighting.uniform(0.0, WL, sun_direction=sun, sun_irradiance=e)
    img = render_image(cam, PlaneTerrain(), table, lighting, settings=RenderSettings(spp=32))
    mu_s = sun[2] / np.linalg.norm(sun)
    f = app.brdf(sun[None, :], -d[None, :], WL)[0]
    np.testing.assert_allclose(img.radiance[1, 4], e * f * mu_s, rtol=5e-3)
    assert f.mean() > 50.0  # a glint, not the sand's diffuse reflection
