"""Batches of sand samples as named columns: what the predictors take as input.

A batch is given as

- one `SandSample`, or a dict of scalars (one sample);
- a list of SandSample or of dicts (one per sample);
- a dict of columns: 1-D arrays of one length n, one value per sample, and scalars, which hold for
  every sample (broadcast);
- a table: a numpy structured array, a pandas.DataFrame or an xarray.Dataset (columns as above).

Each sample means what `SandSample` means: a parameter not given takes its SandSample default
(`sandlight.sample.PARAMETERS`), so ``{"iron_oxide": [0.01, 0.02]}`` is two default samples
with those iron-oxide contents. What could be read more than one way is refused with a
`ParameterError`: arrays of different lengths, arrays of two or more dimensions, a bool where a
number is due, and — in a dict or a list of dicts — a key that is not a sample parameter (a
misspelt name would otherwise silently take the default). A table may carry other columns (a
training set carries its reflectance); they are ignored.

Values are not checked against the parameters' domains here: that is the predictor's (its
training domain).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from sandlight.errors import ParameterError
from sandlight.predictor.domain import FORM_PARAMETER
from sandlight.sample import PARAMETERS

__all__ = ["sample_columns"]

_DEFAULTS = {p.name: p.default for p in PARAMETERS}
#: Types of row values taken without further checks (the common case, kept fast).
_PLAIN_SCALARS = frozenset({float, int, str, np.float64, np.int64, np.str_})
_ACCEPTED = (
    "SandSample(s), dict(s) of parameters, dict of 1-D arrays and scalars, a structured array, "
    "a DataFrame or an xarray.Dataset"
)


def sample_columns(samples: Any) -> dict[str, np.ndarray]:
    """Every SandSample parameter of a batch of samples as a column of one length n.

    Parameters
    ----------
    samples : SandSample, dict, list of them, dict of columns, structured array, DataFrame or
              xarray.Dataset
        The batch (see the module docstring).

    Returns
    -------
    dict of str to ndarray (n,)
        One entry per parameter of `sandlight.sample.PARAMETERS`, in their order: float arrays,
        except ``iron_oxide_form`` as given (names, or integer codes into a model's forms).
        Parameters not given hold their SandSample default.

    Raises
    ------
    ParameterError
        An unsupported container, an empty list, arrays of different lengths or of two or more
        dimensions, a bool or a non-number for a numeric parameter, or an unknown key in a dict.

    Examples
    --------
    >>> columns = sample_columns({"iron_oxide": [0.01, 0.03], "iron_oxide_form": "particles"})
    >>> columns["iron_oxide"].tolist(), columns["iron_oxide_form"].tolist(), columns["porosity"].tolist()
    ([0.01, 0.03], ['particles', 'particles'], [0.4, 0.4])
    """
    given, n = _given(samples)
    columns = {}
    for name, default in _DEFAULTS.items():
        if name not in given:
            columns[name] = np.full(n, default if name == FORM_PARAMETER else float(default))
            continue
        column = given[name]
        columns[name] = np.full(n, column) if column.ndim == 0 else column
    return columns


def _given(samples: Any) -> tuple[dict[str, np.ndarray], int]:
    """The parameter columns a batch gives (numbers as floats, 0-d for a broadcast scalar) and
    its length n."""
    if hasattr(samples, "data_vars") and hasattr(samples, "variables"):  # xarray.Dataset
        return _columns_of({k: samples[k].values for k in _DEFAULTS if k in samples.variables}, strict=False)
    if hasattr(samples, "columns") and hasattr(samples, "to_numpy"):  # pandas.DataFrame
        return _typed({k: samples[k].to_numpy() for k in _DEFAULTS if k in samples.columns}), len(samples)
    if isinstance(samples, np.ndarray) and samples.dtype.names is not None:  # structured array
        if samples.ndim > 1:
            raise ParameterError("samples", f"a structured array of shape {samples.shape}", "a 1-D structured array")
        table = np.atleast_1d(samples)
        return _typed({k: table[k] for k in _DEFAULTS if k in table.dtype.names}), len(table)
    if hasattr(samples, "to_dict") and not isinstance(samples, Mapping):  # one SandSample
        return _rows([samples])
    if isinstance(samples, Mapping):
        if all(_array(k, v).ndim == 0 for k, v in samples.items()):
            return _rows([samples])  # one sample as a dict of scalars
        return _columns_of(samples, strict=True)
    if isinstance(samples, Sequence) and not isinstance(samples, (str, bytes)):
        return _rows(samples)
    raise ParameterError(
        "samples", type(samples).__name__, f"{_ACCEPTED}, or an (n, n_parameters) float array with form codes"
    )


def _columns_of(mapping: Mapping, *, strict: bool) -> tuple[dict[str, np.ndarray], int]:
    """Columns of a dict of arrays and scalars: the arrays 1-D of one length, scalars broadcast."""
    if strict:
        _refuse_unknown(mapping)
    given = {str(k): _array(k, v) for k, v in mapping.items() if k in _DEFAULTS}
    first = None
    for name, column in given.items():
        if column.ndim > 1:
            raise ParameterError(
                name, f"an array of shape {column.shape}", "a scalar or a 1-D array (one value per sample)"
            )
        if column.ndim == 1:
            if first is None:
                first = name
            elif len(column) != len(given[first]):
                raise ParameterError(
                    name,
                    f"{len(column)} values",
                    f"one value per sample: {len(given[first])} values like {first}, or a scalar for all",
                )
    return _typed(given), 1 if first is None else len(given[first])


def _rows(rows: Sequence) -> tuple[dict[str, np.ndarray], int]:
    """Columns of a list of samples (SandSample or dicts of scalars)."""
    rows = [r.to_dict() if hasattr(r, "to_dict") and not isinstance(r, Mapping) else r for r in rows]
    if not rows or not all(isinstance(r, Mapping) for r in rows):
        raise ParameterError("samples", f"a {type(rows).__name__} of {len(rows)}", f"a non-empty list of {_ACCEPTED}")
    keys = set().union(*rows)
    if not keys <= _DEFAULTS.keys():
        _refuse_unknown(next(r for r in rows if not r.keys() <= _DEFAULTS.keys()))
    given = {}
    for name, default in _DEFAULTS.items():
        if name in keys:
            values = [r.get(name, default) for r in rows]
            if not _PLAIN_SCALARS.issuperset(map(type, values)):  # (a bool is not an int here)
                for v in values:
                    if np.ndim(v) != 0:
                        raise ParameterError(name, v, "one value per sample (a scalar) in a list of samples")
                    if isinstance(v, (bool, np.bool_)):
                        raise ParameterError(name, v, "a number, not a bool")
            given[name] = np.asarray(values) if name == FORM_PARAMETER else _numbers(name, values)
    return given, len(rows)


def _typed(columns: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The numeric parameters' columns as floats."""
    return {k: v if k == FORM_PARAMETER else _numbers(k, v) for k, v in columns.items()}


def _array(name: Any, value: Any) -> np.ndarray:
    try:
        return np.asarray(value)
    except ValueError:  # ragged nested sequences
        raise ParameterError(str(name), value, "a scalar or a 1-D array (one value per sample)") from None


def _numbers(name: str, values: Any) -> np.ndarray:
    """A numeric parameter's values as floats (a bool is not a number)."""
    if isinstance(values, np.ndarray) and values.dtype.kind == "b":
        raise ParameterError(name, _shown(values), "numbers, not bools")
    try:
        return np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(name, _shown(values), "a number (or an array of numbers)") from None


def _shown(values: Any) -> Any:
    """Values for a message: a scalar, or the first few of an array."""
    values = np.asarray(values, dtype=object)
    if values.ndim == 0:
        return values.item()
    return values.tolist() if values.size <= 5 else f"{values.size} values, starting {values.ravel()[:3].tolist()}"


def _refuse_unknown(mapping: Mapping) -> None:
    for key, value in mapping.items():
        if key not in _DEFAULTS:
            raise ParameterError(str(key), _shown(value), f"a sample parameter: one of {', '.join(_DEFAULTS)}")
