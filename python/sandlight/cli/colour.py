"""Commands of the colour area: swatches (paper Figures 6, 7 and any grid) and colourise (§4.1.1).

Errors in what the user typed (grid specs, sizes, paths, unreadable images, unknown parameters
or presets) exit with code 2 and a one-line message; a missing spectral model exits with code 1
(see ``sandlight.cli._app.exit_code``).
"""

from __future__ import annotations

from enum import StrEnum
from pathlib import Path

import typer

from sandlight.checks import check_count
from sandlight.cli._app import app
from sandlight.cli._common import COUNT_FORM, PRESET_HELP, SAMPLE_HELP, load_sample, option_names
from sandlight.cli._output import echo, fail
from sandlight.io import check_output_file
from sandlight.sample import SandSample

_GRID_HELP = "NAME=start:stop:count (inclusive), e.g. iron_oxide=0.001:0.05:8"


class Mode(StrEnum):
    managed = "managed"
    paper = "paper"


class PaperFigure(StrEnum):
    six = "6"
    seven = "7"


def _parse_size(text: str | None, option: str) -> tuple[int, int] | None:
    if text is None:
        return None
    parts = text.lower().split("x")
    if len(parts) != 2 or not all(p.strip().isdigit() for p in parts):
        fail(f"{option} {text!r} is not allowed: WIDTHxHEIGHT in pixels, e.g. 800x600")
    return int(parts[0]), int(parts[1])


_ENGINE_HELP = (
    f"Compute the colours with the Monte Carlo engine at this many rays per wavelength, {COUNT_FORM} "
    "(e.g. 2e4), instead of the shipped spectral predictor: slower, any sample."
)


def _provider(engine_rays: str | None):
    """The reflectance provider the user chose: ``None`` (the predictor) or the engine."""
    if engine_rays is None:
        return None
    from sandlight.colour.provider import engine_reflectance_provider

    return engine_reflectance_provider(check_count("--engine-rays", engine_rays))


def _grid_axes(x: str | None, y: str | None):
    from sandlight.colour.swatches import parse_grid_spec

    if (x is None) != (y is None):
        fail("--x and --y go together: give both, e.g. --x iron_oxide=0.001:0.05:8 --y hematite_ratio=0:1:6")
    return parse_grid_spec(x), parse_grid_spec(y)


@app.command("swatches")
def swatches_command(
    sample_file: Path | None = typer.Argument(None, help=f"Base sample: {SAMPLE_HELP} Default: SandSample()."),
    output: Path = typer.Option(..., "-o", "--output", help="PNG file to write (.png, overwritten if it exists)."),
    figure: PaperFigure | None = typer.Option(
        None,
        "--figure",
        help="The paper's Figure 6 (iron oxide × hematite ratio) or 7 "
        "(hematite ratio × saturation). Default 6 unless --x/--y.",
    ),
    x: str | None = typer.Option(None, "--x", help=f"Horizontal axis: {_GRID_HELP}."),
    y: str | None = typer.Option(None, "--y", help=f"Vertical axis (downward): {_GRID_HELP}."),
    preset: str | None = typer.Option(None, "--preset", help=f"Base sample: {PRESET_HELP[0].lower()}{PRESET_HELP[1:]}"),
    sample: Path | None = typer.Option(None, "--sample", help="The base sample file, as SAMPLE.", hidden=True),
    mode: Mode = typer.Option(
        Mode.managed,
        "--mode",
        help="sRGB conversion: managed (Bradford-adapted to D65, clipped) or paper (docs/colour.md).",
    ),
    lab: bool = typer.Option(False, "--lab/--no-lab", help="Print L*a*b* in each cell."),
    size: str | None = typer.Option(
        None, "--size", help="WIDTHxHEIGHT of the PNG in pixels (default: the cells at their own size plus axes)."
    ),
    engine_rays: str | None = typer.Option(None, "--engine-rays", help=_ENGINE_HELP),
) -> None:
    """Swatch grid of sand colours as two sample parameters vary (paper Figures 6 and 7)."""
    from sandlight.colour.swatches import figure6, figure7, swatch_grid

    check_output_file(output, "--output", (".png",))
    if figure is not None and x is not None:
        fail("give --figure or --x/--y, not both")
    size_px = _parse_size(size, "--size")
    axes = _grid_axes(x, y) if (x is not None or y is not None) else None
    provider = _provider(engine_rays)

    if sample_file is not None and sample is not None:
        fail("give the base sample as SAMPLE or --sample, not both")
    base = load_sample(sample_file or sample, preset, default=SandSample())
    if axes is not None:
        grid = swatch_grid(base, axes[0], axes[1], mode=mode.value, reflectance=provider)
        title = f"sRGB ({mode.value}), D50, CIE 1964 10°"
    elif figure in (None, PaperFigure.six):
        grid, title = figure6(base, mode=mode.value, reflectance=provider), f"Figure 6 — sRGB ({mode.value})"
    else:
        grid, title = figure7(base, mode=mode.value, reflectance=provider), f"Figure 7 — sRGB ({mode.value})"
    with option_names({"size_px": "--size"}):
        grid.save_png(output, size_px=size_px, show_lab=lab, title=title)
    clipped = int(grid.out_of_gamut.sum())
    echo(
        f"wrote {output} ({grid.rgb.shape[1]}×{grid.rgb.shape[0]} swatches"
        + (f", {clipped} clipped to the sRGB gamut" if clipped else "")
        + ")"
    )


