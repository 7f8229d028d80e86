"""The sand sample: the physical, measurable parameters of a sand, validated.

Public objects
--------------
Parameter
    Name, unit, default and domain of one sample parameter.
PARAMETERS
    The table of all sample parameters: the single source of truth for validation, the
    documentation (``docs/sample.md`` is generated from it) and the predictors.
SandSample
    An immutable, validated sand sample, built from keyword arguments, a dict, a TOML or JSON
    file, or a named preset shipped in ``sandlight/data/presets/``.

The parameters of issue 2 follow SPLITS (Kimmel & Baranoski 2007) and the paper in
``shared/paper``; ``film_saturation``, ``iron_oxide_particle_size_um``, ``depth_mm``, ``host_absorption``,
``host_scattering`` and ``coating_coverage`` are sandlight's additions (``Parameter.added``). See ``docs/sample.md``.
"""

from __future__ import annotations

import dataclasses
import functools
import json
import math
import numbers
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass
from importlib import resources
from os import PathLike
from pathlib import Path
from typing import Any

from sandlight.errors import ModelFileError, ParameterError
from sandlight.io import read_regular_file

__all__ = ["Parameter", "PARAMETERS", "SandSample", "SEPARATES_TOLERANCE", "MAX_SAMPLE_FILE_BYTES"]

#: Largest sample file read (a complete, commented sample is about 2 kB).
MAX_SAMPLE_FILE_BYTES = 1 << 20


@dataclass(frozen=True)
class Parameter:
    """One sample parameter with its unit, default and allowed domain.

    Attributes
    ----------
    name : str
        Keyword of the parameter in `SandSample`, in files and in dicts.
    unit : str
        Unit of the value ('' for dimensionless fractions and ratios).
    default : float or str
        Value used when the parameter is not given.
    low, high : float or None
        Closed domain [low, high] of a 'float' parameter (``low`` is excluded when
        `low_open`); None for a 'choice' parameter. ``high`` may be ``inf``.
    description : str
        One-line meaning, used in docs, error messages and ``to_toml`` comments.
    kind : {'float', 'choice'}
        A real number, or one of `choices`.
    choices : tuple of str
        The allowed values of a 'choice' parameter.
    low_open : bool
        True if ``low`` itself is not allowed (the domain is (low, high]).
    added : bool
        True for parameters sandlight adds to those of issue 2 / SPLITS.
    """

    name: str
    unit: str
    default: float | str
    low: float | None
    high: float | None
    description: str
    kind: str = "float"
    choices: tuple[str, ...] = ()
    low_open: bool = False
    added: bool = False

    @property
    def allowed(self) -> str:
        """The domain in words, as error messages and the docs state it."""
        if self.kind == "choice":
            return "one of " + ", ".join(repr(c) for c in self.choices)
        left = "(" if self.low_open else "["
        return f"a real number in {left}{self.low:g}, {self.high:g}]"

    def check(self, value: Any) -> float | str:
        """Return `value` as a float (or choice string) if it lies in the domain.

        Raises
        ------
        ParameterError
            If `value` is missing (None), of the wrong type (strings for numbers, bools,
            arrays), NaN, or outside the domain; the message names parameter, value and domain.
        """
        if self.kind == "choice":
            if isinstance(value, str) and value in self.choices:
                return value
            raise ParameterError(self.name, value, self.allowed)
        # Strict JSON has no infinity, so an infinite value is written as the string "inf"
        # (see SandSample.to_dict) and read back here, only where +inf is in the domain.
        if isinstance(value, str) and value == "inf" and self.high == math.inf:
            return math.inf
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            raise ParameterError(self.name, value, self.allowed)
        try:
            x = float(value)
        except (OverflowError, ValueError):  # e.g. an int too large for a float
            raise ParameterError(self.name, value, self.allowed) from None
        above_low = x > self.low if self.low_open else x >= self.low
        if not (above_low and x <= self.high):  # NaN fails every comparison
            raise ParameterError(self.name, value, self.allowed)
        return x


