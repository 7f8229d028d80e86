"""The Monte Carlo check of a predictor fit: the engine at the optimum, next to the predictor.

Public objects
--------------
EngineCheck, check_with_engine
    The engine's spectrum at the best sample (fresh seed, ``rays`` rays per wavelength), the
    surrogate's error there in channel space (predictor − engine), its RMS, and the Monte Carlo
    standard error of that difference. ``consistent`` says whether the error is within what
    the fit assumed: RMS error ≤ `CONSISTENT_RATIO` · √(s̄² + σ̄_MC²), s̄ the RMS hold-out error of
    the answering model and σ̄_MC the RMS Monte Carlo standard error of the check.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from sandlight.retrieval.forward import ForwardModel
from sandlight.retrieval.observation import Observation

__all__ = ["EngineCheck", "check_with_engine", "CONSISTENT_RATIO"]

#: Largest ratio of the check's RMS error to the error the fit assumed that still counts as
#: consistent. The RMS of 16 correlated channels scatters by some 30 % around its expectation
#: (a few independent components), so 1.5 flags a predictor clearly worse than its hold-out
#: error without flagging every fit.
CONSISTENT_RATIO = 1.5


@dataclass(frozen=True)
class EngineCheck:
    rays: int
    seed: int
    engine: np.ndarray  # channel space
    stderr: np.ndarray
    surrogate: np.ndarray
    assumed_rms: float

    @property
    def error(self) -> np.ndarray:
        return self.surrogate - self.engine

    @property
    def rms_error(self) -> float:
        return float(np.sqrt(np.mean(self.error**2)))

    @property
    def consistent(self) -> bool:
        return self.rms_error <= CONSISTENT_RATIO * float(np.sqrt(self.assumed_rms**2 + np.mean(self.stderr**2)))

    def summary(self) -> str:
        return (
            f"engine check ({self.rays} rays): predictor − engine RMS {self.rms_error:.4f} "
            f"(Monte Carlo standard error {np.sqrt(np.mean(self.stderr**2)):.4f}; the fit assumed "
            f"{self.assumed_rms:.4f}): {'consistent' if self.consistent else 'LARGER than assumed'}"
        )


def check_with_engine(
    forward: ForwardModel,
    obs: Observation,
    x: np.ndarray,
    surrogate: np.ndarray,
    assumed_rms: float,
    *,
    rays: int,
    seed: int,
) -> EngineCheck:
    """Run the engine (an EngineForward over the fit's space) at ``x`` and compare with the
    ``surrogate`` values (channel space); ``assumed_rms`` is the model error the fit assumed."""
    result = forward.run(x, rays=rays, seed=seed)
    a = obs.operator
    # Standard errors mapped to channels as if independent between wavelengths.
    stderr = np.sqrt((a**2) @ result.stderr**2)
    return EngineCheck(rays, seed, a @ result.values, stderr, np.asarray(surrogate, float), float(assumed_rms))
