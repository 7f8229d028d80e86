"""A bank of spectral models: each sample is predicted by the most accurate model covering it.

One cubic over every parameter of SandSample is far less accurate than a cubic over a few
parameters with the rest fixed (docs/spectral-predictor.md, "Results"). sandlight therefore ships
several :class:`~sandlight.predictor.spectral.SpectralModel` files: narrow, accurate ones over
the parameters the paper varies (iron oxide, hematite/goethite ratio, saturation) around a
reference sand and around presets, and a broad one over the whole default domain for coverage. A
:class:`ModelBank` ranks them by hold-out error and predicts each sample with the first model
whose training domain contains it.

Public objects
--------------
ModelBank
    The bank: ``predict``, ``select``, ``models``, ``wavelengths_``.
banks_by_grid
    One bank per wavelength grid of some models.
default_model, full_range_model, shipped_banks, default_model_dir
    The models shipped in ``sandlight/data/models/spectral-*.npz``, one bank per wavelength grid:
    the paper's 16 wavelengths (400–700 nm) and the full range (350–2500 nm).
"""

from __future__ import annotations

import functools
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from sandlight.errors import ModelFileError, ParameterError, SandlightError
from sandlight.predictor.domain import FORM_PARAMETER
from sandlight.predictor.samples import sample_columns
from sandlight.predictor.spectral import SpectralModel

#: File names of shipped spectral models inside ``sandlight/data/models``.
SHIPPED_PATTERN = "spectral-*.npz"


def holdout_rms(model: SpectralModel) -> float:
    """A model's hold-out RMS error over all wavelengths (reflectance), inf when unscored."""
    scores = model.holdout_scores_ or {}
    value = scores.get("rms_error_overall")
    return float(value) if value is not None else float("inf")


