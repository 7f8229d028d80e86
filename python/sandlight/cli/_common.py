"""Argument parsing shared by the command modules: samples, ranges."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

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
    from sandlight.errors import ParameterError
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


def parse_range(text: str, name: str) -> np.ndarray:
    """``start:stop:step`` (inclusive of stop when it falls on the grid), or comma-separated values;
    at most `sandlight.optics.MAX_WAVELENGTHS` values."""
    from sandlight.errors import ParameterError
    from sandlight.optics import MAX_WAVELENGTHS

    allowed = (
        "start:stop:step with finite start, stop, step > 0 and stop ≥ start (e.g. 400:700:20), or a "
        f"comma-separated list, of at most {MAX_WAVELENGTHS:,} values"
    )
    try:
        if ":" in text:
            parts = [float(p) for p in text.split(":")]
            if len(parts) != 3 or not np.all(np.isfinite(parts)) or parts[2] <= 0 or parts[1] < parts[0]:
                raise ValueError
            start, stop, step = parts
            # The count is checked as a float, before anything is allocated (400:700:1e-9).
            if (stop - start) / step >= MAX_WAVELENGTHS:
                raise ValueError
            n = int(np.floor((stop - start) / step + 1e-9)) + 1
            return start + step * np.arange(n)
        values = text.split(",")
        if len(values) > MAX_WAVELENGTHS:
            raise ValueError
        return np.array([float(p) for p in values])
    except ValueError:
        raise ParameterError(name, text, allowed) from None


def parse_count(text: str, name: str) -> int:
    """A whole number that may be written like 1e6."""
    from sandlight.errors import ParameterError

    try:
        v = float(text)
    except ValueError:
        raise ParameterError(name, text, "a whole number ≥ 1, e.g. 1e6") from None
    if not np.isfinite(v) or v < 1 or v != int(v):
        raise ParameterError(name, text, "a whole number ≥ 1, e.g. 1e6")
    return int(v)
