"""The two scenes of the paper run end to end from the command line at a tiny size."""

import numpy as np
import pytest
import xarray as xr
from PIL import Image
from typer.testing import CliRunner

from sandlight.cli import app

runner = CliRunner()


@pytest.mark.parametrize("scene", ["desert-day", "beach-drying"])
def test_render_command_writes_frames_and_a_video(tmp_path, scene):
    out = tmp_path / "frames"
    video = tmp_path / f"{scene}.mp4"
    result = runner.invoke(
        app,
        [
            "render",
            scene,
            "-o",
            str(out),
            "--video",
            str(video),
            "--width",
            "32",
            "--height",
            "18",
            "--spp",
            "2",
            "--frames",
            "2",
            "--no-progress",
        ],
    )
    assert result.exit_code == 0, result.output
    pngs = sorted(out.glob("frame_*.png"))
    assert [p.name for p in pngs] == ["frame_0000.png", "frame_0001.png"]
    first = np.asarray(Image.open(pngs[0]))
    assert first.shape == (18, 32, 3)
    assert first.std() > 1  # a picture, not a flat colour
    assert not np.array_equal(first, np.asarray(Image.open(pngs[1])))  # the sun moved
    with xr.open_dataset(out / "frame_0000.nc", engine="h5netcdf") as ds:
        assert ds["XYZ"].shape == (18, 32, 3) and float(ds["XYZ"].min()) >= 0
        assert 0 < float(ds["coverage"].mean()) <= 1
    assert video.stat().st_size > 500
    assert not list(tmp_path.glob(".*")) and not list(out.glob(".*"))  # no temporary files left


def test_spectral_output_and_errors(tmp_path):
    result = runner.invoke(
        app,
        [
            "render",
            "beach-drying",
            "-o",
            str(tmp_path),
            "--width",
            "8",
            "--height",
            "6",
            "--spp",
            "1",
            "--frames",
            "1",
            "--linear",
            "spectral",
            "--no-progress",
        ],
    )
    assert result.exit_code == 0, result.output
    with xr.open_dataset(tmp_path / "frame_0000.nc", engine="h5netcdf") as ds:
        assert ds["radiance"].shape == (6, 8, 16)
        assert ds["radiance"].attrs["units"] == "W m-2 sr-1 nm-1"
    bad = runner.invoke(app, ["render", "beach-drying", "-o", str(tmp_path), "--spp", "0", "--no-progress"])
    assert bad.exit_code == 2 and "spp" in bad.output
    missing = runner.invoke(app, ["render", "no-such-scene", "-o", str(tmp_path)])
    assert missing.exit_code == 2 and "desert-day" in missing.output
    scene = tmp_path / "bad.toml"
    scene.write_text("[camera]\nfov_deg = 400\n[sun]\nlatitude_deg = 30\nday_of_year = 100\nstart_h = 9\nend_h = 10\n")
    wrong = runner.invoke(app, ["render", str(scene), "-o", str(tmp_path)])
    assert wrong.exit_code == 2 and "camera.fov_deg" in wrong.output
