"""The Gaussian likelihood of a fit, with every error source in its covariance.

Public objects
--------------
ErrorBudget
    The error sources besides the measurement noise: the forward model's error (for the
    predictor bank, the answering model's hold-out RMS error per wavelength) and the Monte
    Carlo noise of an engine forward model (its standard errors).
GaussianLikelihood
    −log L of residuals y − A f(θ) under the covariance
    C = diag(σ²) + A (s sᵀ ∘ K) Aᵀ + A diag(σ_MC²) Aᵀ,
    with σ the measurement noise (given per channel, or one value estimated from the
    residuals), s the model error per forward-model wavelength and K the Gaussian correlation
    K_ij = exp(−(λ_i − λ_j)² / (2 ℓ²)) with ℓ = `MODEL_ERROR_CORRELATION_NM`.

Why a correlated model error: a predictor's error is a smooth function of wavelength (it comes
from a few principal components, docs/spectral-predictor.md), so treating it as independent per
wavelength would count it n times over and give intervals far too narrow. ℓ = 100 nm is an
assumption (the errors of the shipped models change sign a few times over 400–700 nm); the
hold-out RMS includes the hold-out samples' own Monte Carlo noise, so s is an upper bound.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize_scalar

from sandlight.retrieval.observation import Observation

__all__ = ["ErrorBudget", "GaussianLikelihood", "MODEL_ERROR_CORRELATION_NM", "SIGMA_RANGE"]

MODEL_ERROR_CORRELATION_NM = 100.0
#: Range in which an unknown measurement noise is estimated (reflectance standard deviation).
SIGMA_RANGE = (1e-5, 0.5)


@dataclass(frozen=True)
class ErrorBudget:
    """Model error s (n_grid,) and Monte Carlo standard errors (n_grid,) of a forward model."""

    model_rms: np.ndarray
    mc_stderr: np.ndarray
    correlation_nm: float = MODEL_ERROR_CORRELATION_NM

    def covariance(self, obs: Observation) -> np.ndarray:
        """A (s sᵀ ∘ K + diag σ_MC²) Aᵀ: the covariance the forward model adds, channel space."""
        g = obs.grid
        k = np.exp(-((g[:, None] - g[None, :]) ** 2) / (2 * self.correlation_nm**2))
        inner = np.outer(self.model_rms, self.model_rms) * k + np.diag(self.mc_stderr**2)
        return obs.operator @ inner @ obs.operator.T


class GaussianLikelihood:
    """−log L(r) = ½ rᵀ C⁻¹ r + ½ log det C + n/2 log 2π for residuals r (see the module).

    With the measurement noise known C is fixed (one Cholesky factor); with one unknown σ the
    forward model's covariance M = Q Λ Qᵀ is diagonalised once, so that C(σ) = Q (σ² + Λ) Qᵀ.
    """

    def __init__(self, obs: Observation, budget: ErrorBudget):
        self.obs = obs
        self.model_cov = budget.covariance(obs)
        self.known = obs.sigma is not None
        if self.known:
            c = self.model_cov + np.diag(obs.sigma**2)
            self._chol = np.linalg.cholesky(c)
            self._logdet = 2 * np.log(np.diag(self._chol)).sum()
        else:
            lam, q = np.linalg.eigh(self.model_cov)
            self._lam, self._q = np.clip(lam, 0, None), q

    def whiten(self, r: np.ndarray, sigma: float | None = None) -> np.ndarray:
        """C^(−½) r for residuals r (..., n): whitened residuals (sum of squares rᵀ C⁻¹ r)."""
        r = np.asarray(r, dtype=float)
        if self.known:
            from scipy.linalg import solve_triangular

            return solve_triangular(self._chol, r.T, lower=True).T
        return (r @ self._q) / np.sqrt(sigma**2 + self._lam)

    def logdet(self, sigma: float | None = None) -> float:
        return float(self._logdet) if self.known else float(np.log(sigma**2 + self._lam).sum())

    def nll(self, r: np.ndarray, sigma: float | None = None) -> np.ndarray:
        """−log L of residuals r (..., n)."""
        w = self.whiten(r, sigma)
        n = self.obs.size
        return 0.5 * (w**2).sum(axis=-1) + 0.5 * self.logdet(sigma) + 0.5 * n * np.log(2 * np.pi)

    def best_sigma(self, r: np.ndarray) -> float:
        """The maximum-likelihood measurement σ for fixed residuals r (n,), in `SIGMA_RANGE`."""
        lo, hi = np.log(SIGMA_RANGE[0]), np.log(SIGMA_RANGE[1])
        found = minimize_scalar(lambda t: float(self.nll(r, np.exp(t))), bounds=(lo, hi), method="bounded")
        return float(np.exp(found.x))
