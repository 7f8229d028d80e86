"""Argument parsing shared by the command modules: samples, the names of options in messages."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import TYPE_CHECKING

from sandlight.errors import ParameterError

if TYPE_CHECKING:
    from sandlight.sample import SandSample

#: Help of the --memory and --geometry options of the commands that trace rays.
MEMORY_HELP = (
    "Path memory of the fast engine: none (the classic model, default), channel, cut, or packed "
    "(closest to the explicit reference; docs/geometry.md)."
)
GEOMETRY_HELP = "on-the-fly (fast, default) or explicit (the slow reference: a stored packing; docs/geometry.md)."


#: The sample of reflectance, brdf and appearance when neither a file nor a preset is given.
DEFAULT_PRESET = "red-dune"


def load_sample(
    sample_file: Path | None,
    preset: str | None,
    *,
    default: SandSample | str | None = DEFAULT_PRESET,
    file_option: str = "SAMPLE",
) -> SandSample:
    """The sample of every command that takes one: a TOML/JSON file or a preset name, not both.

    ``default`` is the sample (or the name of the preset) without either; None means one of
    them is required.
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
        return SandSample.preset(preset)
    if default is None:
        raise ParameterError(both, None, "a sample file (TOML or JSON) or a preset name")
    return SandSample.preset(default) if isinstance(default, str) else default


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
