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
    stopped when σ changes by less than 1 %, or the given tolerance): the joint maximum-likelihood estimate.
"""

from __future__ import annotations

from collections.abc import Callable
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
    tolerance: float = 1e-8,
    sigma0: float | None = None,
    jacobian_step: np.ndarray | None = None,
    seed: int = 0,
) -> Optimum:
    """The maximum-likelihood parameters of ``forward`` over ``space`` (see the module).

    ``diff_step`` is the relative finite-difference step of the Jacobian (scipy's default for a
    smooth predictor; larger for the engine, whose common-random-number objective is smooth only
    above the scale of single rays changing their paths). ``tolerance`` is scipy's ftol, xtol and
    gtol, and the relative change of σ that ends the alternation; ``sigma0`` the first σ tried
    when it is estimated (default `SIGMA_START`). With ``jacobian_step`` the Jacobian returned
    (for the posterior) is not the optimiser's but central differences of these steps in the
    scaled coordinates (one-sided at a bound): the slope over a stretch of the range instead of
    the local one, for an objective that is rough on small scales.
    """
    obs = likelihood.obs
    y, a = obs.values, obs.operator
    width = space.high - space.low
    evaluations = 0
    sigma = None if likelihood.known else (sigma0 or SIGMA_START)

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
            ftol=tolerance,
            xtol=tolerance,
            gtol=tolerance,
        )

    if x0 is not None:
        candidates = space.to_unit(np.clip(x0, space.low, space.high))[None, :]
    else:
        candidates = _starts(space, starts, seed)
    best = min((solve(u, sigma) for u in candidates), key=lambda s: s.cost)
    if sigma is not None:
        for _ in range(_MAX_ALTERNATIONS):
            new = likelihood.best_sigma(y - model_values(best.x))
            done = abs(np.log(new / sigma)) < max(0.01, tolerance)
            sigma = new
            best = solve(best.x, sigma)
            if done:
                break
    jac = (
        best.jac
        if jacobian_step is None
        else _secant_jacobian(lambda u: likelihood.whiten(model_values(u) - y, sigma), best.x, jacobian_step)
    )
    x = space.from_unit(best.x)
    spectrum = forward.predict(x[None, :])[0]
    model = spectrum @ a.T
    residual = y - model
    return Optimum(
        x=x,
        residual=residual,
        model=model,
        spectrum=spectrum,
        jacobian=jac / width,
        sigma=sigma,
        nll=float(likelihood.nll(residual, sigma)),
        evaluations=evaluations,
    )


def _secant_jacobian(fun: Callable[[np.ndarray], np.ndarray], u: np.ndarray, step: np.ndarray) -> np.ndarray:
    """Central differences of ``fun`` at ``u`` with steps ``step`` (one per coordinate) inside
    [0, 1] (one-sided where a step would leave it)."""
    columns = []
    step = np.broadcast_to(step, u.shape)
    for i in range(u.size):
        lo, hi = u.copy(), u.copy()
        lo[i], hi[i] = max(0.0, u[i] - step[i]), min(1.0, u[i] + step[i])
        columns.append((fun(hi) - fun(lo)) / (hi[i] - lo[i]))
    return np.column_stack(columns)
