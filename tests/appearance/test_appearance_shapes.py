"""The BRDF's shape over wavelength (`sandlight.appearance.shapes`): the shape at the sand's own
reflectance for a model that interpolates in log r₀, one shape otherwise."""

import numpy as np
import pytest
from appearance_helpers import directions, from_angles

from sandlight.appearance import SandAppearance
from sandlight.errors import ParameterError
from sandlight.sample import SandSample
from sandlight.spatial.shipped import model_for

WL = np.arange(400.0, 701.0, 20.0)


def spectrum(low, high):
    """A callable spectral source rising log-uniformly from ``low`` to ``high`` over 400–700 nm."""
    r = np.exp(np.linspace(np.log(low), np.log(high), WL.size))
    return lambda sample: (WL, r)


def flat(r):
    return lambda sample: (WL, np.full(WL.size, r))


@pytest.fixture(scope="module")
def dune():
    model = model_for(SandSample.preset("yellow-dune"))
    assert model.absorbers  # the family that interpolates in log r₀
    return model


def relative_rms(f, g):
    return float(np.sqrt(np.mean((f - g) ** 2)) / np.sqrt(np.mean(g**2)))


@pytest.mark.parametrize("combination", ["energy", "product"])
def test_each_wavelength_takes_the_shape_at_its_own_reflectance(dune, combination):
    rising = SandAppearance("yellow-dune", spectrum(0.04, 0.65), dune, combination=combination)
    fixed = SandAppearance("yellow-dune", spectrum(0.04, 0.65), dune, combination=combination, shape="fixed")
    assert len(rising.shapes.shapes) > 2 and len(fixed.shapes.shapes) == 1
    wi, wo = directions(4000, 1, min_z=0.05), directions(4000, 2, min_z=0.05)
    for j in range(WL.size):
        r = rising.normal_reflectance[j]
        # A sand whose reflectance is r at every wavelength has the shape at r at every wavelength;
        # between anchors the blend departs from it by at most ~0.7 % (ANCHOR_TOLERANCE).
        own = SandAppearance("yellow-dune", flat(r), dune, combination=combination, shape="fixed")
        f = rising.brdf(wi, wo, [WL[j]])[:, 0]
        assert relative_rms(f, own.brdf(wi, wo, [WL[j]])[:, 0]) < 0.01
        if abs(np.log(r / fixed.reference_reflectance)) > 1.0:  # far from the 550 nm reflectance
            assert relative_rms(fixed.brdf(wi, wo, [WL[j]])[:, 0], f) > 0.05


@pytest.mark.parametrize("low, high", [(0.01, 0.98), (0.05, 0.4)])
def test_blended_shapes_conserve_energy(dune, low, high):
    app = SandAppearance("yellow-dune", spectrum(low, high), dune)
    np.testing.assert_allclose(app.albedo([0, 0, 1])[0], app.normal_reflectance, atol=1e-12)
    albedo = app.albedo(from_angles(np.linspace(0, 90, 181)))
    assert (albedo >= 0).all() and (albedo <= 1 + 1e-12).all()


def test_blend_is_linear_in_log_reflectance_and_held_beyond_the_anchors(dune):
    shapes = SandAppearance("yellow-dune", spectrum(0.04, 0.65), dune).shapes
    r = shapes.reflectances
    assert (np.diff(r) > 0).all()
    np.testing.assert_array_equal(shapes.blend(r), np.eye(r.size))
    mid = np.sqrt(r[:-1] * r[1:])  # half-way in log r
    w = shapes.blend(mid)
    np.testing.assert_allclose(w.sum(axis=1), 1.0, rtol=1e-14)
    np.testing.assert_allclose(w[np.arange(mid.size), np.arange(mid.size)], 0.5, rtol=1e-12)
    np.testing.assert_array_equal(shapes.blend([r[0] / 2, r[-1] * 1.2]), np.eye(r.size)[[0, -1]])


