"""The training domain of a predictor: which sample parameters vary, over which ranges.

A :class:`Domain` says which :class:`sandlight.sample.SandSample` parameters a predictor takes as
inputs (its *dimensions*, in a fixed order), their ranges and the scale they are drawn and
regressed on, which parameters are held fixed, and which iron-oxide forms it covers. It draws
training samples (Latin hypercube or random, seeded) and checks that inputs lie inside it.

Default domain (:meth:`Domain.default`)
---------------------------------------

===========================  ===============  ================  ===============================
dimension                    range            scale             why this scale
===========================  ===============  ================  ===============================
iron_oxide (mass fraction)   [0, 0.10]        log, c₀ = 1e-4    see "Concentrations" below
magnetite (mass fraction)    [0, 0.05]        log, c₀ = 1e-4    see "Concentrations" below
hematite_ratio               [0, 1]           linear
coating_iron_share           [0.1, 1]         linear            narrower than SandSample (0.01)
iron_oxide_particle_size_um  [0.1, 50] µm     log               sizes act multiplicatively
saturation                   [0, 1]           linear
film_saturation              [0, 1]           linear
porosity                     [0.25, 0.55]     linear
grain_size (mm)              [0.05, 2] mm     log               spans 40×; effects scale with ln d
grain_size_spread            [1, 3]           linear
aspect_ratio                 [1, 3]           linear
silt (mass fraction)         [0, 0.15]        linear            drawn inside the USDA sand class
clay (mass fraction)         [0, 0.10]        linear
===========================  ===============  ================  ===============================

Concentrations: log with an offset
----------------------------------
The engine's reflectance falls fastest at the lowest absorber concentrations: at 400 nm a
coated quartz sand (SandSample defaults, pure goethite) goes from 0.86 (no iron oxide) to 0.61
at c = 10⁻⁴, 0.44 at 3·10⁻⁴, 0.24 at 10⁻³ and 0.02 at 10⁻² (5000 rays). A thin coating absorbs a fraction
∝ c of the light at each grain and the light meets many grains, so r changes by about the same
amount per *factor* of c above the concentration where the coating starts to matter, and is flat
below it. The coordinate t = ln(c + c₀) follows that: ~ln c above c₀, flat below, finite at 0.
c₀ = 10⁻⁴ (0.01 wt%) is where the drop begins; the √c scale of format-1 models (Kubelka–Munk's
1 − r∞ ∝ √(K/S) at weak absorption) spreads the same range 0–0.1 so that the first 0.01 wt%, where
half the drop happens, takes 3 % of the coordinate.

``coating_iron_share`` is trained on [0.1, 1], not SandSample's [0.01, 1]: with 10 wt% iron oxide
a coating of 1 % iron-oxide share would be ten times the mass of the solids, which the mass
balance refuses (sandlight.physics.composition); from 0.1 up every point of the box is a
physical sample.

Fixed: ``depth_mm = inf`` (semi-infinite samples, as in the paper), ``host_absorption = 1``
(the calibrated natural-grain quartz host, docs/optical-constants.md), ``host_scattering = 0`` (clear
host grains) and ``coating_coverage = 1`` (the uniform coating the shipped bank was trained with,
docs/model.md §2.4). Derived: ``sand = 1 − silt −
clay``. Forms: ``coating``, ``mixed`` and ``particles`` (the categorical ``iron_oxide_form`` is
never a dimension; draws give each form an equal share of the samples).

The texture is drawn inside the USDA sand class, silt + 1.5·clay ≤ 0.15 (so sand ≥ 0.85), with
two uniform draw coordinates: the *class fill* f = (silt + 1.5·clay)/0.15 ∈ [0, 1] and the *silt
share* s = silt/(silt + clay) ∈ [0, 1]; then silt + clay = 0.15·f/(s + 1.5·(1 − s)). The
predictor itself takes silt and clay as inputs (smooth in both, and defined at zero fines, where
the silt share is not) and checks the class constraint.

"Drawn on a scale" means uniform in the transformed value: log-scaled parameters are log-uniform
(with an offset: uniform in ln(c + c₀), so about a third of the draws of iron oxide fall below
10⁻³). Regression features are the transformed values mapped linearly to [−1, 1].

Reference-sand domains (:meth:`Domain.reference`)
------------------------------------------------
Narrow domains in which only a few parameters vary (the paper's Figures 6 and 7 vary iron oxide,
the hematite/goethite ratio and the degree of saturation) and every other parameter is fixed at
the *reference sand*, :data:`REFERENCE_SAND` (SandSample's defaults). With few dimensions the
cubic has few monomials and fits the engine much more closely.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from sandlight.errors import ParameterError, SandlightError
from sandlight.sample import PARAMETERS, Parameter

#: Forms of the iron oxide, the values of SandSample.iron_oxide_form.
FORMS = ("coating", "mixed", "particles")
#: USDA texture class "sand": silt + 1.5·clay ≤ 0.15 by mass (docs/model.md §1).
SAND_CLASS_LIMIT = 0.15
CLAY_WEIGHT = 1.5
#: Parameters derived from the dimensions rather than drawn.
DERIVED = ("sand",)
FORM_PARAMETER = "iron_oxide_form"
SCALES = ("linear", "log", "sqrt")
#: Offset c₀ of the log scale of absorber concentrations, mass fraction (module docstring).
CONCENTRATION_OFFSET = 1e-4
#: The reference sand of the narrow domains: SandSample's defaults (docs/sample.md), semi-infinite;
#: every float parameter but the derived ones.
REFERENCE_SAND = {p.name: p.default for p in PARAMETERS if p.kind == "float" and p.name not in DERIVED}
#: Clean quartz sand (the ottawa-quartz preset's kind): no absorber, no fines. A corner of the broad
#: domains that random draws hardly reach (docs/spectral-predictor.md, "Corners of the domain").
CLEAN_SAND = {"iron_oxide": 0.0, "magnetite": 0.0, "silt": 0.0, "clay": 0.0}


@dataclass(frozen=True)
class Dimension:
    """One varying parameter of a domain.

    Attributes
    ----------
    name : str
        The SandSample parameter.
    low, high : float
        Range, low < high, in the parameter's unit.
    scale : {"linear", "log", "sqrt"}
        Scale on which the parameter is drawn uniformly and regressed: t = x, t = ln(x + offset)
        (needs low + offset > 0) or t = √x (needs low >= 0; the scale of format-1 model files,
        kept so that they still load).
    unit : str
        Unit, for messages and metadata ("1" for fractions).
    offset : float
        Offset c₀ >= 0 of the log scale, in the parameter's unit (0 for the others): ln(x + c₀)
        is ~ln x above c₀ and flattens below it, so that a concentration range starting at 0
        is resolved down to about c₀ (see the module docstring).
    """

    name: str
    low: float
    high: float
    scale: str = "linear"
    unit: str = "1"
    offset: float = 0.0

    def __post_init__(self):
        if self.scale not in SCALES:
            raise ParameterError(f"{self.name}.scale", self.scale, f"one of {SCALES}")
        if not (math.isfinite(self.low) and math.isfinite(self.high) and self.low < self.high):
            raise ParameterError(self.name, (self.low, self.high), "a finite range (low, high) with low < high")
        if not (math.isfinite(self.offset) and self.offset >= 0):
            raise ParameterError(f"{self.name}.offset", self.offset, "a finite number >= 0")
        if self.offset and self.scale != "log":
            raise ParameterError(f"{self.name}.offset", self.offset, "0 unless the scale is 'log'")
        if self.scale == "log" and self.low + self.offset <= 0:
            raise ParameterError(
                self.name,
                (self.low, self.high),
                f"low + offset > 0 on a log scale (offset {self.offset:g})"
                if self.offset
                else "low > 0 on a log scale",
            )
        if self.scale == "sqrt" and self.low < 0:
            raise ParameterError(self.name, (self.low, self.high), "low >= 0 on a sqrt scale")

    def forward(self, x: ArrayLike) -> np.ndarray | float:
        """Transformed value (the scale's coordinate)."""
        if self.scale == "log":
            return np.log(np.add(x, self.offset)) if self.offset else np.log(x)
        if self.scale == "sqrt":
            return np.sqrt(x)
        return np.asarray(x, dtype=float)

    def inverse(self, t: ArrayLike) -> np.ndarray | float:
        if self.scale == "log":
            return np.exp(t) - self.offset if self.offset else np.exp(t)
        if self.scale == "sqrt":
            return np.square(t)
        return t

    def from_unit(self, u: ArrayLike) -> np.ndarray:
        """Value at fraction ``u`` ∈ [0, 1] of the transformed range (clipped to [low, high])."""
        t0, t1 = self.forward(self.low), self.forward(self.high)
        # Clip: exp/square of the end points may round a hair outside the range.
        return np.clip(self.inverse(t0 + np.asarray(u) * (t1 - t0)), self.low, self.high)

    def to_dict(self) -> dict:
        return {
            "name": self.name,
            "low": self.low,
            "high": self.high,
            "scale": self.scale,
            "unit": self.unit,
            "offset": self.offset,
        }


def _default_dimensions() -> tuple[Dimension, ...]:
    limit = SAND_CLASS_LIMIT
    return (
        Dimension("iron_oxide", 0.0, 0.10, "log", offset=CONCENTRATION_OFFSET),
        Dimension("hematite_ratio", 0.0, 1.0),
        Dimension("magnetite", 0.0, 0.05, "log", offset=CONCENTRATION_OFFSET),
        Dimension("coating_iron_share", 0.1, 1.0),
        Dimension("iron_oxide_particle_size_um", 0.1, 50.0, "log", "um"),
        Dimension("saturation", 0.0, 1.0),
        Dimension("film_saturation", 0.0, 1.0),
        Dimension("porosity", 0.25, 0.55),
        Dimension("grain_size", 0.05, 2.0, "log", "mm"),
        Dimension("grain_size_spread", 1.0, 3.0),
        Dimension("aspect_ratio", 1.0, 3.0),
        Dimension("silt", 0.0, limit),
        Dimension("clay", 0.0, limit / CLAY_WEIGHT),
    )


@dataclass(frozen=True)
class Domain:
    """Training domain over SandSample parameters (see the module docstring).

    Parameters
    ----------
    dimensions : tuple of Dimension
        Varying parameters, in the order predictors take them.
    forms : tuple of str
        Iron-oxide forms covered (subset of ``FORMS``).
    fixed : mapping
        Parameters held at one value (default ``{"depth_mm": inf, "host_absorption": 1.0,
        "host_scattering": 0.0, "coating_coverage": 1.0}``).
    texture_limit : float
        Upper bound of silt + 1.5·clay, in (0, 0.15] (0.15: the whole sand class).
    """

    dimensions: tuple = field(default_factory=_default_dimensions)
    forms: tuple = FORMS
    fixed: Mapping = field(
        default_factory=lambda: {
            "depth_mm": math.inf,
            "host_absorption": 1.0,
            "host_scattering": 0.0,
            "coating_coverage": 1.0,
        }
    )
    texture_limit: float = SAND_CLASS_LIMIT

    def __post_init__(self):
        object.__setattr__(self, "dimensions", tuple(self.dimensions))
        object.__setattr__(self, "forms", tuple(self.forms))
        object.__setattr__(self, "fixed", dict(self.fixed))
        names = [d.name for d in self.dimensions]
        if len(set(names)) != len(names) or set(names) & set(self.fixed):
            raise ParameterError("dimensions", names, "distinct names, none of them also fixed")
        if set(names + list(self.fixed)) & set(DERIVED + (FORM_PARAMETER,)):
            raise ParameterError("dimensions", names, f"no {DERIVED + (FORM_PARAMETER,)} (derived or categorical)")
        if not self.forms or len(set(self.forms)) != len(self.forms) or not set(self.forms) <= set(FORMS):
            raise ParameterError("forms", self.forms, f"a non-empty subset of {FORMS}")
        if not 0 < self.texture_limit <= SAND_CLASS_LIMIT:
            raise ParameterError(
                "texture_limit", self.texture_limit, f"(0, {SAND_CLASS_LIMIT}] (silt + 1.5·clay inside the sand class)"
            )
        varied = [n for n in ("silt", "clay") if n in names]
        fixed = [n for n in ("silt", "clay") if n in self.fixed]
        if sorted(varied) != ["clay", "silt"] and sorted(fixed) != ["clay", "silt"]:
            raise ParameterError(
                "silt, clay",
                {"varied": varied, "fixed": fixed},
                "both varied or both fixed (sand = 1 − silt − clay is derived)",
            )
        if self._texture_drawn:
            silt, clay = self.dimension("silt"), self.dimension("clay")
            expected = ((0.0, self.texture_limit), (0.0, self.texture_limit / CLAY_WEIGHT))
            if ((silt.low, silt.high), (clay.low, clay.high)) != expected:
                raise ParameterError(
                    "silt, clay",
                    ((silt.low, silt.high), (clay.low, clay.high)),
                    f"{expected}: the ranges follow texture_limit",
                )
        else:
            s, c = self.fixed["silt"], self.fixed["clay"]
            if min(s, c) < 0 or s + CLAY_WEIGHT * c > self.texture_limit + 1e-12:
                raise ParameterError(
                    "silt + 1.5·clay", s + CLAY_WEIGHT * c, f"<= {self.texture_limit} with silt, clay >= 0"
                )

    # ---- construction ------------------------------------------------------------------------
    @classmethod
    def default(cls) -> Domain:
        """The default domain: every float parameter of SandSample over its full range."""
        return cls()

    @classmethod
    def reference(
        cls, dimensions: Iterable[Dimension], forms: Iterable[str] = FORMS, reference: Mapping | None = None
    ) -> Domain:
        """A narrow domain: ``dimensions`` vary, every other parameter is fixed at the
        reference sand.

        Parameters
        ----------
        dimensions : sequence of Dimension
            The varying parameters, in predictor input order.
        forms : sequence of str
            Iron-oxide forms covered.
        reference : mapping, optional
            Values of the fixed parameters (default :data:`REFERENCE_SAND`); needs every float
            parameter of SandSample except ``sand`` (derived).

        Examples
        --------
        >>> d = Domain.reference([Dimension("iron_oxide", 0.001, 0.05, "log"),
        ...                       Dimension("saturation", 0.0, 1.0)])
        >>> d.names, d.fixed["grain_size"]
        (('iron_oxide', 'saturation'), 0.25)
        """
        dimensions = tuple(dimensions)
        varied = {d.name for d in dimensions}
        reference = REFERENCE_SAND if reference is None else reference
        fixed = {k: float(v) for k, v in reference.items() if k not in varied}
        return cls(dimensions, tuple(forms), fixed, SAND_CLASS_LIMIT)

    def restrict(
        self, *, forms: Iterable[str] | None = None, texture_limit: float | None = None, **changes: Any
    ) -> Domain:
        """A smaller domain.

        Parameters
        ----------
        forms : sequence of str, optional
            Keep only these iron-oxide forms.
        texture_limit : float, optional
            New bound of silt + 1.5·clay (the silt and clay ranges follow).
        **changes : (low, high) or float
            A narrower range for a dimension, or a single value to fix it. ``silt`` and ``clay``
            can be fixed (both) but take their ranges from ``texture_limit``.

        Examples
        --------
        >>> d = Domain.default().restrict(forms=["coating"], saturation=0.0,
        ...                               iron_oxide=(0.0, 0.02))
        >>> d.names[:2], d.fixed["saturation"]
        (('iron_oxide', 'hematite_ratio'), 0.0)
        """
        dims, fixed = [], dict(self.fixed)
        unknown = set(changes) - set(self.names)
        if unknown:
            raise ParameterError(
                sorted(unknown)[0], changes[sorted(unknown)[0]], f"a dimension of this domain: {self.names}"
            )
        limit = self.texture_limit if texture_limit is None else float(texture_limit)
        for d in self.dimensions:
            change = changes.get(d.name)
            if change is None:
                if d.name == "silt":
                    d = replace(d, high=limit)
                elif d.name == "clay":
                    d = replace(d, high=limit / CLAY_WEIGHT)
                dims.append(d)
            elif np.ndim(change) == 0:
                value = float(change)
                if not d.low <= value <= d.high:
                    raise ParameterError(d.name, value, f"a value in [{d.low}, {d.high}] {d.unit}")
                fixed[d.name] = value
            else:
                if d.name in ("silt", "clay"):
                    raise ParameterError(d.name, change, "a single value (to fix it); its range follows texture_limit")
                low, high = map(float, change)
                if not d.low <= low < high <= d.high:
                    raise ParameterError(d.name, change, f"a range inside [{d.low}, {d.high}] {d.unit}")
                dims.append(replace(d, low=low, high=high))
        return Domain(tuple(dims), tuple(forms) if forms is not None else self.forms, fixed, limit)

    # ---- properties --------------------------------------------------------------------------
    @functools.cached_property
    def names(self) -> tuple[str, ...]:
        """Names of the dimensions, in predictor input order."""
        return tuple(d.name for d in self.dimensions)

    @functools.cached_property
    def _fixed_values(self) -> np.ndarray:
        """The fixed parameters' values in ``fixed`` order, as an array."""
        return np.array(list(self.fixed.values()), dtype=float)

    @functools.cached_property
    def _bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Each dimension's range widened by 1e-9 of its width, the round-off of values written
        to text and read back, as arrays: a bank tests every sample against
        many domains, and a single call is mostly this test."""
        tol = np.array([1e-9 * (d.high - d.low) for d in self.dimensions])
        return self.low - tol, self.high + tol

    def dimension(self, name: str) -> Dimension:
        for d in self.dimensions:
            if d.name == name:
                return d
        raise KeyError(name)

    @property
    def _texture_drawn(self) -> bool:
        return "silt" in self.names

    @property
    def low(self) -> np.ndarray:
        return np.array([d.low for d in self.dimensions])

    @property
    def high(self) -> np.ndarray:
        return np.array([d.high for d in self.dimensions])

    # ---- serialisation -----------------------------------------------------------------------
    def to_dict(self) -> dict:
        """Plain-JSON description (``inf`` stays a float; Python's json writes ``Infinity``)."""
        return {
            "dimensions": [d.to_dict() for d in self.dimensions],
            "forms": list(self.forms),
            "fixed": dict(self.fixed),
            "texture_limit": self.texture_limit,
        }

    @classmethod
    def from_dict(cls, d: Mapping) -> Domain:
        """The domain of :meth:`to_dict`. A float SandSample parameter that a stored domain
        neither varies nor fixes did not exist when it was trained, so the engine ran at what its
        default means (e.g. ``host_absorption`` 1: the shipped quartz k; ``coating_coverage`` 1:
        the uniform coating): it is fixed there, and a
        sample with another value is outside the domain."""
        dimensions = tuple(Dimension(**x) for x in d["dimensions"])
        fixed = {k: float(v) for k, v in d["fixed"].items()}
        known = {x.name for x in dimensions} | set(fixed) | set(DERIVED)
        fixed.update({p.name: float(p.default) for p in PARAMETERS if p.kind == "float" and p.name not in known})
        return cls(dimensions, tuple(d["forms"]), fixed, float(d["texture_limit"]))

    def check_covers(self, parameters: Iterable[Parameter]) -> None:
        """Check this domain against SandSample's parameter table.

        Every float parameter must be a dimension (with a range inside the parameter's), fixed,
        or derived, so that a training sample is fully determined by the domain.

        Parameters
        ----------
        parameters : iterable of sandlight.sample.Parameter
        """
        for p in parameters:
            if p.name == FORM_PARAMETER:
                if not set(self.forms) <= set(p.choices):
                    raise SandlightError(
                        f"domain forms {self.forms} are not all choices of {p.name}: {tuple(p.choices)}"
                    )
            elif p.name in self.names:
                d = self.dimension(p.name)
                if d.low < p.low or d.high > p.high:
                    raise SandlightError(
                        f"domain range of {p.name} [{d.low}, {d.high}] leaves "
                        f"the parameter's domain [{p.low}, {p.high}]"
                    )
            elif p.name not in self.fixed and p.name not in DERIVED:
                raise SandlightError(
                    f"SandSample parameter {p.name} is neither a dimension, fixed nor derived in this domain"
                )

    # ---- drawing -----------------------------------------------------------------------------
    def draw(self, n: int, seed: int, design: str = "lhs") -> list[dict]:
        """Draw ``n`` sample parameter sets.

        Parameters
        ----------
        n : int
            Number of samples, >= 1.
        seed : int
            Seed (>= 0); the draws depend only on ``(n, seed, design)`` and the domain.
        design : {"lhs", "random"}
            ``"lhs"``: the forms get equal shares (±1) in random order, and the samples of each
            form form a Latin hypercube of the draw coordinates (scipy.stats.qmc). ``"random"``:
            independent uniform draws (forms too), e.g. for a hold-out set.

        Returns
        -------
        list of dict
            One dict per sample: every dimension, the fixed parameters, ``sand`` and
            ``iron_oxide_form``, as plain Python floats and str (SandSample keyword arguments).
        """
        values, codes = self.draw_arrays(n, seed, design)
        columns = self.columns(values, codes)
        return [{k: v[i].item() for k, v in columns.items()} for i in range(len(codes))]

    def columns(self, values: np.ndarray, codes: np.ndarray) -> dict[str, np.ndarray]:
        """The samples of a predictor's inputs as columns of SandSample parameters.

        Parameters
        ----------
        values : ndarray (n, n_dimensions)
            The dimensions' values, in ``names`` order (e.g. from :meth:`draw_arrays`).
        codes : ndarray (n,)
            Form codes indexing ``forms``.

        Returns
        -------
        dict of str to ndarray (n,)
            Every dimension, the fixed parameters, ``sand`` (1 − silt − clay) and
            ``iron_oxide_form`` (names), in that order.
        """
        n = len(codes)
        columns = {name: values[:, j] for j, name in enumerate(self.names)}
        columns.update({k: np.full(n, float(v)) for k, v in self.fixed.items()})
        columns["sand"] = 1.0 - columns["silt"] - columns["clay"]
        columns[FORM_PARAMETER] = np.asarray(self.forms)[codes]
        return columns

    def draw_arrays(self, n: int, seed: int, design: str = "lhs") -> tuple[np.ndarray, np.ndarray]:
        """The draws of :meth:`draw` as arrays: values (n, n_dimensions) in ``names`` order and
        form codes (n,) indexing ``forms`` (the input of ``SpectralModel.predict``)."""
        from scipy.stats import qmc

        if int(n) < 1:
            raise ParameterError("n", n, "an integer >= 1")
        if design not in ("lhs", "random"):
            raise ParameterError("design", design, "'lhs' or 'random'")
        n = int(n)
        d = len(self.dimensions)
        streams = np.random.SeedSequence(int(seed)).spawn(1 + len(self.forms))
        rng = np.random.default_rng(streams[0])
        if design == "random":
            codes = rng.integers(len(self.forms), size=n)
            unit = rng.random((n, d))
        else:
            codes = rng.permutation(np.arange(n) % len(self.forms))
            unit = np.empty((n, d))
            for f in range(len(self.forms)):
                rows = np.flatnonzero(codes == f)
                if rows.size and d:
                    lhs = qmc.LatinHypercube(d, rng=np.random.default_rng(streams[1 + f]))
                    unit[rows] = lhs.random(rows.size)
        values = np.empty((n, d))
        for j, dim in enumerate(self.dimensions):
            if dim.name not in ("silt", "clay"):
                values[:, j] = dim.from_unit(unit[:, j])
        if self._texture_drawn:
            js, jc = self.names.index("silt"), self.names.index("clay")
            fill, share = unit[:, js], unit[:, jc]
            # class fill f = (silt + 1.5·clay)/limit, silt share s = silt/(silt + clay)
            fines = self.texture_limit * fill / (share + CLAY_WEIGHT * (1.0 - share))
            values[:, js] = fines * share
            values[:, jc] = fines * (1.0 - share)
        return values, codes.astype(np.intp)

    # ---- inputs of a predictor ---------------------------------------------------------------
    def check(self, values: np.ndarray, *, extrapolate: bool = False) -> None:
        """Check an (n, n_dimensions) array of raw parameter values.

        Raises
        ------
        ParameterError
            Naming the first offending parameter and value: NaN or inf, outside the range of
            its scale (log needs > 0, sqrt >= 0) always; outside the domain (or the texture
            class bound) unless ``extrapolate``.
        """
        values = np.asarray(values, dtype=float)
        finite = np.isfinite(values)
        if not finite.all():
            row, col = np.argwhere(~finite)[0]
            raise ParameterError(self.names[col], float(values[row, col]), "a finite number")
        for j, dim in enumerate(self.dimensions):
            column = values[:, j]
            if extrapolate:
                bad = column + dim.offset <= 0 if dim.scale == "log" else (column < 0 if dim.scale == "sqrt" else None)
                if bad is not None and bad.any():
                    raise ParameterError(
                        dim.name,
                        float(column[np.argmax(bad)]),
                        f"> {0.0 - dim.offset:g}" if dim.scale == "log" else ">= 0",
                    )
                continue
            bad = ~((column >= self._bounds[0][j]) & (column <= self._bounds[1][j]))  # NaN is outside
            if bad.any():
                raise ParameterError(
                    dim.name,
                    float(column[np.argmax(bad)]),
                    f"[{dim.low:g}, {dim.high:g}] {dim.unit}, the training domain of this "
                    f"predictor (pass extrapolate=True to evaluate outside it)",
                )
        if self._texture_drawn and not extrapolate:
            load = self._texture_load(values)
            bad = load > self.texture_limit * (1 + 1e-9)
            if bad.any():
                raise ParameterError(
                    "silt + 1.5·clay",
                    float(load[np.argmax(bad)]),
                    f"<= {self.texture_limit:g} (sand texture class of the training domain; pass "
                    f"extrapolate=True to evaluate outside it)",
                )

    def _texture_load(self, values: np.ndarray) -> np.ndarray:
        """silt + 1.5·clay of each row (texture dimensions only)."""
        return values[:, self.names.index("silt")] + CLAY_WEIGHT * values[:, self.names.index("clay")]

    def contains(self, columns: Mapping, forms: ArrayLike | None = None) -> np.ndarray:
        """Which samples lie inside this domain (the test of :meth:`check`, without raising).

        Parameters
        ----------
        columns : mapping of str to array_like (n,)
            Parameter values by SandSample name (every dimension and fixed parameter of the
            domain must be present; others are ignored).
        forms : array_like of str (n,), optional
            Iron-oxide form of each sample (None: not checked).

        Returns
        -------
        ndarray of bool (n,)
            True where every dimension is inside its range (and the texture inside the class
            bound), every fixed parameter equals its value and the form is one of ``forms``.
            NaN is outside.
        """
        return self.violations(columns, forms) == 0

    def violations(self, columns: Mapping, forms: ArrayLike | None = None) -> np.ndarray:
        """How many of the conditions of :meth:`contains` each sample fails (0: inside): a
        form not covered, each fixed parameter at another value, each dimension out of its range
        and the texture beyond the class bound count one each. A bank extrapolates with the
        model a sample is nearest to by this count."""
        n = len(next(iter(columns.values()))) if columns else len(forms)
        count = np.zeros(n, dtype=np.intp)
        if forms is not None:
            count += ~np.isin(np.asarray(forms).astype(str), self.forms)
        # One comparison per kind, with the bounds kept as arrays: a bank tests a sample against
        # many domains, and a single call is mostly these tests.
        if self.fixed:
            fixed = np.column_stack([np.asarray(columns[k], dtype=float) for k in self.fixed])
            count += (~at_fixed_value(fixed, self._fixed_values)).sum(axis=1)
        if self.dimensions:
            values = np.column_stack([np.asarray(columns[k], dtype=float) for k in self.names])
            low, high = self._bounds
            count += (~((values >= low) & (values <= high))).sum(axis=1)  # NaN is outside
            if self._texture_drawn:
                count += self._texture_load(values) > self.texture_limit * (1 + 1e-9)
        return count

    def scaled(self, values: np.ndarray) -> np.ndarray:
        """Regression coordinates: each column's transformed value mapped to [−1, 1]."""
        center, halfwidth = self.scaling()
        out = np.empty(np.shape(values), dtype=float)
        for j, dim in enumerate(self.dimensions):
            out[:, j] = dim.forward(values[:, j])
        out -= center
        out /= halfwidth
        return out

    def scaling(self) -> tuple[np.ndarray, np.ndarray]:
        """Center and half-width of each dimension's transformed range."""
        t0 = np.array([float(d.forward(d.low)) for d in self.dimensions])
        t1 = np.array([float(d.forward(d.high)) for d in self.dimensions])
        return (t0 + t1) / 2, (t1 - t0) / 2


def at_fixed_value(values: np.ndarray, fixed: ArrayLike) -> np.ndarray:
    """Values equal to the value a domain fixes (broadcasting): equal, or within 1e-9 relative
    for the round-off of values written to text and read back; inf matches inf, NaN nothing."""
    fixed = np.asarray(fixed, dtype=float)
    with np.errstate(invalid="ignore"):  # inf − inf where depth_mm is fixed at inf
        near = np.isfinite(fixed) & (np.abs(values - fixed) <= 1e-9 * np.abs(fixed))
    return (values == fixed) | near
