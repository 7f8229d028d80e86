"""Wavelength specs are bounded (issue 24 #4): the limit is stated, nothing huge is allocated."""

import pytest
from typer.testing import CliRunner

from sandlight.checks import MAX_WAVELENGTHS, parse_range
from sandlight.cli import app
from sandlight.errors import ParameterError

runner = CliRunner()

BAD = ["400:inf:20", "400:700:1e-9", "-inf:700:20", "400:700:nan"]


@pytest.mark.parametrize("spec", BAD)
def test_reflectance_refuses_unbounded_grids_stating_the_limit(spec):
    # "400:inf:20" raised OverflowError, "400:700:1e-9" MemoryError (a 2 TiB grid).
    res = runner.invoke(app, ["reflectance", "--preset", "red-dune", "-n", "10", "-w", spec])
    assert res.exit_code == 2 and f"--wavelengths = '{spec}' is not allowed" in res.output, res.output
    assert f"at most {MAX_WAVELENGTHS:,} values" in res.output


@pytest.mark.parametrize("spec", BAD[:2])
def test_train_spectral_refuses_unbounded_grids(tmp_path, spec):
    res = runner.invoke(app, ["train-spectral", "--out", str(tmp_path / "run"), "--wavelengths", spec])
    assert res.exit_code == 2 and f"wavelengths = '{spec}' is not allowed" in res.output, res.output
    assert "Traceback" not in res.output


def test_the_limit_itself_is_allowed_and_a_long_list_is_refused():
    assert parse_range("-w", f"400:{400 + (MAX_WAVELENGTHS - 1) * 0.1:g}:0.1").size == MAX_WAVELENGTHS
    with pytest.raises(ParameterError, match="at most"):
        parse_range("-w", ",".join(["500"] * (MAX_WAVELENGTHS + 1)))


def test_a_training_grid_never_passes_its_stop():
    from sandlight.predictor.training import wavelength_grid

    assert wavelength_grid("400:411:3").tolist() == [400.0, 403.0, 406.0, 409.0]  # ended at 412
    assert wavelength_grid("400:700:20").tolist() == parse_range("-w", "400:700:20").tolist()


def test_train_spectral_and_reflectance_refuse_an_out_of_range_wavelength_alike(tmp_path):
    # one check of the engine's range (check_engine_wavelengths was a copy of check_wavelengths)
    allowed = "is not allowed: wavelengths in [350, 2500] nm (the range of the optical constants)"
    res = runner.invoke(app, ["reflectance", "-n", "10", "-w", "300"])
    assert res.exit_code == 2 and f"--wavelengths = 300.0 {allowed}" in res.output, res.output
    res = runner.invoke(app, ["train-spectral", "--out", str(tmp_path / "run"), "--wavelengths", "300:400:50"])
    assert res.exit_code == 2 and f"wavelengths = 300.0 {allowed}" in res.output, res.output
