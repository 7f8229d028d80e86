"""Tests of sandlight.checks: each check returns the value it accepts and refuses the rest with a
ParameterError naming the parameter, the value and what is allowed, in one style."""

import math

import numpy as np
import pytest

from sandlight import checks
from sandlight.errors import ParameterError


def refused(check, *args, **kwargs) -> ParameterError:
    with pytest.raises(ParameterError) as info:
        check(*args, **kwargs)
    return info.value


def test_interval_text_writes_every_kind_of_interval_one_way():
    assert checks.interval_text() == ""
    assert checks.interval_text(0.0, 24.0) == " in [0, 24]"
    assert checks.interval_text(0.0, 90.0, high_open=True) == " in [0, 90)"
    assert checks.interval_text(0.0, 1.0, True, True) == " in (0, 1)"
    assert checks.interval_text(1) == " ≥ 1" and checks.interval_text(0.0, low_open=True) == " > 0"
    assert checks.interval_text(None, 5.0) == " ≤ 5"
    # Integer bounds in full: a seed's upper bound must not read 1.84467e+19.
    assert checks.interval_text(0, 2**64 - 1) == f" in [0, {2**64 - 1}]"


def test_message_names_the_parameter_the_value_and_what_is_allowed():
    e = refused(checks.check_count, "rays", 0)
    assert (e.name, e.value, e.allowed) == ("rays", 0, "a whole number ≥ 1 (e.g. 1e6)")
    assert str(e) == "rays = 0 is not allowed: a whole number ≥ 1 (e.g. 1e6)"


def test_real_array_and_real():
    np.testing.assert_array_equal(checks.check_real_array("x", [1, 2.5], 0.0, 3.0), [1.0, 2.5])
    assert checks.check_real("x", 2, 0.0, 3.0) == 2.0 and isinstance(checks.check_real("x", 2), float)
    assert refused(checks.check_real_array, "x", [1.0, 4.0, 5.0], 0.0, 3.0).value == 4.0  # the first offender
    assert refused(checks.check_real_array, "x", "one").allowed == "a real number"
    assert refused(checks.check_real_array, "x", [math.nan]).allowed == "a finite real number"
    assert refused(checks.check_real_array, "x", []).allowed.startswith("at least one")
    assert refused(checks.check_real, "x", 0.0, 0.0, low_open=True).allowed == "a finite real number > 0"
    assert refused(checks.check_real, "x", [1.0, 2.0]).allowed == "a single real number, not an array"


def test_unit_vectors_are_normalised_and_checked():
    np.testing.assert_allclose(
        checks.check_unit_vectors("d", [[0.0, 0.0, 2.0], [3.0, 4.0, 0.0]]), [[0, 0, 1], [0.6, 0.8, 0]]
    )
    assert "(..., 3)" in refused(checks.check_unit_vectors, "d", [1.0, 2.0]).allowed
    assert refused(checks.check_unit_vectors, "d", [0.0, 0.0, 0.0]).allowed == "non-zero direction vectors"
    assert refused(checks.check_unit_vectors, "d", [0.0, math.inf, 1.0]).allowed == "finite direction vectors"


def test_whole_numbers_and_counts():
    assert checks.check_whole_number("n", np.int64(5), 1, 10) == 5
    for bad in (True, 2.0, "3", 0, 11):
        assert refused(checks.check_whole_number, "n", bad, 1, 10).allowed == "a whole number in [1, 10]"
    pixels = refused(checks.check_whole_number, "width", 0, 1, 100, noun="a whole number of pixels")
    assert pixels.allowed == "a whole number of pixels in [1, 100]"
    assert refused(checks.check_whole_number, "frame", -1, 0).allowed == "a whole number ≥ 0"
    assert checks.check_count("rays", 1e6) == 1_000_000 and checks.check_count("--rays", "2e3") == 2000
    for bad in (0, 1.5, "many", True, math.inf, -3):
        refused(checks.check_count, "rays", bad)


