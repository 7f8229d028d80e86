"""sandlight.calibration.end_members: the inventory of pure powders and their measurements."""

import numpy as np
import pytest
from conftest import needs_shared

from sandlight import calibration as cal
from sandlight.errors import ParameterError

# Issue 17 §1 lists these end-members by name.
ISSUE_17 = {
    "hematite": {"GDS27", "GDS69.a", "GDS69.b", "GDS69.c", "GDS69.d", "GDS69.e", "GDS69.f", "GDS69.g"},
    "goethite": {"WS222-coarse", "WS222-medium", "GDS134", "MPCMA2-B", "WS220", "HS36.3"},
    "quartz": {"HS32.4B", "GDS31", "GDS74"},
}


def test_inventory_holds_every_end_member_issue_17_names():
    for mineral, ids in ISSUE_17.items():
        assert ids <= {m.id for m in cal.end_members(mineral)}
    assert cal.end_members("kaolinite")


def test_gds69_sizes_are_the_sieve_limits_of_the_description():
    sizes = {m.id: m.size_um for m in cal.end_members("hematite")}
    assert sizes["GDS69.a"] == (150.0, 250.0)
    assert sizes["GDS69.d"] == (30.0, 45.0)
    assert sizes["GDS69.f"] == (10.0, 20.0)
    # "< 10 µm": the documented default lower limit d_max/5.
    assert sizes["GDS69.g"] == (2.0, 10.0)


def test_every_record_is_consistent():
    for m in cal.end_members():
        assert 0 < m.size_um[0] < m.size_um[1]
        assert m.use_in_fit or m.excluded_because
        assert m.spectrum.endswith("_AREF")


def test_mixtures_and_coatings_are_not_fitted():
    fitted = {m.id for m in cal.end_members("goethite", fit_only=True)}
    assert "WS220" not in fitted  # 60 vol% quartz
    assert "MPCMA2-B" not in fitted  # a coating on rock
    assert {"WS222-medium", "GDS134"} <= fitted


def test_selection_by_ids_keeps_the_order_and_refuses_unknown_ids():
    picked = cal.end_members("hematite", ids=["GDS69.g", "GDS27"])
    assert [m.id for m in picked] == ["GDS69.g", "GDS27"]
    with pytest.raises(ParameterError, match="ids"):
        cal.end_members("hematite", ids=["GDS69.z"])


def test_unknown_mineral_is_refused_with_the_allowed_names():
    with pytest.raises(ParameterError, match="mineral.*hematite"):
        cal.end_members("magnetite")


@needs_shared
def test_measured_reflectance_of_every_end_member():
    wl = np.array([450.0, 550.0, 1500.0, 2400.0])
    for m in cal.end_members():
        values, sigma = cal.measured_reflectance(m, wl)
        assert values.shape == sigma.shape == wl.shape
        assert np.all((values > 0) & (values < 1)), m.id
        assert np.all(sigma == cal.MEASUREMENT_SIGMA)
    # The grain-size series gets brighter in the near-infrared as the grains get finer.
    series = cal.end_members("hematite", ids=[f"GDS69.{c}" for c in "aceg"])
    at_1500 = [cal.measured_reflectance(m, [1500.0])[0][0] for m in series]
    assert np.all(np.diff(at_1500) > 0)
