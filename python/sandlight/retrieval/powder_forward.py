"""The powder forward model: a dry powder of one pure mineral, traced by the engine.

A :class:`~sandlight.SandSample` is quartz sand with at most 10 wt% iron oxide and cannot
describe a pure mineral powder (the USGS ``Hematite_GDS69`` sieve series). This forward model
fits :class:`sandlight.physics.powder.Powder` instead (docs/retrieval.md, "Powder forward model").

Public objects
--------------
PowderSpace
    The free parameters of a powder (`POWDER_FREEABLE`), the fixed ones and the bounds
    (`POWDER_BOUNDS`). The diameter is fitted in log10 µm: the fit's coordinate of
    ``diameter_um`` is log10 d, so its bounds, the optimiser's steps, the Laplace posterior
    (a log-normal in d) and the identifiability scan are in decades; `PowderSpace.physical`
    maps the coordinates back (µm). ``scale`` is a nuisance: a multiplicative factor on the
    whole model spectrum, for a model whose absolute level is known to be off (documented in
    docs/retrieval.md); fixed at 1 unless it is made free.
PowderForward
    :class:`sandlight.retrieval.forward.EngineForward` over a PowderSpace: the engine traces the
    Powder at the parameter vector with one seed for every call (common random numbers), the
    spectrum and its Monte Carlo standard errors times ``scale``; its Monte Carlo covariance is
    estimated from replicate runs at the optimum (``replicate_covariance``), because the errors
    of a common-random-number spectrum are correlated by reflectance level, not by wavelength
    distance (docs/retrieval.md, "Powder forward model").
POWDER_WAVELENGTHS_NM
    The default wavelength grid of a powder fit.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from sandlight.checks import check_choice, check_real
from sandlight.errors import ParameterError
from sandlight.optics import MATERIALS
from sandlight.physics.media import MEMORIES
from sandlight.physics.powder import Powder
from sandlight.retrieval.forward import EngineForward
from sandlight.retrieval.space import free_and_fixed

__all__ = ["PowderSpace", "PowderForward", "POWDER_FREEABLE", "POWDER_BOUNDS", "POWDER_WAVELENGTHS_NM"]

#: Bounds of the powder parameters (physical units). Diameter: 1–1000 µm, the range of
#: sieved powders and sands (below 1 µm the particles are smaller than the wavelength and the
#: engine's particle optics, docs/model.md, are outside their domain). Porosity: 0.3–0.8,
#: packed to loose powders. Aspect ratio: the engine's prolate spheroids, 1–20. Scale: a
#: factor of 4 either way on the model spectrum. Scattering inside the grains (inclusions and
#: fractures, mm⁻¹, docs/model.md §2.4 item 9): clear grains to a free path of 1 µm.
POWDER_BOUNDS: dict[str, tuple[float, float]] = {
    "diameter_um": (1.0, 1000.0),
    "porosity": (0.3, 0.8),
    "aspect_ratio": (1.0, 20.0),
    "scale": (0.25, 4.0),
    "scattering_per_mm": (0.0, 1000.0),
}
#: Parameters a powder fit can vary (every one of `POWDER_BOUNDS`).
POWDER_FREEABLE: tuple[str, ...] = tuple(POWDER_BOUNDS)
#: Values of the parameters that are neither free nor fixed.
POWDER_DEFAULTS: dict[str, float] = {
    "diameter_um": 10.0,
    "porosity": 0.45,
    "aspect_ratio": 1.0,
    "scale": 1.0,
    "scattering_per_mm": 0.0,
}
#: Default wavelengths of a powder fit (nm): 400–1000 nm every 25 nm.
POWDER_WAVELENGTHS_NM = np.arange(400.0, 1001.0, 25.0)
_LOG = ("diameter_um",)


@dataclass(frozen=True)
class PowderSpace:
    """Free powder parameters over bounds (diameter in log10 µm), the rest at ``base``.

    Build it with `PowderSpace.build`; ``low``/``high`` are in the fit's coordinates. ``memory``
    is the engine's path memory for the powder (an engine setting, not a parameter).
    """

    free: tuple[str, ...]
    material: str
    base: Mapping[str, float]
    low: np.ndarray
    high: np.ndarray
    memory: str = "none"

    @classmethod
    def build(cls, free: Any, fixed: Mapping[str, Any] | None, material: Any, memory: Any = "none") -> PowderSpace:
        """Check ``free``, ``fixed``, ``material`` and ``memory`` and make the space.

        Raises
        ------
        ParameterError
            ``material`` not one of the shipped materials, ``memory`` not one of the engine's
            path memories; ``free`` empty, not a list of names,
            naming a parameter not in `POWDER_FREEABLE` or repeating one; ``fixed`` naming an
            unknown parameter or one also free, or a value outside `POWDER_BOUNDS`.
        """
        check_choice("material", material, MATERIALS)
        check_choice("memory", memory, MEMORIES)
        free, fixed = free_and_fixed(
            free, fixed, POWDER_FREEABLE, "powder parameter names, e.g. ['diameter_um']", lambda _: "a powder parameter"
        )
        base = dict(POWDER_DEFAULTS)
        for name, value in fixed.items():
            if name not in POWDER_BOUNDS:
                raise ParameterError("fixed", name, f"a powder parameter: one of {', '.join(POWDER_BOUNDS)}")
            lo, hi = POWDER_BOUNDS[name]
            base[name] = check_real(name, value, lo, hi)
        low = np.array([cls._coordinate(n, POWDER_BOUNDS[n][0]) for n in free])
        high = np.array([cls._coordinate(n, POWDER_BOUNDS[n][1]) for n in free])
        return cls(tuple(free), material, base, low, high, memory)

    @staticmethod
    def _coordinate(name: str, value: float) -> float:
        return math.log10(value) if name in _LOG else float(value)

    def physical(self, i: int, value: float) -> float:
        """The value (physical units) of free parameter ``i`` at fit coordinate ``value``."""
        return float(10.0**value) if self.free[i] in _LOG else float(value)

    @property
    def size(self) -> int:
        return len(self.free)

    def to_unit(self, x: np.ndarray) -> np.ndarray:
        return (np.asarray(x, dtype=float) - self.low) / (self.high - self.low)

    def from_unit(self, u: np.ndarray) -> np.ndarray:
        return self.low + np.asarray(u, dtype=float) * (self.high - self.low)

    def centre(self) -> np.ndarray:
        return (self.low + self.high) / 2

    def values(self, x: np.ndarray) -> dict[str, float]:
        """The free parameters at fit coordinates ``x``, in physical units (diameter in µm)."""
        x = np.clip(np.asarray(x, dtype=float), self.low, self.high)
        return {n: self.physical(i, v) for i, (n, v) in enumerate(zip(self.free, x, strict=True))}

    def parameters(self, x: np.ndarray) -> dict[str, float]:
        """Every powder parameter (physical units) at fit coordinates ``x``."""
        return {**self.base, **self.values(x)}

    def sample(self, x: np.ndarray) -> Powder:
        """The Powder at fit coordinates ``x`` (``scale`` is not part of it)."""
        p = self.parameters(x)
        return Powder(
            self.material,
            p["diameter_um"],
            porosity=p["porosity"],
            aspect_ratio=p["aspect_ratio"],
            memory=self.memory,
            scattering_per_mm=p["scattering_per_mm"],
        )

    def scale(self, x: np.ndarray) -> np.ndarray:
        """The nuisance scale of each row of ``x`` (k, p) → (k,)."""
        x = np.atleast_2d(np.asarray(x, dtype=float))
        if "scale" not in self.free:
            return np.full(x.shape[0], self.base["scale"])
        i = self.free.index("scale")
        return np.clip(x[:, i], self.low[i], self.high[i])


class PowderForward(EngineForward):
    """The engine's spectrum of the powder at ``x``, times the nuisance scale (see the module)."""

    space: PowderSpace

    def __init__(self, space: PowderSpace, grid_nm: Any, *, rays: int, seed: int = 0, threads: int | None = None):
        super().__init__(space, grid_nm, rays=rays, seed=seed, threads=threads)  # type: ignore[arg-type]
        self.name = f"powder of {space.material}, engine ({self.rays} rays, seed {seed})"

    def predict(self, x: np.ndarray) -> np.ndarray:
        x = np.atleast_2d(np.asarray(x, dtype=float))
        scale = self.space.scale(x)
        out = super().predict(x) * scale[:, None]
        self.stderr = self.stderr * scale[-1]
        return out

    def replicate_covariance(self, x: np.ndarray, replicates: int) -> np.ndarray:
        """The engine's replicate covariance at ``x`` (see EngineForward), times scale²."""
        cov = super().replicate_covariance(x, replicates) * self.space.scale(x)[0] ** 2
        self.mc_covariance = cov
        return cov

    def describe(self) -> str:
        return (
            f"pure {self.space.material} powder (sandlight.physics.powder.Powder), Monte Carlo engine "
            f"(memory {self.space.memory!r}), "
            f"{self.rays} rays per wavelength, seed {self.seed} (common random numbers)"
        )
