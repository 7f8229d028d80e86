"""Tests of sandlight.validation: the model against measured spectra, end to end at a reduced ray
count, the scoring arithmetic, the report writer and the `sandlight validate` command."""

import math

import numpy as np
import pytest
import xarray as xr

from sandlight import validation as v
from sandlight.errors import ParameterError

FEW_WL = [450.0, 550.0, 650.0, 1000.0, 2000.0]
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def results():
    return v.validate(rays=300, wavelengths_nm=FEW_WL, seed=1)


def spectrum(wavelengths, values):
    return xr.DataArray(
        np.asarray(values, dtype=float), dims="wavelength", coords={"wavelength": np.asarray(wavelengths, dtype=float)}
    )


# --- comparing a grid with a measurement ---


def test_measured_on_grid_averages_window_interpolates_gaps_and_skips_deleted():
    s = spectrum([396, 398, 400, 403, 404, 406, 440, 470, 600], [0.1, 9.0, 0.3, 0.5, np.nan, 0.7, 0.2, 0.5, 0.9])
    got = v.measured_on_grid(s, [400.0, 460.0, 540.0, 406.0])
    # 400: channels 396, 398, 400, 403 lie within ±5 nm, 404 is deleted; 396 is 4 nm away.
    assert got[0] == pytest.approx(np.mean([0.1, 9.0, 0.3, 0.5]))
    # 460: no channel within 5 nm; 440 and 470 are 30 nm apart: linear interpolation.
    assert got[1] == pytest.approx(0.2 + (0.5 - 0.2) * 20 / 30)
    # 540: the neighbours 470 and 600 are 130 nm apart (> 50): skipped.
    assert math.isnan(got[2])
    # 406: 403 and 406 lie within the window; the deleted 404 does not count.
    assert got[3] == pytest.approx(np.mean([0.5, 0.7]))


def test_band_error_arithmetic_and_monte_carlo_bound():
    wl = np.array([400.0, 500.0, 600.0, 1000.0])
    meas = np.array([0.2, 0.3, 0.4, 0.5])
    model = meas + np.array([0.1, -0.1, 0.1, 0.3])
    sd = np.array([0.01, 0.01, 0.01, 0.02])
    e = v.band_error(wl, model, sd, meas, "vis", 400, 700, target_rms=0.02)
    assert e.points == 3
    assert e.rms == pytest.approx(0.1)
    assert e.bias == pytest.approx(0.1 / 3)
    # Σ|d|σ/(n RMS) with |d| = 0.1 and σ = 0.01 everywhere is σ itself.
    assert e.rms_mc == pytest.approx(0.01)
    assert e.max_abs == pytest.approx(0.1) and e.max_at_nm in (400.0, 500.0, 600.0)
    assert e.verdict == "missed"
    assert v.band_error(wl, meas + 0.001, sd / 10, meas, "vis", 400, 700, target_rms=0.02).verdict == "met"
    # Within two error bars (2 × 0.01) of the target: not decided either way.
    assert v.band_error(wl, meas + 0.001, sd, meas, "vis", 400, 700, target_rms=0.02).verdict == "undecided"
    assert v.band_error(wl, meas + 0.035, sd, meas, "vis", 400, 700, target_rms=0.02).verdict == "undecided"
    with pytest.raises(ParameterError, match="wavelengths_nm"):
        v.band_error(wl, model, sd, meas, "none", 2000, 2500)


# --- end to end ---


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
        assert r.sample_values == SandSample.preset(r.sample.preset).to_dict()
        direct = read_usgs(usgs_library(r.sample.spectrum))
        assert r.measured == pytest.approx(v.measured_on_grid(direct, FEW_WL))
    # The GDS76 mixture: hematite's absorption edge makes it far darker at 450 than at 2000 nm.
    gds76 = results[0].measured
    assert gds76[0] < 0.3 and gds76[-1] > 0.85


def test_unknown_sample_is_a_parameter_error():
    with pytest.raises(ParameterError, match="samples"):
        v.validate(["Mars_regolith"], rays=10, wavelengths_nm=FEW_WL)


