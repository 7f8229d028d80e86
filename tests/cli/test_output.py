"""What the command line prints: user text verbatim (no rich markup, no highlighting), no
control characters from files, warnings as one plain line (issue 24 #1, #13 and the tour)."""

import os
import subprocess
import sys

from typer.testing import CliRunner

from sandlight.cli import app

runner = CliRunner()


def test_markup_in_an_output_path_is_printed_verbatim(tmp_path):
    (tmp_path / "[").mkdir()
    out = tmp_path / "[" / "]y.nc"  # the path holds "[/]", rich's closing tag
    res = runner.invoke(app, ["reflectance", "--preset", "red-dune", "-w", "550", "-n", "200", "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert f"wrote {out}" in res.output and out.exists()


def test_markup_in_a_value_and_in_a_message_is_printed_verbatim(tmp_path):
    res = runner.invoke(app, ["reflectance", "--preset", "[link=https://example.org]x[/link]", "-n", "10"])
    assert res.exit_code == 2 and "preset = '[link=https://example.org]x[/link]' is not allowed" in res.output
    sample = tmp_path / "s.toml"
    sample.write_text('note = "[/]"\n[sample]\niron_oxide = 0.02\n')
    res = runner.invoke(app, ["reflectance", str(sample), "-n", "10"])
    assert res.exit_code == 2, res.output
    assert "note = '[/]' is not allowed: no keys are allowed outside the [sample] table" in res.output


def test_control_characters_read_from_a_model_file_are_not_printed(tmp_path):
    import copy

    from sandlight.predictor import default_model

    model = copy.deepcopy(default_model().models[0])  # the shipped bank is shared: not changed
    model.name_ = "\x1b[2J\x1b]0;pwned\x07dune\rmodel"  # clear screen, set the title, overwrite the line
    path = model.save(tmp_path / "evil.npz")
    res = runner.invoke(app, ["predict", "--preset", "red-dune", "--model", str(path), "--extrapolate"])
    assert res.exit_code == 0, res.output
    assert "[2J]0;pwneddunemodel" in res.output
    assert not any(c in res.output for c in "\x1b\x07\r")


def test_warnings_are_shown_as_one_plain_line(tmp_path):
    sample = tmp_path / "wet.toml"
    sample.write_text('preset = "red-dune"\nsaturation = 0.6\n')
    res = runner.invoke(app, ["reflectance", str(sample), "-w", "550", "-n", "200", "--memory", "cut"])
    assert res.exit_code == 0, res.output
    lines = [line for line in res.output.splitlines() if "warning" in line.lower()]
    assert len(lines) == 1 and lines[0].startswith("warning: "), res.output
    assert "UserWarning" not in res.output and "warnings.warn" not in res.output and ".py:" not in res.output


def test_digits_inside_names_are_not_highlighted(tmp_path):
    # On a colour terminal rich's highlighter wrapped the "02" of "Hematite.02" in colour codes.
    out = tmp_path / "Hematite.02.nc"
    env = {**os.environ, "FORCE_COLOR": "1", "TERM": "xterm-256color", "COLUMNS": "300"}
    command = ["reflectance", "--preset", "red-dune", "-w", "550", "-n", "100", "-o", str(out)]
    proc = subprocess.run([sys.executable, "-m", "sandlight", *command], capture_output=True, text=True, env=env)
    assert proc.returncode == 0, proc.stderr
    assert "\x1b[" in proc.stdout  # a colour terminal indeed (the table's styles)
    assert f"wrote {out}\n" in proc.stdout


def test_a_scene_name_with_control_characters_is_refused_before_the_progress_bar_shows_it(tmp_path):
    scene = tmp_path / "esc.toml"
    scene.write_text('[scene]\nname = "x\\u001b[2Jy"\n')
    res = runner.invoke(app, ["render", str(scene), "-o", str(tmp_path / "frames"), "--width", "8", "--height", "8"])
    assert res.exit_code == 2 and "scene.name = 'x\\x1b[2Jy' is not allowed: text without control" in res.output
    assert "\x1b" not in res.output and not (tmp_path / "frames").exists()
