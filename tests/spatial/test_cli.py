"""Commands train-spatial and appearance (tiny real-engine run; synthetic models for the table)."""

import json

import numpy as np
import spatial_fakes
import xarray as xr
from typer.testing import CliRunner

from sandlight.cli import app
from sandlight.spatial import Mesh, SpatialModel

runner = CliRunner()


def test_train_spatial_command(tmp_path):
    result = runner.invoke(
        app,
        [
            "train-spatial",
            "--out",
            str(tmp_path),
            "--axis",
            "saturation=0:1:3",
            "--rays",
            "2e4",
            "--stacks",
            "4",
            "--slices",
            "4",
            "--workers",
            "1",
            "--no-progress",
            "--components",
            "1",
        ],
    )
    assert result.exit_code == 0, result.output
    assert "ℓ = 1" in result.output
    model = SpatialModel.load(tmp_path / "spatial-model.npz")
    np.testing.assert_allclose(model.mesh_.nodes[:, 0], [0, 0.5, 1])
    # Bad axes and held-out points are reported as user errors.
    bad = runner.invoke(app, ["train-spatial", "--out", str(tmp_path / "b"), "--axis", "saturation=0:1"])
    assert bad.exit_code == 2 and "--axis" in bad.output
    bad = runner.invoke(
        app, ["train-spatial", "--out", str(tmp_path / "c"), "--holdout", "porosity=0.3", "--rays", "10"]
    )
    assert bad.exit_code == 2 and "--holdout" in bad.output


def test_train_spatial_command_with_path_memory(tmp_path):
    result = runner.invoke(
        app,
        [
            "train-spatial",
            "--preset",
            "red-dune",
            "--out",
            str(tmp_path),
            "--axis",
            "iron_oxide=0.01,0.03",
            "--rays",
            "2e4",
            "--stacks",
            "4",
            "--slices",
            "4",
            "--workers",
            "1",
            "--no-progress",
            "--components",
            "1",
            "--memory",
            "packed",
        ],
    )
    assert result.exit_code == 0, result.output
    assert "engine memory 'packed'" in result.output
    assert SpatialModel.load(tmp_path / "spatial-model.npz").memory_ == "packed"
    bad = runner.invoke(app, ["train-spatial", "--out", str(tmp_path / "b"), "--rays", "10", "--memory", "full"])
    assert bad.exit_code == 2 and "memory" in bad.output


def test_appearance_command_writes_a_table(tmp_path):
    mesh = Mesh.beach(6)
    spatial = SpatialModel(n_components=2).fit(spatial_fakes.measured_nodes(mesh, 10**7), mesh)
    spatial_path = spatial.save(tmp_path / "spatial.npz")
    spectral_path = spatial_fakes.fitted_spectral_model().save(tmp_path / "spectral.npz")
    out = tmp_path / "wet.nc"
    result = runner.invoke(
        app,
        [
            "appearance",
            "--preset",
            "wet-beach",
            "--spectral-model",
            str(spectral_path),
            "--spatial-model",
            str(spatial_path),
            "--table",
            str(out),
            "--n-mu",
            "5",
            "--n-dphi",
            "4",
        ],
    )
    assert result.exit_code == 0, result.output
    assert "albedo" in result.output and "warning:" in result.output  # wet-beach is off the mesh's base sample
    with xr.open_dataset(out, engine="h5netcdf") as ds:
        assert ds["f"].shape == (16, 5, 5, 4)
        assert (ds["albedo"].values <= 1 + 1e-12).all()
    missing = runner.invoke(
        app,
        [
            "appearance",
            "--preset",
            "wet-beach",
            "--spatial-model",
            str(tmp_path / "no.npz"),
            "--spectral-model",
            str(spectral_path),
        ],
    )
    assert missing.exit_code == 2 and "does not exist" in " ".join(missing.output.split())


def test_appearance_over_the_full_range(tmp_path):
    """--mode full-range: r(λ) from the shipped 350-2500 nm models, shape from the shipped model
    that covers the sample (yellow-dune: the dune family, nothing borrowed; wet-beach: the wet
    family's mesh, at its base's other parameters)."""
    out = tmp_path / "dune.nc"
    args = ["appearance", "--preset", "yellow-dune", "--mode", "full-range", "--table", str(out)]
    result = runner.invoke(app, [*args, "--n-mu", "4", "--n-dphi", "3"])
    assert result.exit_code == 0, result.output
    assert "87 wavelengths 350–2500 nm" in result.output and "warning:" not in result.output
    with xr.open_dataset(out, engine="h5netcdf") as ds:
        wl = ds["wavelength"].values
        assert ds["f"].shape[0] == 87 and wl[0] == 350.0 and wl[-1] == 2500.0
        # the dune family's shape follows the sand's reflectance over the range
        assert ds.attrs["shape"] == "reflectance" and len(json.loads(ds.attrs["shape_reflectances"])) > 2
    fixed = runner.invoke(app, ["appearance", "--preset", "yellow-dune", "--shape", "fixed"])
    assert fixed.exit_code == 0 and "shape='fixed' (1 shapes)" in fixed.output
    bad = runner.invoke(app, ["appearance", "--preset", "yellow-dune", "--shape", "wavelength"])
    assert bad.exit_code == 2 and "--shape = 'wavelength' is not allowed" in " ".join(bad.output.split())
    wet = runner.invoke(app, ["appearance", "--preset", "wet-beach", "--mode", "full-range"])
    assert wet.exit_code == 0, wet.output
    assert "87 wavelengths 350–2500 nm" in wet.output and "mesh over saturation, iron_oxide" in wet.output
    both = runner.invoke(
        app, ["appearance", "--preset", "red-dune", "--mode", "full-range", "--spectral-model", "x.npz"]
    )
    assert both.exit_code == 2 and "--mode" in both.output
