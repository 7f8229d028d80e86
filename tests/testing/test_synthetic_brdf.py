"""Synthetic goniophotometer counts: escape probabilities of known BRDFs and multinomial runs."""

import math

import numpy as np
import pytest

from sandlight.errors import ParameterError
from sandlight.gonio import CollectorHemisphere
from sandlight.testing import synthetic_brdf

H = CollectorHemisphere(7, 6)


def test_lambertian_probabilities_reflect_the_albedo_from_every_patch():
    p = synthetic_brdf.lambertian_probabilities(H, 0.4)
    np.testing.assert_allclose(p.sum(axis=1), 0.4, rtol=1e-12)  # Σ_j ω_p(j) = π
    np.testing.assert_allclose(synthetic_brdf.expected_brdf(H, p), 0.4 / math.pi, rtol=1e-12)


def test_band_quadrature_reproduces_the_exact_lambertian_probabilities():
    p = synthetic_brdf.band_probabilities(H, lambda mu_o, mu_i: np.full(np.broadcast(mu_o, mu_i).shape, 0.4 / math.pi))
    np.testing.assert_allclose(p, synthetic_brdf.lambertian_probabilities(H, 0.4), rtol=1e-12)


def test_conservative_half_space_reflects_everything():
    # ω = 1: the isotropic half-space absorbs nothing, so every trial escapes.
    p = synthetic_brdf.chandrasekhar_probabilities(H, 1.0)
    np.testing.assert_allclose(p.sum(axis=1), 1.0, atol=2e-5)


def test_sample_counts_account_for_every_trial_and_are_seeded():
    p = synthetic_brdf.lambertian_probabilities(H, 0.5)
    c = synthetic_brdf.sample_counts(H, p, 100_000, seed=1, lost_probability=0.1)
    np.testing.assert_array_equal(c["counts"].sum(axis=1) + c["absorbed"] + c["lost"], c["launched"])
    assert c["launched"].sum() == 100_000
    assert c["lost"].sum() / 100_000 == pytest.approx(0.1, abs=0.005)
    again = synthetic_brdf.sample_counts(H, p, 100_000, seed=1, lost_probability=0.1)
    assert all(np.array_equal(c[k], again[k]) for k in c)


def test_bad_arguments_are_refused():
    p = synthetic_brdf.lambertian_probabilities(H, 0.5)
    with pytest.raises(ParameterError, match="albedo"):
        synthetic_brdf.lambertian_probabilities(H, 1.5)
    with pytest.raises(ParameterError, match="omega"):
        synthetic_brdf.chandrasekhar_probabilities(H, 0.0)
    with pytest.raises(ParameterError, match="probabilities"):
        synthetic_brdf.sample_counts(H, 3 * p, 10)  # rows sum to 1.5
    with pytest.raises(ParameterError, match="rays"):
        synthetic_brdf.sample_counts(H, p, 0)
