"""sandlight.fit with the predictor bank: recovery, intervals, identifiability, the result."""

import tomllib

import numpy as np
import pytest

import sandlight
from sandlight.errors import ParameterError
from sandlight.predictor import ModelBank, full_range_model
from sandlight.retrieval import NotIdentifiableError
from sandlight.sample import SandSample

FREE = ["iron_oxide", "hematite_ratio"]


def test_noiseless_predictor_spectrum_is_recovered_exactly(dry_spectrum, dry_truth):
    result = sandlight.fit(dry_spectrum, FREE, {"saturation": 0.0}, noise=0.002, check_rays=0)
    assert "reference-dry" in result.model
    assert result.estimate["iron_oxide"] == pytest.approx(dry_truth.iron_oxide, rel=1e-4)
    assert result.estimate["hematite_ratio"] == pytest.approx(dry_truth.hematite_ratio, abs=1e-4)
    assert result.sample.iron_oxide == pytest.approx(dry_truth.iron_oxide, rel=1e-4)
    assert np.max(np.abs(result.residual.values)) < 1e-6


def test_three_parameters_recovered_in_the_wet_range(bank):
    truth = SandSample(iron_oxide=0.008, hematite_ratio=0.7, saturation=0.6)
    spectrum = (bank.wavelengths_, bank.predict([truth])[0])
    result = sandlight.fit(spectrum, [*FREE, "saturation"], noise=0.001, check_rays=0)
    assert "reference-wet" in result.model
    for name in result.free:
        assert result.estimate[name] == pytest.approx(getattr(truth, name), rel=1e-3)


def test_a_spectrum_beyond_700_nm_is_fitted_by_the_full_range_bank():
    """A dry spectrum over 350–2500 nm is answered by the full-range model (which sees its near
    infrared) and recovered exactly: the network is evaluated in double precision, so the
    optimiser's finite-difference Jacobian is a derivative, not rounding noise."""
    full = full_range_model()
    truth = SandSample(iron_oxide=0.012, hematite_ratio=1.0, iron_oxide_form="particles", grain_size=0.3)
    spectrum = (full.wavelengths_, full.predict([truth])[0])
    free = ["iron_oxide", "grain_size"]
    fixed = {"hematite_ratio": 1.0, "iron_oxide_form": "particles"}
    result = sandlight.fit(spectrum, free, fixed, noise=0.002, check_rays=0)
    assert "full-dry" in result.model
    for name in free:
        assert result.estimate[name] == pytest.approx(getattr(truth, name), rel=1e-3)
    # the Laplace interval comes from that Jacobian: it must hold the truth and have a width
    lo, hi = result.interval("grain_size")
    assert lo < truth.grain_size < hi and hi - lo > 1e-3


def test_the_paper_bank_answers_inside_400_700_nm_and_the_full_range_bank_beyond(dry_spectrum):
    wl = np.arange(350.0, 2501.0, 25.0)
    reflectance = full_range_model().predict([SandSample()])[0]
    dry = sandlight.fit((wl, reflectance), FREE, {"saturation": 0.0}, noise=0.01, check_rays=0)
    assert "full-dry" in dry.model
    visible = sandlight.fit(dry_spectrum, FREE, {"saturation": 0.0}, noise=0.01, check_rays=0)
    assert "full-dry" not in visible.model
    # with saturation free the wet full-range model answers, over the whole measurement
    wet = sandlight.fit((wl, reflectance), [*FREE, "saturation"], noise=0.01, check_rays=0)
    assert "full-wet" in wet.model and wet.observation.centres_nm.max() > 700.0


def width(result, name):
    lo, hi = result.interval(name)
    return hi - lo


def test_intervals_shrink_with_less_noise(dry_spectrum, add_noise):
    loud = sandlight.fit(add_noise(dry_spectrum, 0.01, 1), FREE, {"saturation": 0.0}, noise=0.01, check_rays=0)
    quiet = sandlight.fit(add_noise(dry_spectrum, 0.001, 1), FREE, {"saturation": 0.0}, noise=0.001, check_rays=0)
    for name in FREE:
        assert width(quiet, name) < 0.8 * width(loud, name)


