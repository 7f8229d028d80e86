"""BRDF tables, terrain, maps, lighting and post-processing."""

import numpy as np
import pytest

from sandlight.errors import ModelFileError, ParameterError
from sandlight.render import (
    BrdfTable,
    Camera,
    Lighting,
    MaterialMap,
    PlaneTerrain,
    RenderSettings,
    Waterlines,
    dune_field,
    heightfield_from_array,
    post,
    render_image,
)

WL = np.arange(400.0, 701.0, 20.0)


def test_lambertian_table_has_its_albedo_and_oren_nayar_is_reciprocal_with_a_backscatter_lobe():
    albedo = np.linspace(0.1, 0.8, WL.size)
    np.testing.assert_allclose(BrdfTable.lambertian(albedo, WL).albedo(0.3), albedo, rtol=1e-12)
    on = BrdfTable.oren_nayar(0.5, 30.0, WL)
    f = on.f[0, 0]
    np.testing.assert_allclose(f, np.swapaxes(f, 0, 1), rtol=1e-12)  # f(μi, μo) = f(μo, μi)
    k = np.searchsorted(on.mu_i, 0.5)
    assert f[k, k, 0] > f[k, k, -1]  # brighter towards the light (Δφ = 0) than away from it
    # Energy: the directional albedo never exceeds the albedo parameter.
    assert (on.albedo(0.2) <= 0.5 + 1e-9).all()


def test_from_function_reproduces_an_analytic_brdf():
    def brdf(wi, wo, wl):
        return np.broadcast_to(0.3 / np.pi * (1 + 0.5 * wi[:, 2] * wo[:, 2])[:, None], (len(wi), len(wl)))

    t = BrdfTable.from_function(brdf, WL, min_mu=0.0)
    i, o = 5, 9
    assert t.f[0, 3, i, o, 2] == pytest.approx(0.3 / np.pi * (1 + 0.5 * t.mu_i[i] * t.mu_o[o]))


def test_netcdf_round_trip_and_refused_files(tmp_path):
    stack = BrdfTable.stack([BrdfTable.oren_nayar(a, 20.0, WL) for a in (0.2, 0.5)], [0.0, 1.0], "saturation")
    path = stack.to_netcdf(tmp_path / "brdf.nc")
    back = BrdfTable.from_netcdf(path)
    assert back.level_name == "saturation" and back.n_levels == 2
    np.testing.assert_allclose(back.f, stack.f)
    np.testing.assert_allclose(back.dphi, stack.dphi)
    (tmp_path / "junk.nc").write_bytes(b"not a netcdf file")
    with pytest.raises(ModelFileError, match="junk.nc"):
        BrdfTable.from_netcdf(tmp_path / "junk.nc")
    with pytest.raises(FileNotFoundError):
        BrdfTable.from_netcdf(tmp_path / "absent.nc")
    import xarray as xr

    xr.Dataset({"g": ("x", np.ones(3))}).to_netcdf(tmp_path / "foreign.nc", engine="h5netcdf")
    with pytest.raises(ModelFileError, match="not a sandlight BRDF table file"):
        BrdfTable.from_netcdf(tmp_path / "foreign.nc")


def test_tables_reject_bad_arrays_and_interpolate_wavelengths():
    with pytest.raises(ParameterError, match="mu_o"):
        BrdfTable(np.ones((1, 2, 2, 2)), [500, 600], [0, 1], [0.1, 1], [0, np.pi], [0])
    with pytest.raises(ParameterError, match="f"):
        BrdfTable(-np.ones((1, 2, 2, 2)), [500, 600], [0, 1], [0, 1], [0, np.pi], [0])
    t = BrdfTable.lambertian([0.2, 0.6], [400.0, 700.0])
    native = t.native_f([400.0, 550.0, 700.0])
    assert native.shape == (1, 2, 2, 2, 3)
    np.testing.assert_allclose(native[0, 0, 0, 0], np.array([0.2, 0.4, 0.6]) / np.pi, rtol=1e-6)
    with pytest.raises(ParameterError, match="wavelength"):
        t.native_f([380.0, 500.0])
    stack = BrdfTable.lambertian(
        np.array([[0.1] * 2, [0.2] * 2, [0.4] * 2]), [400.0, 700.0], level_values=[0.0, 0.5, 1.0]
    )
    np.testing.assert_allclose(stack.level_coordinate([0.0, 0.25, 0.75, 1.0]), [0.0, 0.5, 1.5, 2.0])
    with pytest.raises(ParameterError):
        stack.level_coordinate([1.2])


