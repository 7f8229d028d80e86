"""Commands train-spatial and appearance (tiny real-engine run; synthetic models for the table)."""

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