class ModelBank:
    """Spectral models tried in order of accuracy; each sample goes to the first that covers it.

    Parameters
    ----------
    models : sequence of SpectralModel
        Fitted models at the same wavelengths. They are ranked by hold-out RMS error
        (``holdout_scores_``; unscored models last), ties by fewer input parameters.

    Attributes
    ----------
    models : tuple of SpectralModel
        The models, most accurate first.
    wavelengths_ : ndarray (n_wl,)
        Wavelengths of every model, nm.

    Examples
    --------
    >>> bank = default_model()                                          # doctest: +SKIP
    >>> r, used = bank.predict([SandSample.preset("red-dune")], return_models=True)  # doctest: +SKIP
    >>> bank.describe(used[0])                                          # doctest: +SKIP
    'red-dune-dry: 2 parameters, form coating; hold-out RMS error 0.0021 over 400–700 nm (40 samples); …'
    """

    def __init__(self, models: Sequence[SpectralModel]):
        models = list(models)
        if not models:
            raise ParameterError("models", [], "at least one fitted SpectralModel")
        for m in models:
            m.check_is_fitted()
        wl = np.asarray(models[0].wavelengths_)
        for m in models[1:]:
            if m.wavelengths_.shape != wl.shape or not np.allclose(m.wavelengths_, wl):
                raise ParameterError(
                    f"wavelengths of model {m.name_!r}",
                    m.wavelengths_.tolist(),
                    f"those of the other models of the bank, {wl.tolist()} nm",
                )
        names = [m.name_ for m in models]
        if len(set(names)) != len(names):
            raise ParameterError("model names", names, "distinct names (name_) in one bank")
        # A bank answers each sample with one of its models: they must share the engine's physics.
        memories = {m.name_: m.memory_ for m in models}
        if len(set(memories.values())) > 1:
            raise ParameterError(
                "engine memory of the models",
                memories,
                "one path memory for the whole bank (train them with the same memory)",
            )
        self.memory_ = models[0].memory_
        self.models = tuple(sorted(models, key=lambda m: (holdout_rms(m), len(m.parameter_names_))))
        self.wavelengths_ = wl

    def __repr__(self) -> str:
        return f"ModelBank({', '.join(m.name_ for m in self.models)})"

    @classmethod
    def load(cls, paths: Iterable[str | Path]) -> ModelBank:
        """A bank of the model files ``paths`` (see :meth:`SpectralModel.load` for errors)."""
        return cls([SpectralModel.load(p) for p in paths])

    def model(self, name: str) -> SpectralModel:
        """The model called ``name``."""
        for m in self.models:
            if m.name_ == name:
                return m
        raise ParameterError("model", name, f"one of {[m.name_ for m in self.models]}")

    def describe(self, which: int | str) -> str:
        """One line on a model (given by name or rank): its name, domain size and hold-out error."""
        m = self.models[which] if isinstance(which, (int, np.integer)) else self.model(which)
        scores = m.holdout_scores_ or {}
        error = (
            f"hold-out RMS error {holdout_rms(m):.4f} over "
            f"{m.wavelengths_[0]:g}–{m.wavelengths_[-1]:g} nm "
            f"({scores.get('n_samples', '?')} samples)"
            if scores
            else "no hold-out score"
        )
        forms = f"{len(m.forms_)} forms" if len(m.forms_) > 1 else f"form {m.forms_[0]}"
        text = f"{m.name_}: {len(m.parameter_names_)} parameters, {forms}; {error}"
        if m.memory_ != "none":
            text += f"; engine memory {m.memory_!r}"
        return f"{text}; {m.description_}" if m.description_ else text

    # -- prediction ------------------------------------------------------------------------------
    def _named_columns(self, samples: Any) -> tuple[dict, np.ndarray, np.ndarray]:
        """Columns by name, the distinct form names and each sample's index into them."""
        if isinstance(samples, np.ndarray) and samples.dtype.names is None:
            raise ParameterError(
                "samples",
                f"a plain array of shape {samples.shape}",
                "named parameters (SandSample(s), dicts, a structured array, a "
                "DataFrame or an xarray.Dataset): the models of a bank take "
                "different parameters; use bank.model(name).predict for arrays",
            )
        columns = sample_columns(samples)  # parameters not given take SandSample's defaults
        names, index = np.unique(np.asarray(columns[FORM_PARAMETER]).astype(str), return_inverse=True)
        return columns, names, index.reshape(-1)

    @staticmethod
    def _codes(model: SpectralModel, names: np.ndarray, index: np.ndarray) -> np.ndarray:
        """Each sample's form code in ``model.forms_`` (−1: a form the model does not know)."""
        lookup = np.array([model.forms_.index(f) if f in model.forms_ else -1 for f in names], dtype=np.intp)
        return lookup[index]

    def select(self, samples: Any) -> np.ndarray:
        """Rank (index into ``models``) of the model that predicts each sample, −1 where none
        covers it.

        A model covers a sample when every input parameter is inside its training range, every
        parameter it fixes has that value and the form is one it was trained on; a parameter the
        samples do not give takes its SandSample default (:mod:`sandlight.predictor.samples`).
        """
        return self._select(*self._named_columns(samples))

    def _select(self, columns: dict, names: np.ndarray, index: np.ndarray) -> np.ndarray:
        choice = np.full(index.shape[0], -1, dtype=np.intp)
        for rank, m in enumerate(self.models):
            domain = m.domain_
            free = np.flatnonzero((choice < 0) & (self._codes(m, names, index) >= 0))
            if not free.size:
                continue
            if free.size == choice.size:  # e.g. a single sample: nothing to take out
                choice[domain.contains(columns)] = rank
                continue
            sub = {n: np.asarray(columns[n])[free] for n in (*domain.names, *domain.fixed)}
            choice[free[domain.contains(sub)]] = rank
        return choice

    def predict(
        self, samples: Any, *, extrapolate: bool = False, return_models: bool = False
    ) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
        """Predicted directional-hemispherical reflectance at normal incidence.

        Parameters
        ----------
        samples : SandSample, list of SandSample or dict, dict of columns, structured array,
                  DataFrame or xarray.Dataset
            Samples with named parameters (:func:`sandlight.predictor.samples.sample_columns`:
            scalars hold for every sample, parameters not given take SandSample's defaults).
        extrapolate : bool
            Predict a sample that no model covers, instead of raising, with the model whose
            domain it is nearest to (fewest conditions failed, :meth:`Domain.violations`; ties:
            the most accurate), evaluated outside its domain: with broad models per water regime
            a dry sample extrapolates with the dry one. Without it the error names the
            parameter out of that model's range.
        return_models : bool
            Also return the name of the model used for each sample.

        Returns
        -------
        ndarray (n_samples, n_wavelengths), and with ``return_models`` an array of str (n,)

        Raises
        ------
        ParameterError
            A sample outside every model's domain (naming the parameter, its value and the range
            of the broadest model) unless ``extrapolate``; NaN, an unknown form, or input that can
            be read more than one way (arrays of different lengths, 2-D arrays) always.
        """
        columns, names, index = self._named_columns(samples)
        choice = self._select(columns, names, index)
        out = np.empty((index.shape[0], self.wavelengths_.size))
        uncovered = np.flatnonzero(choice < 0)
        used = choice.copy()
        if uncovered.size:
            row = {k: np.asarray(v)[uncovered] for k, v in columns.items()}
            nearest = self._nearest(row, names[index[uncovered]])
            if not extrapolate:
                self._raise_uncovered(row, self.models[nearest[0]])
            used[uncovered] = nearest
        for rank, m in enumerate(self.models):
            rows = np.flatnonzero(used == rank)
            if not rows.size:
                continue
            inside, outside = rows[choice[rows] >= 0], rows[choice[rows] < 0]
            if inside.size:
                values = np.column_stack([np.asarray(columns[n], dtype=float)[inside] for n in m.parameter_names_])
                out[inside] = m.predict(values, forms=self._codes(m, names, index)[inside])
            if outside.size:  # the named columns: the fixed parameters are ignored, not taken as inputs
                out[outside] = m.predict({k: np.asarray(v)[outside] for k, v in columns.items()}, extrapolate=True)
        if not return_models:
            return out
        return out, np.array([m.name_ for m in self.models])[used]

    def _nearest(self, columns: dict, forms: np.ndarray) -> np.ndarray:
        """For each sample, the rank of the model whose domain it fails fewest conditions of
        (ties: the better rank, i.e. the more accurate model)."""
        failed = np.array([m.domain_.violations(columns, forms) for m in self.models])
        return np.argmin(failed, axis=0)  # the first of the minima: the best rank

    def _raise_uncovered(self, row: dict, nearest: SpectralModel) -> None:
        """Raise a ParameterError naming why the first of ``row``'s samples is not covered."""
        names = [m.name_ for m in self.models]
        hint = (
            f"no model of the bank {names} covers this sample (pass extrapolate=True to use "
            f"{nearest.name_!r}, the nearest, outside its domain)"
        )
        first = {k: np.asarray(v)[:1] for k, v in row.items()}
        try:
            # The nearest model names the parameter out of its range (or a missing one, NaN).
            nearest.predict(first)
        except ParameterError as exc:
            raise ParameterError(exc.name, exc.value, f"{exc.allowed}; {hint}") from None
        raise ParameterError("sample", {k: _scalar(v[0]) for k, v in row.items()}, hint)


