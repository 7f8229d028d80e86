"""sandlight.calibration.fit: the penalised least-squares fit of log10 k(λ), with a fast fake
forward model (the fit's logic), and its refusal of bad input."""

import numpy as np
import pytest
from calibration_fakes import FakePowder

from sandlight import calibration as cal
from sandlight.errors import ParameterError

WL = np.concatenate([np.arange(350.0, 1000.0, 20.0), np.arange(1000.0, 2501.0, 50.0)])
GRID = np.arange(-6.0, 0.51, 0.25)
SIGMA = 0.005


@pytest.fixture(scope="module")
def members():
    return cal.end_members("hematite", fit_only=True)


@pytest.fixture(scope="module")
def tables(members):
    return [cal.tabulate(m, FakePowder(rays=4000, seed=1), WL, GRID) for m in members]


@pytest.fixture(scope="module")
def truth():
    return cal.edge_and_band_log10_k(WL)


@pytest.fixture(scope="module")
def synthetic(members, truth):
    return cal.synthetic_spectra(FakePowder(rays=4000, seed=2), members, WL, truth, sigma=SIGMA, seed=3)


def test_round_trip_recovers_k_within_its_error_where_identifiable(tables, truth, synthetic):
    values, sigma = synthetic
    fit = cal.KFit().fit(tables, values, sigma)
    ident = cal.identifiability(tables, fit.log10_k_, sigma)
    ok = ident.identifiable
    # The fake's grains are translucent beyond the edge: k is identified there, not in the blue.
    assert ok[WL >= 650].all()
    assert not ok[WL <= 500].any()
    lo, hi = ident.interval_log10_k
    inside = (truth >= lo) & (truth <= hi)
    assert np.mean(inside[ok]) >= 0.85  # the two-standard-error interval: 95 % expected
    assert np.median(np.abs(fit.log10_k_ - truth)[ok]) < 0.02
    # Synthetic data with honest errors: no model error is found, χ² is of the order of its dof.
    assert cal.KFit(model_sigma="auto").fit(tables, values, sigma).model_sigma_ == pytest.approx(0.0, abs=2e-3)
    assert 0.3 < fit.chi2_ / fit.dof_ < 3.0
    # Every residual is of the size of the noise.
    assert max(fit.rms_.values()) < 3 * SIGMA


def test_opaque_wavelengths_are_flagged_not_fitted(tables, truth, synthetic):
    values, sigma = synthetic
    fit = cal.KFit().fit(tables, values, sigma)
    ident = cal.identifiability(tables, fit.log10_k_, sigma)
    blue = np.flatnonzero(WL <= 500)
    assert set(ident.state[:, blue].ravel()) == {"opaque"}
    assert all(ident.verdict(i).startswith("not identifiable") for i in blue)


def test_model_error_is_estimated_from_the_residuals(tables, truth, members):
    # Spectra the model cannot produce: each end-member offset by its own ±0.03 (a wrong surface
    # term, say). The estimated model error is of that size.
    values, sigma = cal.synthetic_spectra(FakePowder(rays=10**9, seed=2), members, WL, truth, sigma=0.0)
    offset = 0.03 * np.where(np.arange(len(members)) % 2, 1.0, -1.0)[:, None]
    fit = cal.KFit(model_sigma="auto").fit(tables, values + offset, np.full(values.shape, SIGMA))
    assert 0.01 < fit.model_sigma_ < 0.04
    assert fit.chi2_ > 10 * fit.dof_


def test_smoothing_straightens_log_k_where_no_data_constrain_it(tables, synthetic):
    values, sigma = synthetic
    rough = cal.KFit(smoothing=0.0).fit(tables, values, sigma)
    smooth = cal.KFit(smoothing=1e4).fit(tables, values, sigma)
    blue = WL <= 500
    assert np.sum(np.diff(smooth.log10_k_[blue], 2) ** 2) < np.sum(np.diff(rough.log10_k_[blue], 2) ** 2)


def test_a_weak_prior_decides_k_only_where_no_data_constrain_it(tables, truth, synthetic):
    values, sigma = synthetic
    plain = cal.KFit().fit(tables, values, sigma)
    ident = cal.identifiability(tables, plain.log10_k_, sigma)
    prior = np.full(WL.size, -0.3)  # k = 0.5 everywhere: right in the opaque blue, far off beyond
    weak = cal.KFit(prior_log10_k=prior).fit(tables, values, sigma)
    ok = ident.identifiable
    # Where the powders see k the 1-decade prior hardly moves the fit (< its own error) ...
    assert np.max(np.abs(weak.log10_k_ - plain.log10_k_)[ok]) < 0.05
    # ... where they are all opaque it draws k to the prior, which the penalty alone does not.
    blue = WL <= 450
    assert np.all(np.abs(weak.log10_k_ - prior)[blue] < np.abs(plain.log10_k_ - prior)[blue])
    assert np.median(np.abs(weak.log10_k_ - prior)[blue]) < 0.1
    # A strong prior wins everywhere.
    strong = cal.KFit(prior_log10_k=prior, prior_sigma_log10_k=1e-4).fit(tables, values, sigma)
    np.testing.assert_allclose(strong.log10_k_, prior, atol=1e-2)


