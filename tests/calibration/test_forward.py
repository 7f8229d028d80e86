"""sandlight.calibration.forward: the engine's powder with a trial k (real engine, few rays)."""

import numpy as np
import pytest

from sandlight import calibration as cal
from sandlight.errors import ParameterError
from sandlight.validation import powder_reflectance

WL = [700.0, 1500.0]


@pytest.fixture(scope="module")
def fine():
    return cal.end_members("hematite", ids=["GDS69.g"])[0]


def test_more_absorption_gives_a_darker_powder(fine):
    forward = cal.EnginePowder(rays=1000)
    rho = [forward.reflectance(fine, WL, k)[0] for k in (1e-5, 1e-3, 1e-1)]
    assert np.all(rho[0] > rho[1]) and np.all(rho[1] > rho[2])
    # Opaque 2-10 µm hematite grains reflect only at their surfaces: a few per cent.
    assert np.all(rho[2] < 0.1)


def test_trial_k_is_the_mineral_k_at_every_wavelength(fine):
    # With k fixed, only n(λ) and 1/λ (α = 4πk/λ) still vary: at the same k the powder is darker
    # at the shorter wavelength, which absorbs more per unit path.
    values, stderr = cal.EnginePowder(rays=2000).reflectance(fine, WL, 1e-3)
    assert values[0] < values[1]
    assert np.all(stderr > 0) and np.all(stderr < 0.02)


def test_the_shipped_constants_are_untouched_afterwards(fine):
    before = powder_reflectance("hematite", fine.size_um, WL, rays=300, seed=5).values
    cal.EnginePowder(rays=300).reflectance(fine, WL, 1e-2)
    after = powder_reflectance("hematite", fine.size_um, WL, rays=300, seed=5).values
    np.testing.assert_array_equal(before, after)


def test_common_random_numbers_and_independent_end_members(fine):
    forward = cal.EnginePowder(rays=300)
    np.testing.assert_array_equal(forward.reflectance(fine, WL, 1e-3)[0], forward.reflectance(fine, WL, 1e-3)[0])
    coarse = cal.end_members("hematite", ids=["GDS69.a"])[0]
    assert forward.member_seed(fine) != forward.member_seed(coarse)
    assert forward.settings(fine, WL) != cal.EnginePowder(rays=301).settings(fine, WL)


@pytest.mark.parametrize("k", [0.0, -1e-3, np.nan, np.inf])
def test_bad_k_is_refused(fine, k):
    with pytest.raises(ParameterError, match="k"):
        cal.EnginePowder(rays=10).reflectance(fine, WL, k)
