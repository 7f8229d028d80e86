"""The parameter space of a fit: which sample parameters are free, which fixed, and their bounds.

Public objects
--------------
ParameterSpace
    Free parameter names, the base sample holding every other value, the bounds of the free
    parameters (the sample's domain, ``sandlight.sample.PARAMETERS``, possibly narrowed by the
    forward model's training domain) and the map from a parameter vector to a `SandSample`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from sandlight.errors import ParameterError
from sandlight.sample import PARAMETERS, SandSample

__all__ = ["ParameterSpace", "FREEABLE", "free_and_fixed"]

#: Parameters a fit can vary: the real-valued ones with a finite domain. ``sand`` follows from
#: silt and clay (sand = 1 − silt − clay), ``depth_mm`` has no finite upper bound, and the
#: iron-oxide form is a choice: these are set in ``fixed`` instead.
FREEABLE: tuple[str, ...] = tuple(
    p.name for p in PARAMETERS if p.kind == "float" and p.name != "sand" and math.isfinite(p.high)
)


@dataclass(frozen=True)
class ParameterSpace:
    """Free parameters over bounds, every other parameter at the base sample's value.

    Parameters
    ----------
    free : sequence of str
        Names of the parameters to fit (each in `FREEABLE`, no repeats, at least one).
    base : SandSample
        The values of the parameters that are not free.
    low, high : ndarray, optional
        Bounds of the free parameters; default the sample's domain (`PARAMETERS`).
    """

    free: tuple[str, ...]
    base: SandSample
    low: np.ndarray = field(default=None)  # type: ignore[assignment]
    high: np.ndarray = field(default=None)  # type: ignore[assignment]

    def __post_init__(self) -> None:
        object.__setattr__(self, "free", tuple(self.free))
        if self.low is None:
            object.__setattr__(self, "low", np.array([SandSample.parameter(n).low for n in self.free], dtype=float))
        if self.high is None:
            object.__setattr__(self, "high", np.array([SandSample.parameter(n).high for n in self.free], dtype=float))

    @classmethod
    def build(
        cls, free: Any, fixed: Mapping[str, Any] | None = None, sample: SandSample | None = None
    ) -> ParameterSpace:
        """Check ``free`` and ``fixed`` and make the space.

        ``fixed`` overrides the values of ``sample`` (default the reference sand,
        ``SandSample()``); when silt or clay are free or fixed and ``sand`` is not, sand is set
        to 1 − silt − clay.

        Raises
        ------
        ParameterError
            ``free`` empty, not a list of names, naming an unknown or a non-freeable parameter,
            repeating one, or naming one that ``fixed`` also sets; ``fixed`` with an unknown
            name or a value outside the domain.
        """
        known = {p.name for p in PARAMETERS}
        free, fixed = free_and_fixed(
            free,
            fixed,
            FREEABLE,
            "sample parameter names, e.g. ['iron_oxide']",
            lambda name: "set it in fixed (it cannot be fitted)" if name in known else "not a sample parameter",
        )
        if sample is None:
            sample = SandSample()
        if not isinstance(sample, SandSample):
            raise ParameterError(
                "sample", type(sample).__name__, "a SandSample (the values of the parameters not fitted)"
            )
        separates = {k: fixed.pop(k) for k in ("silt", "clay") if k in fixed}
        base = sample.replace(**fixed) if fixed else sample
        return cls(tuple(free), _with_sand(base, separates.get("silt", base.silt), separates.get("clay", base.clay)))

    @property
    def size(self) -> int:
        return len(self.free)

    def narrowed(self, low: np.ndarray, high: np.ndarray) -> ParameterSpace:
        """The same space with bounds narrowed to [low, high] (intersected with these bounds)."""
        return ParameterSpace(self.free, self.base, np.maximum(self.low, low), np.minimum(self.high, high))

    def to_unit(self, x: np.ndarray) -> np.ndarray:
        """Parameters mapped to [0, 1] over the bounds (the coordinates the optimiser works in)."""
        return (np.asarray(x, dtype=float) - self.low) / (self.high - self.low)

    def from_unit(self, u: np.ndarray) -> np.ndarray:
        return self.low + np.asarray(u, dtype=float) * (self.high - self.low)

    def physical(self, i: int, value: float) -> float:
        """The value of free parameter ``i`` at fit coordinate ``value``: the fit's coordinates
        are the sample parameters themselves (a powder fit's diameter is in log10 µm)."""
        return float(value)

    def values(self, x: np.ndarray) -> dict[str, float]:
        return {n: float(v) for n, v in zip(self.free, np.asarray(x, dtype=float), strict=True)}

    def sample(self, x: np.ndarray) -> SandSample:
        """The base sample with the free parameters set to ``x`` (sand follows silt and clay)."""
        values = self.values(np.clip(x, self.low, self.high))
        sample = self.base.replace(**{k: v for k, v in values.items() if k not in ("silt", "clay")})
        return _with_sand(sample, values.get("silt", sample.silt), values.get("clay", sample.clay))

    def centre(self) -> np.ndarray:
        return (self.low + self.high) / 2


def _with_sand(sample: SandSample, silt: float, clay: float) -> SandSample:
    """``sample`` with silt and clay set and sand = 1 − silt − clay (the separates sum to 1)."""
    if (silt, clay) == (sample.silt, sample.clay):
        return sample
    return sample.replace(silt=silt, clay=clay, sand=1.0 - silt - clay)


def free_and_fixed(
    free: Any, fixed: Mapping[str, Any] | None, freeable: Sequence[str], names: str, why_not: Callable[[str], str]
) -> tuple[list[str], dict[str, Any]]:
    """``free`` as a list of names (a comma-separated string is split) and ``fixed`` as a dict,
    checked: ``free`` non-empty, each name in ``freeable`` and given once, none also in ``fixed``.

    ``names`` describes the allowed names in the message (e.g. "sample parameter names, e.g.
    ['iron_oxide']"); ``why_not(name)`` says why a name outside ``freeable`` is refused.
    """
    if isinstance(free, str):
        free = [f.strip() for f in free.split(",") if f.strip()]
    if not isinstance(free, Sequence) or not free or not all(isinstance(f, str) for f in free):
        raise ParameterError("free", free, f"a non-empty list of {names}")
    for name in free:
        if name not in freeable:
            raise ParameterError("free", name, f"{why_not(name)}; one of {', '.join(freeable)}")
    if len(set(free)) != len(free):
        raise ParameterError("free", list(free), "each parameter once")
    fixed = dict(fixed or {})
    both = sorted(set(free) & set(fixed))
    if both:
        raise ParameterError("fixed", both, "parameters that are not also free (a parameter is fitted or fixed)")
    return list(free), fixed
