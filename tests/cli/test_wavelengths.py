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
