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

import functools
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

import colour
from sandlight.colour.spectrum import spectrum_to_xyz
from sandlight.colour.srgb import srgb_to_uint8, xyz_to_lab, xyz_to_srgb
from sandlight.errors import ParameterError
from sandlight.predictor.bank import ModelBank, default_model, holdout_rms
from sandlight.sample import SandSample

__all__ = ["Prediction", "predict", "colour_of", "delta_e2000", "spectrum_answer", "colour_answer"]

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


def bank() -> ModelBank:
    """The shipped bank (loaded once; its version warnings said once, in the server's log)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return default_model()


@functools.lru_cache(maxsize=1024)
def predict(sample: SandSample) -> Prediction:
    """The spectrum of ``sample`` from the first model of the bank that covers it.

    The last 1024 answers are kept: the page asks for the same sample's spectrum, colour,
    overlay and export (samples are immutable and hashable, the bank never changes)."""
    models = bank()
    try:
        values, used = models.predict([sample], return_models=True)
    except ParameterError as exc:  # outside every model's domain: the message says which parameter
        return Prediction(None, None, None, None, str(exc))
    name = str(used[0])
    wavelengths, reflectance = models.wavelengths_.copy(), values[0]
    for shared in (wavelengths, reflectance):  # a kept answer must not change
        shared.setflags(write=False)
    return Prediction(wavelengths, reflectance, name, holdout_rms(models.model(name)), models.describe(name))


def colour_of(wavelengths_nm: ArrayLike, reflectance: ArrayLike) -> dict[str, Any]:
    """sRGB (encoded, 0–1, and as #rrggbb), out-of-gamut flag, CIELAB under D50 and D65 of a spectrum
    covering 400–700 nm (`sandlight.colour.spectrum.spectrum_to_xyz`)."""
    xyz50 = spectrum_to_xyz(wavelengths_nm, reflectance)
    xyz65 = spectrum_to_xyz(wavelengths_nm, reflectance, illuminant="D65")
    rgb, outside = xyz_to_srgb(xyz50, return_out_of_gamut=True)
    code = srgb_to_uint8(rgb)
    return {
        "srgb": [float(c) for c in rgb],
        "hex": "#" + "".join(f"{int(c):02x}" for c in code),
        "out_of_gamut": bool(outside),
        "lab_d50": [float(c) for c in xyz_to_lab(xyz50)],
        "lab_d65": [float(c) for c in xyz_to_lab(xyz65, illuminant="D65")],
    }


def delta_e2000(lab_a: ArrayLike, lab_b: ArrayLike) -> float:
    """CIEDE2000 colour difference of two CIELAB colours (same illuminant)."""
    return float(colour.delta_E(np.asarray(lab_a), np.asarray(lab_b), method="CIE 2000"))


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
    p = predict(sample)
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


def _sample_colour(sample: SandSample) -> dict[str, Any]:
    return dict(_kept_sample_colour(sample))


@functools.lru_cache(maxsize=1024)
def _kept_sample_colour(sample: SandSample) -> dict[str, Any]:
    p = predict(sample)
    return _answered_by(p) if not p.covered else {**_answered_by(p), **colour_of(p.wavelengths_nm, p.reflectance)}


def colour_answer(sample: SandSample, compare: SandSample | None) -> dict[str, Any]:
    """The body of ``POST /api/colour``: the colour of ``sample`` (A), of ``compare`` (B) and
    their CIEDE2000 difference under D50 when both are covered."""
    a = _sample_colour(sample)
    answer: dict[str, Any] = {"a": a}
    if compare is not None:
        b = _sample_colour(compare)
        answer["b"] = b
        answer["delta_e2000"] = delta_e2000(a["lab_d50"], b["lab_d50"]) if a["covered"] and b["covered"] else None
    return answer
