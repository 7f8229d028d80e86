"""The Gaussian likelihood of a fit, with every error source in its covariance.

Public objects
--------------
ErrorBudget
    The error sources besides the measurement noise: the forward model's error (for the
    predictor bank, the answering model's hold-out RMS error per wavelength) and the Monte
    Carlo noise of an engine forward model (its standard errors).
GaussianLikelihood
    −log L of residuals y − A f(θ) under the covariance
    C = diag(σ²) + A ((s sᵀ + σ_MC σ_MCᵀ) ∘ K) Aᵀ,
    with σ the measurement noise (given per channel, or one value estimated from the
    residuals), s the model error per forward-model wavelength and K the Gaussian correlation
    K_ij = exp(−(λ_i − λ_j)² / (2 ℓ²)) with ℓ = `MODEL_ERROR_CORRELATION_NM`.

Why a correlated model error: a predictor's error is a smooth function of wavelength (it comes
from a few principal components, docs/spectral-predictor.md), so treating it as independent per
wavelength would count it n times over and give intervals far too narrow. ℓ = 100 nm is an
assumption (the errors of the shipped models change sign a few times over 400–700 nm); the
hold-out RMS includes the hold-out samples' own Monte Carlo noise, so s is an upper bound.
The engine's Monte Carlo error is correlated the same way: with one seed for every wavelength
and every parameter vector (common random numbers) the noise of a spectrum is one smooth
realisation, not independent per wavelength.
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
    """Model error s (n_grid,) and Monte Carlo standard errors (n_grid,) of a forward model.

    ``mc_covariance`` (n_grid, n_grid), when given, is the Monte Carlo covariance estimated
    from replicate runs (:meth:`sandlight.retrieval.forward.EngineForward.replicate_covariance`)
    and replaces σ_MC σ_MCᵀ ∘ K.
    """

    model_rms: np.ndarray
    mc_stderr: np.ndarray
    correlation_nm: float = MODEL_ERROR_CORRELATION_NM
    mc_covariance: np.ndarray | None = None

    def covariance(self, obs: Observation) -> np.ndarray:
        """A ((s sᵀ + σ_MC σ_MCᵀ) ∘ K) Aᵀ: the covariance the forward model adds, channel space."""
        g = obs.grid
        k = np.exp(-((g[:, None] - g[None, :]) ** 2) / (2 * self.correlation_nm**2))
        mc = np.outer(self.mc_stderr, self.mc_stderr) * k if self.mc_covariance is None else self.mc_covariance
        inner = np.outer(self.model_rms, self.model_rms) * k + mc
        return obs.operator @ inner @ obs.operator.T


class GaussianLikelihood:
    """−log L(r) = ½ rᵀ C⁻¹ r + ½ log det C + n/2 log 2π for residuals r (see the module).

    With the measurement noise known C = L Lᵀ is fixed and L⁻¹ computed once; with one unknown
    σ the forward model's covariance M = Q Λ Qᵀ is diagonalised once, so that
    C(σ) = Q (σ² + Λ) Qᵀ.
    """

    def __init__(self, obs: Observation, budget: ErrorBudget):
        self.obs = obs
        self.model_cov = budget.covariance(obs)
        self.known = obs.sigma is not None
        if self.known:
            c = self.model_cov + np.diag(obs.sigma**2)
            chol = np.linalg.cholesky(c)
            self._logdet = 2 * np.log(np.diag(chol)).sum()
            self._white = np.linalg.inv(chol)  # L⁻¹ (n × n, small): whitening is one product
        else:
            lam, q = np.linalg.eigh(self.model_cov)
            self._lam, self._q = np.clip(lam, 0, None), q

    def whiten(self, r: np.ndarray, sigma: float | np.ndarray | None = None) -> np.ndarray:
        """C^(−½) r for residuals r (..., n): whitened residuals (sum of squares rᵀ C⁻¹ r)."""
        r = np.asarray(r, dtype=float)
        if self.known:
            return r @ self._white.T
        return (r @ self._q) / np.sqrt(np.asarray(sigma)[..., None] ** 2 + self._lam)

    def logdet(self, sigma: float | np.ndarray | None = None) -> float | np.ndarray:
        """log det C (one per σ when ``sigma`` is an array)."""
        if self.known:
            return float(self._logdet)
        return np.log(np.asarray(sigma)[..., None] ** 2 + self._lam).sum(axis=-1)

    def nll(self, r: np.ndarray, sigma: float | np.ndarray | None = None) -> np.ndarray:
        """−log L of residuals r (..., n); ``sigma`` one value or one per row of r."""
        w = self.whiten(r, sigma)
        n = self.obs.size
        return 0.5 * (w**2).sum(axis=-1) + 0.5 * self.logdet(sigma) + 0.5 * n * np.log(2 * np.pi)

    def best_sigma(self, r: np.ndarray) -> float:
        """The maximum-likelihood measurement σ for fixed residuals r (n,), in `SIGMA_RANGE`."""
        lo, hi = np.log(SIGMA_RANGE[0]), np.log(SIGMA_RANGE[1])
        found = minimize_scalar(lambda t: float(self.nll(r, np.exp(t))), bounds=(lo, hi), method="bounded")
        return float(np.exp(found.x))