def test_variant_changes_optics_only_for_its_run():
    from sandlight.physics import medium

    original = medium.complex_index
    clear = v.Variant(v.SAMPLES[0].name, "hematite k × 0", "test", k_factor={"hematite": 0.0}, k_factor_from_nm=500.0)
    (preset,) = v.validate([v.SAMPLES[0].name], rays=300, wavelengths_nm=[450.0, 600.0], seed=2)
    (variant,) = v.run_variants([clear], rays=300, wavelengths_nm=[450.0, 600.0], seed=2)
    assert medium.complex_index is original
    # Below 500 nm nothing changed and the random streams are shared: identical values.
    assert variant.model[0] == preset.model[0]
    # Without hematite absorption at 600 nm (on its edge) the mixture is brighter, by far more
    # than the noise.
    assert variant.model[1] > preset.model[1] + 5 * preset.model_stderr[1]


def test_powder_reflectance_opaque_vs_transparent_and_checks():
    quartz = v.powder_reflectance("quartz", (10.0, 100.0), [500.0], rays=400, seed=3)
    hematite = v.powder_reflectance("hematite", 2.5, [500.0], rays=400, seed=3)
    # Hematite absorbs strongly at 500 nm (k ≈ 0.65); quartz is nearly transparent.
    assert hematite.values[0] < 0.2 < 0.7 < quartz.values[0]
    assert quartz.sample["diameter_um"] == [10.0, 100.0]
    with pytest.raises(ParameterError, match="diameter_um"):
        v.powder_reflectance("quartz", (100.0, 10.0), [500.0], rays=10)
    with pytest.raises(ParameterError, match="material"):
        v.powder_reflectance("cheese", 10.0, [500.0], rays=10)
    with pytest.raises(ParameterError, match="porosity"):
        v.powder_reflectance("quartz", 10.0, [500.0], rays=10, porosity=1.0)


# --- the report ---


def test_report_writer_sections_and_update_keeps_hand_written_text(results, tmp_path):
    report = tmp_path / "docs" / "validation.md"
    figs = [tmp_path / "docs" / "img" / f"{r.sample.preset}.png" for r in results]
    v.write_report(report, results, figure_paths=figs, command="sandlight validate --rays 300")
    text = report.read_text(encoding="utf-8")
    for heading in (
        "# Validation against measured spectra",
        "## How to reproduce",
        "## Results",
        "## Spectra",
        "## Diagnostic variants",
        "## The paper's Figure 3, from the model",
    ):
        assert heading in text
    for name in v.REPORT_BLOCKS:
        assert f"<!-- BEGIN validation:{name} -->" in text and f"<!-- END validation:{name} -->" in text
    assert "sandlight validate --rays 300" in text
    assert "(img/gds76-hematite-quartz.png)" in text
    for r in results:
        for e in r.errors.values():
            assert f"| {r.sample.name} | {e.band} | {e.rms:.4f} ± {e.rms_mc:.4f} |" in text

    # A hand-written discussion outside the blocks survives an update; the blocks change.
    report.write_text(text + "\n## Discussion\n\nHand-written.\n", encoding="utf-8")
    v.write_report(report, results, figure_paths=figs, command="sandlight validate --rays 999")
    updated = report.read_text(encoding="utf-8")
    assert "## Discussion\n\nHand-written." in updated
    assert "--rays 999" in updated and "--rays 300" not in updated
    with pytest.raises(ParameterError, match="figure_paths"):
        v.write_report(report, results, figure_paths=figs[:1], command="x")


def test_cli_validate_writes_report_and_figures(tmp_path):
    from typer.testing import CliRunner

    from sandlight.cli import app

    out = tmp_path / "validation.md"
    res = CliRunner().invoke(
        app,
        [
            "validate",
            "--rays",
            "200",
            "--no-variants",
            "--sample",
            "Hematite.02+Quartz.98_GDS76",
            "-o",
            str(out),
            "--figures",
            str(tmp_path / "img"),
        ],
    )
    assert res.exit_code == 0, res.output
    assert (tmp_path / "img" / "validation-gds76-hematite-quartz.png").is_file()
    text = out.read_text(encoding="utf-8")
    assert "--no-variants" in text and "Quartz_GDS74_Sand_Ottawa |" not in text
    bad = CliRunner().invoke(app, ["validate", "--rays", "0", "-o", str(out)])
    assert bad.exit_code == 2 and "--rays" in bad.output
