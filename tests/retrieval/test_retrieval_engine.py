"""The engine as forward model (common random numbers) and the engine check of a bank fit."""

import numpy as np
import pytest

import sandlight
from sandlight.retrieval.forward import EngineForward
from sandlight.retrieval.space import ParameterSpace

RAYS = 2000


def test_common_random_numbers_make_the_engine_repeatable_and_smooth():
    space = ParameterSpace.build(["iron_oxide"], {"saturation": 0.0})
    forward = EngineForward(space, [450.0, 600.0], rays=RAYS, seed=5, threads=1)
    x = np.array([[0.010], [0.010], [0.0101]])
    a, b, c = forward.predict(x)
    np.testing.assert_array_equal(a, b)
    # a 1 % step in iron oxide changes the spectrum by far less than the Monte Carlo error
    assert np.all(np.abs(c - a) < 0.5 * forward.stderr)


def test_engine_fit_recovers_an_engine_spectrum(dry_truth):
    wl = np.arange(400.0, 701.0, 50.0)
    measured = sandlight.reflectance(dry_truth, wl, rays=RAYS, seed=5, share=False, progress=False, threads=1)
    result = sandlight.fit(
        (wl, measured.values),
        ["iron_oxide"],
        {"saturation": 0.0, "hematite_ratio": dry_truth.hematite_ratio},
        method="engine",
        rays=RAYS,
        seed=5,
        wavelengths=wl,
        noise=0.003,
        threads=1,
    )
    assert result.method == "engine" and "Monte Carlo engine" in result.model
    # the same seed as the measurement: the truth reproduces the data exactly
    assert result.estimate["iron_oxide"] == pytest.approx(dry_truth.iron_oxide, rel=0.02)
    lo, hi = result.interval("iron_oxide")
    assert lo < dry_truth.iron_oxide < hi


def test_engine_check_reports_the_surrogate_error(dry_spectrum, dry_truth):
    result = sandlight.fit(
        dry_spectrum, ["iron_oxide", "hematite_ratio"], {"saturation": 0.0}, noise=0.002, check_rays=RAYS, threads=1
    )
    check = result.engine_check
    assert check.rays == RAYS
    engine = sandlight.reflectance(
        result.sample, result.observation.centres_nm, rays=RAYS, seed=check.seed, share=False, progress=False, threads=1
    )
    np.testing.assert_allclose(check.engine, engine.values)
    np.testing.assert_allclose(check.error, result.optimum.model - engine.values)
    assert "engine check" in result.summary()
