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


def test_the_path_memory_is_an_option_recorded_only_when_not_classic(fine):
    # The tables cached before the option existed (classic model) keep their settings.
    classic = cal.EnginePowder(rays=300)
    assert "memory" not in classic.settings(fine, WL)
    packed = cal.EnginePowder(rays=300, memory="packed")
    assert packed.settings(fine, WL) == classic.settings(fine, WL) | {"memory": "packed"}
    with pytest.raises(ParameterError, match="memory"):
        cal.EnginePowder(memory="full")


def test_the_packed_memory_lifts_the_opaque_floor_of_a_coarse_powder():
    # Opaque 150-250 µm grains (k = 0.5): the classic model returns only first-surface Fresnel
    # light, ~0.05; the packed memory, which remembers the pore a ray came through, returns more
    # (0.11 at 450 nm, measured 2026-12-06; GDS69.a itself measures 0.07-0.09 in the blue).
    coarse = cal.end_members("hematite", ids=["GDS69.a"])[0]
    (a, sa), (b, sb) = (
        cal.EnginePowder(rays=4000, memory=m).reflectance(coarse, [450.0], 0.5) for m in ("none", "packed")
    )
    assert b[0] - a[0] > 4 * np.hypot(sa[0], sb[0])
