"""Argument checks shared by every layer of sandlight.

Every check takes the parameter's name and value, returns the value in the type the caller
works with, and on bad input raises :class:`~sandlight.errors.ParameterError` ``(name, value,
allowed)``: the message names the parameter, the offending value and what is allowed, e.g.
``rays = 0 is not allowed: a whole number ≥ 1 (e.g. 1e6)``. Intervals are written one way
everywhere (:func:`interval_text`): ``in [0, 90)``, ``≥ 1``, ``> 0``.

Public objects
--------------
interval_text
    The admissible interval as text.
check_real_array, check_real
    Finite real numbers (array or one number) within an interval.
check_unit_vectors
    Direction vectors of shape (..., 3), normalised.
check_whole_number
    An integer (not a bool, not a float) within an interval.
check_count
    A count ≥ 1 that may be written like ``1e6`` (rays, events, trials).
check_seed, check_threads
    The engine's master seed and worker-thread count.
check_choice
    One of a fixed set of names.
CONTROL_CHARACTERS, check_printable
    Text without terminal control characters (names shown in progress bars and messages).
check_wavelengths, check_incidence
    The engine's wavelengths (nm) and incidence zenith angle (degrees).
check_allocation
    An estimated memory need within a limit (refused before the allocation, not after).
parse_range
    ``start:stop:step`` or a comma-separated list, as typed on the command line.
Interval, StrOptions
    Declared constraints (what a parameter may be), for the predictors' parameter tables.
Table
    A table of a configuration file (TOML/JSON) read key by key with these checks.
"""

from __future__ import annotations

import math
import numbers
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from sandlight.errors import ParameterError

#: Wavelengths the engine's optical constants cover (nm).
WAVELENGTH_RANGE_NM: tuple[float, float] = (350.0, 2500.0)

#: The most wavelengths a grid spec may expand to: 0.2 nm steps over all of WAVELENGTH_RANGE_NM,
#: 25 times finer than the finest table (5 nm). Without a bound "400:700:1e-9" asked for 3e11
#: wavelengths (a 2 TiB array) and "400:inf:20" overflowed.
MAX_WAVELENGTHS = 10_000

#: The most memory one array or image of a command may need (bytes): values inside every
#: parameter's own range can still multiply to more than a machine holds (a 20000² PNG, a
#: 4096 × 4096 table), and an estimate refused up front beats a MemoryError or the OOM killer.
MAX_ALLOCATION_BYTES = 2 << 30

__all__ = [
    "WAVELENGTH_RANGE_NM",
    "MAX_WAVELENGTHS",
    "MAX_ALLOCATION_BYTES",
    "check_allocation",
    "interval_text",
    "is_number",
    "check_real_array",
    "check_real",
    "check_unit_vectors",
    "check_whole_number",
    "check_count",
    "check_seed",
    "check_threads",
    "check_choice",
    "CONTROL_CHARACTERS",
    "check_printable",
    "check_wavelengths",
    "check_incidence",
    "parse_range",
    "Interval",
    "Numbers",
    "StrOptions",
    "Table",
]


def _gib(n_bytes: float) -> str:
    return f"{n_bytes / (1 << 30):.3g} GiB"


def check_allocation(name: str, value: object, n_bytes: float, limit_bytes: float = MAX_ALLOCATION_BYTES) -> None:
    """Refuses ``value`` of parameter ``name`` when the memory it needs, ``n_bytes`` (an
    estimate made before allocating), exceeds ``limit_bytes``; the message states both in GiB."""
    if n_bytes > limit_bytes:
        raise ParameterError(
            name, value, f"needs about {_gib(n_bytes)} of memory, more than the limit of {_gib(limit_bytes)}"
        )


