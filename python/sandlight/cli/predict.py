"""Commands of the spectral predictor: train-spectral, predict."""

from __future__ import annotations

import json
from pathlib import Path

import typer

from sandlight.checks import check_choice, check_count, parse_range
from sandlight.cli._app import app
from sandlight.cli._common import (
    COUNT_FORM,
    PRESET_HELP,
    SAMPLE_HELP,
    SEED_HELP,
    WAVELENGTHS_HELP,
    MemoryOption,
    load_sample,
    option_names,
)
from sandlight.cli._output import echo, show, table
from sandlight.errors import ParameterError
from sandlight.io import cf_attributes, check_output_directory, check_output_file, write_atomically, write_csv

#: The parameters of predictor.training.train_spectral as this command's options.
_TRAINING_OPTIONS = {
    "n_samples": "--samples",
    "wavelengths": "--wavelengths",
    "rays": "--rays",
    "seed": "--seed",
    "n_holdout": "--holdout",
    "holdout_rays": "--holdout-rays",
    "memory": "--memory",
    "n_components": "--components",
    "variance_threshold": "--variance",
    "ridge": "--ridge",
    "degree": "--degree",
    "forms": "--forms",
    "regressor": "--regressor",
    "hidden_units": "--hidden-units",
    "hidden_layers": "--hidden-layers",
    "ensemble": "--ensemble",
    "learning_rates": "--learning-rates",
    "network_validation": "--validation",
    "physical_inputs": "--physical-inputs",
    "enrichment samples": "--clean-corner",
}