def _scalar(value: Any) -> Any:
    return value.item() if isinstance(value, np.generic) else value


def default_model_dir() -> Path:
    """Where the shipped spectral models live in the installed package."""
    from importlib.resources import files

    return Path(str(files("sandlight") / "data" / "models"))


#: The wavelength range of the paper's bank (its 16 wavelengths, every 20 nm), nm.
PAPER_RANGE_NM = (400.0, 700.0)


@functools.lru_cache(maxsize=1)
def shipped_banks() -> tuple[ModelBank, ...]:
    """The spectral models shipped with sandlight, one bank per wavelength grid, narrowest range
    first (loaded once, then cached).

    Raises
    ------
    ModelFileError
        The package has no spectral model (e.g. a source checkout before
        ``scripts/data/train_default_spectral.py`` was run), or a shipped file is unreadable.
    """
    paths = sorted(default_model_dir().glob(SHIPPED_PATTERN))
    if not paths:
        raise ModelFileError(
            f"no spectral model is installed (expected {SHIPPED_PATTERN} in "
            f"{default_model_dir()}); train them with "
            f"scripts/data/train_default_spectral.py, or pass a model file "
            f"(sandlight predict --model PATH)"
        )
    try:
        return banks_by_grid(SpectralModel.load(p) for p in paths)
    except SandlightError as exc:
        if isinstance(exc, ModelFileError):
            raise
        raise ModelFileError(f"the shipped spectral models do not form a bank: {exc}") from exc


def banks_by_grid(models: Iterable[SpectralModel]) -> tuple[ModelBank, ...]:
    """One :class:`ModelBank` per wavelength grid of ``models``, the narrowest range first."""
    grids: dict[tuple[float, ...], list[SpectralModel]] = {}
    for m in models:
        grids.setdefault(tuple(np.round(m.wavelengths_, 6)), []).append(m)
    banks = [ModelBank(group) for group in grids.values()]
    return tuple(sorted(banks, key=lambda b: (float(b.wavelengths_[-1] - b.wavelengths_[0]), b.wavelengths_.size)))


def default_model() -> ModelBank:
    """The paper's bank: the shipped models at its 16 wavelengths, 400–700 nm every 20 nm
    (narrow models around the reference sand and the presets, broad models for the rest).

    Raises
    ------
    ModelFileError
        As :func:`shipped_banks`, or no shipped model spans 400–700 nm.
    """
    low, high = PAPER_RANGE_NM
    banks = shipped_banks()
    for bank in banks:
        if np.isclose(bank.wavelengths_[0], low) and np.isclose(bank.wavelengths_[-1], high):
            return bank
    spans = [f"{b.wavelengths_[0]:g}–{b.wavelengths_[-1]:g} nm" for b in banks]
    raise ModelFileError(
        f"no shipped spectral model spans {low:g}–{high:g} nm (the paper's wavelengths); the shipped ones span {spans}"
    )


def full_range_model() -> ModelBank:
    """The bank of the shipped full-range models: the widest span of wavelengths shipped
    (350–2500 nm, docs/spectral-predictor.md, "Full range").

    Raises
    ------
    ModelFileError
        As :func:`shipped_banks`.
    """
    return shipped_banks()[-1]
