"""NetCDF outputs follow the CF conventions and CSV outputs carry their metadata (issue 24)."""

import json

import pandas as pd
import pytest
import xarray as xr
from typer.testing import CliRunner

from sandlight.cli import app
from sandlight.io import CF_CONVENTIONS

runner = CliRunner()

CF_GLOBAL = ("Conventions", "title", "source", "history", "references")


def _assert_cf(path):
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        assert ds.attrs["Conventions"] == CF_CONVENTIONS
        assert all(ds.attrs[key] for key in CF_GLOBAL)
        for name, variable in {**ds.data_vars, **ds.coords}.items():
            if variable.dtype.kind in "fiu":  # numbers have units and a long name
                assert "units" in variable.attrs and "long_name" in variable.attrs, name
        return dict(ds.attrs)


@pytest.mark.parametrize(
    ("command", "file"),
    [
        (["reflectance", "--preset", "red-dune", "-w", "450,550", "-n", "300", "--seed", str(2**64 - 1)], "r.nc"),
        (["brdf", "--preset", "red-dune", "-n", "2000", "--stacks", "4", "--slices", "3", "--seed", "7"], "b.nc"),
        (["appearance", "--preset", "red-dune", "--n-mu", "4", "--n-dphi", "3"], "t.nc"),
    ],
)
def test_netcdf_outputs_follow_cf_conventions(tmp_path, command, file):
    out = tmp_path / file
    res = runner.invoke(app, [*command, "-o", str(out)])
    assert res.exit_code == 0, res.output
    attrs = _assert_cf(out)
    if "--seed" in command:  # the seed is an integer (it was a string), of the full 64-bit range
        seed = attrs["seed"]
        assert int(seed) == int(command[command.index("--seed") + 1]) and not isinstance(seed, str)


def test_a_rendered_frame_follows_cf_conventions(tmp_path):
    args = ["render", "desert-day", "-o", str(tmp_path), "--width", "8", "--height", "6", "--frames", "1"]
    res = runner.invoke(app, [*args, "--spp", "1", "--linear", "spectral", "--no-progress"])
    assert res.exit_code == 0, res.output
    _assert_cf(tmp_path / "frame_0000.nc")


def test_predict_csv_carries_its_metadata_in_comments(tmp_path):
    out = tmp_path / "p.csv"
    res = runner.invoke(app, ["predict", "--preset", "red-dune", "-o", str(out)])
    assert res.exit_code == 0, res.output
    comments = dict(line[2:].split(": ", 1) for line in out.read_text().splitlines() if line.startswith("# "))
    assert comments["model"] == "red-dune-dry" and json.loads(comments["sample"])["iron_oxide"] == 0.02
    assert comments["units"].startswith("wavelength_nm nm; reflectance 1")
    assert "sandlight" in comments["source"] and "Conventions" not in comments
    table = pd.read_csv(out, comment="#")
    assert list(table.columns) == ["wavelength_nm", "reflectance"] and len(table) == 16


def test_predict_answers_the_wavelengths_asked_for(tmp_path):
    out = tmp_path / "p.csv"
    res = runner.invoke(app, ["predict", "--preset", "red-dune", "-w", "400:700:5", "-o", str(out)])
    assert res.exit_code == 0, res.output
    table = pd.read_csv(out, comment="#")
    assert table["wavelength_nm"].tolist() == list(range(400, 701, 5))
    res = runner.invoke(app, ["predict", "--preset", "red-dune", "-w", "340:700:10"])
    assert res.exit_code == 2 and "--wavelengths = 340.0 is not allowed" in res.output, res.output
    # Beyond 700 nm the full-range models answer; with --mode paper the paper's refuse.
    res = runner.invoke(app, ["predict", "--preset", "red-dune", "-w", "350:2500:10", "-o", str(out)])
    assert res.exit_code == 0 and "model full-dry" in res.output, res.output
    assert pd.read_csv(out, comment="#")["wavelength_nm"].tolist() == list(range(350, 2501, 10))
    res = runner.invoke(app, ["predict", "--preset", "red-dune", "-w", "900", "--mode", "paper"])
    assert res.exit_code == 2 and "--wavelengths = 900.0 is not allowed" in res.output, res.output
    res = runner.invoke(app, ["predict", "--preset", "red-dune", "--mode", "infrared"])
    assert res.exit_code == 2 and "--mode = 'infrared' is not allowed" in res.output, res.output