def test_a_model_without_absorbers_has_one_shape(spatial):
    a = SandAppearance(SandSample(saturation=0.3), spectrum(0.05, 0.6), spatial)
    b = SandAppearance(SandSample(saturation=0.3), spectrum(0.05, 0.6), spatial, shape="fixed")
    assert len(a.shapes.shapes) == 1
    wi, wo = directions(300, 3), directions(300, 4)
    np.testing.assert_array_equal(a.brdf(wi, wo), b.brdf(wi, wo))


def test_unknown_shape_is_refused(spatial):
    with pytest.raises(ParameterError, match="shape"):
        SandAppearance(SandSample(), spectrum(0.05, 0.6), spatial, shape="per-wavelength")


def test_the_stacked_evaluator_is_the_weighted_sum_of_its_shapes(dune):
    from sandlight import _native

    app = SandAppearance("yellow-dune", spectrum(0.02, 0.9), dune)
    wi, wo = directions(2000, 5), directions(2000, 6)
    wi[0, 2], wo[1] = -0.1, [np.nan, 0, 1]  # one pair below the horizon, one NaN
    a, b = app.shapes.weights(app.normal_reflectance)
    want = np.zeros((wi.shape[0], WL.size))
    for k, s in enumerate(app.shapes.shapes):
        one = _native.BandGridBrdf(s.band_grid.grid, s.band_grid.nodes, s.combination.profile)
        want += one.evaluate(wi, wo, np.ascontiguousarray(a[:, k]), np.ascontiguousarray(b[:, k]))
    got = app.brdf(wi, wo)
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-15)
    assert (got[0] == 0).all() and np.isnan(got[1]).all()
    # a single wavelength evaluates only the (at most two) shapes it blends, with the same result
    np.testing.assert_allclose(app.brdf(wi, wo, [WL[3]])[:, 0], got[:, 3], rtol=1e-12)


def test_reference_brdf_is_the_mean_of_the_weights(dune):
    app = SandAppearance("yellow-dune", spectrum(0.03, 0.7), dune)
    wi, wo = directions(500, 7), directions(500, 8)
    # f is linear in the weights, so f at their mean is the mean over wavelengths of f.
    np.testing.assert_allclose(app.reference_brdf(wi, wo), app.brdf(wi, wo).mean(axis=1), rtol=1e-10)
    wo[0, 2] = -0.2
    assert app.reference_brdf(wi, wo)[0] == 0.0


def test_the_table_of_blended_shapes_conserves_their_albedo(dune):
    # The table's values are hat averages of the blended BRDF, per wavelength: integrating its
    # multilinear interpolant gives the table's albedo, which is the model's (r at normal incidence).
    app = SandAppearance("yellow-dune", spectrum(0.03, 0.7), dune)
    ds = app.table(n_mu=17, n_dphi=33, wavelengths_nm=[400.0, 560.0, 700.0])
    assert ds.attrs["shape"] == "reflectance"
    f, mu, dphi = ds["f"].values, ds["mu_o"].values, ds["dphi"].values
    np.testing.assert_array_equal(f, f.transpose(0, 2, 1, 3))
    h = mu[1] - mu[0]
    hat_mu = np.array(
        [
            (h * (mu[q - 1] + 2 * mu[q]) / 6 if q > 0 else 0)
            + (h * (2 * mu[q] + mu[q + 1]) / 6 if q < mu.size - 1 else 0)
            for q in range(mu.size)
        ]
    )
    integral = (2 * np.trapezoid(f, dphi, axis=3)) @ hat_mu
    np.testing.assert_allclose(integral, ds["albedo"].values, rtol=5e-3)
    # The last node's albedo averages the model's over μ in [15/16, 1], where it rises from r.
    np.testing.assert_allclose(ds["albedo"].values[:, -1], app.reflectance_at([400.0, 560.0, 700.0]), rtol=0.03)
