"""Mitsuba's own χ² test of the plugin's sampler against its pdf (`mitsuba.chi2`)."""

from __future__ import annotations

import math

import pytest

pytestmark = pytest.mark.filterwarnings("ignore::sandlight.spatial.model.SpatialApproximationWarning")

SANDS = {
    "dry": {"type": "sand"},
    "wet": {"type": "sand", "saturation": 1.0},
    "red-dune": {"type": "sand", "preset": "red-dune"},
}


@pytest.mark.parametrize("incidence_deg", [0.0, 45.0, 80.0])
@pytest.mark.parametrize("name", sorted(SANDS))
def test_chi2(rgb, name, incidence_deg, tmp_path, monkeypatch):
    mi = rgb
    monkeypatch.chdir(tmp_path)  # a rejected test writes chi2_data.py into the working folder
    from mitsuba.chi2 import BSDFAdapter, ChiSquareTest, SphericalDomain

    th = math.radians(incidence_deg)
    sample, pdf = BSDFAdapter("sand", SANDS[name], wi=mi.Vector3f(math.sin(th), 0.0, math.cos(th)))
    # Integration points per histogram cell and axis: the pdf is a step function on the sampler's
    # cells; at normal incidence the cap's cell (the mirror peak of wet sand, 9 % of the
    # probability within cos θ > 0.9989) lies inside the first histogram row (width 0.0198 in
    # cos θ), so the trapezoid rule needs sub-intervals narrower than the cap (48: 4e-4).
    ires = 48 if incidence_deg == 0.0 else 16
    test = ChiSquareTest(
        domain=SphericalDomain(), sample_func=sample, pdf_func=pdf, sample_dim=3, sample_count=200_000, ires=ires
    )
    passed = test.run()
    print(f"chi2 {name} at {incidence_deg:g} deg: p = {test.p_value:.3f}")
    assert passed, test.messages