PARAMETERS: tuple[Parameter, ...] = (
    Parameter("iron_oxide", "", 0.01, 0.0, 0.10, "hematite + goethite, mass fraction of the solids"),
    Parameter("hematite_ratio", "", 0.5, 0.0, 1.0, "hematite / (hematite + goethite), by mass"),
    Parameter("magnetite", "", 0.0, 0.0, 0.05, "magnetite (separate opaque grains), mass fraction of the solids"),
    Parameter(
        "iron_oxide_form",
        "",
        "coating",
        None,
        None,
        "where the iron oxide sits: 'coating' (in a kaolinite matrix around the grains), "
        "'mixed' (dispersed inside the quartz grains), 'particles' (separate fine particles)",
        kind="choice",
        choices=("coating", "mixed", "particles"),
    ),
    Parameter(
        "coating_iron_share", "", 0.2, 0.01, 1.0, "volume fraction of iron oxide in the coating (the rest is kaolinite)"
    ),
    Parameter("saturation", "", 0.0, 0.0, 1.0, "degree of saturation: fraction of the pore volume filled with water"),
    Parameter(
        "film_saturation",
        "",
        0.15,
        0.0,
        1.0,
        "degree of saturation up to which water sits as films on the grains before pores start to fill",
        added=True,
    ),
    # The separates' single domains follow from the USDA 'sand' class with sand + silt +
    # clay = 1: sand >= 0.85, silt <= 0.15, 1.5 clay <= 0.15. The joint rule is checked too.
    Parameter("sand", "", 0.95, 0.85, 1.0, "USDA sand separate (0.05-2 mm), mass fraction of the host solids"),
    Parameter("silt", "", 0.04, 0.0, 0.15, "USDA silt separate (0.002-0.05 mm), mass fraction of the host solids"),
    Parameter("clay", "", 0.01, 0.0, 0.10, "USDA clay separate (< 0.002 mm), mass fraction of the host solids"),
    Parameter("grain_size", "mm", 0.25, 0.05, 2.0, "median diameter (by mass) of the sand-sized grains"),
    Parameter(
        "grain_size_spread", "", 1.4, 1.0, 3.0, "geometric standard deviation of the sand grain size distribution"
    ),
    Parameter("aspect_ratio", "", 1.4, 1.0, 3.0, "major / minor axis ratio of the prolate spheroid grains"),
    Parameter("porosity", "", 0.40, 0.25, 0.55, "pore volume fraction of the sample"),
    Parameter(
        "iron_oxide_particle_size_um",
        "µm",
        1.0,
        0.1,
        50.0,
        "diameter of the separate iron-oxide particles (form 'particles')",
        added=True,
    ),
    Parameter(
        "depth_mm",
        "mm",
        math.inf,
        0.0,
        math.inf,
        "sample thickness; inf means a semi-infinite sample",
        low_open=True,
        added=True,
    ),
    Parameter(
        "host_absorption",
        "",
        1.0,
        0.0,
        10.0,
        "factor on the absorption (k) of the quartz host grains: 1 is the natural-grain quartz calibrated "
        "on the USGS quartz powders and sands (docs/optical-constants.md), 0 a perfectly clear crystal",
        added=True,
    ),
    Parameter(
        "host_scattering",
        "mm⁻¹",
        0.0,
        0.0,
        100.0,
        "scattering coefficient of the inclusions and micro-fractures inside the quartz host grains "
        "(isotropic, grey): 0 is a clear crystal, the paper's grain",
        added=True,
    ),
    Parameter(
        "coating_coverage",
        "",
        1.0,
        0.0,
        1.0,
        "fraction of a coated particle's surface that carries the coating (patches, t/f thick on them; "
        "the same iron mass): 1 is a uniform coating over the whole surface",
        low_open=True,
        added=True,
    ),
)

_BY_NAME: dict[str, Parameter] = {p.name: p for p in PARAMETERS}
_NAMES: tuple[str, ...] = tuple(_BY_NAME)

#: Tolerance of the rule sand + silt + clay = 1, also applied to the USDA class boundary
#: so that values rounded to six decimals are not rejected.
SEPARATES_TOLERANCE = 1e-6

#: The USDA 'sand' texture class (Soil Survey Manual): sand >= 0.85 and silt + 1.5 clay <= 0.15.
_USDA_SAND_MIN = 0.85
_USDA_SILT_CLAY_MAX = 0.15


def _default(name: str) -> Any:
    return _BY_NAME[name].default


