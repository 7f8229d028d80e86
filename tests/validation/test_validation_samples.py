"""Tests of sandlight.validation.samples: the model against the measured samples, end to end at a
reduced ray count, and validating a medium of one's own."""

import math

import numpy as np
import pytest

import sandlight
from sandlight import validation as v
from sandlight.errors import ParameterError
from sandlight.physics.composition import DEFAULT_FILMS

FEW_WL = [450.0, 550.0, 650.0, 1000.0, 2000.0]
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def results():
    return v.validate(rays=300, wavelengths_nm=FEW_WL, seed=1)


def test_validate_end_to_end_gives_finite_errors_and_a_plot(results, tmp_path):
    assert [r.sample.name for r in results] == [s.name for s in v.SAMPLES]
    for r in results:
        assert r.rays == 300 and r.model.shape == (len(FEW_WL),) and r.skipped == 0
        assert np.all((r.model >= 0) & (r.model <= 1))
        assert np.all(r.model_stderr > 0)
        for band, e in r.errors.items():
            assert e.points == (3 if band == "400–700 nm" else 5)
            assert all(math.isfinite(x) for x in (e.rms, e.rms_mc, e.max_abs, e.max_abs_mc, e.bias))
            assert abs(e.bias) <= e.rms <= e.max_abs + 1e-12
            assert e.target_rms == v.TARGET_RMS[band]
        path = tmp_path / f"{r.sample.preset}.png"
        r.plot(path)
        assert path.read_bytes()[:8] == PNG_SIGNATURE and path.stat().st_size > 10_000


def test_validate_uses_the_presets_and_the_shipped_spectra(results):
    from sandlight.measured import read_usgs, usgs_library
    from sandlight.sample import SandSample

    for r in results:
        assert r.label == f"preset {r.sample.preset}"
        # What was traced: the preset, and the film model, recorded since it is not the
        # pre-issue-17 'uniform' (SandMedium.describe).
        assert r.sample_values == {**SandSample.preset(r.sample.preset).to_dict(), "films": DEFAULT_FILMS}
        direct = read_usgs(usgs_library(r.sample.spectrum))
        assert r.measured == pytest.approx(v.measured_on_grid(direct, FEW_WL))
        # The model is the engine's reflectance of the preset, with the same seed.
        same = sandlight.reflectance(r.sample.preset, FEW_WL, rays=300, seed=1, progress=False)
        np.testing.assert_array_equal(r.model, same.values)
    # The GDS76 mixture: hematite's absorption edge makes it far darker at 450 than at 2000 nm.
    gds76 = results[0].measured
    assert gds76[0] < 0.3 and gds76[-1] > 0.85


def test_unknown_sample_is_a_parameter_error():
    with pytest.raises(ParameterError, match="samples"):
        v.validate(["Mars_regolith"], rays=10, wavelengths_nm=FEW_WL)
    assert v.sample_by_name("ottawa-gds74") is v.SAMPLES[1]


def test_any_traceable_medium_can_be_validated():
    import dataclasses

    from sandlight.physics.powder import Powder

    powder = Powder("hematite", 2.5)
    own = dataclasses.replace(v.SAMPLES[0], medium=powder)
    (r,) = v.validate([own], rays=300, wavelengths_nm=[450.0, 550.0, 2000.0], seed=2)
    assert r.label == "Powder gds76-hematite-quartz"
    assert r.sample_values == powder.describe()
    direct = sandlight.reflectance(powder, [450.0, 550.0, 2000.0], rays=300, seed=2, progress=False)
    np.testing.assert_array_equal(r.model, direct.values)
    # Pure hematite is far darker in the visible than the 98 % quartz mixture that was measured.
    assert r.errors["400–700 nm"].bias < -0.05
