"""One sample loader for every command (issue 24 #6, #14): TOML or JSON, keys at the top level or
in a [sample] table and nowhere else, regular files of bounded size only; bad samples exit 2."""

import json
import os
import resource
import subprocess
import sys

import pytest
from typer.testing import CliRunner

from sandlight.cli import app

runner = CliRunner()

#: Every command that takes a sample file, with the options that make it cheap.
SAMPLE_COMMANDS = {
    "reflectance": lambda f: ["reflectance", f, "-w", "550", "-n", "100"],
    "brdf": lambda f: ["brdf", f, "-n", "100", "--stacks", "7", "--slices", "6", "-o", "b.nc"],
    "predict": lambda f: ["predict", f],
    "appearance": lambda f: ["appearance", f, "--n-mu", "2", "--n-dphi", "2"],
    "train-spatial": lambda f: ["train-spatial", f, "--out", "run", "-n", "100", "--axis", "saturation=0:1:2"],
    "swatches": lambda f: ["swatches", "--sample", f, "-o", "g.png"],
    "colourise": lambda f: ["colourise", "--sample", f, "-o", "c.png"],
}


@pytest.fixture
def here(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return tmp_path


def _reflectances(output: str) -> list[str]:
    return [line for line in output.splitlines() if "nm" not in line and "0." in line]


def test_predict_reads_json_like_every_command(here):
    (here / "s.json").write_text(json.dumps({"preset": "yellow-dune", "saturation": 0.1}))
    (here / "s.toml").write_text('[sample]\npreset = "yellow-dune"\nsaturation = 0.1\n')
    from_json = runner.invoke(app, ["predict", "s.json"])
    from_toml = runner.invoke(app, ["predict", "s.toml"])
    assert from_json.exit_code == 0 and from_toml.exit_code == 0, from_json.output
    assert _reflectances(from_json.output) == _reflectances(from_toml.output) != []


@pytest.mark.parametrize("command", sorted(SAMPLE_COMMANDS))
def test_keys_outside_the_sample_table_are_refused_by_every_command(here, command):
    # predict ignored the top-level iron_oxide (it read only the [sample] table).
    (here / "s.toml").write_text("iron_oxide = 0.02\n[sample]\nsaturation = 0.5\n")
    res = runner.invoke(app, SAMPLE_COMMANDS[command]("s.toml"))
    assert res.exit_code == 2, res.output
    assert "iron_oxide = 0.02 is not allowed: no keys are allowed outside the [sample] table" in res.output


@pytest.mark.parametrize("command", sorted(SAMPLE_COMMANDS))
def test_a_bad_value_exits_2_in_every_command(here, command):
    (here / "s.json").write_text('{"porosity": 0.9}')
    res = runner.invoke(app, SAMPLE_COMMANDS[command]("s.json"))
    assert res.exit_code == 2 and "porosity = 0.9 is not allowed" in res.output, res.output


@pytest.mark.parametrize("command", sorted(SAMPLE_COMMANDS))
def test_a_directory_as_sample_is_refused_by_every_command(here, command):
    (here / "dir.toml").mkdir()
    res = runner.invoke(app, SAMPLE_COMMANDS[command]("dir.toml"))
    assert res.exit_code == 2 and "sample file = 'dir.toml' is not allowed: a regular file" in res.output, res.output
    assert "Traceback" not in res.output


def test_predict_needs_exactly_one_sample(here):
    (here / "s.toml").write_text("")
    for args in (["predict"], ["predict", "s.toml", "--preset", "red-dune"]):
        res = runner.invoke(app, args)
        assert res.exit_code == 2 and "SAMPLE/--preset" in res.output, res.output


def test_predict_plot_is_written_in_the_format_of_its_suffix(here):
    res = runner.invoke(app, ["predict", "--preset", "red-dune", "--plot", "p.svg"])
    assert res.exit_code == 0, res.output
    assert (here / "p.svg").read_text().lstrip().startswith("<?xml") and os.listdir(here) == ["p.svg"]


def _limited() -> None:
    # If a regression read /dev/zero again, fail with MemoryError at 4 GiB, not take the machine.
    resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))


@pytest.mark.parametrize("command", ["predict", "reflectance"])
@pytest.mark.parametrize("kind", ["fifo", "dev-zero"])
def test_special_files_are_refused_without_reading_them(here, command, kind):
    path = here / "s.toml"
    if kind == "fifo":
        os.mkfifo(path)  # opening it for reading waited for a writer for ever
    else:
        path.symlink_to("/dev/zero")  # read until MemoryError
    proc = subprocess.run(
        [sys.executable, "-m", "sandlight", *SAMPLE_COMMANDS[command]("s.toml")],
        capture_output=True,
        text=True,
        timeout=120,
        preexec_fn=_limited,
        env={**os.environ, "COLUMNS": "200"},
    )
    assert proc.returncode == 2, proc.stderr
    assert "sample file = 's.toml' is not allowed: a regular file (not a directory, device, pipe or socket)" in (
        proc.stderr
    )