def interval_text(
    low: float | None = None, high: float | None = None, low_open: bool = False, high_open: bool = False
) -> str:
    """The interval [low, high] as text with a leading space (``" in [0, 24]"``, ``" ≥ 1"``),
    or ``""`` when both bounds are None; ``low_open``/``high_open`` exclude the bound.

    Integer bounds are written in full, other numbers in ``%g``.
    """
    if low is None and high is None:
        return ""
    if high is None:
        return f" {'>' if low_open else '≥'} {_number_text(low)}"
    if low is None:
        return f" {'<' if high_open else '≤'} {_number_text(high)}"
    return f" in {'(' if low_open else '['}{_number_text(low)}, {_number_text(high)}{')' if high_open else ']'}"


def in_interval(
    x: Any, low: float | None = None, high: float | None = None, low_open: bool = False, high_open: bool = False
) -> np.bool_ | np.ndarray:
    """Whether ``x`` (a number, or an array element by element) lies in the interval of
    :func:`interval_text`: a bound None is no bound, ``low_open``/``high_open`` exclude the bound.
    NaN lies in no interval. Numbers are compared as they are (a Python int of any size exactly)."""
    above = True if low is None else (x > low if low_open else x >= low)
    below = True if high is None else (x < high if high_open else x <= high)
    return np.logical_and(above, below)


def _number_text(x: float) -> str:
    # Integers in full (a seed bound of 2**64 - 1 must not read 1.84467e+19), other numbers in %g.
    return str(int(x)) if isinstance(x, (int, np.integer)) else f"{x:g}"


def is_number(value: Any) -> bool:
    """Whether ``value`` is a Python or numpy real number (a bool is not)."""
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool)


def check_real_array(
    name: str,
    value: Any,
    low: float | None = None,
    high: float | None = None,
    *,
    low_open: bool = False,
    high_open: bool = False,
) -> np.ndarray:
    """``value`` as a float64 array whose every element is finite and in the interval.

    Parameters
    ----------
    name : str
        Parameter name used in the error message.
    value : array_like
        Scalar or array of real numbers.
    low, high : float, optional
        Bounds of the admissible interval (None: unbounded on that side).
    low_open, high_open : bool
        Whether the bound itself is excluded.

    Raises
    ------
    ParameterError
        If ``value`` is not numeric, contains NaN or infinities, is empty, or leaves the interval.
        The reported value is the first offending element.
    """
    interval = interval_text(low, high, low_open, high_open)
    if isinstance(value, (str, bytes)):
        raise ParameterError(name, value, f"a real number{interval}")
    try:
        array = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ParameterError(name, value, f"a real number{interval}") from None
    if array.size == 0:
        raise ParameterError(name, value, f"at least one real number{interval}")
    bad = ~np.isfinite(array) | ~in_interval(array, low, high, low_open, high_open)
    if bad.any():
        first = array.reshape(-1)[np.flatnonzero(bad.reshape(-1))[0]]
        reported = first.item() if array.ndim else value
        raise ParameterError(name, reported, f"a finite real number{interval}")
    return array


def check_real(
    name: str,
    value: Any,
    low: float | None = None,
    high: float | None = None,
    *,
    low_open: bool = False,
    high_open: bool = False,
) -> float:
    """Like :func:`check_real_array` but requires a single number and returns a Python float."""
    array = check_real_array(name, value, low, high, low_open=low_open, high_open=high_open)
    if array.ndim != 0:
        raise ParameterError(name, value, "a single real number, not an array")
    return float(array)


def check_unit_vectors(name: str, value: Any) -> np.ndarray:
    """``value`` (shape (..., 3)) normalised to unit length.

    Raises
    ------
    ParameterError
        If the last axis is not of length 3, an element is not finite, or a vector has zero length.
    """
    try:
        array = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ParameterError(name, value, "an array of shape (..., 3) of real numbers") from None
    if array.ndim == 0 or array.shape[-1] != 3:
        raise ParameterError(
            name,
            f"array of shape {array.shape}",
            "an array of shape (..., 3): direction vectors (x east, y north, z up)",
        )
    if not np.isfinite(array).all():
        raise ParameterError(name, "an array containing NaN or infinity", "finite direction vectors")
    norm = np.linalg.norm(array, axis=-1, keepdims=True)
    if (norm <= 1e-12).any():
        raise ParameterError(name, "an array containing a zero-length vector", "non-zero direction vectors")
    return array / norm


