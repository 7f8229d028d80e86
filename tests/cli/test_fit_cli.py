"""sandlight fit: a CSV spectrum in, the fit as TOML and a plot out; bad options named."""

import tomllib

import numpy as np
import pytest
from typer.testing import CliRunner

from sandlight.cli import app
from sandlight.cli.fit import parse_fixed
from sandlight.errors import ParameterError
from sandlight.predictor import default_model
from sandlight.sample import SandSample

runner = CliRunner()


@pytest.fixture()
def spectrum_csv(tmp_path):
    bank = default_model()
    truth = SandSample(iron_oxide=0.02, hematite_ratio=0.3)
    path = tmp_path / "dune.csv"
    rows = "\n".join(f"{w:g},{r:.6f}" for w, r in zip(bank.wavelengths_, bank.predict([truth])[0], strict=True))
    path.write_text("wavelength_nm,reflectance\n" + rows + "\n")
    return path


def test_fit_writes_the_toml_and_the_plot(spectrum_csv, tmp_path):
    out, png = tmp_path / "fit.toml", tmp_path / "fit.png"
    res = runner.invoke(
        app,
        [
            "fit",
            str(spectrum_csv),
            "--free",
            "iron_oxide,hematite_ratio",
            "--fixed",
            "saturation=0",
            "--noise",
            "0.002",
            "--check-rays",
            "0",
            "-o",
            str(out),
            "--plot",
            str(png),
        ],
    )
    assert res.exit_code == 0, res.output
    assert "iron_oxide = 0.02" in res.output and "reference-dry" in res.output
    doc = tomllib.loads(out.read_text())
    assert doc["parameters"]["hematite_ratio"]["estimate"] == pytest.approx(0.3, abs=1e-3)
    assert SandSample.from_dict(doc["sample"]).saturation == 0.0
    assert png.stat().st_size > 1000


def test_fit_names_the_bad_option(spectrum_csv):
    res = runner.invoke(app, ["fit", str(spectrum_csv), "--free", "iron_oxide", "--fixed", "iron_oxide=0.1"])
    assert res.exit_code == 2 and "also free" in res.output
    res = runner.invoke(app, ["fit", str(spectrum_csv), "--free", "iron_oxide", "--method", "guess"])
    assert res.exit_code == 2 and "--method = 'guess' is not allowed" in res.output


def test_parse_fixed():
    assert parse_fixed("saturation=0, iron_oxide_form=mixed") == {"saturation": 0.0, "iron_oxide_form": "mixed"}
    assert parse_fixed(None) == {}
    with pytest.raises(ParameterError, match="NAME=VALUE"):
        parse_fixed("saturation")
    assert np.isclose(parse_fixed("grain_size=1e-1")["grain_size"], 0.1)
