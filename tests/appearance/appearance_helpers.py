"""Directions and quadratures shared by the appearance tests."""

import math

import numpy as np
import pytest

from sandlight.spatial.model import default_model_path

#: Hemisphere of the synthetic spatial model of conftest.py.
STACKS, SLICES = 7, 8

#: Tests of the shipped spatial model (skipped before it is trained).
shipped = pytest.mark.skipif(not default_model_path().is_file(), reason="shipped spatial model not trained yet")


def directions(n, seed, *, min_z=0.0):
    rng = np.random.default_rng(seed)
    d = rng.normal(size=(n, 3))
    d[:, 2] = np.abs(d[:, 2]) + min_z
    return d / np.linalg.norm(d, axis=1, keepdims=True)


def from_angles(theta_deg, phi_deg=0.0):
    t, p = np.radians(theta_deg), np.radians(phi_deg)
    return np.stack(np.broadcast_arrays(np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)), axis=-1)


def hemisphere_quadrature(n_mu=400, n_phi=200):
    """Midpoint rule over the hemisphere in (μ, φ): directions (M, 3) and weights dω (M,)."""
    mu = (np.arange(n_mu) + 0.5) / n_mu
    phi = (np.arange(n_phi) + 0.5) / n_phi * 2 * math.pi
    M, P = np.meshgrid(mu, phi, indexing="ij")
    s = np.sqrt(1 - M**2)
    d = np.stack([s * np.cos(P), s * np.sin(P), M], axis=-1).reshape(-1, 3)
    return d, np.full(d.shape[0], (1 / n_mu) * (2 * math.pi / n_phi))