def check_whole_number(
    name: str, value: Any, low: int | None = None, high: int | None = None, *, noun: str = "a whole number"
) -> int:
    """``value`` as an int: a Python or numpy integer (not a bool, not a float) in [low, high].

    ``noun`` starts the message (e.g. ``"a whole number of pixels"``).
    """
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not in_interval(value, low, high):
        raise ParameterError(name, value, noun + interval_text(low, high))
    return int(value)


def check_count(name: str, value: Any) -> int:
    """A count ≥ 1 (rays, events, trials) as an int; integral floats and numeric text such as
    ``1e6`` or ``"1e6"`` are accepted."""
    allowed = "a whole number ≥ 1 (e.g. 1e6)"
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ParameterError(name, value, allowed) from None
    if not math.isfinite(number) or number < 1 or number != int(number) or isinstance(value, bool):
        raise ParameterError(name, value, allowed)
    return int(number)


def check_seed(name: str, value: Any) -> int:
    """A master seed of the counter-based random streams: an integer in [0, 2**64)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not (0 <= int(value) < 2**64):
        raise ParameterError(name, value, "an integer in [0, 2**64)")
    return int(value)


def check_threads(name: str, value: Any) -> int | None:
    """Worker threads: None (all cores) or an integer in [1, 1024]."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not (1 <= int(value) <= 1024):
        raise ParameterError(name, value, "None (all cores) or an integer in [1, 1024]")
    return int(value)


def check_choice(name: str, value: Any, allowed: Sequence[str]) -> str:
    """``value`` if it is one of the names ``allowed`` (compared exactly, as strings)."""
    if not isinstance(value, str) or value not in allowed:
        raise ParameterError(name, value, "one of " + ", ".join(repr(a) for a in allowed))
    return value


#: C0 control characters except tab and newline, DEL, C1 control characters (ESC starts the
#: terminal's escape sequences, CR overwrites the line), and the bidirectional embeddings,
#: overrides and isolates, which reorder what the terminal shows.
CONTROL_CHARACTERS = re.compile("[\x00-\x08\x0b-\x1f\x7f-\x9f\u202a-\u202e\u2066-\u2069]")


def check_printable(name: str, value: str) -> str:
    """``value`` if it holds none of `CONTROL_CHARACTERS` (a name read from a file and shown on
    the terminal: ``ESC[2J`` in it would clear the screen)."""
    found = CONTROL_CHARACTERS.search(value)
    if found is not None:
        raise ParameterError(name, value, f"text without control characters (found {found.group()!r})")
    return value


def check_wavelengths(name: str, value: Any) -> np.ndarray:
    """Vacuum wavelengths (nm) for the engine: a non-empty 1-D float array, each finite and in
    :data:`WAVELENGTH_RANGE_NM` (a scalar becomes one wavelength)."""
    wl = np.atleast_1d(np.asarray(value, dtype=float))
    if wl.ndim != 1 or wl.size == 0:
        raise ParameterError(name, value, "a non-empty 1-D sequence of wavelengths in nm")
    low, high = WAVELENGTH_RANGE_NM
    bad = ~np.isfinite(wl) | (wl < low) | (wl > high)
    if bad.any():
        raise ParameterError(
            name, float(wl[bad][0]), f"wavelengths in [{low:g}, {high:g}] nm (the range of the optical constants)"
        )
    return wl


def check_incidence(name: str, value: Any) -> float:
    """Zenith angle θᵢ of incident light as a float, in [0, 90) degrees."""
    allowed = "a number in [0, 90) degrees"
    try:
        angle = float(value)
    except (TypeError, ValueError):
        raise ParameterError(name, value, allowed) from None
    if not (0.0 <= angle < 90.0):
        raise ParameterError(name, value, allowed)
    return angle