def test_intervals_contain_the_truth_and_lie_in_the_bounds(dry_spectrum, dry_truth, add_noise):
    result = sandlight.fit(add_noise(dry_spectrum, 0.005, 7), FREE, {"saturation": 0.0}, check_rays=0)
    assert result.sigma_estimated
    # the noise estimate: one σ from 16 channels, within a factor of two of the truth
    assert 0.0025 < result.sigma < 0.01
    for i, name in enumerate(FREE):
        lo, hi = result.interval(name)
        assert result.space.low[i] <= lo < result.estimate[name] < hi <= result.space.high[i]
        assert lo <= getattr(dry_truth, name) <= hi
        lo99, hi99 = result.interval(name, level=0.99)
        assert lo99 < lo and hi99 > hi


def test_a_flat_likelihood_gives_no_interval(dry_spectrum):
    result = sandlight.fit(dry_spectrum, FREE, {"saturation": 0.0}, noise=0.3, check_rays=0)
    assert not result.identifiable("hematite_ratio")
    with pytest.raises(NotIdentifiableError, match="hematite_ratio is not identifiable"):
        result.interval("hematite_ratio")
    assert "not identifiable" in result.summary()
    assert not result.to_xarray()["identifiable"].sel(parameter="hematite_ratio")


def test_result_exports(dry_spectrum, tmp_path):
    result = sandlight.fit(dry_spectrum, FREE, {"saturation": 0.0}, noise=0.002, check_rays=0)
    path = tmp_path / "fit.toml"
    result.save(path)
    doc = tomllib.loads(path.read_text())
    assert doc["format"] == "sandlight-fit"
    assert SandSample.from_dict(doc["sample"]) == result.sample
    assert doc["parameters"]["iron_oxide"]["low_95"] < doc["parameters"]["iron_oxide"]["high_95"]
    assert doc["correlation"]["iron_oxide"][0] == pytest.approx(1.0)
    ds = result.to_xarray()
    assert set(ds.data_vars) >= {"measured", "fitted", "residual", "estimate", "low_95", "high_95", "correlation"}
    np.testing.assert_allclose(ds["measured"] - ds["fitted"], ds["residual"])
    corr = result.correlation.values
    np.testing.assert_allclose(corr, corr.T)
    assert abs(corr[0, 1]) <= 1
    result.plot(tmp_path / "fit.png")
    assert (tmp_path / "fit.png").stat().st_size > 1000


def test_bad_input_is_named(dry_spectrum):
    wl, r = dry_spectrum
    with pytest.raises(ParameterError, match="reflectance at 440 nm"):
        sandlight.fit((wl, np.where(wl == 440, np.nan, r)), FREE)
    with pytest.raises(ParameterError, match="micrometres"):
        sandlight.fit((wl / 1000, r), FREE)
    with pytest.raises(ParameterError, match="left to fit"):
        sandlight.fit(dry_spectrum, FREE, mask=[(350, 800)])
    with pytest.raises(ParameterError, match="not a sample parameter"):
        sandlight.fit(dry_spectrum, ["iron_oxyde"])
    with pytest.raises(ParameterError, match="also free"):
        sandlight.fit(dry_spectrum, FREE, {"iron_oxide": 0.01})
    with pytest.raises(ParameterError, match="method"):
        sandlight.fit(dry_spectrum, FREE, method="magic")
    with pytest.raises(ParameterError, match="noise"):
        sandlight.fit(dry_spectrum, FREE, noise=-1.0)
    result = sandlight.fit(dry_spectrum, FREE, {"saturation": 0.0}, noise=0.002, check_rays=0)
    with pytest.raises(ParameterError, match="level"):
        result.interval("iron_oxide", level=95)
    with pytest.raises(ParameterError, match="free parameters"):
        result.interval("saturation")


def test_free_parameters_no_model_covers_are_refused_with_a_hint(bank, dry_spectrum):
    dry_only = ModelBank([bank.model("reference-dry")])
    with pytest.raises(ParameterError, match="method='engine'"):
        sandlight.fit(dry_spectrum, ["iron_oxide", "saturation"], bank=dry_only)
    with pytest.raises(ParameterError, match="method='engine'"):
        sandlight.fit(dry_spectrum, ["iron_oxide"], {"saturation": 0.0, "grain_size": 1.0}, bank=dry_only)
    result = sandlight.fit(dry_spectrum, ["iron_oxide"], {"saturation": 0.0}, bank=dry_only, noise=0.002, check_rays=0)
    assert result.candidates.keys() == {"reference-dry"}
