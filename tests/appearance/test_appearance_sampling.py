"""Sampling the appearance's BRDF: chi-square against the pdf, weights, normalisation, symmetry."""

import math

import numpy as np
import pytest
from appearance_helpers import SLICES, STACKS, directions, from_angles, hemisphere_quadrature

from sandlight.appearance import DEFENSIVE_COSINE_SHARE
from sandlight.testing.chi2 import SIGNIFICANCE, hemisphere_chi2


def cell_edges(app, split=2):
    """Bin edges aligned with the sampler's cells for an incident azimuth of 0."""
    h = app.spatial.hemisphere
    first = np.concatenate([[0], 1 + SLICES * np.arange(STACKS - 1)])
    z = np.unique(np.concatenate([h.bounds[first, 0], [1.0]]))
    mu = np.unique(np.concatenate([np.linspace(a, b, split + 1) for a, b in zip(z[:-1], z[1:])]))
    step = 2 * math.pi / SLICES
    b = np.concatenate([[0.0], step * (np.arange(SLICES) + 0.5), [2 * math.pi]])
    phi = np.unique(np.concatenate([np.linspace(a, c, split + 1) for a, c in zip(b[:-1], b[1:])]))
    return mu, phi


@pytest.mark.parametrize("theta", [0.0, 37.0, 75.0, 88.0])
@pytest.mark.parametrize("method", ["brdf", "cosine"])
def test_sampler_follows_its_pdf_chi_square(app, theta, method):
    n = 200_000
    rng = np.random.default_rng(int(theta * 10) + (method == "brdf"))
    wi = np.broadcast_to(from_angles(theta), (n, 3))
    wo, weight, pdf = app.sample(wi, rng.random(n), rng.random(n), 550.0, method=method)
    mu_edges, phi_edges = cell_edges(app)
    result = hemisphere_chi2(
        wo, lambda d: app.pdf(np.broadcast_to(wi[0], d.shape), d, method=method), mu_edges=mu_edges, phi_edges=phi_edges
    )
    assert result.pdf_integral == pytest.approx(1.0, abs=1e-3)
    assert result.passed(SIGNIFICANCE), result


def test_chi_square_detects_a_wrong_pdf(app):
    n = 200_000
    rng = np.random.default_rng(11)
    wi = np.broadcast_to(from_angles(75.0), (n, 3))
    wo, _, _ = app.sample(wi, rng.random(n), rng.random(n), method="cosine")
    mu_edges, phi_edges = cell_edges(app)
    result = hemisphere_chi2(
        wo, lambda d: app.pdf(np.broadcast_to(wi[0], d.shape), d, method="brdf"), mu_edges=mu_edges, phi_edges=phi_edges
    )
    assert result.p_value < 1e-6


@pytest.mark.parametrize("method", ["brdf", "cosine"])
def test_weight_is_f_cos_over_pdf(app, method):
    n = 2000
    rng = np.random.default_rng(12)
    wi = directions(n, 13)
    wo, weight, pdf = app.sample(wi, rng.random(n), rng.random(n), [450.0, 650.0], method=method)
    assert weight.shape == (n, 2) and (wo[:, 2] > 0).all()
    np.testing.assert_allclose(np.linalg.norm(wo, axis=1), 1.0, rtol=1e-12)
    np.testing.assert_allclose(pdf, app.pdf(wi, wo, method=method), rtol=1e-12)
    expected = app.brdf(wi, wo, [450.0, 650.0]) * wo[:, 2:3] / pdf[:, None]
    np.testing.assert_allclose(weight, expected, rtol=1e-12)
    _, scalar, _ = app.sample(wi, rng.random(n), rng.random(n), 550.0, method=method)
    assert scalar.shape == (n,)


@pytest.mark.parametrize("theta", [20.0, 85.0])
def test_sampled_weights_estimate_the_albedo(app, theta):
    n = 400_000
    rng = np.random.default_rng(14)
    wi = np.broadcast_to(from_angles(theta, 50.0), (n, 3))
    exact = app.albedo(wi[0], [550.0])[0, 0]
    spread = {}
    for method in ("brdf", "cosine"):
        _, w, _ = app.sample(wi, rng.random(n), rng.random(n), 550.0, method=method)
        se = w.std() / math.sqrt(n)
        assert abs(w.mean() - exact) < 4 * se
        spread[method] = w.std()
    if theta > 80:  # at grazing incidence the tabulated sampler beats cosine sampling
        assert spread["brdf"] < spread["cosine"]


@pytest.mark.parametrize("method", ["brdf", "cosine"])
def test_pdf_is_normalised(app, method):
    d, w = hemisphere_quadrature(600, 320)
    for theta in (0.0, 45.0, 89.0):
        wi = np.broadcast_to(from_angles(theta, 10.0), d.shape)
        assert (app.pdf(wi, d, method=method) * w).sum() == pytest.approx(1.0, abs=2e-3)


def test_defensive_share_bounds_the_weight(app):
    n = 20000
    rng = np.random.default_rng(15)
    wi = directions(n, 16)
    wo, weight, _ = app.sample(wi, rng.random(n), rng.random(n), 700.0)
    f = app.brdf(wi, wo, [700.0])[:, 0]
    assert (weight <= math.pi * f / DEFENSIVE_COSINE_SHARE * (1 + 1e-12)).all()


def test_sampling_commutes_with_rotation_about_the_normal(app):
    n = 1000
    rng = np.random.default_rng(17)
    u1, u2 = rng.random(n), rng.random(n)
    wi = directions(n, 18)
    angle = 0.7
    rot = np.array([[math.cos(angle), -math.sin(angle), 0], [math.sin(angle), math.cos(angle), 0], [0, 0, 1]])
    wo, w, p = app.sample(wi, u1, u2, 550.0)
    wo_r, w_r, p_r = app.sample(wi @ rot.T, u1, u2, 550.0)
    np.testing.assert_allclose(wo_r, wo @ rot.T, atol=1e-10)
    np.testing.assert_allclose(p_r, p, rtol=1e-9)
