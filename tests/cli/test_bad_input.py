"""Every subcommand's bad-input path (issue 24, Proof): exit code 2, one message naming the
option, the value and what is allowed, no traceback, no file written. And one consistent
command line: every option has help, flags show no "<bool>", counts are accepted as 1e5."""

import click
import pytest
import typer
import xarray as xr
from typer.testing import CliRunner

from sandlight.cli import app
from sandlight.predictor import SpectralModel

runner = CliRunner()

#: One bad value per subcommand: (arguments, what the message must say). The arguments name
#: outputs relative to the working directory (a fresh tmp_path), checked to stay empty.
BAD = {
    "version": (["version", "--foo"], "No such option: --foo"),
    "reflectance": (["reflectance", "-n", "0", "-o", "r.nc"], "--rays = '0' is not allowed: a whole number ≥ 1"),
    "demo": (["demo", "-n", "1e5x", "-o", "d"], "--rays = '1e5x' is not allowed"),
    "brdf": (["brdf", "--slices", "0", "-o", "b.nc"], "--slices = 0 is not allowed: a whole number in [1, 10000]"),
    "train-spectral": (["train-spectral", "--rays", "1.5", "-o", "ts"], "--rays = '1.5' is not allowed"),
    "predict": (["predict", "--preset", "nope", "-o", "p.csv"], "--preset = 'nope' is not allowed: one of"),
    "train-spatial": (["train-spatial", "--axis", "saturation", "-o", "sp"], "--axis = 'saturation' is not allowed"),
    "appearance": (["appearance", "--n-mu", "1", "-o", "t.nc"], "--n-mu = 1 is not allowed: an integer in [2, 4096]"),
    "swatches": (["swatches", "--size", "10x10", "-o", "s.png"], "--size = (10, 10) is not allowed: width 168"),
    "colourise": (
        ["colourise", "--preset", "red-dune", "--engine-rays", "0", "-o", "c.png"],
        "--engine-rays = '0' is not allowed",
    ),
    "render": (["render", "desert-day", "-o", "fr", "--spp", "0"], "--spp = 0 is not allowed: a whole number in"),
    "sky": (
        ["sky", "--latitude", "30", "--day", "100", "--time", "12", "--size", "5", "-o", "k.png"],
        "--size = 5 is not allowed: a whole number of pixels in [16, 4096]",
    ),
    "validate": (["validate", "--rays", "0", "-o", "v/report.md"], "--rays = '0' is not allowed"),
    "fit": (
        ["fit", "missing.csv", "--free", "iron_oxide", "--check-rays", "0", "-o", "f.toml"],
        "no such spectrum file: missing.csv",
    ),
    "serve": (
        ["serve", "--host", "0.0.0.0", "--no-open"],
        "--host = '0.0.0.0' is not allowed: a loopback address (127.0.0.1, ::1, localhost) unless --allow-remote",
    ),
}


def _commands():
    group = typer.main.get_command(app)
    ctx = click.Context(group)
    return {name: group.get_command(ctx, name) for name in group.list_commands(ctx)}


def test_every_subcommand_has_a_bad_input_case():
    assert set(_commands()) == set(BAD)


@pytest.mark.parametrize("command", sorted(BAD))
def test_bad_input_exits_2_naming_the_option_without_traceback_or_file(tmp_path, monkeypatch, command):
    monkeypatch.chdir(tmp_path)
    args, message = BAD[command]
    res = runner.invoke(app, args)
    text = " ".join(res.output.replace("│", " ").split())  # usage errors come in a box
    assert res.exit_code == 2 and message in text, res.output
    assert "Traceback" not in res.output and res.exception is None or isinstance(res.exception, SystemExit)
    assert not list(tmp_path.iterdir()), list(tmp_path.iterdir())


def test_every_option_has_help_and_flags_show_no_type():
    for name, command in _commands().items():
        for param in command.params:
            if isinstance(param, click.Option):
                assert param.help, (name, param.name)
        res = runner.invoke(app, [name, "--help"], terminal_width=200)
        assert res.exit_code == 0 and "<bool>" not in res.output, (name, res.output)


