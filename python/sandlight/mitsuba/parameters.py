"""The `sand` plugin's parameters: what a scene may say, checked, and the appearances it builds.

Public objects
--------------
PLUGIN_NAME
    ``"sand"``.
SandSpec
    The parsed parameters: the sample, the combination, the models, and the one parameter a
    texture may vary with its levels.
PluginParameterError
    A `ParameterError` whose message starts as Mitsuba's do (``[sand] …``).
appearance_levels
    The `SandAppearance` of every level of a spec (cached: scenes and tests instantiate the
    plugin many times).

Parameters (all optional; ``{"type": "sand"}`` is the default `SandSample()`):

- ``preset`` (string) or ``sample_file`` (path of a sample TOML/JSON): the base sample.
- any `SandSample` parameter by its name (``saturation``, ``iron_oxide``, …, a float, or a
  string for ``iron_oxide_form``): overrides the base sample's value. One numeric parameter may
  instead be a Mitsuba texture (``bitmap`` with ``raw=True``, ``checkerboard``, …; its first
  channel is read): the plugin then builds ``levels`` appearances of that parameter, evenly
  spaced over [``level_min``, ``level_max``] (default: the parameter's domain), and blends the two
  levels around the texture's value at each point.
- ``levels`` (integer 2–64, default 16), ``level_min``, ``level_max`` (floats).
- ``combination`` (``"energy"``, default, or ``"product"``), ``shape`` (``"reflectance"``, default,
  or ``"fixed"``), ``spectral_model``, ``spatial_model`` (paths; default the shipped models): as
  `SandAppearance`.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from sandlight.appearance import COMBINATIONS, SHAPES, SandAppearance
from sandlight.appearance.sources import resolve_spatial
from sandlight.errors import ParameterError
from sandlight.sample import PARAMETERS, SandSample

__all__ = ["PLUGIN_NAME", "SandSpec", "PluginParameterError", "appearance_levels", "MAX_LEVELS"]

PLUGIN_NAME = "sand"
MAX_LEVELS = 64
DEFAULT_LEVELS = 16
_SAMPLE_PARAMETERS = {p.name: p for p in PARAMETERS}
_OWN = (
    "preset",
    "sample_file",
    "levels",
    "level_min",
    "level_max",
    "combination",
    "shape",
    "spectral_model",
    "spatial_model",
)


class PluginParameterError(ParameterError):
    """A bad plugin parameter; the message reads ``[sand] parameter "name" = value is not allowed: …``."""

    def __str__(self) -> str:
        return f"[{PLUGIN_NAME}] parameter {super().__str__()}"


def _refuse(name: str, value: object, allowed: str) -> PluginParameterError:
    return PluginParameterError(name, value, allowed)


@dataclass(frozen=True)
class SandSpec:
    """Parsed plugin parameters (module docstring).

    Attributes
    ----------
    sample : SandSample
        The sample (for a textured parameter, with that parameter at ``level_values[0]``).
    combination : str
    spectral_model, spatial_model : str or None
        Paths, or None for the shipped models.
    varied : str or None
        The parameter a texture sets, if any.
    level_values : tuple of float
        The levels of ``varied`` (empty when nothing is textured).
    shape : str
        `SandAppearance`'s ``shape``.
    """

    sample: SandSample
    combination: str = "energy"
    spectral_model: str | None = None
    spatial_model: str | None = None
    varied: str | None = None
    level_values: tuple[float, ...] = ()
    shape: str = "reflectance"

    @classmethod
    def parse(cls, values: dict, textured: tuple[str, ...] = ()) -> SandSpec:
        """The spec of plugin parameters ``values`` (name → Python value; textures left out and
        named in ``textured``).

        Raises
        ------
        PluginParameterError
            An unknown name, a wrong type, a value out of its domain, two textured parameters, a
            preset that does not exist, an unreadable sample file.
        """
        for name in list(values) + list(textured):
            if name not in _OWN and name not in _SAMPLE_PARAMETERS:
                raise _refuse(
                    name, values.get(name, "a texture"), "a SandSample parameter or one of " + ", ".join(_OWN)
                )
        if len(textured) > 1:
            raise _refuse(textured[1], "a texture", f"at most one textured parameter ({textured[0]} is one already)")
        for name in textured:
            p = _SAMPLE_PARAMETERS.get(name)
            if p is None or p.kind != "float":
                raise _refuse(name, "a texture", "a number (only numeric SandSample parameters may be textures)")
        sample = cls._base_sample(values)
        overrides = {k: v for k, v in values.items() if k in _SAMPLE_PARAMETERS}
        try:
            sample = sample.replace(**overrides) if overrides else sample
        except ParameterError as e:
            raise _refuse(e.name, e.value, e.allowed) from None
        combination = values.get("combination", "energy")
        if combination not in COMBINATIONS:
            raise _refuse("combination", combination, f"one of {COMBINATIONS}")
        shape = values.get("shape", "reflectance")
        if shape not in SHAPES:
            raise _refuse("shape", shape, f"one of {SHAPES}")
        models = {}
        for name in ("spectral_model", "spatial_model"):
            path = values.get(name)
            if path is not None and not (isinstance(path, str) and Path(path).expanduser().is_file()):
                raise _refuse(name, path, "the path of an existing model file")
            models[name] = None if path is None else str(Path(path).expanduser())
        varied = textured[0] if textured else None
        level_values = cls._levels(values, varied, sample)
        if varied is not None:
            sample = sample.replace(**{varied: level_values[0]})
        else:
            for name in ("levels", "level_min", "level_max"):
                if name in values:
                    raise _refuse(name, values[name], "nothing: levels apply only when a parameter is a texture")
        return cls(
            sample, combination, models["spectral_model"], models["spatial_model"], varied, level_values, shape=shape
        )

    @staticmethod
    def _base_sample(values: dict) -> SandSample:
        if "preset" in values and "sample_file" in values:
            raise _refuse("sample_file", values["sample_file"], "only one of preset and sample_file")
        if "preset" in values:
            name = values["preset"]
            if not isinstance(name, str) or name not in SandSample.presets():
                raise _refuse("preset", name, f"one of {SandSample.presets()}")
            return SandSample.preset(name)
        if "sample_file" in values:
            path = values["sample_file"]
            try:
                return SandSample.from_file(path)
            except (ParameterError, OSError, ValueError) as e:
                raise _refuse("sample_file", path, f"a readable sample file ({e})") from None
        return SandSample()

    @staticmethod
    def _levels(values: dict, varied: str | None, sample: SandSample) -> tuple[float, ...]:
        if varied is None:
            return ()
        n = values.get("levels", DEFAULT_LEVELS)
        if isinstance(n, bool) or not isinstance(n, int) or not 2 <= n <= MAX_LEVELS:
            raise _refuse("levels", n, f"a whole number in [2, {MAX_LEVELS}]")
        p = _SAMPLE_PARAMETERS[varied]
        bounds = []
        for name, default in (("level_min", p.low), ("level_max", p.high)):
            v = values.get(name, default)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise _refuse(name, v, f"a finite number (the levels of {varied}, domain [{p.low}, {p.high}])")
            bounds.append(float(v))
        lo, hi = bounds
        if not lo < hi:
            raise _refuse("level_max", hi, f"a number above level_min ({lo})")
        levels = tuple(float(v) for v in np.linspace(lo, hi, n))
        try:  # every level must be a valid sample
            sample.replace(**{varied: lo})
            sample.replace(**{varied: hi})
        except ParameterError as e:
            raise _refuse("level_min" if e.value == lo else "level_max", e.value, e.allowed) from None
        return levels

    def samples(self) -> list[SandSample]:
        """The sample of every level (one when nothing is textured)."""
        if self.varied is None:
            return [self.sample]
        return [self.sample.replace(**{self.varied: v}) for v in self.level_values]


@functools.lru_cache(maxsize=32)
def appearance_levels(spec: SandSpec) -> tuple[SandAppearance, ...]:
    """`SandAppearance` of every level of ``spec`` (cached: equal specs share them), all with one
    spatial model (by default the shipped one that covers every level)."""
    samples = spec.samples()
    spatial = resolve_spatial(spec.spatial_model, samples)
    return tuple(
        SandAppearance(s, spec.spectral_model, spatial, combination=spec.combination, shape=spec.shape) for s in samples
    )