def parse_range(name: str, text: str) -> np.ndarray:
    """``start:stop:step`` (inclusive of stop when it falls on the grid), or comma-separated values,
    as typed on the command line (``name`` is the option, e.g. ``--wavelengths``); at most
    `MAX_WAVELENGTHS` values."""
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


# Declared constraints: a table of what each parameter may be (scikit-learn's
# ``_parameter_constraints``), used by the predictors' estimator base.


@dataclass(frozen=True)
class Interval:
    """Finite integers (``kind=numbers.Integral``) or real numbers (``numbers.Real``) in an interval.

    Parameters
    ----------
    kind : numbers.Integral or numbers.Real
        Integral admits Python and numpy integers; Real also floats. Never bool.
    low, high : float or None
        Bounds; None for no bound (the value must still be finite).
    closed : {"both", "left", "right", "neither"}
        Which bounds belong to the interval.
    """

    kind: type
    low: float | None
    high: float | None
    closed: str = "both"

    def admits(self, value: Any) -> bool:
        if isinstance(value, (bool, np.bool_)) or not isinstance(value, self.kind):
            return False
        if not isinstance(value, numbers.Integral) and not math.isfinite(value):
            return False
        inclusive_low, inclusive_high = self.closed in ("both", "left"), self.closed in ("both", "right")
        above = self.low is None or (value >= self.low if inclusive_low else value > self.low)
        below = self.high is None or (value <= self.high if inclusive_high else value < self.high)
        return above and below

    def __str__(self) -> str:
        integer = self.kind is numbers.Integral
        inclusive_low, inclusive_high = self.closed in ("both", "left"), self.closed in ("both", "right")
        noun = "an integer" if integer else "a number"
        if self.low is not None and self.high is not None:
            if integer and inclusive_low and inclusive_high:
                return f"{noun} in {self.low:g}..{self.high:g}"
            left, right = "[" if inclusive_low else "(", "]" if inclusive_high else ")"
            return f"{noun} in {left}{self.low:g}, {self.high:g}{right}"
        finite = noun if integer else "a finite number"
        if self.low is not None:
            return f"{finite} {'>=' if inclusive_low else '>'} {self.low:g}"
        if self.high is not None:
            return f"{finite} {'<=' if inclusive_high else '<'} {self.high:g}"
        return finite


@dataclass(frozen=True)
class Names:
    """A sequence (tuple or list) of distinct strings, each one of ``options``."""

    options: tuple[str, ...]

    def admits(self, value: Any) -> bool:
        return (
            isinstance(value, (tuple, list))
            and all(isinstance(v, str) and v in self.options for v in value)
            and len(set(value)) == len(value)
        )

    def __str__(self) -> str:
        return f"a sequence of distinct names from {self.options}"


@dataclass(frozen=True)
class Numbers:
    """A sequence (tuple or list) of ``min_len`` to ``max_len`` numbers, each admitted by ``each``."""

    each: Interval
    min_len: int
    max_len: int

    def admits(self, value: Any) -> bool:
        return (
            isinstance(value, (tuple, list))
            and self.min_len <= len(value) <= self.max_len
            and all(self.each.admits(v) for v in value)
        )

    def __str__(self) -> str:
        return f"a sequence of {self.min_len} to {self.max_len} values, each {self.each}"


@dataclass(frozen=True)
class StrOptions:
    """One of a few strings."""

    options: tuple[str, ...]

    def admits(self, value: Any) -> bool:
        return isinstance(value, str) and value in self.options

    def __str__(self) -> str:
        return f"one of {self.options}"