@pytest.mark.parametrize(
    "args",
    [
        ["reflectance", "-w", "550", "--rays", "1e2"],
        [
            "train-spectral",
            "--rays",
            "1e2",
            "--samples",
            "12",
            "--degree",
            "1",
            "--holdout",
            "0",
            "-w",
            "550",
            "--workers",
            "1",
        ],
        ["swatches", "--engine-rays", "1e2", "--x", "iron_oxide=0.01:0.02:2", "--y", "saturation=0:1:2"],
    ],
)
def test_counts_written_like_1e2_are_accepted_everywhere(tmp_path, args):
    out = tmp_path / ("s.png" if args[0] == "swatches" else "run" if args[0] == "train-spectral" else "r.nc")
    res = runner.invoke(app, [*args, "-o", str(out), *(["--no-progress"] if args[0] == "train-spectral" else [])])
    assert res.exit_code == 0, res.output
    assert out.exists()


def test_reflectance_without_a_sample_says_which_it_uses():
    res = runner.invoke(app, ["reflectance", "-w", "550", "-n", "100"])
    assert res.exit_code == 0 and "no sample given: using the red-dune preset" in res.output, res.output


def test_train_spectral_names_a_bad_regressor_before_any_run(tmp_path):
    out = tmp_path / "run"
    res = runner.invoke(app, ["train-spectral", "--regressor", "forest", "-w", "550", "-o", str(out), "--no-progress"])
    assert res.exit_code == 2 and "--regressor = 'forest' is not allowed" in res.output, res.output
    assert not (out / "training").exists()


def test_train_spectral_clean_corner_adds_samples_there_and_refuses_a_negative_count(tmp_path):
    out = tmp_path / "run"
    args = ["train-spectral", "--rays", "1e2", "--samples", "12", "--degree", "1", "--holdout", "0", "-w", "550"]
    res = runner.invoke(app, [*args, "--workers", "1", "--clean-corner", "6", "-o", str(out), "--no-progress"])
    assert res.exit_code == 0, res.output
    with xr.open_dataset(out / "enrichment" / "dataset.nc") as extra:
        assert extra.sizes["sample"] == 6 and (extra["iron_oxide"].values == 0).all()
    assert SpectralModel.load(out / "spectral-model.npz").training_set_["enrichment"]["n_samples"] == 6
    bad = runner.invoke(app, [*args, "--clean-corner", "-1", "-o", str(tmp_path / "bad"), "--no-progress"])
    assert bad.exit_code == 2 and "--clean-corner = -1 is not allowed" in bad.output, bad.output


def test_train_spectral_takes_the_broad_recipe_and_refuses_it_for_monomials(tmp_path):
    out = tmp_path / "run"
    args = ["train-spectral", "--rays", "1e2", "--samples", "40", "--holdout", "0", "-w", "550", "--workers", "1"]
    recipe = ["--regressor", "network", "--hidden-units", "8", "--learning-rates", "1e-3,1e-4"]
    recipe += ["--validation", "error", "--physical-inputs"]
    res = runner.invoke(app, [*args, *recipe, "-o", str(out), "--no-progress"])
    assert res.exit_code == 0, res.output
    model = SpectralModel.load(out / "spectral-model.npz")
    assert model.learning_rates == (1e-3, 1e-4) and model.network_validation == "error"
    assert len(model.physical_inputs) == 5
    for bad, message in (
        (["--physical-inputs"], "--physical-inputs = True is not allowed: only with --regressor network"),
        (["--regressor", "network", "--learning-rates", "fast"], "--learning-rates = 'fast' is not allowed"),
        (["--regressor", "network", "--validation", "loss"], "--validation = 'loss' is not allowed"),
    ):
        res = runner.invoke(app, [*args, *bad, "-o", str(tmp_path / "bad"), "--no-progress"])
        assert res.exit_code == 2 and message in res.output, res.output
        assert not (tmp_path / "bad" / "training").exists()
