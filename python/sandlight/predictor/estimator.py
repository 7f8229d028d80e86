"""The estimator contract of sandlight's predictors (scikit-learn's, without importing it).

A predictor subclasses `Estimator`:

- ``__init__`` takes keyword arguments with defaults and only stores them under the same names;
  the parameter names are read from its signature (``inspect.signature``, as scikit-learn's
  ``BaseEstimator._get_param_names``), which gives ``get_params``, ``set_params`` (hence
  ``sklearn.base.clone``) and ``__repr__``;
- ``_parameter_constraints`` declares, for every parameter, what it may be:
  `sandlight.checks.Interval`, `sandlight.checks.StrOptions` or ``None``, as scikit-learn's
  table of the same name. ``fit`` calls
  `Estimator.validate_params`, which raises `sandlight.errors.ParameterError` naming the
  parameter, the value and everything allowed. A bool is never a number (``n_components=True``
  is refused);
- learned attributes end in ``_``; `Estimator.check_is_fitted` refuses an estimator without any;
- the model file is ``_model_file`` (a `sandlight.predictor.model_file.ModelFileFormat`):
  ``save`` writes ``_metadata()`` and ``_arrays()``, ``load`` rebuilds with ``_from_parts``.
"""

from __future__ import annotations

import inspect
from collections.abc import Mapping
from pathlib import Path
from typing import Any, ClassVar, Self

import numpy as np

from sandlight.checks import Interval, StrOptions
from sandlight.errors import ModelFileError, ParameterError, SandlightError
from sandlight.predictor.model_file import ModelFileFormat, warn_if_other_version

__all__ = ["Estimator"]


def _admits(constraint: Interval | StrOptions | None, value: Any) -> bool:
    return value is None if constraint is None else constraint.admits(value)


def _describe(constraints: list) -> str:
    return " or ".join("None" if c is None else str(c) for c in constraints)


def _same(a: Any, b: Any) -> bool:
    """a and b are the same parameter value (no elementwise comparison of arrays)."""
    return a is b or (type(a) is type(b) and not isinstance(a, np.ndarray) and a == b)


class Estimator:
    """Base of sandlight's predictors (see the module docstring).

    Subclasses declare ``_parameter_constraints`` (every ``__init__`` parameter) and
    ``_model_file``, and implement ``_metadata``, ``_arrays`` and ``_from_parts``.
    """

    _parameter_constraints: ClassVar[dict[str, list]] = {}
    _model_file: ClassVar[ModelFileFormat]

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        names = set(cls._parameter_names())
        if names != set(cls._parameter_constraints):  # a programming error, caught at import
            raise TypeError(
                f"{cls.__name__}: _parameter_constraints {sorted(cls._parameter_constraints)} must "
                f"list exactly the __init__ parameters {sorted(names)}"
            )

    @classmethod
    def _parameter_names(cls) -> list[str]:
        """Names of the ``__init__`` keyword parameters, in signature order."""
        parameters = inspect.signature(cls.__init__).parameters.values()
        if any(p.kind in (p.VAR_POSITIONAL, p.VAR_KEYWORD) for p in parameters):
            raise TypeError(f"{cls.__name__}.__init__ must name its parameters (no *args, **kwargs)")
        return [p.name for p in parameters if p.name != "self"]

    # ---- parameters ------------------------------------------------------------------------
    def get_params(self, deep: bool = True) -> dict[str, Any]:
        """The parameters, by name (``deep`` is accepted for scikit-learn; there are no
        sub-estimators)."""
        return {name: getattr(self, name) for name in self._parameter_names()}

    def set_params(self, **params: Any) -> Self:
        """Set parameters by name; returns self. Values are checked by ``fit``."""
        valid = self._parameter_names()
        for name, value in params.items():
            if name not in valid:
                raise ParameterError(name, value, f"one of {sorted(valid)}")
            setattr(self, name, value)
        return self

    def __repr__(self) -> str:
        defaults = {p.name: p.default for p in inspect.signature(type(self).__init__).parameters.values()}
        changed = ", ".join(f"{k}={v!r}" for k, v in self.get_params().items() if not _same(v, defaults[k]))
        return f"{type(self).__name__}({changed})"

    def validate_params(self) -> None:
        """Check every parameter against ``_parameter_constraints``.

        Raises
        ------
        ParameterError
            Naming the first parameter that is not allowed, its value and what is.
        """
        for name, constraints in self._parameter_constraints.items():
            value = getattr(self, name)
            if not any(_admits(c, value) for c in constraints):
                raise ParameterError(name, value, _describe(constraints))

    def check_is_fitted(self) -> None:
        """Raise `SandlightError` unless ``fit`` or ``load`` has set learned attributes (names
        ending in ``_``)."""
        if not any(k.endswith("_") and not k.startswith("__") for k in vars(self)):
            name = type(self).__name__
            raise SandlightError(f"this {name} is not fitted yet: call fit() or {name}.load()")

    # ---- persistence -----------------------------------------------------------------------
    def save(self, path: str | Path) -> Path:
        """Write the model as plain arrays + JSON metadata in an ``.npz`` file (never pickle).

        The file is written atomically (temporary file, then rename). Returns the path.
        """
        self.check_is_fitted()
        return self._model_file.write(path, self._metadata(), self._arrays())

    @classmethod
    def load(cls, path: str | Path) -> Self:
        """Read a model written by ``save``.

        Raises
        ------
        ModelFileError
            The file is missing, not a model file of this kind, truncated, corrupt, of a newer
            format version, or internally inconsistent.

        Warns
        -----
        ModelVersionWarning
            The file was written by another sandlight version.
        """
        path = Path(path)
        meta, data = cls._model_file.read(path)
        try:
            model = cls._from_parts(meta, data, path)
        except (KeyError, TypeError, ValueError) as exc:  # ParameterError is a ValueError
            raise ModelFileError(f"{path} is an incomplete or inconsistent {cls._model_file.kind} file: {exc}") from exc
        warn_if_other_version(path, meta)
        return model

    def _metadata(self) -> dict[str, Any]:
        """The model's entries of the file's JSON metadata (the format header is added)."""
        raise NotImplementedError

    def _arrays(self) -> dict[str, np.ndarray]:
        """The arrays written to the file, by name."""
        raise NotImplementedError

    @classmethod
    def _params_from_file(cls, params: Mapping) -> Self:
        """An unfitted estimator with a file's ``params`` metadata, validated. JSON has no
        tuples: a list is read back as a tuple where ``__init__``'s default is one (so a loaded
        model's ``get_params`` equals the saved one's); a parameter absent from an older file
        takes its default."""
        defaults = {p.name: p.default for p in inspect.signature(cls.__init__).parameters.values()}
        tuples = {k for k, v in params.items() if isinstance(v, list) and isinstance(defaults.get(k), tuple)}
        model = cls(**{k: tuple(v) if k in tuples else v for k, v in params.items()})
        model.validate_params()
        return model

    @classmethod
    def _from_parts(cls, meta: Mapping, data: Mapping[str, np.ndarray], path: Path) -> Self:
        """The fitted model from a file's metadata and arrays (raise KeyError, TypeError or
        ValueError for anything inconsistent)."""
        raise NotImplementedError