def test_engine_arguments():
    assert checks.check_seed("seed", 2**64 - 1) == 2**64 - 1
    for bad in (-1, 2**64, 1.0, True):
        assert refused(checks.check_seed, "seed", bad).allowed == "an integer in [0, 2**64)"
    assert checks.check_threads("threads", None) is None and checks.check_threads("threads", 4) == 4
    refused(checks.check_threads, "threads", 0)
    assert checks.check_choice("memory", "cut", ("none", "cut")) == "cut"
    assert refused(checks.check_choice, "memory", "long", ("none", "cut")).allowed == "one of 'none', 'cut'"
    refused(checks.check_choice, "memory", None, ("none",))
    np.testing.assert_array_equal(checks.check_wavelengths("wavelengths_nm", 550), [550.0])
    assert refused(checks.check_wavelengths, "wavelengths_nm", [500.0, 3000.0]).value == 3000.0
    assert refused(checks.check_wavelengths, "wavelengths_nm", [[500.0]]).allowed.startswith("a non-empty 1-D")
    assert checks.check_incidence("incidence_deg", "45") == 45.0
    for bad in (90.0, -1.0, math.nan, "steep"):
        assert refused(checks.check_incidence, "incidence_deg", bad).allowed == "a number in [0, 90) degrees"


def test_parse_range_on_and_off_the_grid():
    np.testing.assert_allclose(checks.parse_range("-w", "400:700:100"), [400, 500, 600, 700])
    np.testing.assert_allclose(checks.parse_range("-w", "400:750:100"), [400, 500, 600, 700])
    np.testing.assert_allclose(checks.parse_range("-w", "450, 550"), [450, 550])
    for bad in ("700:400:10", "400:700:0", "400:700", "red"):
        assert refused(checks.parse_range, "-w", bad).name == "-w"


def test_table_reads_checked_values_and_refuses_unknown_keys():
    t = checks.Table({"fov_deg": 40, "n": 3, "sky": {"turbidity": 3.0}, "mode": "mis"}, "camera", "scene.toml")
    assert t.number("fov_deg", None, 0.0, 170.0, lo_open=True, hi_open=True) == 40.0
    assert t.integer("n", 1, 1, 10) == 3 and t.choice("mode", ("mis", "brdf")) == "mis"
    assert t.table("sky").number("turbidity", 2.0) == 3.0
    np.testing.assert_array_equal(t.vector("up", 3, default=[0.0, 0.0, 1.0]), [0.0, 0.0, 1.0])
    t.finish()
    e = refused(checks.Table({"fov": 40}, "camera", "scene.toml").finish)
    assert e.name == "camera.fov" and "unknown key 'fov'" in e.allowed and e.allowed.endswith("(in scene.toml)")
    e = refused(
        checks.Table({"fov_deg": 200}, "camera").number, "fov_deg", None, 0.0, 170.0, lo_open=True, hi_open=True
    )
    assert (e.name, e.value, e.allowed) == ("camera.fov_deg", 200, "a number in (0, 170)")
    assert refused(checks.Table({}, "camera").number, "fov_deg").value == "missing"


def test_allocation_within_the_limit_passes_and_beyond_it_is_refused_with_both_figures():
    from sandlight.checks import MAX_ALLOCATION_BYTES, check_allocation

    check_allocation("size", 10, MAX_ALLOCATION_BYTES)
    with pytest.raises(ParameterError, match=r"size = 10 is not allowed: needs about 3 GiB .* limit of 2 GiB"):
        check_allocation("size", 10, 3 << 30)
    with pytest.raises(ParameterError, match="limit of 0.5 GiB"):
        check_allocation("size", 10, 1 << 30, limit_bytes=1 << 29)


def test_names_admit_distinct_known_names_only():
    names = checks.Names(("iron_oxide", "grain_size"))
    assert names.admits(()) and names.admits(["grain_size"]) and names.admits(("iron_oxide", "grain_size"))
    assert not names.admits(("iron_oxide", "iron_oxide"))  # repeated
    assert not names.admits(("colour",)) and not names.admits("iron_oxide") and not names.admits(None)
    assert "iron_oxide" in str(names)
