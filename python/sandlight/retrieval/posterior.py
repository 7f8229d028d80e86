"""The posterior of the free parameters: a Laplace approximation (default) or emcee samples.

Public objects
--------------
LaplacePosterior
    The Gaussian approximation at the optimum: covariance Σ = (Jᵀ C⁻¹ J)⁻¹ (J the Jacobian of
    the model values; the Gauss–Newton Hessian of −log L), truncated to the bounds (the prior
    is uniform over the parameter domain). A central interval at level q is the interval
    between the (1 ∓ q)/2 quantiles of that truncated normal. When the measurement σ was
    estimated from the residuals, the half-widths use Student's t with n − p − 1 degrees of
    freedom instead of the normal (σ is uncertain too): the standard deviation is scaled by
    t_ν((1 + q)/2) / z((1 + q)/2) before truncation.
SampledPosterior, sample_posterior
    Markov chain Monte Carlo with emcee's affine-invariant ensemble sampler (Goodman & Weare
    2010; Foreman-Mackey et al. 2013) over the bounded parameters, uniform prior; with an
    unknown σ, ln σ is sampled too (Jeffreys prior 1/σ). Intervals are sample quantiles.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
from scipy import stats

from sandlight.retrieval.forward import ForwardModel
from sandlight.retrieval.likelihood import SIGMA_RANGE, GaussianLikelihood
from sandlight.retrieval.space import ParameterSpace

__all__ = ["LaplacePosterior", "SampledPosterior", "sample_posterior", "CONVERGED_AUTOCORRELATIONS"]

#: A chain is taken as converged when it is this many integrated autocorrelation times long
#: (the rule of thumb of emcee's documentation).
CONVERGED_AUTOCORRELATIONS = 50


def _correlation(cov: np.ndarray) -> np.ndarray:
    sd = np.sqrt(np.diag(cov))
    with np.errstate(invalid="ignore", divide="ignore"):
        return cov / np.outer(sd, sd)


@dataclass(frozen=True)
class LaplacePosterior:
    x: np.ndarray
    covariance: np.ndarray
    low: np.ndarray
    high: np.ndarray
    dof: int | None = None  # Student-t degrees of freedom when σ was estimated
    kind: str = "laplace"

    @classmethod
    def at(cls, x: np.ndarray, jacobian: np.ndarray, space: ParameterSpace, dof: int | None) -> LaplacePosterior:
        fisher = jacobian.T @ jacobian
        cov = np.linalg.pinv(fisher, rcond=1e-12, hermitian=True)
        # A parameter the spectrum does not move at the optimum carries no information there:
        # pinv would give it zero variance (a zero-width interval); it gets an infinite one.
        blind = ~np.any(jacobian != 0, axis=0)
        cov[blind, :] = cov[:, blind] = 0.0
        cov[blind, blind] = np.inf
        return cls(np.asarray(x, float), cov, space.low, space.high, dof)

    @property
    def sd(self) -> np.ndarray:
        return np.sqrt(np.clip(np.diag(self.covariance), 0, None))

    @property
    def correlation(self) -> np.ndarray:
        return _correlation(self.covariance)

    def interval(self, i: int, level: float) -> tuple[float, float]:
        p = (1 + level) / 2
        sd = self.sd[i]
        if self.dof is not None:
            sd = sd * stats.t.ppf(p, self.dof) / stats.norm.ppf(p)
        lo, hi, x = self.low[i], self.high[i], self.x[i]
        if not np.isfinite(sd) or sd <= 0:  # no information at the optimum: the whole range
            return (float(lo), float(hi))
        dist = stats.truncnorm((lo - x) / sd, (hi - x) / sd, loc=x, scale=sd)
        return (float(dist.ppf((1 - level) / 2)), float(dist.ppf(p)))


@dataclass(frozen=True)
class SampledPosterior:
    samples: np.ndarray  # (n_samples, p) physical units
    acceptance: float
    autocorrelation_steps: float
    steps: int  # steps per walker after burn-in
    kind: str = "emcee"

    @property
    def converged(self) -> bool:
        """emcee's rule of thumb: the kept chain is longer than 50 autocorrelation times."""
        return bool(self.steps > CONVERGED_AUTOCORRELATIONS * self.autocorrelation_steps)

    @property
    def x(self) -> np.ndarray:
        return np.median(self.samples, axis=0)

    @property
    def sd(self) -> np.ndarray:
        return self.samples.std(axis=0, ddof=1)

    @property
    def covariance(self) -> np.ndarray:
        return np.atleast_2d(np.cov(self.samples, rowvar=False))

    @property
    def correlation(self) -> np.ndarray:
        return _correlation(self.covariance)

    def interval(self, i: int, level: float) -> tuple[float, float]:
        lo, hi = np.quantile(self.samples[:, i], [(1 - level) / 2, (1 + level) / 2])
        return (float(lo), float(hi))


def sample_posterior(
    forward: ForwardModel,
    space: ParameterSpace,
    likelihood: GaussianLikelihood,
    start: LaplacePosterior,
    sigma: float | None,
    *,
    walkers: int | None = None,
    steps: int = 3000,
    burn: int = 1000,
    seed: int = 0,
) -> SampledPosterior:
    """emcee samples of the posterior, started in a small ball around the optimum."""
    import emcee

    obs = likelihood.obs
    y, a = obs.values, obs.operator
    p = space.size
    estimate_sigma = not likelihood.known
    ndim = p + int(estimate_sigma)
    walkers = walkers or max(16, 4 * ndim)
    width = space.high - space.low
    lo_s, hi_s = np.log(SIGMA_RANGE[0]), np.log(SIGMA_RANGE[1])

    def log_prob(theta: np.ndarray) -> np.ndarray:
        u = theta[:, :p]
        out = np.full(theta.shape[0], -np.inf)
        ok = np.all((u >= 0) & (u <= 1), axis=1)
        if estimate_sigma:
            ok &= (theta[:, p] > lo_s) & (theta[:, p] < hi_s)
        if not ok.any():
            return out
        model = forward.predict(space.from_unit(u[ok])) @ a.T
        r = y - model
        # Jeffreys prior 1/σ is uniform in ln σ: no extra term.
        out[ok] = -likelihood.nll(r, np.exp(theta[ok, p]) if estimate_sigma else None)
        return out

    rng = np.random.default_rng(seed)
    u0 = space.to_unit(start.x)
    spread = np.clip(start.sd / width, 1e-4, 0.1)
    init = np.clip(u0 + 0.1 * spread * rng.standard_normal((walkers, p)), 1e-6, 1 - 1e-6)
    if estimate_sigma:
        init = np.column_stack([init, np.log(sigma) + 0.01 * rng.standard_normal(walkers)])
    sampler = emcee.EnsembleSampler(walkers, ndim, log_prob, vectorize=True)
    sampler.random_state = np.random.RandomState(seed).get_state()  # emcee's own generator, seeded
    sampler.run_mcmc(init, steps, progress=False)
    chain = sampler.get_chain(discard=burn, flat=True)
    # emcee logs a warning when the chain is short for its autocorrelation time; the time is
    # kept instead (SampledPosterior.converged) and reported by FitResult.summary.
    emcee_log = logging.getLogger("emcee")
    level = emcee_log.level
    emcee_log.setLevel(logging.ERROR)
    try:
        tau = float(np.max(sampler.get_autocorr_time(discard=burn, quiet=True)))
    finally:
        emcee_log.setLevel(level)
    return SampledPosterior(
        space.from_unit(chain[:, :p]), float(np.mean(sampler.acceptance_fraction)), tau, steps - burn
    )
