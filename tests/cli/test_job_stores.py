"""train-spectral and train-spatial check their settings and their job stores before the first
task (issue 24 #12): a clear message, exit 2, nothing computed."""

import os

import pytest
from typer.testing import CliRunner

from sandlight.cli import app

runner = CliRunner()

SPECTRAL = ["train-spectral", "--samples", "20", "--rays", "100", "--workers", "1", "--no-progress"]
SPATIAL = ["train-spatial", "-n", "1000", "--stacks", "5", "--slices", "4", "--axis", "saturation=0:1:2"]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        # failed inside every task, after 3 attempts each, with "run the job again to retry"
        (["--wavelengths", "300:400:50"], "--wavelengths = 300.0 is not allowed: wavelengths in [350, 2500] nm"),
        (["--seed", "-1"], "--seed = -1 is not allowed: an integer in [0, 2**64)"),  # a traceback
        (["--holdout", "-1"], "--holdout = -1 is not allowed: an integer >= 0"),  # silently meant none
    ],
)
def test_train_spectral_checks_its_settings_before_any_task(tmp_path, args, message):
    res = runner.invoke(app, [*SPECTRAL, "--out", str(tmp_path / "run"), *args])
    assert res.exit_code == 2 and message in res.output, res.output
    assert "Traceback" not in res.output and not list(tmp_path.rglob("shard-*.nc"))


def test_train_spatial_checks_its_wavelength_before_any_task(tmp_path):
    res = runner.invoke(app, [*SPATIAL, "--out", str(tmp_path / "run"), "--wavelength", "300"])
    assert res.exit_code == 2 and "--wavelengths = 300.0 is not allowed" in res.output, res.output
    assert not list(tmp_path.rglob("shard-*.nc"))


@pytest.mark.parametrize(
    ("damage", "message"),
    [
        (lambda store: (store / "job.json").write_text("[]"), "is not a sandlight job settings file"),
        (lambda store: (store / "dataset.nc").write_bytes(os.urandom(500)), "is not a readable dataset"),
    ],
)
def test_a_damaged_store_is_refused_with_a_message(tmp_path, damage, message):
    out = tmp_path / "run"
    assert runner.invoke(app, [*SPECTRAL, "--holdout", "0", "--out", str(out)]).exit_code == 0
    damage(out / "training")
    res = runner.invoke(app, [*SPECTRAL, "--holdout", "0", "--out", str(out)])
    assert res.exit_code == 2 and message in res.output, res.output
    assert "Traceback" not in res.output
