"""The chi-square harness: accepts exact samplers, rejects wrong densities."""

import math

import numpy as np
import pytest

from sandlight.errors import ParameterError
from sandlight.testing.chi2 import SIGNIFICANCE, hemisphere_chi2


def cosine_samples(n, seed):
    rng = np.random.default_rng(seed)
    u1, u2 = rng.random(n), rng.random(n)
    r, phi = np.sqrt(u1), 2 * math.pi * u2
    return np.stack([r * np.cos(phi), r * np.sin(phi), np.sqrt(1 - u1)], axis=1)


def cosine_pdf(d):
    return np.clip(d[:, 2], 0, None) / math.pi


def uniform_pdf(d):
    return np.full(d.shape[0], 1 / (2 * math.pi))


def test_exact_sampler_passes():
    results = [hemisphere_chi2(cosine_samples(50_000, seed), cosine_pdf) for seed in range(5)]
    assert all(r.passed(SIGNIFICANCE) for r in results)
    assert results[0].pdf_integral == pytest.approx(1.0, abs=1e-4)
    assert results[0].dof == results[0].n_bins - 1


def test_wrong_density_fails():
    result = hemisphere_chi2(cosine_samples(50_000, 1), uniform_pdf)
    assert result.p_value < 1e-10
    # A slightly wrong density (a 3 % tilt in azimuth) is also caught with enough samples.
    tilted = lambda d: cosine_pdf(d) * (1 + 0.03 * d[:, 0] / np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-300))  # noqa: E731
    assert hemisphere_chi2(cosine_samples(400_000, 2), tilted).p_value < 1e-3


def test_directions_outside_the_hemisphere_fail():
    d = cosine_samples(10_000, 3)
    d[0, 2] = -0.5
    result = hemisphere_chi2(d, cosine_pdf)
    assert result.outside == 1 and result.p_value == 0.0 and not result.passed()


def test_sparse_bins_are_pooled():
    # 500 samples in 20 × 24 bins: most bins expect about 1 count and are pooled.
    result = hemisphere_chi2(cosine_samples(500, 4), cosine_pdf)
    assert result.n_bins < 480 and result.passed()


def test_bad_arguments():
    with pytest.raises(ParameterError, match="directions"):
        hemisphere_chi2(np.zeros((3, 2)), cosine_pdf)
    with pytest.raises(ParameterError, match="mu_edges"):
        hemisphere_chi2(cosine_samples(10, 5), cosine_pdf, mu_edges=[0.5, 0.2])
    with pytest.raises(ParameterError, match="pdf"):
        hemisphere_chi2(cosine_samples(10, 5), lambda d: -cosine_pdf(d))
