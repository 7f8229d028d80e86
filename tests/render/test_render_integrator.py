"""The path tracer against closed forms: unit sky, sun only, non-Lambertian albedo, estimators
agreeing within noise, shadows on a heightfield, determinism."""

import numpy as np
import pytest

from sandlight.errors import ParameterError
from sandlight.render import (
    BrdfTable,
    Camera,
    HeightfieldTerrain,
    Lighting,
    MaterialMap,
    PlaneTerrain,
    RenderSettings,
    render_image,
)
from sandlight.render.image import native_scene

WL = np.arange(400.0, 701.0, 20.0)
ALBEDO = np.linspace(0.2, 0.7, WL.size)


def downward_camera(width=12, height=8, pitch=-35.0, z=2.0):
    return Camera.heading([0.0, 0.0, z], 30.0, pitch, 40.0, width, height)


@pytest.mark.parametrize("estimator", ["mis", "brdf", "light"])
@pytest.mark.parametrize("sampling", ["table", "cosine"])
def test_white_lambertian_plane_under_unit_sky_has_unit_radiance(estimator, sampling):
    # L = ∫ (1/π) · 1 · cos θ dω = 1 for every pixel and band: the integrator is unbiased.
    table = BrdfTable.lambertian(np.ones(WL.size), WL)
    img = render_image(
        downward_camera(),
        PlaneTerrain(),
        table,
        Lighting.uniform(1.0, WL),
        settings=RenderSettings(spp=64, estimator=estimator, sampling=sampling),
    )
    assert (img.coverage == 1).all()
    assert abs(img.radiance.mean() - 1.0) < 5e-3
    # Per pixel: exact for cosine-like sampling, a few per cent of noise for light sampling.
    assert np.abs(img.radiance - 1.0).max() < 0.15


def test_grey_plane_under_a_coloured_sky_reflects_albedo_times_sky():
    sky = np.linspace(0.5, 2.0, WL.size)
    img = render_image(
        downward_camera(),
        PlaneTerrain(1.5),
        BrdfTable.lambertian(ALBEDO, WL),
        Lighting.uniform(sky, WL),
        settings=RenderSettings(spp=64),
    )
    np.testing.assert_allclose(img.radiance.mean(axis=(0, 1)), ALBEDO * sky, rtol=3e-3)


@pytest.mark.parametrize("elevation_deg", [12.0, 55.0])
def test_sun_only_plane_follows_lambert(elevation_deg):
    # L = E a/π cos θs with E the normal irradiance of the sun.
    e = np.linspace(1.0, 2.0, WL.size)
    el = np.radians(elevation_deg)
    sun = [np.cos(el), 0.3 * np.cos(el), np.sin(el)]
    lighting = Lighting.uniform(0.0, WL, sun_direction=sun, sun_irradiance=e)
    img = render_image(
        downward_camera(), PlaneTerrain(), BrdfTable.lambertian(ALBEDO, WL), lighting, settings=RenderSettings(spp=32)
    )
    cos_s = np.asarray(sun)[2] / np.linalg.norm(sun)
    expected = e * ALBEDO / np.pi * cos_s
    np.testing.assert_allclose(img.radiance.mean(axis=(0, 1)), expected, rtol=2e-3)


def test_non_lambertian_plane_under_unit_sky_gives_the_directional_albedo():
    # Under a unit sky L(ω_o) = ∫ f(ω_i, ω_o) cos θ_i dω_i: the albedo at the view angle (the
    # tabulated Oren–Nayar BRDF is reciprocal).
    table = BrdfTable.oren_nayar(ALBEDO, 30.0, WL)
    cam = downward_camera(width=4, height=3, pitch=-50.0)
    img = render_image(cam, PlaneTerrain(), table, Lighting.uniform(1.0, WL), settings=RenderSettings(spp=400))
    mu_o = -cam.directions()[..., 2]
    expected = np.array([[table.albedo(m) for m in row] for row in mu_o])
    np.testing.assert_allclose(img.radiance, expected, rtol=0.03)
    # Oren–Nayar darkens and brightens with angle: the test is not a constant.
    assert np.ptp(expected[..., 8]) > 0.01


def _scene_images(estimator, sampling, seed, spp=192):
    from sandlight.sky import sun_direction

    lighting = Lighting.preetham(3.0, sun_direction(30.0, 172, 9.0), WL, resolution=(24, 64))
    lighting = Lighting(
        WL, lighting.sky_radiance, lighting.sun_direction, np.zeros(WL.size), lighting.sun_solid_angle_sr
    )
    table = BrdfTable.oren_nayar(ALBEDO, 25.0, WL)
    img = render_image(
        downward_camera(width=8, height=6, pitch=-25.0),
        PlaneTerrain(),
        table,
        lighting,
        settings=RenderSettings(spp=spp, estimator=estimator, sampling=sampling, seed=seed),
    )
    # Band average per pixel: the bands of one path are fully correlated, pixels are independent.
    return img.radiance.astype(float).mean(axis=-1)