@pytest.mark.parametrize(
    "parameters",
    [{"prior_log10_k": np.zeros(3)}, {"prior_log10_k": np.full(WL.size, np.nan)}, {"prior_sigma_log10_k": 0.0}],
)
def test_bad_priors_are_refused(tables, synthetic, parameters):
    with pytest.raises(ParameterError, match="prior"):
        cal.KFit(**parameters).fit(tables, synthetic[0])


def test_predict_gives_the_fitted_reflectance_and_holdout_predicts_others(tables, synthetic):
    values, sigma = synthetic
    fit = cal.KFit().fit(tables, values, sigma)
    np.testing.assert_allclose(fit.predict(tables), fit.fitted_)
    ids = [t.member_id for t in tables]
    held, rms = cal.holdout(cal.KFit(), tables, values, test_ids=["GDS69.b", "GDS69.d"])
    assert held.member_ids_ == tuple(i for i in ids if i not in ("GDS69.b", "GDS69.d"))
    assert set(rms) == {"GDS69.b", "GDS69.d"}
    # The fake model is right: predictions are as good as the noise of tables and spectra allows.
    noise = np.sqrt(np.mean(sigma**2) + np.mean([t.stderr**2 for t in tables]))
    assert max(rms.values()) < 1.5 * noise


def test_refitting_discards_the_previous_fit(tables, synthetic):
    values, sigma = synthetic
    fit = cal.KFit().fit(tables, values, sigma)
    fit.fit(tables[:2], values[:2], sigma[:2])
    assert fit.member_ids_ == tuple(t.member_id for t in tables[:2])
    assert fit.fitted_.shape == (2, WL.size)


# --- bad input ---


@pytest.mark.parametrize(
    "parameters, name",
    [
        ({"smoothing": -1.0}, "smoothing"),
        ({"smoothing": np.nan}, "smoothing"),
        ({"reference_step_nm": 0.0}, "reference_step_nm"),
        ({"measurement_sigma": 0.0}, "measurement_sigma"),
        ({"model_sigma": "guess"}, "model_sigma"),
        ({"model_sigma": -0.01}, "model_sigma"),
        ({"max_nfev": 0}, "max_nfev"),
    ],
)
def test_bad_parameters_are_refused_at_fit(tables, synthetic, parameters, name):
    with pytest.raises(ParameterError, match=name):
        cal.KFit(**parameters).fit(tables, synthetic[0])


def test_bad_measurements_are_refused(tables, synthetic):
    values = synthetic[0]
    fit = cal.KFit()
    with pytest.raises(ParameterError, match="measured.*shape"):
        fit.fit(tables, values[:, :-1])
    with pytest.raises(ParameterError, match="measured"):
        fit.fit(tables, values * 100.0)  # percent, not fractions
    with pytest.raises(ParameterError, match="measured"):
        fit.fit(tables, -values)
    bad = values.copy()
    bad[0, 3] = np.inf
    with pytest.raises(ParameterError, match="measured"):
        fit.fit(tables, bad)
    with pytest.raises(ParameterError, match="measured"):
        fit.fit(tables, np.full(values.shape, np.nan))
    with pytest.raises(ParameterError, match="sigma"):
        fit.fit(tables, values, np.zeros(values.shape))


def test_missing_measurements_are_skipped(tables, synthetic):
    values, sigma = synthetic
    gappy = values.copy()
    gappy[:, 5] = np.nan  # no end-member measured at one wavelength
    fit = cal.KFit().fit(tables, gappy, sigma)
    assert np.isnan(fit.residuals_[:, 5]).all()
    assert np.isfinite(fit.log10_k_).all()


def test_bad_tables_are_refused(tables, synthetic):
    values = synthetic[0]
    with pytest.raises(ParameterError, match="tables"):
        cal.KFit().fit([], values[:0])
    member = cal.end_members("hematite", ids=["GDS27"])[0]
    other = cal.tabulate(member, FakePowder(), WL[:-1] + 1.0, GRID[:-1])
    with pytest.raises(ParameterError, match="tables"):
        cal.KFit().fit([tables[0], other], values[:2])


def test_predict_before_fit_and_on_another_grid_is_refused(tables, synthetic):
    with pytest.raises(ParameterError, match="fit"):
        cal.KFit().predict(tables)
    fit = cal.KFit().fit(tables, synthetic[0])
    member = cal.end_members("hematite", ids=["GDS27"])[0]
    with pytest.raises(ParameterError, match="grid of the fit"):
        fit.predict([cal.tabulate(member, FakePowder(), WL[:-1], GRID)])


def test_holdout_refuses_unknown_or_all_ids(tables, synthetic):
    with pytest.raises(ParameterError, match="test_ids"):
        cal.holdout(cal.KFit(), tables, synthetic[0], test_ids=["GDS99"])
    with pytest.raises(ParameterError, match="test_ids"):
        cal.holdout(cal.KFit(), tables, synthetic[0], test_ids=[t.member_id for t in tables])
