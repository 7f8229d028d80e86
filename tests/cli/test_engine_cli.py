"""The engine's commands: reflectance, demo, brdf; errors; Ctrl-C."""

import json
import os
import signal
import subprocess
import sys
import time

import pandas as pd
import pytest
import xarray as xr
from typer.testing import CliRunner

from sandlight.cli import app

runner = CliRunner()


def test_reflectance_writes_netcdf_csv_and_plot(tmp_path):
    nc, csv, png = tmp_path / "r.nc", tmp_path / "r.csv", tmp_path / "r.png"
    res = runner.invoke(
        app, ["reflectance", "--preset", "red-dune", "-w", "450,650", "-n", "2000", "-o", str(nc), "--plot", str(png)]
    )
    assert res.exit_code == 0, res.output
    ds = xr.open_dataset(nc, engine="h5netcdf")
    assert ds["reflectance"].shape == (2,) and ds.attrs["rays"] == 2000
    res = runner.invoke(app, ["reflectance", "--preset", "red-dune", "-w", "450:650:100", "-n", "1e3", "-o", str(csv)])
    assert res.exit_code == 0, res.output
    table = pd.read_csv(csv, comment="#")
    assert table.shape == (3, 5) and list(table.columns)[:2] == ["wavelength_nm", "reflectance"]
    comments = [line for line in csv.read_text().splitlines() if line.startswith("# ")]
    assert "# rays: 1000" in comments and "# seed: 0" in comments
    assert any("units: wavelength_nm nm" in c for c in comments)
    assert png.stat().st_size > 1000


def test_reflectance_shares_paths_unless_told_not_to(tmp_path):
    # Sharing applies to the classic model and to the path memories, the default 'packed'
    # included (docs/transport.md).
    cases = [(["--memory", "none"], 1), (["--memory", "none", "--no-share"], 0), ([], 1), (["--no-share"], 0)]
    for flag, shared in cases:
        nc = tmp_path / f"r{len(flag)}.nc"
        args = ["reflectance", "--preset", "red-dune", "-w", "450,550", "-n", "1000", "-o", str(nc), *flag]
        res = runner.invoke(app, args)
        assert res.exit_code == 0, res.output
        ds = xr.open_dataset(nc, engine="h5netcdf")
        assert ds.attrs["spectral_sharing"] == shared and ds["covariance"].shape == (2, 2)


def test_reflectance_dispersion_tolerance_cuts_the_groups(tmp_path):
    # Quartz's index spans 0.017 over 400–700 nm: one group at the default 0.02, several at 0.005.
    groups = {}
    for tolerance in ("0.02", "0.005"):
        nc = tmp_path / f"r{tolerance}.nc"
        args = ["reflectance", "--preset", "ottawa-quartz", "-w", "400:700:100", "-n", "500", "-o", str(nc)]
        res = runner.invoke(app, [*args, "--dispersion-tolerance", tolerance])
        assert res.exit_code == 0, res.output
        ds = xr.open_dataset(nc, engine="h5netcdf")
        assert ds.attrs["dispersion_tolerance"] == float(tolerance)
        groups[tolerance] = len(json.loads(ds.attrs["spectral_groups"]))
    assert groups["0.02"] == 1 and groups["0.005"] > 1
    bad = ["reflectance", "--preset", "red-dune", "-w", "550", "-n", "10", "--dispersion-tolerance", "2"]
    res = runner.invoke(app, bad)
    assert res.exit_code == 2 and "--dispersion-tolerance" in res.output, res.output


def test_reflectance_with_path_memory_and_explicit_geometry(tmp_path):
    nc = tmp_path / "r.nc"
    res = runner.invoke(
        app, ["reflectance", "--preset", "red-dune", "-w", "550", "-n", "3000", "--memory", "cut", "-o", str(nc)]
    )
    assert res.exit_code == 0, res.output
    assert xr.open_dataset(nc, engine="h5netcdf").attrs["memory"] == "cut"
    for args, needle in [(["--memory", "full"], "memory"), (["--geometry", "packed"], "geometry")]:
        res = runner.invoke(app, ["reflectance", "--preset", "red-dune", "-w", "550", "-n", "10", *args])
        assert res.exit_code == 2 and needle in res.output, res.output


def test_reflectance_from_a_sample_file(tmp_path):
    f = tmp_path / "s.toml"
    f.write_text('preset = "yellow-dune"\nsaturation = 0.5\n')
    res = runner.invoke(app, ["reflectance", str(f), "-w", "550", "-n", "500"])
    assert res.exit_code == 0, res.output


