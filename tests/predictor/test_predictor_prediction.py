"""sandlight.predict (sandlight.predictor.prediction): the shipped bank at any wavelength it spans,
with the answering model and its hold-out error."""

import math

import numpy as np
import pytest
import xarray as xr

import sandlight
from sandlight.errors import ParameterError
from sandlight.predictor.bank import default_model, full_range_model
from sandlight.predictor.prediction import interpolate_spectra


def test_one_preset_at_the_models_wavelengths_is_the_banks_answer():
    bank = default_model()
    ds = sandlight.predict("red-dune")
    values, used = bank.predict([sandlight.SandSample.preset("red-dune")], return_models=True)
    assert ds["reflectance"].dims == ("wavelength",)  # one sample: no sample dimension
    np.testing.assert_array_equal(ds["wavelength"].values, bank.wavelengths_)
    np.testing.assert_array_equal(ds["reflectance"].values, values[0])
    assert str(ds["model"].values) == used[0] and not bool(ds["extrapolated"])
    np.testing.assert_array_equal(ds["holdout_rms"].values, bank.model(used[0]).holdout_scores_["rms_error"])
    assert ds.attrs["Conventions"].startswith("CF") and ds["wavelength"].attrs["units"] == "nm"


def test_between_the_models_wavelengths_the_spectrum_is_interpolated_without_overshoot():
    samples = [sandlight.SandSample.preset(p) for p in ("red-dune", "yellow-dune", "wet-beach")]
    wl = np.arange(400.0, 700.5, 2.5)
    ds = sandlight.predict(samples, wl)
    at_nodes = sandlight.predict(samples)
    assert ds["reflectance"].dims == ("sample", "wavelength") and ds["reflectance"].shape == (3, wl.size)
    nodes = at_nodes["wavelength"].values
    on_node = np.isin(wl, nodes)
    np.testing.assert_allclose(ds["reflectance"].values[:, on_node], at_nodes["reflectance"].values, atol=1e-12)
    # PCHIP is monotone between nodes: every value lies within its two neighbouring node values.
    i = np.clip(np.searchsorted(nodes, wl, side="right") - 1, 0, nodes.size - 2)
    lo = np.minimum(at_nodes["reflectance"].values[:, i], at_nodes["reflectance"].values[:, i + 1])
    hi = np.maximum(at_nodes["reflectance"].values[:, i], at_nodes["reflectance"].values[:, i + 1])
    r = ds["reflectance"].values
    assert np.all(r >= lo - 1e-12) and np.all(r <= hi + 1e-12)
    assert list(ds["model"].values) == list(at_nodes["model"].values)


def test_pchip_follows_a_steep_measured_edge():
    # GDS76 (2 wt% hematite in quartz: the steepest edge of the shipped measurements) sampled at
    # 20 nm and interpolated back: within 0.004 everywhere in 400-700 nm (measured 0.0030;
    # scripts/studies/spectral_interpolation.py).
    from sandlight.measured import read_usgs, usgs_library

    spectrum = read_usgs(usgs_library("Hematite.02+Quartz.98_GDS76")).dropna("wavelength")
    wl, r = spectrum["wavelength"].values, spectrum.values
    nodes, fine = np.arange(400.0, 701.0, 20.0), np.arange(400.0, 701.0, 1.0)
    error = interpolate_spectra(nodes, np.interp(nodes, wl, r), fine) - np.interp(fine, wl, r)
    assert np.max(np.abs(error)) < 0.004


@pytest.mark.parametrize("wavelengths", [[340.0, 500.0], [500.0, 2510.0], [math.nan], [], "blue"])
def test_wavelengths_outside_the_models_are_refused_with_their_name(wavelengths):
    with pytest.raises(ParameterError, match="wavelengths_nm"):
        sandlight.predict("red-dune", wavelengths)


def test_the_papers_models_refuse_what_only_the_full_range_answers():
    with pytest.raises(ParameterError, match=r"wavelengths_nm.*\[400, 700\]"):
        sandlight.predict("red-dune", [500.0, 900.0], mode="paper")
    with pytest.raises(ParameterError, match="mode"):
        sandlight.predict("red-dune", mode="visible")