@app.command("train-spectral")
def train_spectral_command(
    out: Path = typer.Option(
        ...,
        "-o",
        "--output",
        "--out",
        help="Output directory: job stores (resumed), model and report (overwritten).",
    ),
    samples: int = typer.Option(3000, "--samples", help="Training samples, ≥ 1 (paper: 3000)."),
    rays: str = typer.Option("1e5", "--rays", "-n", help=f"Rays per sample and wavelength, {COUNT_FORM}."),
    wavelengths: str = typer.Option("400:700:20", "--wavelengths", "-w", help=WAVELENGTHS_HELP),
    seed: int = typer.Option(0, "--seed", help=f"{SEED_HELP} It sets the draws and every engine seed."),
    holdout: int | None = typer.Option(
        None, "--holdout", help="Hold-out samples, ≥ 0 (default: max(20, N/10) of --samples N)."
    ),
    holdout_rays: str | None = typer.Option(
        None, "--holdout-rays", help=f"Rays per hold-out sample and wavelength, {COUNT_FORM} (default: --rays)."
    ),
    workers: int | None = typer.Option(
        None, "--workers", help="Local worker processes (1: in-process) (default: one per CPU)."
    ),
    dask_local: int | None = typer.Option(None, "--dask-local", help="Start a Dask LocalCluster of N workers."),
    scheduler: str | None = typer.Option(None, "--scheduler", help="Dask scheduler address, tcp://HOST:PORT."),
    fit_only: bool = typer.Option(False, "--fit-only", help="Only refit from the complete datasets in --out."),
    n_components: int | None = typer.Option(
        None, "--components", help="Principal components (default: by --variance)."
    ),
    variance: float = typer.Option(
        0.999, "--variance", help="Explained-variance threshold in (0, 1]: the fewest components reaching it."
    ),
    ridge: float = typer.Option(0.0, "--ridge", help="Ridge penalty, ≥ 0 (0: least squares)."),
    degree: int = typer.Option(3, "--degree", help="Degree of the monomials (paper: 3)."),
    forms: str = typer.Option(
        "separate",
        "--forms",
        help="The iron-oxide form: 'separate' (one regression per form) or 'onehot' (indicator inputs).",
    ),
    regressor: str = typer.Option(
        "monomials",
        "--regressor",
        help="'monomials' (the paper's, --degree) or 'network' (a tanh network, for many parameters).",
    ),
    hidden_units: int = typer.Option(128, "--hidden-units", help="Units per hidden layer of a network, 1-1024."),
    hidden_layers: int = typer.Option(2, "--hidden-layers", help="Hidden layers of a network, 1-4."),
    ensemble: int = typer.Option(1, "--ensemble", help="Networks fitted from successive seeds and averaged, 1-16."),
    learning_rates: str = typer.Option(
        "1e-3",
        "--learning-rates",
        help="Adam's learning rate of a network, or 2-4 falling rates separated by commas, each "
        "run until no gain (the broad models: 1e-3,1e-4,1e-5).",
    ),
    validation: str = typer.Option(
        "r2",
        "--validation",
        help="What stops a network's fit: 'r2' (the scores' mean R²) or 'error' (the reflectance's "
        "error; the broad models').",
    ),
    physical_inputs: bool = typer.Option(
        False,
        "--physical-inputs/--no-physical-inputs",
        help="Give a network the lengths the engine derives from the parameters by mass balance as "
        "inputs too (the broad models'; docs/spectral-predictor.md, 'Physical inputs').",
    ),
    clean_corner: int = typer.Option(
        0,
        "--clean-corner",
        help="Extra training samples at clean quartz sand (iron oxide, magnetite, silt, clay 0), "
        "a corner random draws hardly reach, ≥ 0 (docs/spectral-predictor.md, 'Corners of the domain').",
    ),
    progress: bool = typer.Option(True, "--progress/--no-progress", help="Show a progress bar with an ETA."),
    memory: MemoryOption = None,
) -> None:
    """Generate a training set with the engine and fit the spectral predictor (resumable:
    run the same command again to continue after an interruption)."""
    from sandlight.jobs import make_executor
    from sandlight.predictor import Domain
    from sandlight.predictor.physical_inputs import PHYSICAL_INPUTS
    from sandlight.predictor.training import clean_corner as corner_of
    from sandlight.predictor.training import train_spectral

    check_output_directory(out, "--output")
    n = check_count("--rays", rays)
    n_holdout = None if holdout_rays is None else check_count("--holdout-rays", holdout_rays)
    try:
        rates = tuple(float(r) for r in learning_rates.split(","))
    except ValueError:
        raise ParameterError(
            "--learning-rates", learning_rates, "numbers separated by commas, e.g. 1e-3,1e-4"
        ) from None
    if physical_inputs and regressor != "network":
        raise ParameterError(
            "--physical-inputs", True, "only with --regressor network (the monomials take the parameters)"
        )
    if clean_corner < 0:
        raise ParameterError("--clean-corner", clean_corner, "an integer >= 0 (0: none)")
    corner = (clean_corner, corner_of(Domain.default())) if clean_corner else None
    executor = None if fit_only else make_executor(workers, dask_local, scheduler)
    with option_names(_TRAINING_OPTIONS):
        run = train_spectral(
            out,
            samples,
            n,
            wavelengths,
            seed,
            n_holdout=holdout,
            executor=executor,
            fit_only=fit_only,
            progress=progress,
            holdout_rays=n_holdout,
            memory=memory,
            enrichment=corner,
            model_params={
                "n_components": n_components,
                "variance_threshold": variance,
                "ridge": ridge,
                "forms": forms,
                "degree": degree,
                "regressor": regressor,
                "hidden_units": hidden_units,
                "hidden_layers": hidden_layers,
                "ensemble": ensemble,
                "learning_rates": rates,
                "network_validation": validation,
                "physical_inputs": PHYSICAL_INPUTS if physical_inputs else (),
            },
        )
    model, report = run.model, run.report
    ratio = model.explained_variance_ratio_
    echo(f"training set: {run.training.dataset_path} ({run.training.n_total} samples, engine memory {model.memory_!r})")
    echo(
        f"principal components: k = {model.n_components_}, explained variance "
        f"{ratio[: model.n_components_].sum():.5%} "
        f"(per component: {', '.join(f'{r:.4%}' for r in ratio[: model.n_components_])})"
    )
    echo(f"training RMS error {model.training_rms_:.5f} (PCA floor {model.reconstruction_rms_:.5f})")
    if report is not None:
        show(report.table())
    echo(f"times: generation {run.generation_s:.1f} s (this run), fit {run.fit_s:.2f} s")
    echo(f"model: {run.model_path}")