class Table:
    """A table of a configuration file (TOML or JSON) being read, key by key, with checks.

    A bad value is reported as a :class:`~sandlight.errors.ParameterError` whose name is the dotted
    key (``camera.fov_deg``), with the value, the allowed range and the file it came from. Keys
    never read are refused by :meth:`finish` with the list of allowed ones (a typo must not be
    silently ignored).

    Parameters
    ----------
    data : mapping or None
        The table's keys and values (None: empty).
    prefix : str
        Its dotted name ('' for the top level).
    source : str
        The file it came from, quoted in messages ('' for none).
    """

    def __init__(self, data: Any, prefix: str, source: str = "") -> None:
        self.prefix = prefix
        self.source = source
        if data is None:
            data = {}
        if not isinstance(data, Mapping):
            raise self.error(prefix or "scene", data, "a table of keys and values")
        self.data = dict(data)
        self.used: set[str] = set()

    def name(self, key: str) -> str:
        """The dotted name of ``key`` in this table."""
        return f"{self.prefix}.{key}" if self.prefix else key

    def error(self, name: str, value: Any, allowed: str) -> ParameterError:
        """The error for a bad ``value`` of ``name``, naming the file it came from."""
        where = f" (in {self.source})" if self.source else ""
        return ParameterError(name, value, allowed + where)

    def has(self, key: str) -> bool:
        """Whether the table holds ``key``."""
        return key in self.data

    def raw(self, key: str, default: Any = None) -> Any:
        """The value of ``key`` unchecked (``default`` if absent); the key counts as read."""
        self.used.add(key)
        return self.data.get(key, default)

    def table(self, key: str) -> Table:
        """The sub-table ``key`` (empty if absent)."""
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
        """A finite number in the interval; required when ``default`` is None."""
        value = self.raw(key, default)
        interval = interval_text(lo, hi, lo_open, hi_open)
        if value is None:
            raise self.error(self.name(key), "missing", "a number" + interval)
        if not is_number(value) or not math.isfinite(float(value)):
            raise self.error(self.name(key), value, "a finite number" + interval)
        v = float(value)
        if not in_interval(v, lo, hi, lo_open, hi_open):
            raise self.error(self.name(key), value, "a number" + interval)
        return v

    def integer(self, key: str, default: int | None = None, lo: int | None = None, hi: int | None = None) -> int:
        """A whole number in [lo, hi] (integral floats such as 2.0 are accepted)."""
        value = self.raw(key, default)
        allowed = "a whole number" + interval_text(lo, hi)
        if value is None:
            raise self.error(self.name(key), "missing", allowed)
        if isinstance(value, bool) or not is_number(value) or float(value) != int(value):
            raise self.error(self.name(key), value, allowed)
        v = int(value)
        if not in_interval(v, lo, hi):
            raise self.error(self.name(key), value, allowed)
        return v

    def boolean(self, key: str, default: bool) -> bool:
        """true or false."""
        value = self.raw(key, default)
        if not isinstance(value, bool):
            raise self.error(self.name(key), value, "true or false")
        return value

    def string(self, key: str, default: str | None = None) -> str:
        """A non-empty string; required when ``default`` is None."""
        value = self.raw(key, default)
        if not isinstance(value, str) or not value:
            raise self.error(self.name(key), value if value is not None else "missing", "a non-empty string")
        return value

    def choice(self, key: str, options: Sequence[str], default: str | None = None) -> str:
        """One of ``options``; required when ``default`` is None."""
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
        """A list of ``length`` (or one of several lengths) finite numbers in [lo, hi]."""
        value = self.raw(key, default)
        lengths = (length,) if isinstance(length, int) else tuple(length)
        allowed = f"a list of {' or '.join(map(str, lengths))} finite numbers" + interval_text(lo, hi)
        if value is None:
            raise self.error(self.name(key), "missing", allowed)
        if (
            not isinstance(value, (list, tuple))
            or len(value) not in lengths
            or not all(is_number(v) and math.isfinite(float(v)) for v in value)
        ):
            raise self.error(self.name(key), value, allowed)
        array = np.array([float(v) for v in value])
        if not in_interval(array, lo, hi).all():
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
