"""Tests of sandlight.validation.scoring: a measured spectrum on the model grid, the band errors
and their Monte Carlo bound, and scoring a run."""

import math

import numpy as np
import pytest
import xarray as xr

from sandlight.errors import ParameterError
from sandlight.validation import scoring


def spectrum(wavelengths, values):
    return xr.DataArray(
        np.asarray(values, dtype=float), dims="wavelength", coords={"wavelength": np.asarray(wavelengths, dtype=float)}
    )


def test_measured_on_grid_averages_window_interpolates_gaps_and_skips_deleted():
    s = spectrum([396, 398, 400, 403, 404, 406, 440, 470, 600], [0.1, 9.0, 0.3, 0.5, np.nan, 0.7, 0.2, 0.5, 0.9])
    got = scoring.measured_on_grid(s, [400.0, 460.0, 540.0, 406.0])
    # 400: channels 396, 398, 400, 403 lie within ±5 nm, 404 is deleted; 396 is 4 nm away.
    assert got[0] == pytest.approx(np.mean([0.1, 9.0, 0.3, 0.5]))
    # 460: no channel within 5 nm; 440 and 470 are 30 nm apart: linear interpolation.
    assert got[1] == pytest.approx(0.2 + (0.5 - 0.2) * 20 / 30)
    # 540: the neighbours 470 and 600 are 130 nm apart (> 50): skipped.
    assert math.isnan(got[2])
    # 406: 403 and 406 lie within the window; the deleted 404 does not count.
    assert got[3] == pytest.approx(np.mean([0.5, 0.7]))


def test_band_error_arithmetic_and_monte_carlo_bound():
    wl = np.array([400.0, 500.0, 600.0, 1000.0])
    meas = np.array([0.2, 0.3, 0.4, 0.5])
    model = meas + np.array([0.1, -0.1, 0.1, 0.3])
    sd = np.array([0.01, 0.01, 0.01, 0.02])
    e = scoring.band_error(wl, model, sd, meas, "vis", 400, 700, target_rms=0.02)
    assert e.points == 3
    assert e.rms == pytest.approx(0.1)
    assert e.bias == pytest.approx(0.1 / 3)
    # Σ|d|σ/(n RMS) with |d| = 0.1 and σ = 0.01 everywhere is σ itself.
    assert e.rms_mc == pytest.approx(0.01)
    assert e.max_abs == pytest.approx(0.1) and e.max_at_nm in (400.0, 500.0, 600.0)
    assert e.verdict == "missed"
    assert scoring.band_error(wl, meas + 0.001, sd / 10, meas, "vis", 400, 700, target_rms=0.02).verdict == "met"
    # Within two error bars (2 × 0.01) of the target: not decided either way.
    assert scoring.band_error(wl, meas + 0.001, sd, meas, "vis", 400, 700, target_rms=0.02).verdict == "undecided"
    assert scoring.band_error(wl, meas + 0.035, sd, meas, "vis", 400, 700, target_rms=0.02).verdict == "undecided"
    with pytest.raises(ParameterError, match="wavelengths_nm"):
        scoring.band_error(wl, model, sd, meas, "none", 2000, 2500)


def test_model_wavelengths_default_to_the_model_grid():
    grid = scoring.model_wavelengths_nm()
    assert grid.size == 67 and grid[0] == 400.0 and grid[-1] == 2500.0
    np.testing.assert_array_equal(np.diff(grid[:31]), 10.0)
    np.testing.assert_array_equal(scoring.model_wavelengths_nm(550), [550.0])


def test_score_takes_the_run_and_scores_every_band():
    from types import SimpleNamespace

    wl = np.array([450.0, 650.0, 1500.0])
    run = SimpleNamespace(
        wavelengths=wl,
        values=np.array([0.3, 0.5, 0.7]),
        stderr=np.full(3, 0.01),
        rays=1000,
        seed=9,
        sample={"grain_size": 0.3},
    )
    meas = spectrum([450.0, 650.0, 1500.0], [0.25, 0.5, 0.8])
    r = scoring.score("a sample", "preset x", run, meas, elapsed_s=2.0)
    assert set(r.errors) == set(scoring.BANDS_NM)
    vis, full = r.errors["400–700 nm"], r.errors["400–2500 nm"]
    assert vis.points == 2 and vis.rms == pytest.approx(math.sqrt(0.05**2 / 2))
    assert full.points == 3 and full.bias == pytest.approx((0.05 + 0.0 - 0.1) / 3)
    assert (r.rays, r.seed, r.elapsed_s, r.sample_values, r.label) == (1000, 9, 2.0, {"grain_size": 0.3}, "preset x")
    assert r.skipped == 0
