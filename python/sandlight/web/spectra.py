"""What the explorer says of a sample's spectrum and colour, as JSON-ready dicts.

The spectrum comes from the bank of shipped spectral predictors (`sandlight.predictor.bank`): the
most accurate model whose training domain holds the sample answers, and the answer names it with
its hold-out error. The shipped models answer at 400–700 nm; outside every model's domain (and
beyond 400–700 nm) only the Monte Carlo engine answers, which the page offers as a job
(`sandlight.web.jobs`).

The colour of a spectrum follows `sandlight.colour`: CIE XYZ under D50 and D65 (CIE 1964 10°
observer), sRGB ("managed": Bradford-adapted to D65, IEC 61966-2-1), CIELAB relative to the
perfect reflector under each illuminant, and CIEDE2000 between two samples under D50
(colour-science's ``delta_E(method="CIE 2000")``; Sharma, Wu & Dalal 2005).
"""

from __future__ import annotations

import threading
import warnings
from collections import OrderedDict
from collections.abc import Hashable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

import colour
from sandlight.colour.spectrum import spectrum_to_xyz_under
from sandlight.colour.srgb import srgb_to_uint8, xyz_to_lab, xyz_to_srgb
from sandlight.errors import ParameterError
from sandlight.predictor.bank import ModelBank, default_model, holdout_rms
from sandlight.sample import SandSample

__all__ = [
    "Prediction",
    "predict",
    "predict_many",
    "colour_of",
    "colours_of",
    "sample_colours",
    "spectrum_answer",
    "spectrum_answers",
    "colour_answer",
    "colour_answers",
]

#: The engine's wavelength range, nm (where a Monte Carlo job can answer).
ENGINE_RANGE_NM = (350.0, 2500.0)


@dataclass(frozen=True)
class Prediction:
    """A sample's predicted spectrum, or why no model answers.

    Attributes
    ----------
    wavelengths_nm, reflectance : ndarray or None
        The spectrum (nm; directional-hemispherical reflectance at normal incidence, a fraction);
        None when no model covers the sample.
    model : str or None
        The name of the model that answered.
    holdout_rms : float or None
        Its hold-out RMS error over all its wavelengths (reflectance).
    description : str
        The bank's one-line description of the model, or why no model covers the sample.
    """

    wavelengths_nm: np.ndarray | None
    reflectance: np.ndarray | None
    model: str | None
    holdout_rms: float | None
    description: str

    @property
    def covered(self) -> bool:
        """Whether a model answered."""
        return self.model is not None


class _Kept(OrderedDict):
    """The last ``size`` answers by sample, least recently used dropped first (thread-safe: job
    threads read it too)."""

    def __init__(self, size: int) -> None:
        super().__init__()
        self.size = size
        self._lock = threading.Lock()

    def __getitem__(self, key: Hashable) -> Any:
        with self._lock:
            self.move_to_end(key)
            return super().__getitem__(key)

    def put(self, key: Hashable, value: Any) -> None:
        with self._lock:
            self[key] = value
            self.move_to_end(key)
            while len(self) > self.size:
                self.popitem(last=False)


_KEPT_PREDICTIONS = _Kept(1024)
_KEPT_COLOURS = _Kept(1024)