def test_dune_field_is_periodic_and_has_dune_like_slopes():
    d = dune_field(size_m=102.4, cells=256, ripple_height_m=0.0, seed=3)
    h = d.heights_m.astype(float)
    step = np.abs(np.diff(h, axis=1)).mean()
    # Wrapping seam no rougher than any other column step.
    assert np.abs(h[:, 0] - h[:, -1]).mean() < 3 * step
    assert np.abs(h[0] - h[-1]).mean() < 3 * step
    gy, gx = np.gradient(h, d.spacing_m[0])
    slope_deg = np.degrees(np.arctan(np.hypot(gx, gy)))
    assert 25.0 < np.percentile(slope_deg, 99.5) < 45.0  # lee faces near the angle of repose
    assert h.min() == 0.0 and 4.0 < h.max() < 9.0
    with pytest.raises(ParameterError, match="cells"):
        dune_field(cells=1000)


def test_heightfield_from_array_and_camera_placement():
    hf = heightfield_from_array(np.array([[0.0, 1.0], [0.0, 1.0]]), size_m=(10.0, 10.0), height_range_m=(1.0, 3.0))
    assert hf.height_at(0.0, 0.0) == pytest.approx(2.0)
    assert hf.height_at(50.0, 50.0) == pytest.approx(hf.outside_m)
    with pytest.raises(ParameterError, match="heightfield"):
        heightfield_from_array(np.array([[0.0, 2.0], [0.0, 1.0]]), size_m=(1, 1), height_range_m=(0, 1))
    with pytest.raises(ParameterError, match="camera.forward"):
        Camera([0, 0, 1], [0, 0, -1], 60.0, 8, 8)


def test_waterlines_are_brownian_and_the_beach_dries():
    w = Waterlines(extent_m=(-50.0, -10.0, 50.0, 20.0), resolution_m=0.05, seed=4)
    x, line1, line2 = w.curves()
    # Brownian motion: increments with standard deviation roughness·√Δx.
    inc = np.diff(line1)
    assert inc.std() == pytest.approx(w.roughness_m_per_sqrt_m * np.sqrt(0.05), rel=0.05)
    assert abs(np.corrcoef(inc[:-1], inc[1:])[0, 1]) < 0.05
    m0, m1 = w.map(0.0), w.map(1.0)
    far_sea, far_land = m0.value_at(0.0, -9.0), m0.value_at(0.0, 19.0)
    assert far_sea == pytest.approx(w.start[0], abs=1e-3) and far_land == pytest.approx(w.start[2], abs=1e-3)
    assert m1.value_at(0.0, 19.0) == pytest.approx(w.end[2], abs=1e-3)
    assert (m1.values <= m0.values + 1e-12).all()


def test_horizontal_irradiance_meters_a_white_plane_to_display_white():
    # A white Lambertian plane under sun and sky reflects E/π: "auto" exposure shows it as Y = 1.
    from sandlight.sky import sun_direction

    lighting = Lighting.preetham(3.0, sun_direction(30.0, 172, 10.0), WL, resolution=(45, 128))
    cam = Camera.heading([0.0, 0.0, 2.0], 0.0, -40.0, 40.0, 8, 6)
    img = render_image(
        cam, PlaneTerrain(), BrdfTable.lambertian(np.ones(WL.size), WL), lighting, settings=RenderSettings(spp=128)
    )
    y = post.spectral_to_xyz(img.radiance, WL)[..., 1] / post.white_level("auto", lighting, WL)
    assert y.mean() == pytest.approx(1.0, rel=0.01)
    rgb = post.to_srgb(post.spectral_to_xyz(img.radiance, WL), post.white_level("auto", lighting, WL))
    assert rgb.mean() > 0.9