def _unknown_key_error(key: Any, value: Any) -> ParameterError:
    return ParameterError(str(key), value, "not a sample parameter; allowed keys: preset, " + ", ".join(_NAMES))


@dataclass(frozen=True, kw_only=True)
class SandSample:
    """A sand sample described by physical, measurable parameters.

    Immutable and hashable; every value is checked against `PARAMETERS` on construction, and
    the separates against the USDA 'sand' class. See ``docs/sample.md`` for the meaning, unit
    and domain of each parameter, and `SandSample.parameter` for the table entry.

    Parameters
    ----------
    iron_oxide : float
        Hematite + goethite, mass fraction of the solids, in [0, 0.10].
    hematite_ratio : float
        Hematite / (hematite + goethite) by mass, in [0, 1].
    magnetite : float
        Magnetite, mass fraction of the solids, in [0, 0.05].
    iron_oxide_form : {'coating', 'mixed', 'particles'}
        Where the iron oxide sits.
    coating_iron_share : float
        Volume fraction of iron oxide in the kaolinite coating, in [0.01, 1].
    saturation : float
        Degree of saturation S (pore volume fraction filled with water), in [0, 1].
    film_saturation : float
        S up to which water forms films on the grains before pores fill, in [0, 1].
    sand, silt, clay : float
        USDA separates, mass fractions of the host solids; sum 1 (within 1e-6), sand >= 0.85
        and silt + 1.5 clay <= 0.15.
    grain_size : float
        Median diameter by mass of the sand-sized grains, mm, in [0.05, 2.0].
    grain_size_spread : float
        Geometric standard deviation of that size distribution, in [1, 3].
    aspect_ratio : float
        Prolate spheroid major/minor axis ratio, in [1, 3].
    porosity : float
        Pore volume fraction, in [0.25, 0.55].
    iron_oxide_particle_size_um : float
        Diameter of separate iron-oxide particles, µm, in [0.1, 50].
    depth_mm : float
        Sample thickness, mm, in (0, inf]; inf (default) is semi-infinite.
    host_absorption : float
        Factor (dimensionless) on the imaginary index k of the quartz host grains (sand and silt),
        in [0, 10]: 1 (default) is natural-grain quartz as calibrated on the USGS quartz powders
        and Ottawa sand (docs/optical-constants.md); 0 a perfectly clear crystal; > 1 a more
        stained or included host.
    host_scattering : float
        Scattering coefficient σ of the quartz host grains' interior, mm⁻¹, in [0, 100]: fluid and
        mineral inclusions and micro-fractures, isotropic and the same at every wavelength
        (docs/model.md §2.4). 0 (default) is a clear crystal, as in the paper; σ·D ≳ 1 a
        milky grain.
    coating_coverage : float
        Fraction (dimensionless) of a coated particle's surface that carries the coating, in
        (0, 1] ('coating' form only). At coverage f the coating on the covered patches is t_c/f
        thick, t_c the uniform thickness of the mass balance, so the iron mass is unchanged; the
        rest of the surface is bare quartz (or kaolinite). The engine draws at every surface
        point a ray meets whether it lies on a patch, with probability f, independently of the
        other points (docs/model.md §2.4). Physics: the iron-oxide–clay coatings of red and
        yellow dune sands are not uniform skins; they are concentrated in the hollows and
        embayments of the grains and abraded from the exposed highs, so grains show stained
        hollows beside clean quartz (Walker 1979, "Red color in dune sand", USGS Professional
        Paper 1052; Folk 1976, J. Sediment. Petrol. 46, 604–615, Simpson Desert). Less of the
        grain surface filters the light, and the light that misses the patches leaves
        unfiltered, so the sand is paler and less chromatic at the same iron content. The
        default stays 1 (the uniform coating of the paper, and what the shipped predictor bank
        was trained with) until a measured coated sand can check a value: it is not to be tuned
        to a spectrum.

    Raises
    ------
    ParameterError
        If a value is missing, non-numeric, NaN, out of its domain, or the separates are
        inconsistent.

    Examples
    --------
    >>> s = SandSample(iron_oxide=0.02, hematite_ratio=0.8)
    >>> s.replace(saturation=1.0).saturation
    1.0
    >>> SandSample.preset("red-dune").iron_oxide_form
    'coating'
    """

    iron_oxide: float = _default("iron_oxide")
    hematite_ratio: float = _default("hematite_ratio")
    magnetite: float = _default("magnetite")
    iron_oxide_form: str = _default("iron_oxide_form")
    coating_iron_share: float = _default("coating_iron_share")
    saturation: float = _default("saturation")
    film_saturation: float = _default("film_saturation")
    sand: float = _default("sand")
    silt: float = _default("silt")
    clay: float = _default("clay")
    grain_size: float = _default("grain_size")
    grain_size_spread: float = _default("grain_size_spread")
    aspect_ratio: float = _default("aspect_ratio")
    porosity: float = _default("porosity")
    iron_oxide_particle_size_um: float = _default("iron_oxide_particle_size_um")
    depth_mm: float = _default("depth_mm")
    host_absorption: float = _default("host_absorption")
    host_scattering: float = _default("host_scattering")
    coating_coverage: float = _default("coating_coverage")

    def __post_init__(self) -> None:
        for p in PARAMETERS:
            object.__setattr__(self, p.name, p.check(getattr(self, p.name)))
        self._check_separates()

    def _check_separates(self) -> None:
        given = f"sand={self.sand!r}, silt={self.silt!r}, clay={self.clay!r}"
        # The sums are rounded to 12 digits for the message only (0.19, not 0.19000000000000003).
        total = self.sand + self.silt + self.clay
        if abs(total - 1.0) > SEPARATES_TOLERANCE:
            raise ParameterError(
                "sand + silt + clay", round(total, 12), f"1 within {SEPARATES_TOLERANCE:g} (mass fractions; {given})"
            )
        # USDA texture triangle, 'sand' class: silt + 1.5 clay <= 15 % (sand >= 85 % is the
        # domain of `sand`). Both are needed: sand = 0.86, clay = 0.10 passes the first only.
        silt_clay = self.silt + 1.5 * self.clay
        if silt_clay > _USDA_SILT_CLAY_MAX + SEPARATES_TOLERANCE:
            raise ParameterError(
                "silt + 1.5·clay",
                round(silt_clay, 12),
                f"<= {_USDA_SILT_CLAY_MAX:g} for the USDA 'sand' class "
                f"(sand >= {_USDA_SAND_MIN:g} and silt + 1.5·clay <= {_USDA_SILT_CLAY_MAX:g}; "
                f"{given})",
            )

    # -- construction -----------------------------------------------------------------------

    @staticmethod
    def parameter(name: str) -> Parameter:
        """The `Parameter` (unit, default, domain) of the parameter called `name`."""
        try:
            return _BY_NAME[name]
        except (KeyError, TypeError):
            raise ParameterError("parameter", name, "one of " + ", ".join(_NAMES)) from None

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> SandSample:
        """Build a sample from a mapping of parameter names to values.

        An optional key ``preset`` names a preset giving the base values, which the other
        keys override. Missing parameters take their defaults; unknown keys raise
        `ParameterError` naming the key and listing the allowed ones.
        """
        return cls._from_mapping(data, allow_preset=True)

    @classmethod
    def _from_mapping(cls, data: Any, *, allow_preset: bool) -> SandSample:
        if not isinstance(data, Mapping):
            raise ParameterError("sample", data, "a table mapping parameter names to values")
        values = dict(data)
        base: dict[str, Any] = {}
        if allow_preset and "preset" in values:
            base = cls.preset(values.pop("preset"))._values()
        for key, value in values.items():
            if key not in _BY_NAME:
                raise _unknown_key_error(key, value)
        return cls(**{**base, **values})

    @classmethod
    def from_file(cls, path: str | PathLike[str]) -> SandSample:
        """Read a sample from a TOML (``.toml``) or JSON (``.json``) file.

        The parameters are keys at the top level or in a ``[sample]`` table (then no other
        top-level key is allowed); ``preset = "name"`` gives base values that the other keys
        override. An empty file gives the default sample.

        Raises
        ------
        FileNotFoundError
            If `path` does not exist.
        ParameterError
            If `path` is not a regular file (a directory, a device, a pipe) or is larger than
            `MAX_SAMPLE_FILE_BYTES`; it is not read.
        ModelFileError
            If the suffix is neither .toml nor .json, or the file does not parse; the message
            names the file and the parse problem.
        ParameterError
            For unknown keys and invalid values; the message also names the file.
        """
        path = Path(path)
        suffix = path.suffix.lower()
        if suffix not in (".toml", ".json"):
            raise ModelFileError(
                f"{path}: cannot tell the format of a sample file from the suffix {path.suffix!r}; use .toml or .json"
            )
        raw = read_regular_file(path, "sample file", max_bytes=MAX_SAMPLE_FILE_BYTES)
        try:
            text = raw.decode("utf-8")
            doc = tomllib.loads(text) if suffix == ".toml" else json.loads(text) if text.strip() else {}
        except (UnicodeDecodeError, tomllib.TOMLDecodeError, json.JSONDecodeError) as exc:
            raise ModelFileError(f"{path}: not a valid {suffix[1:].upper()} file: {exc}") from exc
        if not isinstance(doc, dict):
            raise ModelFileError(
                f"{path}: expected a table of sample parameters at the top level, found a {type(doc).__name__}"
            )
        if "sample" in doc:
            for key, value in doc.items():
                if key != "sample":
                    raise ParameterError(str(key), value, f"no keys are allowed outside the [sample] table (in {path})")
            doc = doc["sample"]
        try:
            return cls.from_dict(doc)
        except ParameterError as exc:  # say which file the bad value came from
            raise ParameterError(exc.name, exc.value, f"{exc.allowed} (in {path})") from None

    @classmethod
    def preset(cls, name: str) -> SandSample:
        """The named preset shipped with sandlight; see `presets` for the names.

        Raises
        ------
        ParameterError
            If there is no preset of that name; the message lists the available ones.
        """
        names = cls.presets()
        if not isinstance(name, str) or name not in names:
            raise ParameterError("preset", name, "one of " + ", ".join(names))
        return _load_preset(name)

    @staticmethod
    def presets() -> tuple[str, ...]:
        """Names of the shipped presets, sorted."""
        return tuple(
            sorted(
                entry.name.removesuffix(".toml") for entry in _preset_dir().iterdir() if entry.name.endswith(".toml")
            )
        )

    def replace(self, **changes: Any) -> SandSample:
        """A copy with some parameters changed (and validated again)."""
        for key, value in changes.items():
            if key not in _BY_NAME:
                raise _unknown_key_error(key, value)
        return dataclasses.replace(self, **changes)

    # -- export -----------------------------------------------------------------------------

    def _values(self) -> dict[str, Any]:
        return {name: getattr(self, name) for name in _NAMES}

    def to_dict(self) -> dict[str, float | str]:
        """All parameters as a plain dict that strict JSON can hold.

        An infinite `depth_mm` is written as the string ``"inf"``, which `from_dict` reads
        back (strict JSON has no infinity).
        """
        return {k: ("inf" if v == math.inf else v) for k, v in self._values().items()}

    def to_toml(self) -> str:
        """The sample as TOML text that `from_file` reads back, one commented line per key."""
        lines = ["# sandlight sand sample: read it with sandlight.SandSample.from_file"]
        for p in PARAMETERS:
            value = getattr(self, p.name)
            # repr of a float is the shortest text that reads back exactly and is valid TOML
            # ("0.01", "1e-05", "inf"); a choice is a basic string.
            text = json.dumps(value) if isinstance(value, str) else repr(value)
            unit = f" [{p.unit}]" if p.unit else ""
            lines.append(f"{p.name} = {text}  # {p.description}{unit}; {p.allowed}")
        return "\n".join(lines) + "\n"


def _preset_dir():
    """The directory of preset TOML files inside the installed package."""
    return resources.files("sandlight") / "data" / "presets"


@functools.cache
def _load_preset(name: str) -> SandSample:
    # Samples are immutable, so one instance per preset can be shared.
    text = (_preset_dir() / f"{name}.toml").read_text(encoding="utf-8")
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ModelFileError(f"preset {name!r}: not a valid TOML file: {exc}") from exc
    try:
        return SandSample._from_mapping(doc, allow_preset=False)
    except ParameterError as exc:
        raise ParameterError(exc.name, exc.value, f"{exc.allowed} (in preset {name!r})") from None