def test_bad_inputs_exit_2_with_a_message(tmp_path):
    for args, needle in [
        (["reflectance", "--preset", "red-dune", "-w", "200", "-n", "10"], "--wavelengths = 200.0 is not allowed"),
        (["reflectance", "--preset", "red-dune", "-n", "lots"], "--rays"),
        (["reflectance", "--preset", "no-such-preset", "-n", "10"], "no-such-preset"),
        (["reflectance", str(tmp_path / "missing.toml"), "-n", "10"], "missing.toml"),
        (["reflectance", "--preset", "red-dune", "-w", "400:300:10"], "--wavelengths"),
        (
            ["brdf", "--preset", "red-dune", "--stacks", "1", "-n", "10", "-o", str(tmp_path / "b.nc")],
            "--stacks = 1 is not allowed",
        ),
    ]:
        res = runner.invoke(app, args)
        assert res.exit_code == 2, (args, res.output)
        assert needle in res.output, (args, res.output)


def test_brdf_command(tmp_path):
    out, png = tmp_path / "b.nc", tmp_path / "b.png"
    res = runner.invoke(
        app,
        [
            "brdf",
            "--preset",
            "red-dune",
            "-n",
            "20000",
            "--stacks",
            "7",
            "--slices",
            "6",
            "-o",
            str(out),
            "--plot",
            str(png),
        ],
    )
    assert res.exit_code == 0, res.output
    from sandlight.gonio.io import read_netcdf

    assert read_netcdf(out).hemisphere.n_patches == 37 and png.exists()
    assert not (tmp_path / "b.nc.checkpoint.npz").exists()
    cut = tmp_path / "cut.nc"
    res = runner.invoke(
        app,
        [
            "brdf",
            "--preset",
            "red-dune",
            "-n",
            "5000",
            "--stacks",
            "7",
            "--slices",
            "6",
            "--memory",
            "cut",
            "-o",
            str(cut),
        ],
    )
    assert res.exit_code == 0, res.output
    assert read_netcdf(cut).sample["memory"] == "cut"


@pytest.mark.parametrize("share", ["--share", "--no-share"])
def test_brdf_command_over_several_wavelengths_writes_one_file_each(tmp_path, share):
    from sandlight.gonio.io import read_netcdf

    out = tmp_path / "b.nc"
    args = ["brdf", "--preset", "red-dune", "-w", "500,600", "-n", "3000", "--stacks", "5", "--slices", "4"]
    res = runner.invoke(app, [*args, share, "-o", str(out)])
    assert res.exit_code == 0, res.output
    files = sorted(p.name for p in tmp_path.iterdir())
    assert files == ["b-500nm.nc", "b-600nm.nc"], files
    b = read_netcdf(tmp_path / "b-600nm.nc")
    assert b.wavelength_nm == 600.0 and (b.squares is not None) == (share == "--share")
    assert "at 600 nm" in res.output


def test_brdf_refuses_a_malformed_checkpoint_with_exit_2(tmp_path):
    out = tmp_path / "b.nc"
    ck = tmp_path / "b.nc.checkpoint.npz"
    args = ["brdf", "--preset", "red-dune", "-n", "5000", "--stacks", "7", "--slices", "6", "-o", str(out)]
    for content in (b"", b"PK\x03\x04 truncated"):
        ck.write_bytes(content)
        res = runner.invoke(app, args)
        assert res.exit_code == 2, res.output
        assert "b.nc.checkpoint.npz" in res.output and "delete it to start afresh" in res.output
        assert "Traceback" not in res.output and "Aborted" not in res.output and not out.exists()


def test_brdf_with_too_few_rays_warns_of_the_nan_values(tmp_path):
    out = tmp_path / "b.nc"
    res = runner.invoke(app, ["brdf", "--preset", "red-dune", "--rays", "100", "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert "13561 of 13561 BRDF values are NaN" in res.output and "at least about 10280 rays" in res.output
    # after the warning, the summary line said "normal-incidence reflectance nan"
    assert "normal-incidence reflectance unknown (too few rays: see the warning)" in res.output
    assert "nan" not in res.output


def test_ctrl_c_stops_a_long_run_cleanly(tmp_path):
    out = tmp_path / "never.nc"
    proc = subprocess.Popen(
        [sys.executable, "-m", "sandlight", "reflectance", "--preset", "ottawa-quartz", "-n", "1e10", "-o", str(out)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        cwd=tmp_path,
        env={**os.environ, "COLUMNS": "200"},
        # A shell's background job inherits SIGINT ignored; give the child the default.
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    # Interrupt once the run has started (start-up time varies with the machine's load).
    deadline = time.monotonic() + 120
    line = b""
    while b"tracing" not in line and time.monotonic() < deadline:
        line = proc.stdout.readline()
    assert b"tracing" in line, "the run never started"
    time.sleep(1.0)
    proc.send_signal(signal.SIGINT)
    try:
        _, err = proc.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        proc.kill()
        raise AssertionError("the run did not stop within 30 s of Ctrl-C") from None
    assert proc.returncode == 130, err
    assert b"interrupted" in err
    assert not out.exists() and not list(tmp_path.glob(".never.nc*"))
