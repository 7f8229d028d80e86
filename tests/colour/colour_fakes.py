"""Test helpers of the colour tests: a stand-in sample, a fake provider, spectra and data.

The fake provider is NOT physics: it maps a few parameters to a smooth spectrum so that the
colour pipeline (batching, grid order, modes, images) can be tested without a spectral model.
Physical trends are tested only against the real default provider (fixture ``real_provider``).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

REPO_ROOT = Path(__file__).resolve().parents[2]
# The shared reference material sits beside the repository (<repo>/../shared); a git worktree
# elsewhere can point at it with SANDLIGHT_SHARED.
SHARED = Path(os.environ.get("SANDLIGHT_SHARED", REPO_ROOT.parent / "shared"))
USGS_CSV = SHARED / "data" / "measured" / "usgs_splib07a" / "csv"


class FakeSample:
    """Duck-typed stand-in for ``SandSample``: a dict of parameters with ``replace``."""

    DEFAULTS = {"iron_oxide": 0.01, "hematite_ratio": 0.5, "saturation": 0.0}

    def __init__(self, **params):
        self.params = {**self.DEFAULTS, **params}

    def replace(self, **changes):
        return FakeSample(**{**self.params, **changes})

    def __repr__(self):
        return f"FakeSample({self.params})"


class FakeProvider:
    """A logistic 'absorption edge' spectrum driven by plain parameter dicts; counts calls."""

    def __init__(self):
        self.calls = 0

    def __call__(self, samples, wavelengths_nm):
        self.calls += 1
        wl = np.asarray(wavelengths_nm, dtype=float)
        rows = []
        for s in samples:
            p = s.params if isinstance(s, FakeSample) else dict(s)
            edge_nm = 500.0 + 100.0 * p["hematite_ratio"]
            low = 0.4 - 6.0 * p["iron_oxide"]
            high = 0.6 - 0.3 * p["saturation"]
            rows.append(low + (high - low) / (1.0 + np.exp(-(wl - edge_nm) / 25.0)))
        return np.array(rows)


def logistic_spectrum(wavelengths_nm, edge_nm=560.0, width_nm=30.0, low=0.08, high=0.5):
    """A smooth sand-like reflectance: dark in the blue, bright in the red."""
    wl = np.asarray(wavelengths_nm, dtype=float)
    return low + (high - low) / (1.0 + np.exp(-(wl - edge_nm) / width_nm))


def read_usgs(stem: str) -> tuple[np.ndarray, np.ndarray]:
    """(wavelength_nm, reflectance) of a USGS splib07a CSV, deleted channels dropped."""
    path = USGS_CSV / f"{stem}.csv"
    if not path.is_file():
        pytest.skip(f"shared measured data not found at {path}")
    data = np.genfromtxt(path, delimiter=",", skip_header=2)
    data = data[np.isfinite(data[:, 1])]
    return data[:, 0], data[:, 1]
