"""Argument parsing shared by the command modules: samples, the names of options in messages."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from sandlight.errors import ParameterError

if TYPE_CHECKING:
    from sandlight.sample import SandSample

#: Help of the options every command that takes them shares (one name, one meaning, units and
#: defaults stated).
SAMPLE_HELP = "Sample description: a TOML or JSON file (keys at the top level or in a [sample] table)."
PRESET_HELP = "A named preset instead of a sample file (e.g. red-dune; the list: docs/sample.md)."
SEED_HELP = (
    "Master seed of the random streams, an integer in [0, 2^64): the same seed gives the same result for any --threads."
)
THREADS_HELP = "Worker threads (default: all cores); results do not depend on it."
STACKS_HELP = "Collector hemisphere: polar stacks, 2–10000, the top one the undivided cap (paper: 31)."
SLICES_HELP = (
    "Collector hemisphere: azimuthal slices of every stack below the cap, 1–10000 (paper: 30; "
    "1 + (stacks − 1)·slices equal-solid-angle patches)."
)
#: How counts are written (checks.check_count): rays, trials.
COUNT_FORM = "a whole number ≥ 1, written like 100000 or 1e5"
WAVELENGTHS_HELP = (
    "Wavelengths in nm, each in [350, 2500]: start:stop:step (stop included when on the grid) or a "
    "comma-separated list."
)
WAVELENGTH_HELP = "Wavelength in nm, in [350, 2500] (one)."
#: The engine's parameters (sandlight.reflectance, gonio.brdf) as the options of the commands.
ENGINE_OPTIONS = {
    "wavelengths_nm": "--wavelengths",
    "wavelength_nm": "--wavelengths",
    "rays": "--rays",
    "incidence_deg": "--incidence",
    "seed": "--seed",
    "threads": "--threads",
    "memory": "--memory",
    "geometry": "--geometry",
    "dispersion_tolerance": "--dispersion-tolerance",
    "stacks": "--stacks",
    "slices": "--slices",
    "method": "--method",
}
#: Help of the --memory and --geometry options of the commands that trace rays.
MEMORY_HELP = (
    "Path memory of the fast engine: packed (closest to the explicit reference, default), none (the "
    "classic model), channel or cut (docs/geometry.md)."
)
GEOMETRY_HELP = "on-the-fly (fast, default) or explicit (the slow reference: a stored packing; docs/geometry.md)."


#: The sample of reflectance, brdf and appearance when neither a file nor a preset is given.
DEFAULT_PRESET = "red-dune"

#: The options the commands that trace a sample share, as parameter types (one declaration:
#: ``seed: SeedOption = 0``); the default stays at the command.
SampleFileArgument = Annotated[Path | None, typer.Argument(help=f"{SAMPLE_HELP} Default: the {DEFAULT_PRESET} preset.")]
PresetOption = Annotated[str | None, typer.Option("--preset", help=PRESET_HELP)]
SeedOption = Annotated[int, typer.Option("--seed", help=SEED_HELP)]
ThreadsOption = Annotated[int | None, typer.Option("--threads", help=THREADS_HELP)]
MemoryOption = Annotated[str | None, typer.Option("--memory", help=MEMORY_HELP)]
GeometryOption = Annotated[str, typer.Option("--geometry", help=GEOMETRY_HELP)]
StacksOption = Annotated[int, typer.Option("--stacks", help=STACKS_HELP)]
SlicesOption = Annotated[int, typer.Option("--slices", help=SLICES_HELP)]
ShareOption = Annotated[
    bool,
    typer.Option(
        "--share/--no-share",
        help="Spectral path sharing: trace wavelengths of nearly equal indices together (default; "
        "docs/transport.md). --no-share traces every wavelength on its own.",
    ),
]
DispersionToleranceOption = Annotated[
    float,
    typer.Option(
        "--dispersion-tolerance",
        help="Largest spread of the direction-setting refractive indices within one group of shared "
        "wavelengths, in [0, 1] (0.005 removes the 0.4 % tilt the default leaves on a clear "
        "quartz sand at 1e7 rays, docs/transport.md).",
    ),
]


def load_sample(
    sample_file: Path | None,
    preset: str | None,
    *,
    default: SandSample | str | None = DEFAULT_PRESET,
    file_option: str = "SAMPLE",
) -> SandSample:
    """The sample of every command that takes one: a TOML/JSON file or a preset name, not both.

    ``default`` is the sample (or the name of the preset, which the command then says it uses)
    without either; None means one of them is required.
    ``file_option`` names the file's argument in messages (``SAMPLE`` or ``--sample``). Files are
    read by `SandSample.from_file` (regular files of bounded size, keys at the top level or in a
    ``[sample]`` table, nothing else).
    """
    from sandlight.sample import SandSample

    both = f"{file_option}/--preset"
    if sample_file is not None and preset is not None:
        raise ParameterError(both, f"{sample_file} and {preset}", "give a sample file or a preset, not both")
    if sample_file is not None:
        return SandSample.from_file(sample_file)
    if preset is not None:
        with option_names({"preset": "--preset"}):
            return SandSample.preset(preset)
    if default is None:
        raise ParameterError(both, None, "a sample file (TOML or JSON) or a preset name")
    if isinstance(default, str):
        from sandlight.cli._output import echo

        echo(f"no sample given: using the {default} preset (give a sample file or --preset)")
        return SandSample.preset(default)
    return default


@contextlib.contextmanager
def option_names(names: Mapping[str, str]) -> Iterator[None]:
    """A `ParameterError` raised inside names the command's option instead of the API's
    parameter (``names``: parameter -> option, e.g. ``{"tile_px": "--tile"}``), so that the
    message says what the user typed."""
    try:
        yield
    except ParameterError as exc:
        if exc.name not in names:
            raise
        raise ParameterError(names[exc.name], exc.value, exc.allowed) from None
