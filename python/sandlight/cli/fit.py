"""The fit command: sample parameters from a measured spectrum (docs/retrieval.md)."""

from __future__ import annotations

from pathlib import Path

import typer

from sandlight.checks import check_count
from sandlight.cli._app import app
from sandlight.cli._common import (
    COUNT_FORM,
    PresetOption,
    SeedOption,
    ThreadsOption,
    load_sample,
    option_names,
)
from sandlight.cli._output import echo
from sandlight.errors import ParameterError
from sandlight.io import check_output_file

#: The parameters of sandlight.fit as this command's options.
_FIT_OPTIONS = {
    "free": "--free",
    "fixed": "--fixed",
    "method": "--method",
    "noise": "--noise",
    "mask": "--mask",
    "sensor": "--sensor",
    "posterior": "--posterior",
    "rays": "--rays",
    "check_rays": "--check-rays",
    "seed": "--seed",
    "threads": "--threads",
    "spectrum_name": "--spectrum-name",
}


def parse_fixed(text: str | None) -> dict[str, float | str]:
    """``"saturation=0,iron_oxide_form=mixed"`` as a dict (numbers as floats)."""
    out: dict[str, float | str] = {}
    for part in (text or "").split(","):
        if not part.strip():
            continue
        name, sep, value = part.partition("=")
        if not sep or not name.strip() or not value.strip():
            raise ParameterError(
                "--fixed", text, "NAME=VALUE pairs separated by commas, e.g. saturation=0,grain_size=0.3"
            )
        try:
            out[name.strip()] = float(value)
        except ValueError:
            out[name.strip()] = value.strip()
    return out


@app.command("fit")
def fit_command(
    spectrum: Path = typer.Argument(
        ..., help="Measured spectrum: CSV (wavelength_nm, reflectance), USGS splib07 ASCII or ENVI library (.hdr)."
    ),
    free: str = typer.Option(
        ..., "--free", help="Parameters to fit, comma-separated (e.g. iron_oxide,hematite_ratio,saturation)."
    ),
    fixed: str | None = typer.Option(
        None, "--fixed", help="Other parameters' values: NAME=VALUE,... (override the sample)."
    ),
    sample_file: Path | None = typer.Option(
        None,
        "--sample",
        help="Sample file (TOML/JSON) with the values of the parameters not fitted (default: the reference sand).",
    ),
    preset: PresetOption = None,
    method: str = typer.Option(
        "bank",
        "--method",
        help="bank (the shipped predictor bank, fast; then an engine check) or engine (Monte Carlo, "
        "common random numbers).",
    ),
    noise: float | None = typer.Option(
        None, "--noise", help="Measurement standard deviation (reflectance); default: estimated from the residuals."
    ),
    mask: str | None = typer.Option(
        None, "--mask", help="Wavelengths left out: water-vapour, or intervals in nm like 1350-1450,1800-1950."
    ),
    sensor: str | None = typer.Option(
        None,
        "--sensor",
        help="Fit in sensor bands: landsat-oli, sentinel2-msi (Gaussian approximations) or an SRF CSV file.",
    ),
    posterior: str = typer.Option("laplace", "--posterior", help="laplace (Gaussian at the optimum) or emcee (MCMC)."),
    rays: str = typer.Option("2e4", "--rays", "-n", help=f"Rays per wavelength of the engine fit, {COUNT_FORM}."),
    check_rays: str = typer.Option(
        "2e4",
        "--check-rays",
        help=f"Rays per wavelength of the engine check after a bank fit, {COUNT_FORM}; 0: no check.",
    ),
    seed: SeedOption = 0,
    threads: ThreadsOption = None,
    spectrum_name: str | None = typer.Option(
        None, "--spectrum-name", help="The spectrum to take from an ENVI library holding several."
    ),
    output: Path | None = typer.Option(
        None, "-o", "--output", help="Write the fit as TOML (.toml, overwritten): [sample], [fit], [parameters.NAME]."
    ),
    plot: Path | None = typer.Option(None, "--plot", help="Save measured, fitted and residual: .png (overwritten)."),
) -> None:
    """Fit sample parameters to a measured spectrum, with 95 % intervals that count the
    measurement noise, the predictor's error and the Monte Carlo noise."""
    from sandlight.retrieval import fit

    if output is not None:
        check_output_file(output, "--output", (".toml",), make_dirs=True)
    if plot is not None:
        check_output_file(plot, "--plot", (".png",), make_dirs=True)
    n_rays = check_count("--rays", rays)
    n_check = 0 if check_rays.strip() == "0" else check_count("--check-rays", check_rays)
    sample = load_sample(sample_file, preset, default=None) if (sample_file or preset) else None
    with option_names(_FIT_OPTIONS):
        result = fit(
            spectrum,
            free,
            parse_fixed(fixed),
            method=method,
            sample=sample,
            noise=noise,
            mask=mask,
            sensor=sensor,
            posterior=posterior,
            rays=n_rays,
            check_rays=n_check,
            seed=seed,
            threads=threads,
            spectrum_name=spectrum_name,
        )
    echo(result.summary())
    if output is not None:
        result.save(output)
        echo(f"fit: {output}")
    if plot is not None:
        result.plot(plot, title=f"{spectrum.name}: " + ", ".join(f"{k} = {v:.3g}" for k, v in result.estimate.items()))
        echo(f"plot: {plot}")
