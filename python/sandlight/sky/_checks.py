"""Input validation shared by the daylight modules.

Every public function of :mod:`sandlight.sky` turns its numeric inputs into float arrays here, so
that a bad value (non-numeric, NaN, infinite, out of range) is reported the same way everywhere:
as :class:`sandlight.errors.ParameterError` naming the parameter, the offending value and the
admissible range.
"""

from __future__ import annotations

import numpy as np

from sandlight.errors import ParameterError


def real_array(
    name: str,
    value,
    low: float | None = None,
    high: float | None = None,
    *,
    low_open: bool = False,
    high_open: bool = False,
) -> np.ndarray:
    """Return ``value`` as a float64 array, checking that every element is finite and in range.

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
    interval = _interval_text(low, high, low_open, high_open)
    if isinstance(value, (str, bytes)):
        raise ParameterError(name, value, f"a real number {interval}")
    try:
        array = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ParameterError(name, value, f"a real number {interval}") from None
    if array.size == 0:
        raise ParameterError(name, value, f"at least one real number {interval}")
    bad = ~np.isfinite(array)
    if low is not None:
        bad |= (array <= low) if low_open else (array < low)
    if high is not None:
        bad |= (array >= high) if high_open else (array > high)
    if bad.any():
        first = array.reshape(-1)[np.flatnonzero(bad.reshape(-1))[0]]
        reported = first.item() if array.ndim else value
        raise ParameterError(name, reported, f"a finite real number {interval}")
    return array


def real_scalar(
    name: str,
    value,
    low: float | None = None,
    high: float | None = None,
    *,
    low_open: bool = False,
    high_open: bool = False,
) -> float:
    """Like :func:`real_array` but requires a single number and returns a Python float."""
    array = real_array(name, value, low, high, low_open=low_open, high_open=high_open)
    if array.ndim != 0:
        raise ParameterError(name, value, "a single real number, not an array")
    return float(array)


def unit_vectors(name: str, value) -> np.ndarray:
    """Return ``value`` (shape (..., 3)) normalised to unit length.

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


def _interval_text(low, high, low_open, high_open) -> str:
    if low is None and high is None:
        return ""
    if high is None:
        return f"{'>' if low_open else '>='} {low:g}"
    if low is None:
        return f"{'<' if high_open else '<='} {high:g}"
    return f"in {'(' if low_open else '['}{low:g}, {high:g}{')' if high_open else ']'}"
