"""The posterior: emcee against the Laplace approximation; Student-t when σ is estimated."""

import numpy as np
import pytest

import sandlight

FREE = ["iron_oxide", "hematite_ratio"]


@pytest.fixture(scope="module")
def noisy_dry(dry_spectrum, add_noise):
    return add_noise(dry_spectrum, 0.004, 3)


def test_emcee_and_laplace_agree_for_a_well_constrained_fit(noisy_dry):
    laplace = sandlight.fit(noisy_dry, FREE, {"saturation": 0.0}, noise=0.004, check_rays=0)
    mcmc = sandlight.fit(noisy_dry, FREE, {"saturation": 0.0}, noise=0.004, posterior="emcee", check_rays=0)
    assert mcmc.posterior.kind == "emcee" and mcmc.posterior.converged
    for i, name in enumerate(FREE):
        lo_l, hi_l = laplace.interval(name)
        lo_m, hi_m = mcmc.interval(name)
        width = hi_l - lo_l
        # the posterior is nearly Gaussian here: intervals agree to a fifth of their width
        assert abs(lo_m - lo_l) < 0.2 * width and abs(hi_m - hi_l) < 0.2 * width
        assert mcmc.posterior.sd[i] == pytest.approx(laplace.posterior.sd[i], rel=0.2)
    np.testing.assert_allclose(mcmc.correlation.values, laplace.correlation.values, atol=0.1)


def test_an_estimated_noise_widens_the_interval_by_students_t(noisy_dry):
    known = sandlight.fit(noisy_dry, FREE, {"saturation": 0.0}, noise=0.004, check_rays=0)
    estimated = sandlight.fit(noisy_dry, FREE, {"saturation": 0.0}, check_rays=0)
    assert estimated.posterior.dof == estimated.observation.size - 3
    assert known.posterior.dof is None
    # with σ fixed at the estimate, the t interval is wider than the normal one
    assert estimated.posterior.sd[0] > 0
    lo, hi = estimated.interval("iron_oxide")
    normal = type(estimated.posterior)(
        estimated.posterior.x, estimated.posterior.covariance, estimated.space.low, estimated.space.high, None
    )
    lo_n, hi_n = normal.interval(0, 0.95)
    assert hi - lo > 1.05 * (hi_n - lo_n)


def test_a_parameter_the_spectrum_does_not_move_gets_its_whole_range():
    """A zero Jacobian column (no information at the optimum) must not give a zero-width
    interval, which would claim certainty; its interval is the whole range."""
    from sandlight.retrieval.posterior import LaplacePosterior
    from sandlight.retrieval.space import ParameterSpace

    space = ParameterSpace.build(["iron_oxide", "grain_size"], {}, None)
    jacobian = np.array([[300.0, 0.0], [100.0, 0.0], [-200.0, 0.0]])  # whitened, per unit of each
    post = LaplacePosterior.at(np.array([0.01, 0.3]), jacobian, space, None)
    assert post.interval(1, 0.95) == (space.low[1], space.high[1])
    lo, hi = post.interval(0, 0.95)
    assert lo < 0.01 < hi and hi - lo < 0.5 * (space.high[0] - space.low[0])  # the informed one stays narrow