@app.command()
def predict(
    sample_file: Path | None = typer.Argument(None, help=f"{SAMPLE_HELP} This or --preset is required."),
    preset: str | None = typer.Option(None, "--preset", help=PRESET_HELP),
    model_path: Path | None = typer.Option(None, "--model", help="Model file (default: the shipped model)."),
    output: Path | None = typer.Option(
        None, "-o", "--output", help="Write a CSV file (.csv, overwritten if it exists)."
    ),
    plot: Path | None = typer.Option(
        None, "--plot", help="Save a plot: .png, .pdf or .svg, as the suffix says (overwritten if it exists)."
    ),
    extrapolate: bool = typer.Option(False, "--extrapolate", help="Allow samples outside the training domain."),
    wavelengths: str | None = typer.Option(
        None,
        "--wavelengths",
        "-w",
        help="Wavelengths in nm within the models' range (350-2500), start:stop:step or a list (default: the "
        "models' own; between them PCHIP interpolation, docs/spectral-predictor.md).",
    ),
    mode: str = typer.Option(
        "auto",
        "--mode",
        help="Which shipped models answer: auto (the paper's 400-700 nm models when --wavelengths lie there, "
        "else the full-range ones), paper or full-range.",
    ),
) -> None:
    """Predict the spectral reflectance of a sand sample in microseconds.

    Without --model, the most accurate shipped model whose training domain contains the sample
    answers (--mode says which wavelength range's models); the command says which one and its
    hold-out error.
    """
    from sandlight.predictor.bank import ModelBank
    from sandlight.predictor.prediction import PREDICT_MODES, answering_bank
    from sandlight.predictor.prediction import predict as predict_spectrum
    from sandlight.predictor.spectral import SpectralModel

    if output is not None:
        check_output_file(output, "--output", (".csv",), make_dirs=True)
    if plot is not None:
        check_output_file(plot, "--plot", (".png", ".pdf", ".svg"), make_dirs=True)
    sample = load_sample(sample_file, preset, default=None)
    label = preset if sample_file is None else sample_file.stem
    wl = None if wavelengths is None else parse_range("--wavelengths", wavelengths)
    check_choice("--mode", mode, PREDICT_MODES)
    bank = answering_bank(wl, mode) if model_path is None else ModelBank([SpectralModel.load(model_path)])
    try:
        ds = predict_spectrum(sample, wl, extrapolate=extrapolate, bank=bank)
    except ParameterError as exc:
        # The option's name on the command line, not the Python argument's.
        raise ParameterError(
            "--wavelengths" if exc.name == "wavelengths_nm" else exc.name, exc.value, exc.allowed
        ) from None
    reflectance, model = ds["reflectance"].values, bank.model(str(ds["model"].values))
    outside = bool(ds["extrapolated"])  # no model covers it: the nearest one extrapolated
    echo(
        f"model {bank.describe(model.name_)}" + (" [extrapolated: the sample is outside its domain]" if outside else "")
    )
    wavelengths = ds["wavelength"].values
    if output is not None:
        metadata = {
            **cf_attributes("sandlight spectral predictor reflectance", "sandlight predict"),
            "model": model.name_,
            "sample": json.dumps(sample.to_dict(), sort_keys=True),
            "extrapolated": outside,
            "units": "wavelength_nm nm; reflectance 1 (directional-hemispherical, normal incidence)",
        }
        write_csv(output, ("wavelength_nm", "reflectance"), zip(wavelengths, reflectance), ("%g", "%.6f"), metadata)
    else:
        rows = [(f"{w:g}", f"{r:.4f}") for w, r in zip(wavelengths, reflectance)]
        table(("wavelength (nm)", "reflectance"), rows, title=f"reflectance of {label}")
    if plot is not None:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(6, 4))
        ax.plot(wavelengths, reflectance, marker="o")
        ax.set(
            xlabel="wavelength (nm)",
            ylabel="directional-hemispherical reflectance",
            title=f"{label} (spectral predictor)",
            ylim=(0, max(1e-3, reflectance.max()) * 1.1),
        )
        ax.grid(alpha=0.3)
        fig.tight_layout()
        write_atomically(plot, lambda tmp: fig.savefig(tmp, format=plot.suffix[1:].lower()))
        plt.close(fig)
