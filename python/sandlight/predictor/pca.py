"""Principal component analysis of noisy Monte Carlo results, shared by the predictors.

The spectral (paper §3.1.1) and spatial (§3.2.2) predictors both decompose centred training data
by SVD and keep the fewest components whose cumulative variance share reaches a threshold. Their
data carry Monte Carlo noise, which spreads over every direction; with standard errors known, the
share is taken of the *signal* variance (noise variance subtracted), so that noise does not
inflate the number of components. How much noise lies along each direction is the predictor's
own model (`SpectralModel`: u·diag(⟨σ²⟩)u per direction; `SpatialModel`: an even floor).

Public functions
----------------
principal_directions
    Variance along each principal direction, and the directions, of centred data.
variance_ratio, signal_variance_ratio
    Shares of the variance, without or with the noise subtracted.
n_components_for
    The fewest components whose cumulative share reaches a threshold.
"""

from __future__ import annotations

import numpy as np

__all__ = ["principal_directions", "variance_ratio", "signal_variance_ratio", "n_components_for"]


def principal_directions(centred: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Principal directions of centred data by SVD: centred = U S Vᵀ.

    Parameters
    ----------
    centred : ndarray (n, m)
        One centred observation per row.

    Returns
    -------
    variance : ndarray (min(n, m),)
        Variance along each direction, S²/(n − 1) (unbiased, like a noise estimate it is
        compared with), decreasing.
    directions : ndarray (min(n, m), m)
        The principal directions Vᵀ (orthonormal rows).
    """
    _, s, vt = np.linalg.svd(centred, full_matrices=False)
    return s**2 / max(centred.shape[0] - 1, 1), vt


def variance_ratio(variance: np.ndarray) -> np.ndarray:
    """Share of the total variance along each direction; [1, 0, …] when there is none (the mean
    describes everything)."""
    total = variance.sum()
    return variance / total if total > 0 else np.r_[1.0, np.zeros(len(variance) - 1)]


def signal_variance_ratio(variance: np.ndarray, noise_variance: np.ndarray | float) -> np.ndarray:
    """Share of the noise-free variance along each direction: the noise variance along it is
    subtracted (clamped at 0) before the shares are taken; [1, 0, …] when all is noise."""
    return variance_ratio(np.maximum(variance - noise_variance, 0.0))


def n_components_for(ratio: np.ndarray, threshold: float, limit: int) -> int:
    """The fewest leading components whose cumulative ``ratio`` reaches ``threshold`` (less a
    relative 10⁻¹² against round-off in the sum), at most ``limit``."""
    return min(int(np.searchsorted(np.cumsum(ratio), threshold * (1 - 1e-12))) + 1, limit)