def test_wavelengths_beyond_the_visible_are_answered_by_the_full_range_models():
    full = full_range_model()
    assert full.wavelengths_[0] == 350.0 and full.wavelengths_[-1] == 2500.0
    wl = np.arange(350.0, 2501.0, 5.0)  # PCHIP between the 25 nm nodes
    ds = sandlight.predict("red-dune", wl)
    assert str(ds["model"].values) == "full-dry" and not bool(ds["extrapolated"])
    assert ds["reflectance"].shape == wl.shape and np.all(np.isfinite(ds["holdout_rms"].values))
    nodes = sandlight.predict("red-dune", mode="full-range")
    np.testing.assert_array_equal(nodes["wavelength"].values, full.wavelengths_)
    np.testing.assert_allclose(ds["reflectance"].values[::5], nodes["reflectance"].values, atol=1e-12)
    # Physics the model must carry: red sand darkest in the blue, brighter beyond the iron edge.
    r = nodes["reflectance"].values
    assert r[full.wavelengths_ == 450.0][0] < 0.5 * r[full.wavelengths_ == 800.0][0]


def test_in_the_visible_the_full_range_and_the_papers_models_agree_within_their_errors():
    # The reference sand, dry: the centre of both banks' domains. Each answer is off the truth by
    # about its model's hold-out RMS; the two are independent models (other training sets).
    wl = np.arange(400.0, 701.0, 20.0)
    paper = sandlight.predict(sandlight.SandSample(), wl)
    full = sandlight.predict(sandlight.SandSample(), wl, mode="full-range")
    assert str(paper["model"].values) == "reference-dry" and str(full["model"].values) == "full-dry"
    both = np.hypot(paper["holdout_rms"].values, full["holdout_rms"].values)
    assert np.all(np.abs(paper["reflectance"].values - full["reflectance"].values) < 4 * both)


def test_wet_sand_over_the_full_range_is_darker_and_shows_the_water_bands():
    # wet-beach (saturation 0.8) from full-wet, the same sand dry from full-dry: darker at every
    # wavelength, and darkest relative to dry in water's absorption bands at 1450 and 1940 nm.
    wl = np.array([500.0, 1000.0, 1300.0, 1450.0, 1650.0, 1940.0, 2200.0])
    wet = sandlight.predict("wet-beach", wl)
    dry = sandlight.predict(sandlight.SandSample.preset("wet-beach").replace(saturation=0.0), wl)
    assert str(wet["model"].values) == "full-wet" and str(dry["model"].values) == "full-dry"
    ratio = wet["reflectance"].values / dry["reflectance"].values
    assert np.all(ratio < 1.0)
    band = dict(zip(wl, ratio))
    assert band[1450.0] < min(band[1300.0], band[1650.0]) and band[1940.0] < min(band[1650.0], band[2200.0])


def test_a_sample_no_model_covers_is_refused_unless_extrapolated(tmp_path):
    outside = sandlight.SandSample(host_absorption=0.5)  # every model fixes host_absorption at 1
    with pytest.raises(ParameterError, match="host_absorption"):
        sandlight.predict(outside)
    ds = sandlight.predict(outside, [450.0, 555.0], extrapolate=True)
    # Every model fails host_absorption alone: the most accurate one covering the rest answers.
    assert bool(ds["extrapolated"]) and str(ds["model"].values) == "reference-dry"
    ds.to_netcdf(tmp_path / "p.nc", engine="h5netcdf")
    with xr.open_dataset(tmp_path / "p.nc", engine="h5netcdf") as back:
        np.testing.assert_array_equal(back["reflectance"].values, ds["reflectance"].values)
        assert bool(back["extrapolated"])


def test_a_batch_may_name_presets_among_its_samples():
    ds = sandlight.predict([sandlight.SandSample(iron_oxide=0.01), "yellow-dune"])
    alone = sandlight.predict("yellow-dune")
    assert ds["reflectance"].shape[0] == 2 and str(ds["model"].values[1]) == str(alone["model"].values)
    np.testing.assert_allclose(ds["reflectance"].values[1], alone["reflectance"].values, rtol=1e-12, atol=1e-15)


def test_a_dict_of_columns_is_a_batch_and_a_dict_of_scalars_one_sample():
    batch = sandlight.predict({"iron_oxide": [0.005, 0.02], "hematite_ratio": 0.5})
    one = sandlight.predict({"iron_oxide": 0.005, "hematite_ratio": 0.5})
    assert batch["reflectance"].shape[0] == 2 and one["reflectance"].dims == ("wavelength",)
    # Batched and single evaluation sum the monomials in another order: equal to rounding.
    np.testing.assert_allclose(batch["reflectance"].values[0], one["reflectance"].values, rtol=1e-12, atol=1e-15)
