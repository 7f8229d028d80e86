"""Commands of the virtual goniophotometer: brdf."""

from __future__ import annotations

import math
from pathlib import Path

import typer

from sandlight.checks import check_count
from sandlight.cli._app import app
from sandlight.cli._common import GEOMETRY_HELP, MEMORY_HELP, load_sample
from sandlight.cli._output import echo
from sandlight.io import check_output_file


@app.command()
def brdf(
    sample_file: Path | None = typer.Argument(None, help="Sample description (TOML or JSON)."),
    preset: str | None = typer.Option(None, "--preset", help="Named preset instead of a file."),
    wavelength: float = typer.Option(550.0, "--wavelength", "-w", help="Wavelength (nm)."),
    rays: str = typer.Option("1e6", "--rays", "-n", help="Trials (the paper uses 1e8)."),
    stacks: int = typer.Option(31, "--stacks"),
    slices: int = typer.Option(30, "--slices"),
    seed: int = typer.Option(0, "--seed"),
    threads: int | None = typer.Option(None, "--threads"),
    method: str = typer.Option("average", "--method", help="average (the paper) or pooled."),
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
