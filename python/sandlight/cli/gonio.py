"""Commands of the virtual goniophotometer: brdf."""

from __future__ import annotations

import math
from pathlib import Path

import typer

from sandlight.checks import check_count
from sandlight.cli._app import app
from sandlight.cli._common import (
    COUNT_FORM,
    ENGINE_OPTIONS,
    WAVELENGTH_HELP,
    GeometryOption,
    MemoryOption,
    PresetOption,
    SampleFileArgument,
    SeedOption,
    SlicesOption,
    StacksOption,
    ThreadsOption,
    load_sample,
    option_names,
)
from sandlight.cli._output import echo
from sandlight.io import check_output_file


@app.command()
def brdf(
    sample_file: SampleFileArgument = None,
    preset: PresetOption = None,
    wavelength: float = typer.Option(550.0, "--wavelengths", "--wavelength", "-w", help=WAVELENGTH_HELP),
    rays: str = typer.Option(
        "1e6", "--rays", "-n", help=f"Trials (rays), {COUNT_FORM} (the paper uses 1e8; 901 patches need about 1e4)."
    ),
    stacks: StacksOption = 31,
    slices: SlicesOption = 30,
    seed: SeedOption = 0,
    threads: ThreadsOption = None,
    method: str = typer.Option(
        "average", "--method", help="Reduction of the counts to a BRDF: average (the paper) or pooled."
    ),
    output: Path = typer.Option(
        Path("brdf.nc"), "-o", "--output", help="NetCDF output (.nc, overwritten if it exists)."
    ),
    plot: Path | None = typer.Option(
        None, "--plot", help="PNG: polar map at 30° and principal-plane curves (.png, overwritten if it exists)."
    ),
    memory: MemoryOption = None,
    geometry: GeometryOption = "on-the-fly",
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
