"""Commands of the transport engine: reflectance, demo, version."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import typer

from sandlight.checks import check_count, check_wavelengths, parse_range
from sandlight.cli._app import app
from sandlight.cli._common import (
    COUNT_FORM,
    DEFAULT_PRESET,
    ENGINE_OPTIONS,
    WAVELENGTHS_HELP,
    DispersionToleranceOption,
    GeometryOption,
    MemoryOption,
    PresetOption,
    SampleFileArgument,
    SeedOption,
    ShareOption,
    ThreadsOption,
    load_sample,
    option_names,
)
from sandlight.cli._output import echo, table
from sandlight.io import check_output_directory, check_output_file
from sandlight.physics.spectral_groups import DISPERSION_TOLERANCE

if TYPE_CHECKING:
    from sandlight.engine import ReflectanceResult


@app.command()
def version() -> None:
    """Print the sandlight version."""
    import sandlight

    echo(sandlight.__version__)


@app.command()
def reflectance(
    sample_file: SampleFileArgument = None,
    preset: PresetOption = None,
    wavelengths: str = typer.Option("400:700:20", "--wavelengths", "-w", help=WAVELENGTHS_HELP),
    rays: str = typer.Option("1e5", "--rays", "-n", help=f"Rays per wavelength, {COUNT_FORM}."),
    incidence: float = typer.Option(0.0, "--incidence", help="Incidence zenith angle θᵢ in degrees, in [0, 90)."),
    seed: SeedOption = 0,
    threads: ThreadsOption = None,
    output: Path | None = typer.Option(
        None, "-o", "--output", help="Write .nc (NetCDF) or .csv, as the suffix says (overwritten if it exists)."
    ),
    plot: Path | None = typer.Option(
        None, "--plot", help="Write a PNG plot of the spectrum (.png, overwritten if it exists)."
    ),
    memory: MemoryOption = None,
    geometry: GeometryOption = "on-the-fly",
    share: ShareOption = True,
    dispersion_tolerance: DispersionToleranceOption = DISPERSION_TOLERANCE,
) -> None:
    """Monte Carlo directional-hemispherical reflectance of a sand sample."""
    from sandlight.engine import reflectance as run

    _check_outputs(output, plot)
    sample = load_sample(sample_file, preset)
    wl = check_wavelengths("--wavelengths", parse_range("--wavelengths", wavelengths))
    n = check_count("--rays", rays)
    echo(f"tracing {n:,} rays at each of {wl.size} wavelength(s)…")
    with option_names(ENGINE_OPTIONS):
        result = run(
            sample,
            wl,
            rays=n,
            incidence_deg=incidence,
            seed=seed,
            threads=threads,
            memory=memory,
            geometry=geometry,
            share=share,
            dispersion_tolerance=dispersion_tolerance,
        )
    _report(result, output, plot, title=str(sample_file or preset or DEFAULT_PRESET))


def _check_outputs(output: Path | None, plot: Path | None) -> None:
    """Refuse unwritable outputs before the computation."""
    if output is not None:
        check_output_file(output, "--output", (".nc", ".csv"), make_dirs=True)
    if plot is not None:
        check_output_file(plot, "--plot", (".png",), make_dirs=True)


def _report(result: ReflectanceResult, output: Path | None, plot: Path | None, *, title: str) -> None:
    rows = [
        (f"{wl:g}", f"{v:.4f}", f"{e:.4f}", f"{events:.1f}", str(int(capped)))
        for wl, v, e, events, capped in zip(
            result.wavelengths, result.values, result.stderr, result.mean_events_per_ray, result.capped
        )
    ]
    table(("λ (nm)", "reflectance", "± stderr", "events/ray", "capped"), rows)
    echo(f"{result.rays:,} rays per wavelength in {result.elapsed_s:.1f} s")
    if output is not None:
        if output.suffix.lower() == ".csv":
            result.to_csv(output)
        else:
            result.to_netcdf(output)
        echo(f"wrote {output}")
    if plot is not None:
        result.plot(plot, title=title)
        echo(f"wrote {plot}")


@app.command()
def demo(
    output_dir: Path = typer.Option(
        Path("sandlight-demo"),
        "-o",
        "--output",
        "--output-dir",
        help="Where to write red-dune.nc and red-dune.png (created if missing; the files are overwritten).",
    ),
    rays: str = typer.Option("2e5", "--rays", "-n", help=f"Rays per wavelength, {COUNT_FORM}."),
) -> None:
    """The main job on its embedded default: the reflectance spectrum of a red dune sand,
    computed with the Monte Carlo engine and plotted."""
    from sandlight.engine import reflectance as run
    from sandlight.sample import SandSample

    check_output_directory(output_dir, "--output")
    n = check_count("--rays", rays)
    sample = SandSample.preset(DEFAULT_PRESET)
    echo(f"sandlight demo: {DEFAULT_PRESET} sand, 400–2500 nm")
    result = run(
        sample,
        parse_range("wavelengths", "400:700:20").tolist() + [800, 900, 1000, 1200, 1400, 1600, 1900, 2200, 2500],
        rays=n,
    )
    _report(
        result,
        output_dir / "red-dune.nc",
        output_dir / "red-dune.png",
        title="red-dune sand (sandlight Monte Carlo)",
    )
