"""Reading validated values out of a scene file's tables.

Every value of a scene TOML passes through :class:`Table`, so that a bad value is reported the
same way everywhere: a :class:`~sandlight.errors.ParameterError` whose name is the dotted key
(``camera.fov_deg``), with the value and the allowed range, and the file it came from. Unknown
keys are refused with the list of allowed ones (a typo must not be silently ignored).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from sandlight.errors import ParameterError


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool)


class Table:
    """A TOML table being read; ``prefix`` is its dotted name, ``source`` the file (or '')."""

    def __init__(self, data: Any, prefix: str, source: str = ""):
        self.prefix = prefix
        self.source = source
        if data is None:
            data = {}
        if not isinstance(data, Mapping):
            raise self.error(prefix or "scene", data, "a table of keys and values")
        self.data = dict(data)
        self.used: set[str] = set()

    def name(self, key: str) -> str:
        return f"{self.prefix}.{key}" if self.prefix else key

    def error(self, name: str, value: Any, allowed: str) -> ParameterError:
        where = f" (in {self.source})" if self.source else ""
        return ParameterError(name, value, allowed + where)

    def has(self, key: str) -> bool:
        return key in self.data

    def raw(self, key: str, default: Any = None) -> Any:
        self.used.add(key)
        return self.data.get(key, default)

    def table(self, key: str) -> Table:
        self.used.add(key)
        return Table(self.data.get(key), self.name(key), self.source)

    def number(
        self,
        key: str,
        default: float | None = None,
        lo: float | None = None,
        hi: float | None = None,
        *,
        lo_open: bool = False,
        hi_open: bool = False,
    ) -> float:
        value = self.raw(key, default)
        allowed = "a number" + _interval(lo, hi, lo_open, hi_open)
        if value is None:
            raise self.error(self.name(key), "missing", allowed)
        if not _is_number(value) or not math.isfinite(float(value)):
            raise self.error(self.name(key), value, "a finite number" + _interval(lo, hi, lo_open, hi_open))
        v = float(value)
        if (lo is not None and (v < lo or (lo_open and v == lo))) or (
            hi is not None and (v > hi or (hi_open and v == hi))
        ):
            raise self.error(self.name(key), value, allowed)
        return v

    def integer(self, key: str, default: int | None = None, lo: int | None = None, hi: int | None = None) -> int:
        value = self.raw(key, default)
        allowed = "a whole number" + _interval(lo, hi, False, False)
        if value is None:
            raise self.error(self.name(key), "missing", allowed)
        if isinstance(value, bool) or not _is_number(value) or float(value) != int(value):
            raise self.error(self.name(key), value, allowed)
        v = int(value)
        if (lo is not None and v < lo) or (hi is not None and v > hi):
            raise self.error(self.name(key), value, allowed)
        return v

    def boolean(self, key: str, default: bool) -> bool:
        value = self.raw(key, default)
        if not isinstance(value, bool):
            raise self.error(self.name(key), value, "true or false")
        return value

    def string(self, key: str, default: str | None = None) -> str:
        value = self.raw(key, default)
        if not isinstance(value, str) or not value:
            raise self.error(self.name(key), value if value is not None else "missing", "a non-empty string")
        return value

    def choice(self, key: str, options: Sequence[str], default: str | None = None) -> str:
        value = self.raw(key, default)
        if value not in options:
            raise self.error(
                self.name(key),
                value if value is not None else "missing",
                "one of " + ", ".join(repr(o) for o in options),
            )
        return value

    def vector(
        self,
        key: str,
        length: int | Sequence[int],
        default: Sequence[float] | None = None,
        lo: float | None = None,
        hi: float | None = None,
    ) -> np.ndarray:
        value = self.raw(key, default)
        lengths = (length,) if isinstance(length, int) else tuple(length)
        allowed = f"a list of {' or '.join(map(str, lengths))} finite numbers" + _interval(lo, hi, False, False)
        if value is None:
            raise self.error(self.name(key), "missing", allowed)
        if (
            not isinstance(value, (list, tuple))
            or len(value) not in lengths
            or not all(_is_number(v) and math.isfinite(float(v)) for v in value)
        ):
            raise self.error(self.name(key), value, allowed)
        array = np.array([float(v) for v in value])
        if (lo is not None and (array < lo).any()) or (hi is not None and (array > hi).any()):
            raise self.error(self.name(key), value, allowed)
        return array

    def finish(self) -> None:
        """Refuse keys that were never read (typos, options of another type)."""
        unknown = sorted(set(self.data) - self.used)
        if unknown:
            allowed = ", ".join(sorted(self.used)) or "no keys"
            raise self.error(
                self.name(unknown[0]),
                self.data[unknown[0]],
                f"a known key; unknown key {unknown[0]!r} (allowed here: {allowed})",
            )


def _interval(lo, hi, lo_open, hi_open) -> str:
    if lo is None and hi is None:
        return ""
    if hi is None:
        return f" {'>' if lo_open else '≥'} {lo:g}"
    if lo is None:
        return f" {'<' if hi_open else '≤'} {hi:g}"
    return f" in {'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}"