def test_mis_brdf_and_cosine_sampling_converge_to_the_same_image():
    reference = _scene_images("mis", "table", 1)
    noise = _scene_images("mis", "table", 2) - reference  # difference of two independent renders
    sigma_mis = noise.std() / np.sqrt(2)
    for estimator, sampling in [("brdf", "table"), ("brdf", "cosine"), ("mis", "cosine"), ("light", "table")]:
        other = _scene_images(estimator, sampling, 3)
        other_noise = (_scene_images(estimator, sampling, 4) - other).std() / np.sqrt(2)
        diff = other - reference
        # Same expectation: the image means agree within 5 standard errors of the mean ...
        se_mean = np.hypot(sigma_mis, other_noise) / np.sqrt(diff.size)
        assert abs(diff.mean()) < 5 * se_mean + 1e-4 * reference.mean(), (estimator, sampling)
        # ... and the per-pixel differences are no larger than the noise explains.
        assert diff.std() < 1.3 * np.hypot(sigma_mis, other_noise), (estimator, sampling)


def test_mis_beats_cosine_sampling_under_a_sky_with_a_low_sun():
    mis = [_scene_images("mis", "table", s, spp=64) for s in (5, 6)]
    cos = [_scene_images("brdf", "cosine", s, spp=64) for s in (5, 6)]
    assert (mis[0] - mis[1]).std() < (cos[0] - cos[1]).std()


def hill_terrain():
    # A Gaussian hill 3 m high on flat ground (heightfield embedded in the plane z = 0).
    x = np.arange(-20.0, 20.01, 0.25)
    xx, yy = np.meshgrid(x, x)
    h = 3.0 * np.exp(-(xx**2 + yy**2) / (2 * 2.0**2))
    return HeightfieldTerrain(h, (-20.0, -20.0), (0.25, 0.25), wrap=False, outside_m=0.0)


def test_shadows_exist_on_a_heightfield():
    terrain = hill_terrain()
    el = np.radians(15.0)
    sun = np.array([np.cos(el), 0.0, np.sin(el)])  # low sun in the east: the shadow falls west
    lighting = Lighting.uniform(0.0, WL, sun_direction=sun, sun_irradiance=1.0)
    cam = Camera.look_at([0.0, -0.5, 40.0], [0.0, 0.0, 0.0], 30.0, 48, 48)  # looking almost straight down
    img = render_image(
        cam, terrain, BrdfTable.lambertian(np.full(WL.size, 0.5), WL), lighting, settings=RenderSettings(spp=16)
    )
    lum = img.radiance[..., 8]
    flat = 0.5 / np.pi * np.sin(el)
    # Where each pixel's centre meets the ground (a plane z = 0 is close enough outside the hill).
    d = cam.directions()
    t = -cam.position[2] / d[..., 2]
    x, y = cam.position[0] + t * d[..., 0], cam.position[1] + t * d[..., 1]
    behind = (x < -4.0) & (x > -8.0) & (np.abs(y) < 0.8)  # 3 m / tan 15° ≈ 11 m of shadow behind the hill
    # Far from the hill (its slope < 3·10⁻⁴ beyond 9 m: at a 15° sun even small tilts matter).
    open_ground = (np.hypot(x, y) > 9.0) & ~((x < 0) & (np.abs(y) < 5.0))
    assert behind.sum() >= 4 and open_ground.sum() > 100
    assert (lum[behind] < 1e-6).all()
    # The solar disc's finite size makes cos θ vary by ±1.7 % between samples at 15°.
    np.testing.assert_allclose(lum[open_ground], flat, rtol=0.03)
    assert abs(lum[open_ground].mean() / flat - 1.0) < 2e-3
    # Unshadowed slopes facing the sun are brighter than flat ground.
    assert lum.max() > 2.0 * flat


def test_occlusion_rays_agree_with_the_surface():
    terrain = hill_terrain()
    scene = native_scene(
        downward_camera(), terrain, BrdfTable.lambertian(np.full(WL.size, 0.5), WL), Lighting.uniform(1.0, WL)
    )
    origins = np.array([[-9.0, 0.0, 0.01], [9.0, 0.0, 0.01], [0.0, 0.0, 10.0]])
    to_sun = np.array([np.cos(np.radians(15.0)), 0.0, np.sin(np.radians(15.0))])
    t, n = scene.intersect(origins, np.array([to_sun, to_sun, [0.0, 0.0, -1.0]]))
    # Behind the hill the ray to the sun passes x = 0 at 9 tan 15° = 2.4 m < 3 m: blocked.
    assert np.isfinite(t[0]) and 5.0 < t[0] * to_sun[0] < 9.0 and np.isinf(t[1])
    # The summit node, 3 m high; the patches around it tilt by a few degrees.
    assert abs(t[2] - (10.0 - 3.0)) < 1e-3 and n[2, 2] > 0.98


