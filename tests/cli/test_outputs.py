"""Outputs are checked before any work (issue 24 #2, #17, #18): a directory where a file is
expected, a missing or unwritable directory, a suffix that is not the format written: exit 2
with a message naming the option, no traceback, nothing written. --help says outputs are
overwritten."""

import os

import pytest
from typer.testing import CliRunner

from sandlight.cli import app

runner = CliRunner()

RUN = ["--preset", "red-dune", "-n", "2000"]


@pytest.fixture
def places(tmp_path, monkeypatch):
    """A file, a directory and a directory that cannot be written (as root, chmod does not stop
    a write, so os.access is told so)."""
    (tmp_path / "file.txt").write_text("mine")
    (tmp_path / "dir").mkdir()
    (tmp_path / "dir.png").mkdir()
    (tmp_path / "ro").mkdir()
    access = os.access
    read_only = str(tmp_path / "ro")
    monkeypatch.setattr(os, "access", lambda p, mode, **kw: os.path.abspath(p) != read_only and access(p, mode, **kw))
    monkeypatch.chdir(tmp_path)
    return tmp_path


CASES = [
    (["reflectance", *RUN, "-o", "dir"], "--output = 'dir' is not allowed: a file, but this is a directory"),
    (["reflectance", *RUN, "-o", "out.txt"], "--output = 'out.txt' is not allowed: a file name ending in .nc or .csv"),
    (["reflectance", *RUN, "-o", "file.txt/r.nc"], "'file.txt' is a file"),
    (["reflectance", *RUN, "-o", "ro/r.nc"], "a path in a directory you can write to ('ro' is not)"),
    (["reflectance", *RUN, "--plot", "ro/new/p.png"], "--plot = 'ro/new/p.png'"),
    (["reflectance", *RUN, "--plot", "p.pdf"], "a file name ending in .png"),
    (["brdf", *RUN, "-o", "b.nc", "--plot", "missing/p.png"], "--plot = 'missing/p.png' is not allowed"),
    (["brdf", *RUN, "-o", "missing/b.nc"], "('missing' does not exist)"),
    (["brdf", *RUN, "-o", "b.txt"], "a file name ending in .nc"),
    (
        ["demo", "-n", "1000", "-o", "file.txt"],
        "--output = 'file.txt' is not allowed: a directory, but this is a file",
    ),
    (
        ["train-spectral", "--out", "file.txt", "--samples", "20", "--rays", "100", "--workers", "1"],
        "--output = 'file.txt' is not allowed: a directory",
    ),
    (
        ["train-spatial", "--out", "ro/run", "-n", "1000", "--axis", "saturation=0:1:2", "--workers", "1"],
        "--output = 'ro/run' is not allowed",
    ),
    (["predict", "--preset", "red-dune", "-o", "dir"], "--output = 'dir' is not allowed"),
    (["predict", "--preset", "red-dune", "-o", "r.txt"], "a file name ending in .csv"),
    (
        ["predict", "--preset", "red-dune", "--plot", "dir"],
        "--plot = 'dir' is not allowed: a file, but this is a directory",
    ),
    (["appearance", "--preset", "red-dune", "--table", "t.csv"], "--output = 't.csv' is not allowed"),
    (["sky", "--latitude", "30", "--day", "100", "--time", "12", "-o", "k.jpg"], "a file name ending in .png"),
    (["swatches", "-o", "ro/g.png"], "--output = 'ro/g.png' is not allowed"),
    (["colourise", "--preset", "red-dune", "-o", "dir.png"], "--output = 'dir.png' is not allowed: a file, but"),
    (["colourise", "--preset", "red-dune", "-o", "photo.xyz"], "another extension pillow can write"),
    (["render", "desert-day", "-o", "file.txt"], "--output = 'file.txt' is not allowed: a directory"),
    (["render", "desert-day", "-o", "frames", "--video", "v.avi"], "a file name ending in .mp4"),
    (["validate", "-n", "100", "--no-variants", "-o", "report.txt"], "a file name ending in .md"),
    (["validate", "-n", "100", "--no-variants", "--figures", "file.txt"], "--figures = 'file.txt' is not allowed"),
]


@pytest.mark.parametrize(("args", "message"), CASES, ids=[" ".join(a[:1] + a[-2:]) for a, _ in CASES])
def test_a_bad_output_is_refused_before_any_work(places, args, message):
    before = sorted(p.relative_to(places) for p in places.rglob("*"))
    res = runner.invoke(app, args)
    assert res.exit_code == 2, res.output
    assert message in res.output and "Traceback" not in res.output
    assert sorted(p.relative_to(places) for p in places.rglob("*")) == before  # nothing written


def test_a_video_into_a_read_only_directory_is_refused_before_rendering(places):
    # It rendered every frame, then failed with "No such file or directory: …part -> v.mp4" (#18).
    res = runner.invoke(app, ["render", "desert-day", "-o", "frames", "--video", "ro/v.mp4", "--no-progress"])
    assert res.exit_code == 2 and "--video = 'ro/v.mp4' is not allowed" in res.output, res.output
    assert not (places / "frames").exists()


@pytest.mark.parametrize(
    "command",
    [
        "reflectance",
        "demo",
        "brdf",
        "train-spectral",
        "train-spatial",
        "predict",
        "appearance",
        "validate",
        "swatches",
        "colourise",
        "render",
        "sky",
    ],
)
def test_help_says_outputs_are_overwritten(command):
    res = runner.invoke(app, [command, "--help"], env={"COLUMNS": "200"})
    assert res.exit_code == 0 and "overwritten" in res.output, res.output


def test_an_os_error_during_the_work_is_a_message_not_a_traceback(places, monkeypatch):
    # Checks before the work cannot foresee everything (a disk that fills up, a file system
    # remounted read-only): such OS errors were tracebacks.
    from sandlight.engine import ReflectanceResult

    def refuse(self, path):
        raise PermissionError(13, "Permission denied", str(path))

    monkeypatch.setattr(ReflectanceResult, "to_netcdf", refuse)
    res = runner.invoke(app, ["reflectance", *RUN, "-w", "550", "-o", "r.nc"])
    assert res.exit_code == 2, res.output
    assert "error: [Errno 13] Permission denied: 'r.nc'" in res.output and "Traceback" not in res.output
