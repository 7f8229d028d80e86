"""Commands of the virtual goniophotometer: brdf."""

from __future__ import annotations

import math
from pathlib import Path

import typer

from sandlight.checks import check_count
from sandlight.cli._app import app
from sandlight.cli._common import (
    COUNT_FORM,
    DEFAULT_PRESET,
    ENGINE_OPTIONS,
    GEOMETRY_HELP,
    MEMORY_HELP,
    PRESET_HELP,
    SAMPLE_HELP,
    SEED_HELP,
    SLICES_HELP,
    STACKS_HELP,
    THREADS_HELP,
    WAVELENGTH_HELP,
    load_sample,
    option_names,
)
from sandlight.cli._output import echo
from sandlight.io import check_output_file


@app.command()
def brdf(
    sample_file: Path | None = typer.Argument(None, help=f"{SAMPLE_HELP} Default: the {DEFAULT_PRESET} preset."),
    preset: str | None = typer.Option(None, "--preset", help=PRESET_HELP),
    wavelength: float = typer.Option(550.0, "--wavelengths", "--wavelength", "-w", help=WAVELENGTH_HELP),
    rays: str = typer.Option(
        "1e6", "--rays", "-n", help=f"Trials (rays), {COUNT_FORM} (the paper uses 1e8; 901 patches need about 1e4)."
    ),
    stacks: int = typer.Option(31, "--stacks", help=STACKS_HELP),
    slices: int = typer.Option(30, "--slices", help=SLICES_HELP),
    seed: int = typer.Option(0, "--seed", help=SEED_HELP),
    threads: int | None = typer.Option(None, "--threads", help=THREADS_HELP),
    method: str = typer.Option(
        "average", "--method", help="Reduction of the counts to a BRDF: average (the paper) or pooled."
    ),
    output: Path = typer.Option(
        Path("brdf.nc"), "-o", "--output", help="NetCDF output (.nc, overwritten if it exists)."
    ),
    plot: Path | None = typer.Option(
        None, "--plot", help="PNG: polar map at 30° and principal-plane curves (.png, overwritten if it exists)."
    ),
    memory: str | None = typer.Option(None, "--memory", help=MEMORY_HELP),
    geometry: str = typer.Option("on-the-fly", "--geometry", help=GEOMETRY_HELP),
) -> None:
    """Measure the BRDF of a sand sample with the virtual goniophotometer (paper §3.2.1).

    Interrupted runs resume: the counts are checkpointed beside the output every minute."""
    from sandlight.gonio.io import to_netcdf
    from sandlight.gonio.measure import brdf as measure
    from sandlight.gonio.plots import save_overview_png

    check_output_file(output, "--output", (".nc",))
    if plot is not None:
        check_output_file(plot, "--plot", (".png",))
    sample = load_sample(sample_file, preset)
    with option_names(ENGINE_OPTIONS):
        result = measure(
            sample,
            wavelength,
            rays=check_count("--rays", rays),
            stacks=stacks,
            slices=slices,
            seed=seed,
            threads=threads,
            method=method,
            checkpoint=output.with_name(output.name + ".checkpoint.npz"),
            memory=memory,
            geometry=geometry,
        )
    to_netcdf(result, output)
    rho = result.normal_reflectance
    if math.isnan(rho):  # the warning above says why: too few rays for every incoming patch
        echo(f"normal-incidence reflectance unknown (too few rays: see the warning); wrote {output}")
    else:
        echo(f"normal-incidence reflectance {rho:.4f} ± {result.reduced.normal_reflectance_stderr:.4f}; wrote {output}")
    if plot is not None:
        save_overview_png(result, plot)
        echo(f"wrote {plot}")
