"""Which free parameters the data constrain: a flat likelihood gives no interval, only a flag.

Public objects
--------------
NotIdentifiableError
    Raised when an interval is asked of a parameter whose likelihood is flat.
scan_identifiability
    For every free parameter, −2 Δlog L along its whole bounded range with the other parameters
    at the optimum (a conditional scan). If the largest Δχ² = 2 Δ(−log L) stays below the
    χ²₁ quantile of a level q, every value of the parameter is inside the q likelihood region:
    the data do not constrain it at that level. The conditional scan is an upper bound of the
    profile likelihood's Δχ², so a parameter flat here is flat in the profile too.
"""

from __future__ import annotations

import numpy as np
from scipy import stats

from sandlight.errors import SandlightError
from sandlight.retrieval.forward import ForwardModel
from sandlight.retrieval.likelihood import GaussianLikelihood
from sandlight.retrieval.space import ParameterSpace

__all__ = ["NotIdentifiableError", "scan_identifiability", "is_flat"]


class NotIdentifiableError(SandlightError):
    """The data do not constrain a parameter (flat likelihood over its range)."""


def scan_identifiability(
    forward: ForwardModel,
    space: ParameterSpace,
    likelihood: GaussianLikelihood,
    x: np.ndarray,
    sigma: float | None,
    points: int = 21,
) -> np.ndarray:
    """Largest Δχ² along each free parameter's range (others at ``x``), shape (p,)."""
    a, y = likelihood.obs.operator, likelihood.obs.values
    best = float(likelihood.nll(y - forward.predict(x[None, :])[0] @ a.T, sigma))
    out = np.empty(space.size)
    for i in range(space.size):
        grid = np.tile(x, (points, 1))
        grid[:, i] = np.linspace(space.low[i], space.high[i], points)
        nll = likelihood.nll(y - forward.predict(grid) @ a.T, sigma)
        out[i] = 2 * (float(np.max(nll)) - best)
    return out


def is_flat(max_delta_chi2: float, level: float) -> bool:
    """True when the whole range lies inside the likelihood region of ``level``."""
    return bool(max_delta_chi2 < stats.chi2.ppf(level, df=1))
