"""Forward models of a fit: sample parameters → reflectance spectrum on a wavelength grid.

Public objects
--------------
BankForward
    One model of the shipped predictor bank (:class:`sandlight.predictor.ModelBank`); its error
    budget is the model's hold-out RMS error per wavelength.
bank_candidates
    The models of a bank that can answer a fit: their inputs include every free parameter and
    their training domain holds every other parameter of the base sample. Each comes with the
    fit's bounds narrowed to its training domain.
EngineForward
    The Monte Carlo engine (:func:`sandlight.reflectance`) with the same seed at every call
    (common random numbers: the same random streams for every parameter vector, so the
    objective does not jump by fresh noise at every evaluation; it is still rough where a
    parameter changes the paths, e.g. saturation: see ``retrieve.ENGINE_JACOBIAN_STEP``); its
    error budget is the Monte Carlo standard error. Wavelengths are traced one by one
    (``share=False``): the same random streams at every wavelength too, and at 2·10⁴ rays a
    standard error several times smaller at the bright red end than with spectral path sharing
    (0.003 against 0.011 at 700 nm for 2 % iron oxide: scripts/studies/retrieval_engine_roughness.py),
    for twice the time.

Both have ``name``, ``grid`` (nm), ``predict(X)`` for parameter vectors X (k, p) giving
spectra (k, n_grid), and ``budget()`` giving their :class:`ErrorBudget`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Protocol

import numpy as np
from numpy.typing import ArrayLike

from sandlight.errors import ParameterError
from sandlight.predictor.domain import at_fixed_value
from sandlight.retrieval.likelihood import ErrorBudget
from sandlight.retrieval.space import ParameterSpace

if TYPE_CHECKING:
    from sandlight.engine import ReflectanceResult
    from sandlight.predictor import ModelBank, SpectralModel

__all__ = ["ForwardModel", "BankForward", "EngineForward", "bank_candidates"]


class ForwardModel(Protocol):
    """What the fit needs of a forward model."""

    name: str
    grid: np.ndarray
    space: ParameterSpace

    def predict(self, x: np.ndarray) -> np.ndarray: ...
    def budget(self) -> ErrorBudget: ...
    def describe(self) -> str: ...


class BankForward:
    """One SpectralModel of a bank evaluated at the free parameters, the rest at the base."""

    def __init__(self, model: SpectralModel, space: ParameterSpace):
        self.model = model
        self.name = model.name_
        self.grid = np.asarray(model.wavelengths_, dtype=float)
        self.space = space
        names = model.parameter_names_
        base = space.base
        self._base_row = np.array([getattr(base, n) for n in names], dtype=float)
        self._columns = [names.index(n) for n in space.free]
        self._form = model.forms_.index(base.iron_oxide_form)
        scores = model.holdout_scores_ or {}
        rms = scores.get("rms_error", scores.get("rms_error_overall", np.inf))
        self.model_rms = np.broadcast_to(np.asarray(rms, dtype=float), self.grid.shape).copy()

    def predict(self, x: np.ndarray) -> np.ndarray:
        x = np.atleast_2d(np.asarray(x, dtype=float))
        rows = np.tile(self._base_row, (x.shape[0], 1))
        rows[:, self._columns] = np.clip(x, self.space.low, self.space.high)
        # Double precision: the optimiser's Jacobian is a finite difference over a step of ~10⁻⁸.
        return self.model.predict(rows, forms=np.full(x.shape[0], self._form), extrapolate=False, precision="double")

    def budget(self) -> ErrorBudget:
        return ErrorBudget(self.model_rms, np.zeros_like(self.grid))

    def describe(self) -> str:
        return f"predictor bank model {self.name!r} (hold-out RMS error {np.sqrt(np.mean(self.model_rms**2)):.4f})"


def bank_candidates(bank: ModelBank, space: ParameterSpace) -> list[BankForward]:
    """The bank's models that can answer a fit over ``space``, each over its narrowed space.

    Raises
    ------
    ParameterError
        No model takes every free parameter while holding the base sample's other values (the
        message names the free parameters and the form, and points to ``method='engine'``).
    """
    base = space.base
    out = []
    for m in bank.models:
        d = m.domain_
        if not set(space.free) <= set(m.parameter_names_) or base.iron_oxide_form not in m.forms_:
            continue
        if any(not at_fixed_value(np.array([getattr(base, k)], float), v)[0] for k, v in d.fixed.items()):
            continue
        others = {n: np.array([getattr(base, n)], float) for n in d.names if n not in space.free}
        if any(not (d.dimension(n).low <= v[0] <= d.dimension(n).high) for n, v in others.items()):
            continue
        low = np.array([d.dimension(n).low for n in space.free])
        high = np.array([d.dimension(n).high for n in space.free])
        narrowed = space.narrowed(low, high)
        if np.any(narrowed.low >= narrowed.high):
            continue
        out.append(BankForward(m, narrowed))
    if not out:
        raise ParameterError(
            "free",
            list(space.free),
            f"parameters that a model of the predictor bank varies around the given sample (form "
            f"{base.iron_oxide_form!r}); the bank's models: "
            + "; ".join(f"{m.name_}: {', '.join(m.parameter_names_)}" for m in bank.models[:4])
            + " …; or fit with the engine (method='engine')",
        )
    return out


class EngineForward:
    """The Monte Carlo engine at ``rays`` rays per wavelength, one seed for every call."""

    def __init__(
        self,
        space: ParameterSpace,
        grid_nm: ArrayLike,
        *,
        rays: int,
        seed: int = 0,
        threads: int | None = None,
        memory: str | None = None,
    ):
        from sandlight.checks import check_count

        self.space = space
        self.grid = np.asarray(grid_nm, dtype=float)
        self.rays = check_count("rays", rays)
        self.seed = seed
        self.threads = threads
        self.memory = memory
        self.name = f"engine ({self.rays} rays, seed {seed})"
        self.stderr = np.zeros_like(self.grid)
        self.mc_covariance: np.ndarray | None = None
        self.calls = 0

    def run(self, x: np.ndarray, *, rays: int | None = None, seed: int | None = None) -> ReflectanceResult:
        """The engine's ReflectanceResult at one parameter vector."""
        from sandlight.engine import reflectance

        self.calls += 1
        return reflectance(
            self.space.sample(x),
            self.grid,
            rays=rays or self.rays,
            seed=self.seed if seed is None else seed,
            threads=self.threads,
            memory=self.memory,
            progress=False,
            share=False,
        )

    def predict(self, x: np.ndarray) -> np.ndarray:
        x = np.atleast_2d(np.asarray(x, dtype=float))
        out = np.empty((x.shape[0], self.grid.size))
        for i, row in enumerate(x):
            result = self.run(row)
            out[i] = result.values
            self.stderr = result.stderr
        return out

    def replicate_covariance(self, x: np.ndarray, replicates: int) -> np.ndarray:
        """The Monte Carlo covariance of the spectrum at ``x`` from ``replicates`` runs with
        other seeds (seed + 1 …), kept for `budget`. With common random numbers the errors of
        all wavelengths come from the same paths: they are correlated by the reflectance's
        level and path lengths rather than by the distance in wavelength, which the Gaussian
        kernel of the budget assumes. The sample covariance has rank ≤ replicates − 1; the
        measurement noise keeps the total covariance positive definite."""
        x = np.asarray(x, dtype=float)
        spectra = [self.run(x, seed=self.seed + 1 + r).values for r in range(replicates)]
        self.mc_covariance = np.atleast_2d(np.cov(np.array(spectra), rowvar=False))
        return self.mc_covariance

    def budget(self) -> ErrorBudget:
        return ErrorBudget(
            np.zeros_like(self.grid), np.asarray(self.stderr, dtype=float), mc_covariance=self.mc_covariance
        )

    def describe(self) -> str:
        return f"Monte Carlo engine, {self.rays} rays per wavelength, seed {self.seed} (common random numbers)"
