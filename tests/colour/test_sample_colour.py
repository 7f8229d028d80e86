"""sample_xyz / sample_rgb / sample_lab, the reflectance provider, and physical colour trends."""

import sys
import types

import numpy as np
import pytest
from colour_fakes import FakeSample

from sandlight.colour import (
    PREDICTOR_WAVELENGTHS_NM,
    sample_lab,
    sample_rgb,
    sample_xyz,
    spectrum_to_xyz,
    xyz_to_lab,
    xyz_to_srgb,
)
from sandlight.errors import SandlightError


class TestSampleColour:
    def test_single_sample_goes_through_spectrum_to_xyz(self, fake_sample, fake_provider):
        spectrum = fake_provider([fake_sample], PREDICTOR_WAVELENGTHS_NM)[0]
        xyz = sample_xyz(fake_sample, reflectance=fake_provider)
        assert xyz.shape == (3,)
        np.testing.assert_allclose(xyz, spectrum_to_xyz(PREDICTOR_WAVELENGTHS_NM, spectrum))
        np.testing.assert_allclose(sample_rgb(fake_sample, reflectance=fake_provider), xyz_to_srgb(xyz))
        np.testing.assert_allclose(
            sample_rgb(fake_sample, mode="paper", reflectance=fake_provider), xyz_to_srgb(xyz, mode="paper")
        )
        np.testing.assert_allclose(sample_lab(fake_sample, reflectance=fake_provider), xyz_to_lab(xyz))

    def test_list_of_samples_is_one_provider_call(self, fake_provider):
        samples = [FakeSample(hematite_ratio=h) for h in (0.0, 0.5, 1.0)]
        rgb = sample_rgb(samples, reflectance=fake_provider)
        assert rgb.shape == (3, 3)
        assert fake_provider.calls == 1
        for s, row in zip(samples, rgb):
            np.testing.assert_allclose(row, sample_rgb(s, reflectance=fake_provider), rtol=1e-14)
        rgb, out = sample_rgb(tuple(samples), reflectance=fake_provider, return_out_of_gamut=True)
        assert out.shape == (3,)

    def test_plain_dict_sample(self, fake_provider):
        lab = sample_lab({"iron_oxide": 0.02, "hematite_ratio": 0.3, "saturation": 0.0}, reflectance=fake_provider)
        assert lab.shape == (3,) and 0 < lab[0] < 100

    def test_dense_wavelengths_can_be_requested(self, fake_sample, fake_provider):
        wl = np.arange(380.0, 781.0, 5.0)
        coarse = sample_lab(fake_sample, reflectance=fake_provider)
        dense = sample_lab(fake_sample, reflectance=fake_provider, wavelengths_nm=wl)
        np.testing.assert_allclose(dense, coarse, atol=0.05)  # smooth spectrum: same colour


class TestProvider:
    def test_no_model_gives_clear_error(self, fake_sample, monkeypatch):
        monkeypatch.setitem(sys.modules, "sandlight.predictor", None)  # makes the import fail
        with pytest.raises(SandlightError, match="No spectral model is available.*reflectance="):
            sample_rgb(fake_sample)

    def test_default_provider_uses_default_model(self, fake_sample, fake_provider, monkeypatch):
        class Model:
            wavelengths_ = PREDICTOR_WAVELENGTHS_NM

            def predict(self, samples):
                return fake_provider(samples, self.wavelengths_)

        module = types.ModuleType("sandlight.predictor")
        module.default_model = Model
        monkeypatch.setitem(sys.modules, "sandlight.predictor", module)
        np.testing.assert_allclose(sample_rgb(fake_sample), sample_rgb(fake_sample, reflectance=fake_provider))
        with pytest.raises(SandlightError, match="predicts at wavelengths"):
            sample_rgb(fake_sample, wavelengths_nm=np.arange(400.0, 701.0, 10.0))

    def test_wrong_shape_from_provider(self, fake_sample):
        def bad(samples, wavelengths_nm):
            return np.zeros((len(samples), wavelengths_nm.size - 1))

        with pytest.raises(SandlightError, match=r"shape \(1, 15\).*\(1, 16\)"):
            sample_rgb(fake_sample, reflectance=bad)

    def test_nan_from_provider(self, fake_sample):
        def bad(samples, wavelengths_nm):
            return np.full((len(samples), wavelengths_nm.size), np.nan)

        with pytest.raises(SandlightError, match="NaN"):
            sample_rgb(fake_sample, reflectance=bad)


# Physical trends: only meaningful with a real spectral model, never with the fake provider.
def hue_angle_deg(lab):
    return np.degrees(np.arctan2(lab[..., 2], lab[..., 1]))


def test_more_hematite_is_redder(real_provider):
    from sandlight.sample import SandSample

    base = SandSample(iron_oxide=0.02)
    ratios = np.linspace(0.0, 1.0, 5)
    lab = sample_lab([base.replace(hematite_ratio=float(h)) for h in ratios], reflectance=real_provider)
    hue = hue_angle_deg(lab)
    # Goethite is yellow, hematite red: the CIELAB hue angle falls as hematite replaces goethite.
    assert np.all(np.diff(hue) < 0.5), hue
    assert hue[0] - hue[-1] > 5.0, hue


def test_wetter_is_darker(real_provider):
    from sandlight.sample import SandSample

    base = SandSample.preset("red-dune")
    saturations = [0.0, 0.5, 1.0]
    lab = sample_lab([base.replace(saturation=s) for s in saturations], reflectance=real_provider)
    assert np.all(np.diff(lab[:, 0]) < 0), lab[:, 0]
    assert lab[0, 0] - lab[-1, 0] > 3.0, lab[:, 0]
