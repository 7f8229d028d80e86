"""Commands of the virtual goniophotometer: brdf."""

from __future__ import annotations

import math
from pathlib import Path

import typer

from sandlight.checks import check_count, check_wavelengths, parse_range
from sandlight.cli._app import app
from sandlight.cli._common import (
    COUNT_FORM,
    ENGINE_OPTIONS,
    WAVELENGTHS_HELP,
    GeometryOption,
    MemoryOption,
    PresetOption,
    SampleFileArgument,
    SeedOption,
    ShareOption,
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
    wavelengths: str = typer.Option(
        "550",
        "--wavelengths",
        "--wavelength",
        "-w",
        help=f"{WAVELENGTHS_HELP} Several write one file per wavelength, NAME-<λ>nm.nc (and .png).",
    ),
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
    share: ShareOption = True,
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
    wl = check_wavelengths("--wavelengths", parse_range("--wavelengths", wavelengths))
    with option_names(ENGINE_OPTIONS):
        results = measure(
            sample,
            wl,
            rays=check_count("--rays", rays),
            stacks=stacks,
            slices=slices,
            seed=seed,
            threads=threads,
            method=method,
            checkpoint=output.with_name(output.name + ".checkpoint.npz"),
            memory=memory,
            geometry=geometry,
            share=share,
        )
    for result in results:
        lam = f"-{result.wavelength_nm:g}nm" if wl.size > 1 else ""
        path = output.with_name(f"{output.stem}{lam}{output.suffix}")
        to_netcdf(result, path)
        rho = result.normal_reflectance
        at = f" at {result.wavelength_nm:g} nm" if wl.size > 1 else ""
        if math.isnan(rho):  # the warning above says why: too few rays for every incoming patch
            echo(f"normal-incidence reflectance{at} unknown (too few rays: see the warning); wrote {path}")
        else:
            stderr = result.reduced.normal_reflectance_stderr
            echo(f"normal-incidence reflectance{at} {rho:.4f} ± {stderr:.4f}; wrote {path}")
        if plot is not None:
            png = plot.with_name(f"{plot.stem}{lam}{plot.suffix}")
            save_overview_png(result, png)
            echo(f"wrote {png}")
