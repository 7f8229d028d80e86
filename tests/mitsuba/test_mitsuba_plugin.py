"""The `sand` plugin evaluates, samples and refuses as `SandAppearance` says (compared live)."""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest

from sandlight.appearance import SandAppearance
from sandlight.errors import ParameterError
from sandlight.mitsuba.tables import PROJECTION_WAVELENGTHS_NM, PluginTables, rgb_projection
from sandlight.sample import SandSample

pytestmark = pytest.mark.filterwarnings("ignore::sandlight.spatial.model.SpatialApproximationWarning")

SANDS = {
    "dry": ({"type": "sand"}, SandSample()),
    "wet": ({"type": "sand", "saturation": 1.0}, SandSample(saturation=1.0)),
    "red-dune": ({"type": "sand", "preset": "red-dune"}, "red-dune"),
}
N = 3000


def appearance(sample):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return SandAppearance(sample)


def directions(rng, n):
    v = rng.normal(size=(n, 3))
    v[:, 2] = np.abs(v[:, 2]) + 1e-3
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def reference_pdf(app, wi, wo):
    """f_ref cos θ_o / A_ref (sandlight.mitsuba.tables, "Sampling tables") from SandAppearance:
    f_ref its BRDF at the reference spectrum, A_ref the mean of its albedo over the model's
    wavelengths (the albedo is linear in the weights)."""
    albedo = app.albedo(wi).mean(axis=1)
    return app.reference_brdf(wi, wo) * np.clip(wo[:, 2], 0, None) / albedo


def interaction(mi, wi, wavelengths=None):
    import drjit as dr

    si = dr.zeros(mi.SurfaceInteraction3f, wi.shape[0])
    si.wi = mi.Vector3f(wi.T.astype(np.float32))
    if wavelengths is not None:
        si.wavelengths = mi.Spectrum(*[np.full(wi.shape[0], w, dtype=np.float32) for w in wavelengths])
    return si


def vec(mi, w):
    return mi.Vector3f(w.T.astype(np.float32))


@pytest.mark.parametrize("name", sorted(SANDS))
def test_spectral_eval_and_pdf_are_the_appearances(spectral, name):
    mi = spectral
    params, sample = SANDS[name]
    bsdf, app = mi.load_dict(params), appearance(sample)
    rng = np.random.default_rng(1)
    wi, wo = directions(rng, N), directions(rng, N)
    lam = np.array([403.0, 487.5, 600.0, 699.0])
    si, ctx = interaction(mi, wi, lam), mi.BSDFContext()
    value = np.array(bsdf.eval(ctx, si, vec(mi, wo))).T
    expected = app.brdf(wi, wo, lam) * wo[:, 2:3]
    np.testing.assert_allclose(value, expected, rtol=2e-5, atol=2e-6 * expected.max())
    pdf = np.array(bsdf.pdf(ctx, si, vec(mi, wo)))
    np.testing.assert_allclose(pdf, reference_pdf(app, wi, wo), rtol=1e-4, atol=1e-6)
    both = bsdf.eval_pdf(ctx, si, vec(mi, wo))
    np.testing.assert_array_equal(np.array(both[0]).T, value)
    np.testing.assert_array_equal(np.array(both[1]), pdf)


def test_spectral_reflectance_is_held_outside_the_models_range(spectral):
    mi = spectral
    bsdf = mi.load_dict({"type": "sand"})
    rng = np.random.default_rng(2)
    wi, wo = directions(rng, 100), directions(rng, 100)
    ctx = mi.BSDFContext()
    outside = np.array(bsdf.eval(ctx, interaction(mi, wi, [360.0, 380.0, 720.0, 830.0]), vec(mi, wo)))
    ends = np.array(bsdf.eval(ctx, interaction(mi, wi, [400.0, 400.0, 700.0, 700.0]), vec(mi, wo)))
    np.testing.assert_array_equal(outside, ends)
    assert (ends[0] != ends[2]).any()


def test_rgb_eval_is_the_documented_projection(rgb):
    mi = rgb
    app = appearance(SandSample(saturation=1.0))
    bsdf = mi.load_dict({"type": "sand", "saturation": 1.0})
    rng = np.random.default_rng(3)
    wi, wo = directions(rng, 400), directions(rng, 400)
    value = np.array(bsdf.eval(mi.BSDFContext(), interaction(mi, wi), vec(mi, wo))).T
    fine = np.arange(400.0, 701.0)
    f = app.brdf(wi, wo, fine)  # 1 nm, linear between the model's nodes like the plugin
    f_wide = np.stack([np.interp(PROJECTION_WAVELENGTHS_NM, fine, row) for row in f])
    expected = f_wide @ rgb_projection().T * wo[:, 2:3]
    np.testing.assert_allclose(value, expected, rtol=2e-5, atol=2e-6 * expected.max())


