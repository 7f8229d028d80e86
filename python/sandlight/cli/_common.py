"""Shared by the command modules: loading the sample, reporting errors, option help texts.

The checks of option values (counts, ranges) are in :mod:`sandlight.checks`.
"""

from __future__ import annotations

import contextlib
from pathlib import Path

import typer
from rich.console import Console

from sandlight.errors import SandlightError

err_console = Console(stderr=True)

#: Help of the --memory and --geometry options of the commands that trace rays.
MEMORY_HELP = (
    "Path memory of the fast engine: none (the classic model, default), channel, cut, or packed "
    "(closest to the explicit reference; docs/geometry.md)."
)
GEOMETRY_HELP = "on-the-fly (fast, default) or explicit (the slow reference: a stored packing; docs/geometry.md)."


@contextlib.contextmanager
def user_errors():
    """Turns sandlight's user-facing errors into a one-line message and exit code 2."""
    try:
        yield
    except (SandlightError, FileNotFoundError) as e:
        err_console.print(f"[bold red]error:[/] {e}", soft_wrap=True)
        raise typer.Exit(2) from None
    except KeyboardInterrupt:
        err_console.print("[yellow]interrupted: nothing was written[/]")
        raise typer.Exit(130) from None


def load_sample(sample_file: Path | None, preset: str | None):
    """The sample from a TOML/JSON file or a preset name (exactly one; default preset red-dune)."""
    from sandlight.errors import ParameterError
    from sandlight.sample import SandSample

    if sample_file is not None and preset is not None:
        raise ParameterError(
            "SAMPLE/--preset", f"{sample_file} and {preset}", "give a sample file or a preset, not both"
        )
    if sample_file is not None:
        return SandSample.from_file(sample_file)
    return SandSample.preset(preset or "red-dune")