def test_colour_matrix_scale_and_luminance_exposure():
    m = post.xyz_matrix(WL)
    assert (np.ones(WL.size) @ m)[1] == pytest.approx(1.0, rel=1e-3)  # flat unit spectrum: Y = 1
    # 683 lm/W × ∫ȳ dλ: a flat 1 W m⁻² sr⁻¹ nm⁻¹ spectrum is about 80 kcd/m² (10° observer).
    white = post.white_level(80000.0, None, WL)
    assert 0.9 < white < 1.1
    with pytest.raises(ParameterError, match="exposure"):
        post.white_level(-1.0, None, WL)


def test_texture_quotient_and_grain():
    rng = np.random.default_rng(0)
    photo = np.clip(0.5 + 0.1 * rng.standard_normal((64, 64, 3)), 0, 1)
    q = post.texture_quotient(photo, blur_px=8.0)
    assert q.mean() == pytest.approx(1.0, abs=0.03) and q.std() > 0.05
    flat = post.texture_quotient(np.full((32, 32, 3), 0.4), blur_px=5.0)
    np.testing.assert_allclose(flat, 1.0, atol=1e-9)
    mask = np.zeros((64, 64), bool)
    mask[32:] = True
    qm = post.texture_quotient(photo, blur_px=8.0, ground_mask=mask)
    assert (qm[:32] == 1).all()
    xyz = np.ones((64, 64, 3))
    coverage = np.zeros((64, 64))
    np.testing.assert_array_equal(post.apply_quotient(xyz, q, coverage), xyz)  # the sky is untouched
    g = post.grain_field(200, 300, amount=0.1, seed=1)
    assert g.mean() == pytest.approx(1.0, abs=0.01) and g.std() == pytest.approx(0.1, rel=0.05)
    tiled = post.fit_to(q, 100, 150, "tile")
    np.testing.assert_array_equal(tiled[:64, :64], q)


def test_material_map_from_image(tmp_path):
    from PIL import Image

    img = np.zeros((2, 2), np.uint8)
    img[0, :] = 255  # top row (north) white
    Image.fromarray(img).save(tmp_path / "map.png")
    m = MaterialMap.from_image(tmp_path / "map.png", extent_m=(0.0, 0.0, 10.0, 10.0), value_range=(0.2, 0.6))
    assert m.value_at(5.0, 10.0) == pytest.approx(0.6) and m.value_at(5.0, 0.0) == pytest.approx(0.2)


def test_soft_highlights_keep_midtones_and_roll_off_smoothly():
    y = np.linspace(0.0, 5.0, 501)
    s = post.soft_highlights(y)
    np.testing.assert_array_equal(s[y <= 0.8], y[y <= 0.8])
    assert (np.diff(s) > 0).all() and s.max() < 1.0
    slope = (post.soft_highlights(0.8 + 1e-6) - 0.8) / 1e-6
    assert slope == pytest.approx(1.0, rel=1e-4)  # no kink at the knee
    xyz = np.array([[0.3, 0.3, 0.3], [3.0, 3.0, 2.0]])
    soft, clip = post.to_srgb(xyz, 1.0), post.to_srgb(xyz, 1.0, highlights="clip")
    np.testing.assert_array_equal(soft[0], clip[0])
    # A bright yellowish white is compressed (its hue kept), not clipped to flat white.
    assert (soft[1] <= clip[1] + 1e-12).all() and soft[1].min() < clip[1].min() - 0.05
    with pytest.raises(ParameterError, match="highlights"):
        post.to_srgb(xyz, 1.0, highlights="filmic")


def test_repr_gives_shapes_and_ranges_not_the_arrays():
    # A table of the renderer's size: printing it must not dump its 4-D array (issue 24).
    wl = np.arange(400.0, 701.0, 10.0)
    stack = BrdfTable.stack(
        [
            BrdfTable.oren_nayar(a, 20.0, wl, mu=np.linspace(0, 1, 33), dphi=np.linspace(0, np.pi, 33))
            for a in (0.2, 0.6)
        ],
        [0.0, 1.0],
        "saturation",
    )
    text = repr(stack)
    assert len(text) < 250 and "array" not in text and "\n" not in text
    assert "2 levels (saturation 0…1)" in text and "31 wavelengths 400–700 nm" in text
    assert "33 × 33 × 33" in text
    assert f"f in [{stack.f.min():.4g}, {stack.f.max():.4g}] sr⁻¹" in text
    assert "1 level (level 0)" in repr(BrdfTable.lambertian(0.5, [550.0]))