@pytest.mark.parametrize("name", ["dry", "wet"])
def test_sample_weight_is_eval_over_pdf(rgb, name):
    mi = rgb
    bsdf = mi.load_dict(SANDS[name][0])
    rng = np.random.default_rng(4)
    wi = directions(rng, N)
    si, ctx = interaction(mi, wi), mi.BSDFContext()
    u = rng.random((3, N)).astype(np.float32)
    bs, weight = bsdf.sample(ctx, si, mi.Float(u[0]), mi.Point2f(u[1:]))
    wo = np.array(bs.wo).T
    assert (wo[:, 2] > 0).all()
    np.testing.assert_allclose(np.linalg.norm(wo, axis=1), 1.0, atol=1e-5)
    value, pdf = (np.array(x) for x in bsdf.eval_pdf(ctx, si, bs.wo))
    np.testing.assert_allclose(np.array(bs.pdf), pdf, rtol=1e-6)
    np.testing.assert_allclose(np.array(weight), value / pdf, rtol=1e-5)


@pytest.mark.parametrize("name", ["dry", "wet"])
@pytest.mark.parametrize("theta_deg", [30.0, 75.0])
def test_sample_weights_average_to_the_albedo(rgb, name, theta_deg):
    # E[f cos θ_o / pdf] = ∫ f cos θ_o dω_o, the directional albedo (projected to RGB).
    mi = rgb
    params, sample = SANDS[name]
    bsdf, app = mi.load_dict(params), appearance(sample)
    n = 40000
    th = np.radians(theta_deg)
    wi = np.tile([np.sin(th), 0.0, np.cos(th)], (n, 1))
    u = np.random.default_rng(6).random((3, n)).astype(np.float32)
    _, weight = bsdf.sample(mi.BSDFContext(), interaction(mi, wi), mi.Float(u[0]), mi.Point2f(u[1:]))
    weight = np.array(weight)
    fine = np.arange(400.0, 701.0)
    albedo = np.interp(PROJECTION_WAVELENGTHS_NM, fine, app.albedo(wi[0], fine)[0])
    expected = rgb_projection() @ albedo
    se = weight.std(axis=1) / np.sqrt(n)
    assert (np.abs(weight.mean(axis=1) - expected) < 4 * se).all(), (weight.mean(axis=1), expected, se)


def test_textured_saturation_blends_the_levels(rgb):
    mi = rgb

    levels = 5  # saturation 0, 0.25, 0.5, 0.75, 1
    value = 0.6  # between the levels 0.5 and 0.75, weight 0.4 on 0.75
    texture = {"type": "bitmap", "data": mi.TensorXf(np.full((2, 2, 1), value, dtype=np.float32)), "raw": True}
    bsdf = mi.load_dict({"type": "sand", "saturation": texture, "levels": levels})
    rng = np.random.default_rng(5)
    wi, wo = directions(rng, 500), directions(rng, 500)
    si, ctx = interaction(mi, wi), mi.BSDFContext()
    got = np.array(bsdf.eval(ctx, si, vec(mi, wo))).T
    fine = np.arange(400.0, 701.0)

    def rgb_f(s):
        f = appearance(SandSample(saturation=s)).brdf(wi, wo, fine)
        wide = np.stack([np.interp(PROJECTION_WAVELENGTHS_NM, fine, row) for row in f])
        return wide @ rgb_projection().T * wo[:, 2:3]

    expected = 0.6 * rgb_f(0.5) + 0.4 * rgb_f(0.75)
    np.testing.assert_allclose(got, expected, rtol=1e-4, atol=2e-6 * expected.max())
    pdf = np.array(bsdf.pdf(ctx, si, vec(mi, wo)))
    # pdf = Σ w f_ref cos θ_o / Σ w A_ref over the two levels (weights 0.6, 0.4).
    lo, hi = appearance(SandSample(saturation=0.5)), appearance(SandSample(saturation=0.75))
    f_cos = 0.6 * reference_pdf(lo, wi, wo) * lo.albedo(wi).mean(axis=1)
    f_cos += 0.4 * reference_pdf(hi, wi, wo) * hi.albedo(wi).mean(axis=1)
    expected_pdf = f_cos / (0.6 * lo.albedo(wi).mean(axis=1) + 0.4 * hi.albedo(wi).mean(axis=1))
    np.testing.assert_allclose(pdf, expected_pdf, rtol=1e-4, atol=1e-6)
    params = mi.traverse(bsdf)
    assert any(k.startswith("saturation.") for k in params.keys())  # noqa: SIM118 (the texture's own parameters)
    assert "saturation" not in params  # textured: not a plain float


@pytest.mark.parametrize("name", ["dry", "wet"])
@pytest.mark.parametrize("theta_deg", [0.0, 70.0])
def test_pdf_integrates_to_one(rgb, name, theta_deg):
    mi = rgb
    bsdf = mi.load_dict(SANDS[name][0])
    # Midpoint rule in (θ, φ), 1800 × 180 cells: 0.05° in θ resolves the cap (θ < 2.7°).
    theta = (np.arange(1800) + 0.5) * (np.pi / 2 / 1800)
    phi = (np.arange(180) + 0.5) * (2 * np.pi / 180)
    T, P = (x.ravel() for x in np.meshgrid(theta, phi, indexing="ij"))
    wo = np.stack([np.sin(T) * np.cos(P), np.sin(T) * np.sin(P), np.cos(T)], axis=1)
    th = np.radians(theta_deg)
    wi = np.tile([np.sin(th), 0.0, np.cos(th)], (wo.shape[0], 1))
    pdf = np.array(bsdf.pdf(mi.BSDFContext(), interaction(mi, wi), vec(mi, wo)))
    total = np.sum(pdf * np.sin(T)) * (np.pi / 2 / 1800) * (2 * np.pi / 180)
    assert abs(total - 1.0) < 2e-3, total