def test_material_map_blends_the_table_levels():
    stack = BrdfTable.lambertian(
        np.array([np.full(WL.size, 0.2), np.full(WL.size, 0.8)]), WL, level_values=[0.0, 1.0], level_name="saturation"
    )
    light = Lighting.uniform(1.0, WL)
    img = render_image(
        downward_camera(), PlaneTerrain(), stack, light, MaterialMap.uniform(0.25), settings=RenderSettings(spp=64)
    )
    # The image mean scatters by 0.05 % between seeds at 64 spp.
    np.testing.assert_allclose(img.radiance.mean(), 0.2 + 0.25 * 0.6, rtol=2e-3)
    with pytest.raises(ParameterError, match="material"):
        render_image(downward_camera(), PlaneTerrain(), stack, light, None)
    with pytest.raises(ParameterError, match="saturation"):
        render_image(downward_camera(), PlaneTerrain(), stack, light, MaterialMap.uniform(1.5))


def test_images_do_not_depend_on_the_thread_count_and_frames_differ():
    from sandlight.sky import sun_direction

    lighting = Lighting.preetham(3.0, sun_direction(30.0, 172, 10.0), WL, resolution=(16, 32))
    args = (
        downward_camera(width=16, height=8, pitch=-10.0, z=6.0),
        hill_terrain(),
        BrdfTable.oren_nayar(ALBEDO, 20.0, WL),
        lighting,
    )
    one = render_image(*args, settings=RenderSettings(spp=4, threads=1, max_bounces=2))
    two = render_image(*args, settings=RenderSettings(spp=4, threads=2, max_bounces=2))
    assert one.radiance.mean() > 0
    np.testing.assert_array_equal(one.radiance, two.radiance)
    other = render_image(*args, settings=RenderSettings(spp=4, threads=2, max_bounces=2), frame=1)
    assert not np.array_equal(one.radiance, other.radiance)


def test_sky_seen_directly_and_the_solar_disc():
    sky = np.linspace(0.1, 0.3, WL.size)
    sun = np.array([0.0, 10.0, 0.5])  # in the middle of the picture, 2.9° up
    lighting = Lighting.uniform(sky, WL, sun_direction=sun, sun_irradiance=1.0, sun_solid_angle_sr=0.05)
    cam = Camera.look_at([0.0, 0.0, 1.0], [0.0, 10.0, 1.5], 30.0, 31, 17)
    img = render_image(cam, PlaneTerrain(), BrdfTable.lambertian(ALBEDO, WL), lighting, settings=RenderSettings(spp=16))
    centre = cam.directions()[8, 15]
    assert centre @ (sun / np.linalg.norm(sun)) > np.cos(np.sqrt(0.05 / np.pi))
    np.testing.assert_allclose(img.radiance[8, 15], sky + 1.0 / 0.05, rtol=1e-5)  # sky + disc
    np.testing.assert_allclose(img.radiance[0, 0], sky, rtol=1e-5)
    assert img.coverage[0, 0] == 0 and img.coverage[-1, 0] == 1


def test_settings_reject_bad_values():
    for kwargs, name in [
        ({"spp": 0}, "spp"),
        ({"estimator": "path"}, "estimator"),
        ({"sampling": "ggx"}, "sampling"),
        ({"max_bounces": 0}, "max_bounces"),
        ({"threads": 0}, "threads"),
    ]:
        with pytest.raises(ParameterError, match=name):
            RenderSettings(**kwargs)


@pytest.mark.parametrize("estimator", ["mis", "brdf"])
def test_white_furnace_on_a_heightfield_with_interreflections(estimator):
    # A white Lambertian terrain under a uniform unit sky is in radiative equilibrium: with
    # enough bounces every visible point has radiance 1, hollows included (light they do not get
    # from the sky comes from the surrounding slopes).
    x = np.arange(-10.0, 10.01, 0.25)
    xx, yy = np.meshgrid(x, x)
    h = 2.0 * np.cos(xx) * np.cos(0.7 * yy)  # egg-crate bumps with slopes up to 65°
    terrain = HeightfieldTerrain(h, (-10.0, -10.0), (0.25, 0.25), wrap=True)
    table = BrdfTable.lambertian(np.ones(WL.size), WL)
    cam = Camera.look_at([0.0, -6.0, 6.0], [0.0, 0.0, 0.0], 50.0, 12, 9)
    one = render_image(
        cam,
        terrain,
        table,
        Lighting.uniform(1.0, WL),
        settings=RenderSettings(spp=48, max_bounces=1, estimator=estimator),
    )
    many = render_image(
        cam,
        terrain,
        table,
        Lighting.uniform(1.0, WL),
        settings=RenderSettings(spp=256, max_bounces=40, estimator=estimator),
    )
    assert (many.coverage == 1).all()
    # Standard error of the image mean ≈ 0.003 for MIS (BRDF sampling is exact here).
    assert abs(many.radiance.mean() - 1.0) < 0.012
    assert one.radiance.mean() < 0.97  # direct light alone misses what the hollows receive from the slopes
