"""The best fit: maximum likelihood by bounded non-linear least squares (scipy).

Public objects
--------------
Optimum
    The best parameters, the residuals, the whitened Jacobian there, the measurement noise
    (given or estimated) and −log L.
maximise_likelihood
    Minimise ½ rᵀ C⁻¹ r over the free parameters (``scipy.optimize.least_squares``, trust-region
    reflective, in coordinates scaled to [0, 1] over the bounds), from several starting points.
    With an unknown measurement σ, the parameters and σ are found by alternating the least
    squares at fixed σ with the maximum-likelihood σ at fixed residuals (each step lowers −log L;
    stopped when σ changes by less than 1 %): the joint maximum-likelihood estimate.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares
from scipy.stats import qmc

from sandlight.retrieval.forward import ForwardModel
from sandlight.retrieval.likelihood import GaussianLikelihood
from sandlight.retrieval.space import ParameterSpace

__all__ = ["Optimum", "maximise_likelihood"]

#: Starting value of an unknown measurement σ (reflectance) before it is estimated.
SIGMA_START = 0.01
_MAX_ALTERNATIONS = 20


@dataclass(frozen=True)
class Optimum:
    x: np.ndarray
    residual: np.ndarray  # measured − model, channel space
    model: np.ndarray  # model values in channel space
    spectrum: np.ndarray  # model spectrum on the forward grid
    jacobian: np.ndarray  # whitened, d(C^(-1/2) model)/dx, (n, p), physical units
    sigma: float | None  # the estimated σ (None when given)
    nll: float
    evaluations: int


def _starts(space: ParameterSpace, n: int, seed: int) -> np.ndarray:
    """Starting points in unit coordinates: the centre, then a Latin hypercube."""
    points = [np.full(space.size, 0.5)]
    if n > 1:
        points += list(0.05 + 0.9 * qmc.LatinHypercube(d=space.size, seed=seed).random(n - 1))
    return np.array(points)


def maximise_likelihood(
    forward: ForwardModel,
    space: ParameterSpace,
    likelihood: GaussianLikelihood,
    *,
    starts: int = 4,
    x0: np.ndarray | None = None,
    diff_step: float | None = None,
    seed: int = 0,
) -> Optimum:
    """The maximum-likelihood parameters of ``forward`` over ``space`` (see the module).

    ``diff_step`` is the relative finite-difference step of the Jacobian (scipy's default for a
    smooth predictor; larger for the engine, whose common-random-number objective is smooth only
    above the scale of single rays changing their paths).
    """
    obs = likelihood.obs
    y, a = obs.values, obs.operator
    width = space.high - space.low
    evaluations = 0
    sigma = None if likelihood.known else SIGMA_START

    def model_values(u: np.ndarray) -> np.ndarray:
        nonlocal evaluations
        evaluations += 1
        return forward.predict(space.from_unit(u)[None, :])[0] @ a.T

    def solve(u0: np.ndarray, s: float | None):
        return least_squares(
            lambda u: likelihood.whiten(model_values(u) - y, s),
            u0,
            bounds=(0.0, 1.0),
            method="trf",
            diff_step=diff_step,
            x_scale=1.0,
        )

    if x0 is not None:
        candidates = space.to_unit(np.clip(x0, space.low, space.high))[None, :]
    else:
        candidates = _starts(space, starts, seed)
    best = min((solve(u, sigma) for u in candidates), key=lambda s: s.cost)
    if sigma is not None:
        for _ in range(_MAX_ALTERNATIONS):
            new = likelihood.best_sigma(y - model_values(best.x))
            done = abs(np.log(new / sigma)) < 0.01
            sigma = new
            best = solve(best.x, sigma)
            if done:
                break
    x = space.from_unit(best.x)
    spectrum = forward.predict(x[None, :])[0]
    model = spectrum @ a.T
    residual = y - model
    return Optimum(
        x=x,
        residual=residual,
        model=model,
        spectrum=spectrum,
        jacobian=best.jac / width,
        sigma=sigma,
        nll=float(likelihood.nll(residual, sigma)),
        evaluations=evaluations,
    )