@pytest.mark.parametrize(
    ("params", "name"),
    [
        ({"saturation": 1.5}, "saturation"),
        ({"preset": "no-such-sand"}, "preset"),
        ({"colour": 0.3}, "colour"),
        ({"combination": "sum"}, "combination"),
        ({"shape": "wavelength"}, "shape"),
        ({"levels": 8}, "levels"),
        ({"sample_file": "/nonexistent/sand.toml"}, "sample_file"),
        ({"preset": "wet-beach", "sample_file": "/nonexistent/sand.toml"}, "sample_file"),
        ({"iron_oxide_form": "dust"}, "iron_oxide_form"),
    ],
)
def test_bad_parameters_are_refused_by_name(rgb, params, name):
    mi = rgb
    with pytest.raises(RuntimeError, match=rf'\[sand\] parameter "?{name}"?'):
        mi.load_dict({"type": "sand", **params})


def test_bad_texture_parameters_are_refused_by_name(rgb):
    mi = rgb

    def tex():
        return {"type": "bitmap", "data": mi.TensorXf(np.full((2, 2, 1), 0.5, dtype=np.float32)), "raw": True}

    with pytest.raises(RuntimeError, match=r'\[sand\] parameter "?porosity"?'):
        mi.load_dict({"type": "sand", "saturation": tex(), "porosity": tex()})
    with pytest.raises(RuntimeError, match=r'\[sand\] parameter "?iron_oxide_form"?'):
        mi.load_dict({"type": "sand", "iron_oxide_form": tex()})
    with pytest.raises(RuntimeError, match=r'\[sand\] parameter "?levels"?'):
        mi.load_dict({"type": "sand", "saturation": tex(), "levels": 1})


def test_scalar_variants_are_refused(load_variant):
    from sandlight.errors import ParameterError

    with pytest.raises(ParameterError, match="variant"):
        load_variant("scalar_rgb")


def test_traverse_exposes_the_sample_and_rebuilds_on_change(rgb):
    mi = rgb
    bsdf = mi.load_dict({"type": "sand"})
    params = mi.traverse(bsdf)
    assert "saturation" in params and "iron_oxide" in params
    rng = np.random.default_rng(8)
    wi, wo = directions(rng, 200), directions(rng, 200)
    ctx = mi.BSDFContext()
    params["saturation"] = 1.0
    params.update()
    changed = np.array(bsdf.eval(ctx, interaction(mi, wi), vec(mi, wo)))
    fresh = np.array(mi.load_dict({"type": "sand", "saturation": 1.0}).eval(ctx, interaction(mi, wi), vec(mi, wo)))
    np.testing.assert_array_equal(changed, fresh)
    params["saturation"] = 1.5
    with pytest.raises(ValueError, match=r'\[sand\] parameter "?saturation"?'):
        params.update()


def test_tables_hold_every_shape_and_refuse_a_blend_that_needs_the_fallback():
    blended = appearance("red-dune")
    n_shapes = len(blended.shapes.shapes)
    assert n_shapes > 1
    tables = PluginTables.build([blended])
    assert tables.shapes == n_shapes and tables.grid.size == n_shapes * blended.band_grid.grid.size
    # Shapes whose product would reflect more than arrives between two anchors: refused by name.
    first = blended.shapes.shapes[0]
    bright = dataclasses.replace(first.band_grid, albedo_nodes=first.band_grid.albedo_nodes * 1e3)
    shapes = (dataclasses.replace(first, band_grid=bright), *blended.shapes.shapes[1:])
    blended.shapes = dataclasses.replace(blended.shapes, shapes=shapes)
    with pytest.raises(ParameterError, match="appearances"):
        PluginTables.build([blended])


def test_fixed_shape_is_the_appearances_too(spectral):
    mi = spectral
    bsdf = mi.load_dict({"type": "sand", "preset": "red-dune", "shape": "fixed"})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        app = SandAppearance("red-dune", shape="fixed")
    rng = np.random.default_rng(4)
    wi, wo = directions(rng, 500), directions(rng, 500)
    lam = np.array([420.0, 510.5, 640.0, 690.0])
    value = np.array(bsdf.eval(mi.BSDFContext(), interaction(mi, wi, lam), vec(mi, wo))).T
    expected = app.brdf(wi, wo, lam) * wo[:, 2:3]
    np.testing.assert_allclose(value, expected, rtol=2e-5, atol=2e-6 * expected.max())
    blended = np.array(
        mi.load_dict({"type": "sand", "preset": "red-dune"}).eval(
            mi.BSDFContext(), interaction(mi, wi, lam), vec(mi, wo)
        )
    ).T
    assert np.abs(blended - value).max() > 0.01 * value.max()  # the shapes do differ
