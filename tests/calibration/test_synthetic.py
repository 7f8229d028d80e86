"""The round trip of issue 17 §1 (a) with the real engine, at reduced size: spectra from the
engine at a known k(λ) plus noise are fitted back within their error where k is identifiable."""

import numpy as np
import pytest

from sandlight import calibration as cal

WL = np.array([650.0, 700.0, 800.0, 870.0, 1000.0, 1500.0, 2200.0])
GRID = np.arange(-4.5, -1.49, 0.25)
SIGMA = 0.005


@pytest.fixture(scope="module")
def case():
    members = cal.end_members("hematite", ids=["GDS27", "GDS69.f", "GDS69.g"])
    tables = [cal.tabulate(m, cal.EnginePowder(rays=2000, seed=0), WL, GRID) for m in members]
    truth = cal.edge_and_band_log10_k(WL, floor=-3.3, edge_nm=550.0)
    values, sigma = cal.synthetic_spectra(cal.EnginePowder(rays=2000, seed=1), members, WL, truth, sigma=SIGMA, seed=2)
    return tables, truth, values, sigma


def test_engine_round_trip_recovers_k_within_its_error(case):
    tables, truth, values, sigma = case
    fit = cal.KFit().fit(tables, values, sigma)
    ident = cal.identifiability(tables, fit.log10_k_, sigma)
    # Fine hematite grains are translucent beyond the edge: k is identified at every wavelength.
    assert ident.identifiable.all()
    lo, hi = ident.interval_log10_k
    inside = (truth >= lo) & (truth <= hi)  # the two-standard-error interval (95 %)
    assert inside.sum() >= WL.size - 1
    assert np.all(np.abs(fit.log10_k_ - truth) <= 0.75 * (hi - lo))  # three standard errors
    assert np.max(np.abs(fit.log10_k_ - truth)) < 0.1
    assert max(fit.rms_.values()) < 0.02


def test_synthetic_spectra_carry_their_monte_carlo_error(case):
    tables, truth, values, sigma = case
    assert values.shape == sigma.shape == (3, WL.size)
    assert np.all(sigma > SIGMA)  # the noise added ⊕ the engine's own error
    # The band at 870 nm darkens the spectra of every end-member.
    i = list(WL).index(870.0)
    assert np.all(values[:, i] < values[:, i - 2]) and np.all(values[:, i] < values[:, i + 1])
