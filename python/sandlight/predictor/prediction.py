"""``sandlight.predict``: the shipped spectral models' reflectance at any wavelength they span,
with the answering model and its hold-out error, as an xarray Dataset.

Two banks are shipped (:func:`~sandlight.predictor.bank.shipped_banks`): the paper's, at its 16
wavelengths (400–700 nm every 20 nm; narrow models around the reference sand and the presets,
broad ones for the rest), and the full range, 350–2500 nm every 25 nm (dry sand for now). A call
takes the paper's bank when every wavelength asked for lies in 400–700 nm (its narrow models are
the more accurate), the full range otherwise (``mode`` chooses one).

The models answer at their own wavelengths. Between them the spectrum is interpolated with a
monotone piecewise-cubic Hermite interpolant (PCHIP, Fritsch & Carlson 1980,
``scipy.interpolate.PchipInterpolator``): it never overshoots, so a reflectance stays within the
range of its neighbouring nodes, and it follows a steep absorption edge better than straight
lines. Its error, measured on measured USGS spectra sub-sampled at the models' nodes and
interpolated back to 1 nm (``scripts/studies/spectral_interpolation.py``), is at most 0.0010
RMS and 0.004 at any wavelength over 400–700 nm (20 nm nodes), 0.0018 RMS and 0.019 at a
measurement artefact over 350–2500 nm (25 nm nodes), below the models' own hold-out errors
(docs/spectral-predictor.md, "Any wavelength" and "Full range"). The hold-out error of a model
between its nodes is interpolated linearly.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike
from scipy.interpolate import PchipInterpolator

from sandlight.checks import check_choice
from sandlight.errors import ParameterError
from sandlight.io import cf_attributes
from sandlight.predictor.bank import ModelBank, default_model, full_range_model
from sandlight.sample import SandSample

__all__ = ["predict", "answering_bank", "interpolate_spectra", "PREDICT_MODES"]

#: Which shipped bank answers: "auto" (the paper's when the wavelengths allow, module docstring),
#: "paper" (400–700 nm only) or "full-range" (350–2500 nm, also inside 400–700 nm).
PREDICT_MODES = ("auto", "paper", "full-range")


def predict(
    samples: Any,
    wavelengths_nm: ArrayLike | None = None,
    *,
    extrapolate: bool = False,
    bank: ModelBank | None = None,
    mode: str = "auto",
) -> xr.Dataset:
    """Predicted directional-hemispherical reflectance at normal incidence, from the spectral
    models, in microseconds a sample.

    Parameters
    ----------
    samples : SandSample, preset name, or a batch
        One sample (a :class:`~sandlight.SandSample`, a preset name or a dict of parameters), or
        a batch: a list of such samples, or columns as :meth:`ModelBank.predict` takes them (a
        dict of columns, a structured array, a DataFrame, an xarray.Dataset).
    wavelengths_nm : array_like, optional
        Vacuum wavelengths in nm within the models' range (350–2500 nm for the shipped models);
        None: the answering bank's own wavelengths. Between those, PCHIP interpolation (module
        docstring).
    extrapolate : bool
        Let the model nearest to a sample no model covers answer it outside its domain, instead of
        raising (``extrapolated`` then says so).
    bank : ModelBank, optional
        The models (default: a shipped bank, as ``mode`` says).
    mode : {"auto", "paper", "full-range"}
        Which shipped bank answers when ``bank`` is not given: "auto" the paper's bank
        (:func:`~sandlight.predictor.bank.default_model`) if ``wavelengths_nm`` is None or
        within 400–700 nm, else the full-range bank
        (:func:`~sandlight.predictor.bank.full_range_model`); "paper" and "full-range" that
        bank always; ignored when ``bank`` is given.

    Returns
    -------
    xarray.Dataset
        ``reflectance`` (sample, wavelength), ``holdout_rms`` (sample, wavelength: the answering
        model's hold-out RMS error at that wavelength), ``model`` (sample: its name) and
        ``extrapolated`` (sample); ``wavelength`` in nm. For one sample the ``sample`` dimension
        is dropped.

    Raises
    ------
    ParameterError
        A wavelength outside the models' range or not finite (naming ``wavelengths_nm``), a
        sample that no model covers (unless ``extrapolate``; the message names the parameter
        out of the nearest model's range), an unknown ``mode``, or a malformed sample.
    """
    mode = check_choice("mode", mode, PREDICT_MODES)
    bank = answering_bank(wavelengths_nm, mode) if bank is None else bank
    single = isinstance(samples, (SandSample, str, dict)) and not _is_columns(samples)
    if single:
        batch = [_as_sample(samples)]
    elif isinstance(samples, (list, tuple)):
        batch = [_as_sample(s) for s in samples]  # preset names among the samples
    else:
        batch = samples
    nodes = np.asarray(bank.wavelengths_, dtype=float)
    wl = nodes if wavelengths_nm is None else _check_within(wavelengths_nm, nodes)
    values, used = bank.predict(batch, extrapolate=extrapolate, return_models=True)
    outside = bank.select(batch) < 0
    # One error curve per answering model, not per sample (batches of millions).
    names, which = np.unique(used, return_inverse=True)
    curves = np.array([_holdout_rms(bank, name, nodes) for name in names])
    if wl is not nodes:
        values = interpolate_spectra(nodes, values, wl)
        curves = np.array([np.interp(wl, nodes, c) for c in curves])
    errors = curves[which.reshape(-1)]
    ds = xr.Dataset(
        {
            "reflectance": (("sample", "wavelength"), values, _attrs("directional-hemispherical reflectance", "1")),
            "holdout_rms": (
                ("sample", "wavelength"),
                errors,
                _attrs("hold-out RMS error of the answering model", "1"),
            ),
            "model": (("sample",), used.astype(str), {"long_name": "the spectral model that answered"}),
            "extrapolated": (
                ("sample",),
                outside,
                {"long_name": "no model covers the sample: the nearest model answered outside its domain"},
            ),
        },
        coords={"wavelength": ("wavelength", wl, _attrs("vacuum wavelength", "nm"))},
        attrs={
            **cf_attributes("sandlight spectral predictor reflectance", "sandlight.predict"),
            "incidence": "normal",
            "interpolation": "PCHIP between the models' wavelengths" if wl is not nodes else "none",
        },
    )
    return ds.isel(sample=0) if single else ds


def interpolate_spectra(nodes_nm: ArrayLike, values: ArrayLike, wavelengths_nm: ArrayLike) -> np.ndarray:
    """Spectra known at ``nodes_nm`` (increasing, nm; ``values`` (..., n_nodes)) at
    ``wavelengths_nm`` within them, by PCHIP along the last axis (module docstring)."""
    return PchipInterpolator(np.asarray(nodes_nm, dtype=float), np.asarray(values, dtype=float), axis=-1)(
        np.asarray(wavelengths_nm, dtype=float)
    )


def _is_columns(samples: Any) -> bool:
    # A dict of columns (a batch) holds sequences; a dict of one sample's parameters scalars.
    return isinstance(samples, dict) and any(np.ndim(v) > 0 for v in samples.values())


def _as_sample(sample: Any) -> Any:
    return SandSample.preset(sample) if isinstance(sample, str) else sample


def answering_bank(wavelengths_nm: ArrayLike | None = None, mode: str = "auto") -> ModelBank:
    """The shipped bank that :func:`predict` asks for ``wavelengths_nm`` in ``mode`` (module
    docstring; ``mode`` as :func:`predict` takes it, checked there)."""
    if mode == "paper":
        return default_model()
    if mode == "full-range":
        return full_range_model()
    paper = default_model()
    if wavelengths_nm is None:
        return paper
    try:
        wl = np.asarray(wavelengths_nm, dtype=float)
    except (TypeError, ValueError):
        return paper  # refused by name by _check_within
    low, high = paper.wavelengths_[0], paper.wavelengths_[-1]
    inside = wl.size > 0 and bool(np.all((wl >= low) & (wl <= high)))
    return paper if inside or not np.all(np.isfinite(wl)) else full_range_model()


def _check_within(wavelengths_nm: ArrayLike, nodes: np.ndarray) -> np.ndarray:
    """``wavelengths_nm`` as a 1-D float array, each finite and within the models' range."""
    try:
        wl = np.atleast_1d(np.asarray(wavelengths_nm, dtype=float))
    except (TypeError, ValueError):
        raise ParameterError("wavelengths_nm", wavelengths_nm, "wavelengths in nm") from None
    low, high = float(nodes[0]), float(nodes[-1])
    allowed = f"wavelengths in [{low:g}, {high:g}] nm, the range of the spectral models"
    if wl.ndim != 1 or wl.size == 0:
        raise ParameterError("wavelengths_nm", wavelengths_nm, "a non-empty 1-D sequence of " + allowed)
    bad = ~np.isfinite(wl) | (wl < low) | (wl > high)
    if bad.any():
        raise ParameterError("wavelengths_nm", float(wl[bad][0]), allowed)
    return wl


def _holdout_rms(bank: ModelBank, name: str, nodes: np.ndarray) -> np.ndarray:
    """The hold-out RMS error of model ``name`` at each of the bank's wavelengths (NaN if unscored)."""
    scores = bank.model(name).holdout_scores_ or {}
    rms = scores.get("rms_error")
    return np.asarray(rms, dtype=float) if rms is not None else np.full(nodes.size, np.nan)


def _attrs(long_name: str, units: str) -> dict[str, str]:
    return {"long_name": long_name, "units": units}