@app.command("colourise")
def colourise_command(
    image: Path | None = typer.Argument(
        None, help="Photo of sand (any format pillow reads). Default: the shipped texture."
    ),
    output: Path = typer.Option(
        ...,
        "-o",
        "--output",
        help="Image file to write, in the format its suffix says (.png, .jpg, .tif, ...; overwritten if it exists).",
    ),
    preset: str | None = typer.Option(None, "--preset", help=PRESET_HELP),
    sample: Path | None = typer.Option(
        None, "--sample", help=f"{SAMPLE_HELP} (An option here: the argument is the photo.)"
    ),
    grid: bool = typer.Option(
        False, "--grid", help="Mosaic over --x/--y (base: --preset/--sample or the default sample)."
    ),
    x: str | None = typer.Option(None, "--x", help=f"Grid horizontal axis: {_GRID_HELP}."),
    y: str | None = typer.Option(None, "--y", help=f"Grid vertical axis: {_GRID_HELP}."),
    mode: Mode = typer.Option(
        Mode.managed,
        "--mode",
        help="sRGB conversion of the sample: managed (Bradford-adapted to D65, clipped) or paper (docs/colour.md).",
    ),
    linear: bool = typer.Option(
        False, "--linear/--encoded", help="Shift in linear light instead of encoded sRGB (paper)."
    ),
    tile: str | None = typer.Option(
        None, "--tile", help="Grid tile WIDTHxHEIGHT in pixels, each 1–4096 (default: the photo's own size)."
    ),
    labels: bool = typer.Option(True, "--labels/--no-labels", help="Grid: axes with values."),
    engine_rays: str | None = typer.Option(None, "--engine-rays", help=_ENGINE_HELP),
) -> None:
    """Give a photo of sand the colour of a sample (paper §4.1.1), or a grid of colours."""
    from sandlight.colour.colourise import (
        COLOURISE_BYTES_PER_PIXEL,
        LOAD_BYTES_PER_PIXEL,
        colourise,
        colourise_grid,
        default_texture_path,
        image_format,
        load_image,
        save_image,
    )

    if grid and labels:
        if output.suffix.lower() != ".png":
            fail(f"--output {str(output)!r}: a labelled grid is written as .png (or use --no-labels)")
    else:
        image_format(output)
    check_output_file(output, "--output")

    if grid:
        if x is None or y is None:
            fail("--grid needs --x NAME=a:b:n and --y NAME=a:b:n")
        axes = _grid_axes(x, y)
    else:
        if x is not None or y is not None:
            fail("--x/--y need --grid")
        if preset is None and sample is None:
            fail("give --preset NAME or --sample FILE (or --grid with --x/--y)")
    tile_px = _parse_size(tile, "--tile")
    provider = _provider(engine_rays)
    need = LOAD_BYTES_PER_PIXEL if grid else COLOURISE_BYTES_PER_PIXEL[linear]
    with option_names({"image": "IMAGE"}):
        photo = load_image(default_texture_path() if image is None else image, bytes_per_pixel=need)

    base = load_sample(sample, preset, default=SandSample(), file_option="--sample")
    if not grid:
        save_image(output, colourise(photo, base, mode=mode.value, linear=linear, reflectance=provider))
        echo(f"wrote {output} ({photo.shape[1]}×{photo.shape[0]})")
        return
    with option_names({"tile_px": "--tile", "image": "IMAGE"}):
        result = colourise_grid(
            photo, base, axes[0], axes[1], tile_px=tile_px, mode=mode.value, linear=linear, reflectance=provider
        )
    result.save_png(output, labels=labels)
    echo(f"wrote {output} ({len(axes[0].values)}×{len(axes[1].values)} tiles)")