def bank() -> ModelBank:
    """The shipped bank (loaded once; its version warnings said once, in the server's log)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return default_model()


def predict(sample: SandSample) -> Prediction:
    """The spectrum of ``sample`` from the first model of the bank that covers it."""
    return predict_many([sample])[0]


def predict_many(samples: Sequence[SandSample]) -> list[Prediction]:
    """The spectra of ``samples``, the ones not kept evaluated by the bank in one vectorised call.

    The last 1024 answers are kept: the page asks for the same sample's spectrum, colour,
    overlay and export (samples are immutable and hashable, the bank never changes)."""
    todo = list(dict.fromkeys(s for s in samples if s not in _KEPT_PREDICTIONS))
    if todo:
        models = bank()
        try:  # usually every sample is covered: one call
            inside, outside = todo, []
            values, used = models.predict(inside, return_models=True)
        except ParameterError:  # some are not: split them off and say why for each
            covered = models.select(todo) >= 0
            inside = [s for s, c in zip(todo, covered) if c]
            outside = [s for s, c in zip(todo, covered) if not c]
            values, used = models.predict(inside, return_models=True) if inside else ([], [])
        for sample, reflectance, name in zip(inside, values, used):
            _KEPT_PREDICTIONS.put(sample, _answered(models, reflectance, str(name)))
        for sample in outside:
            _KEPT_PREDICTIONS.put(sample, _not_covered(models, sample))
    return [_KEPT_PREDICTIONS[s] for s in samples]


def _answered(models: ModelBank, reflectance: np.ndarray, name: str) -> Prediction:
    wavelengths = models.wavelengths_.copy()
    reflectance = reflectance.copy()
    for shared in (wavelengths, reflectance):  # a kept answer must not change
        shared.setflags(write=False)
    return Prediction(wavelengths, reflectance, name, holdout_rms(models.model(name)), models.describe(name))


def _not_covered(models: ModelBank, sample: SandSample) -> Prediction:
    try:
        models.predict([sample])
    except ParameterError as exc:  # outside every model's domain: the message says which parameter
        return Prediction(None, None, None, None, str(exc))
    raise AssertionError(f"the bank predicts {sample!r}, which it said no model covers")


def colour_of(wavelengths_nm: ArrayLike, reflectance: ArrayLike) -> dict[str, Any]:
    """sRGB (encoded, 0–1, and as #rrggbb), out-of-gamut flag, CIELAB under D50 and D65 of a spectrum
    covering 400–700 nm (`sandlight.colour.spectrum.spectrum_to_xyz`)."""
    return colours_of(wavelengths_nm, np.asarray(reflectance, dtype=float)[None])[0]


def colours_of(wavelengths_nm: ArrayLike, reflectance: ArrayLike) -> list[dict[str, Any]]:
    """`colour_of` for each row of ``reflectance`` (n, wavelengths), in one vectorised pass."""
    xyz = spectrum_to_xyz_under(wavelengths_nm, reflectance, illuminants=("D50", "D65"))
    xyz50, xyz65 = xyz[..., 0, :], xyz[..., 1, :]
    rgb, outside = xyz_to_srgb(xyz50, return_out_of_gamut=True)
    codes = srgb_to_uint8(rgb)
    lab50, lab65 = xyz_to_lab(xyz50), xyz_to_lab(xyz65, illuminant="D65")
    return [
        {
            "srgb": rgb[i].tolist(),
            "hex": "#" + "".join(f"{int(c):02x}" for c in codes[i]),
            "out_of_gamut": bool(outside[i]),
            "lab_d50": lab50[i].tolist(),
            "lab_d65": lab65[i].tolist(),
        }
        for i in range(len(rgb))
    ]


def _uncovered(prediction: Prediction) -> dict[str, Any]:
    return {
        "covered": False,
        "model": None,
        "reason": prediction.description,
        "monte_carlo": {
            "endpoint": "/api/jobs/reflectance",
            "wavelength_range_nm": list(ENGINE_RANGE_NM),
            "message": "no shipped model covers this sample: refine with Monte Carlo",
        },
    }


def _answered_by(p: Prediction) -> dict[str, Any]:
    """The fields of an answer that name the model (or, uncovered, why there is none)."""
    if not p.covered:
        return _uncovered(p)
    return {"covered": True, "model": p.model, "holdout_rms": p.holdout_rms}


def spectrum_answer(sample: SandSample) -> dict[str, Any]:
    """The body of ``POST /api/spectrum`` (docs/explorer.md)."""
    return spectrum_answers([sample])[0]


def spectrum_answers(samples: Sequence[SandSample]) -> list[dict[str, Any]]:
    """`spectrum_answer` of each sample, the bank called once for all not kept."""
    return [_spectrum_body(p) for p in predict_many(samples)]


def _spectrum_body(p: Prediction) -> dict[str, Any]:
    if not p.covered:
        return _uncovered(p)
    return {
        **_answered_by(p),
        "description": p.description,
        "wavelengths_nm": p.wavelengths_nm.tolist(),
        "reflectance": p.reflectance.tolist(),
        "note": (
            f"the shipped models answer at {p.wavelengths_nm[0]:g}–{p.wavelengths_nm[-1]:g} nm; "
            f"Monte Carlo covers {ENGINE_RANGE_NM[0]:g}–{ENGINE_RANGE_NM[1]:g} nm"
        ),
    }


def sample_colours(samples: Sequence[SandSample]) -> list[dict[str, Any]]:
    """The colour answer of each sample (`colour_of` of its prediction, or why no model covers it);
    the ones not kept computed in one vectorised pass."""
    todo = list(dict.fromkeys(s for s in samples if s not in _KEPT_COLOURS))
    predictions = dict(zip(todo, predict_many(todo)))
    covered = [s for s in todo if predictions[s].covered]
    if covered:
        wavelengths = predictions[covered[0]].wavelengths_nm
        rows = np.stack([predictions[s].reflectance for s in covered])
        for sample, colour_answer_ in zip(covered, colours_of(wavelengths, rows)):
            _KEPT_COLOURS.put(sample, {**_answered_by(predictions[sample]), **colour_answer_})
    for sample in (s for s in todo if not predictions[s].covered):
        _KEPT_COLOURS.put(sample, _answered_by(predictions[sample]))
    return [dict(_KEPT_COLOURS[s]) for s in samples]


def colour_answers(pairs: Sequence[tuple[SandSample, SandSample | None]]) -> list[dict[str, Any]]:
    """The bodies of ``POST /api/colour`` for (A, B) pairs: the colour of A, of B (None: no
    comparison) and their CIEDE2000 difference under D50 when both are covered."""
    distinct = list(dict.fromkeys(x for pair in pairs for x in pair if x is not None))
    found = dict(zip(distinct, sample_colours(distinct)))
    answers = [{"a": found[a]} if b is None else {"a": found[a], "b": found[b]} for a, b in pairs]
    compared = [x for x in answers if "b" in x]
    for answer in compared:
        answer["delta_e2000"] = None
    both = [x for x in compared if x["a"]["covered"] and x["b"]["covered"]]
    if both:
        lab_a, lab_b = (np.array([x[k]["lab_d50"] for x in both]) for k in "ab")
        for answer, de in zip(both, np.atleast_1d(colour.delta_E(lab_a, lab_b, method="CIE 2000"))):
            answer["delta_e2000"] = float(de)
    return answers


def colour_answer(sample: SandSample, compare: SandSample | None) -> dict[str, Any]:
    """The body of ``POST /api/colour`` for one pair (`colour_answers`)."""
    return colour_answers([(sample, compare)])[0]
