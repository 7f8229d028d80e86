"""Scoring the model against a measured spectrum: the model grid, the measurement brought to
it, and the error per wavelength band with its Monte Carlo error bar.

Public objects
--------------
BANDS_NM, TARGET_RMS
    The bands of issue 3 §3 and their RMS targets: ≤ 0.02 over 400–700 nm, ≤ 0.03 over 400–2500 nm.
default_wavelengths_nm, model_wavelengths_nm
    The model grid: every 10 nm in 400–700 nm, every 50 nm in 750–2500 nm (or the one given).
measured_on_grid
    A measured spectrum brought to the model's wavelengths (window average, else interpolation).
BandError, band_error
    Model-minus-measurement errors over one band.
ValidationResult, score
    A model run against one measured sample, scored per band.

Comparing a model grid with a measured spectrum
-----------------------------------------------
The Beckman spectrometer of the USGS library samples every 1.6–4 nm below 700 nm and every
5–30 nm beyond. At each model wavelength λ the measured value is the mean of the valid channels
with |λ_c − λ| ≤ 5 nm; when no channel lies that close, it is the linear interpolation between
the nearest valid channels on either side, provided they are at most 50 nm apart; otherwise the
wavelength is skipped. Deleted channels (−1.23e34 in the file, NaN after
:func:`sandlight.measured.read_usgs`) are dropped first.

Monte Carlo error bars
----------------------
Each model value has the standard error σᵢ = √(ρ(1 − ρ)/N). To first order the RMS error moves
by δRMS = Σ dᵢ δᵢ / (n · RMS), dᵢ = model − measured. The engine uses the same random streams at
every wavelength, so the δᵢ are correlated; the reported error bar is the bound
Σ |dᵢ| σᵢ / (n · RMS), which holds whatever the correlation (it is the fully correlated case).
The error bar of the maximum absolute error is σ at the wavelength where it occurs.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from sandlight.errors import ParameterError

if TYPE_CHECKING:
    import xarray as xr

    from sandlight.engine import ReflectanceResult
    from sandlight.validation.samples import ValidationSample

__all__ = [
    "BANDS_NM",
    "TARGET_RMS",
    "HALF_WINDOW_NM",
    "MAX_GAP_NM",
    "default_wavelengths_nm",
    "model_wavelengths_nm",
    "measured_on_grid",
    "BandError",
    "band_error",
    "ValidationResult",
    "score",
]

# Issue 3 §3: RMS reflectance error targets per band (band limits in nm, inclusive).
BANDS_NM: dict[str, tuple[float, float]] = {"400–700 nm": (400.0, 700.0), "400–2500 nm": (400.0, 2500.0)}
TARGET_RMS: dict[str, float] = {"400–700 nm": 0.02, "400–2500 nm": 0.03}

# See "Comparing a model grid with a measured spectrum" in the module docstring.
HALF_WINDOW_NM = 5.0
MAX_GAP_NM = 50.0


def default_wavelengths_nm() -> np.ndarray:
    """The model grid (nm): 400–700 every 10 nm, then 750–2500 every 50 nm (67 wavelengths)."""
    return np.concatenate([np.arange(400.0, 701.0, 10.0), np.arange(750.0, 2501.0, 50.0)])


def model_wavelengths_nm(wavelengths_nm: npt.ArrayLike | None = None) -> np.ndarray:
    """``wavelengths_nm`` (nm) as a 1-D float array, or :func:`default_wavelengths_nm` when None."""
    if wavelengths_nm is None:
        return default_wavelengths_nm()
    return np.atleast_1d(np.asarray(wavelengths_nm, dtype=float))


def measured_on_grid(
    spectrum: xr.DataArray,
    wavelengths_nm: npt.ArrayLike,
    *,
    half_window_nm: float = HALF_WINDOW_NM,
    max_gap_nm: float = MAX_GAP_NM,
) -> np.ndarray:
    """A measured spectrum at the model's wavelengths.

    Parameters
    ----------
    spectrum : xarray.DataArray
        Reflectance along ``wavelength`` (nm), NaN for deleted channels, as returned by
        :func:`sandlight.measured.read_usgs` or :func:`sandlight.measured.read_csv`.
    wavelengths_nm : array_like
        Model wavelengths (nm).
    half_window_nm : float
        Channels within ± this of a model wavelength are averaged (nm, > 0).
    max_gap_nm : float
        Where no channel lies in the window, interpolate linearly between the nearest valid
        channels on either side if they are at most this far apart (nm); otherwise NaN.

    Returns
    -------
    numpy.ndarray
        Measured reflectance (fraction) at each model wavelength; NaN where skipped.
    """
    if not half_window_nm > 0 or not max_gap_nm > 0:
        raise ParameterError("half_window_nm/max_gap_nm", (half_window_nm, max_gap_nm), "both > 0 nm")
    w = np.asarray(spectrum["wavelength"].values, dtype=float)
    v = np.asarray(spectrum.values, dtype=float)
    ok = np.isfinite(v)
    w, v = w[ok], v[ok]
    grid = np.atleast_1d(np.asarray(wavelengths_nm, dtype=float))
    out = np.full(grid.shape, np.nan)
    for i, lam in enumerate(grid):
        window = np.abs(w - lam) <= half_window_nm
        if window.any():
            out[i] = v[window].mean()
            continue
        j = int(np.searchsorted(w, lam))
        if 0 < j < w.size and w[j] - w[j - 1] <= max_gap_nm:
            out[i] = np.interp(lam, w[j - 1 : j + 1], v[j - 1 : j + 1])
    return out


@dataclass(frozen=True)
class BandError:
    """Model-minus-measurement error over one wavelength band.

    Attributes
    ----------
    band : str
        e.g. ``"400–700 nm"``; limits in ``low_nm``, ``high_nm`` (inclusive).
    points : int
        Model wavelengths compared (skipped wavelengths excluded).
    rms, rms_mc : float
        RMS error √(mean d²), d = model − measured (reflectance), and its Monte Carlo error bar
        (module docstring).
    max_abs, max_abs_mc, max_at_nm : float
        Largest |d|, its Monte Carlo error bar, and where it occurs (nm).
    bias : float
        Mean d: positive when the model is too bright.
    target_rms : float
        The target for this band (NaN if none).
    """

    band: str
    low_nm: float
    high_nm: float
    points: int
    rms: float
    rms_mc: float
    max_abs: float
    max_abs_mc: float
    max_at_nm: float
    bias: float
    target_rms: float = math.nan

    @property
    def verdict(self) -> str:
        """``"met"``, ``"missed"``, or ``"undecided"`` when the target lies within 2 error bars."""
        if not math.isfinite(self.target_rms) or not math.isfinite(self.rms):
            return "no target"
        if abs(self.rms - self.target_rms) <= 2.0 * self.rms_mc:
            return "undecided"
        return "met" if self.rms < self.target_rms else "missed"


def band_error(
    wavelengths_nm: npt.ArrayLike,
    model: npt.ArrayLike,
    stderr: npt.ArrayLike,
    measured: npt.ArrayLike,
    band: str,
    low_nm: float,
    high_nm: float,
    target_rms: float = math.nan,
) -> BandError:
    """Errors of ``model`` (± ``stderr``) against ``measured`` over [low_nm, high_nm].

    Wavelengths where the measurement is NaN are left out. Raises ``ParameterError`` if no
    wavelength is left.
    """
    wl = np.asarray(wavelengths_nm, dtype=float)
    sel = (wl >= low_nm) & (wl <= high_nm) & np.isfinite(measured)
    if not sel.any():
        raise ParameterError(
            "wavelengths_nm", f"{wl.min():g}–{wl.max():g} nm", f"at least one wavelength with a measurement in {band}"
        )
    d = np.asarray(model, dtype=float)[sel] - np.asarray(measured, dtype=float)[sel]
    s = np.asarray(stderr, dtype=float)[sel]
    n = d.size
    rms = float(np.sqrt(np.mean(d * d)))
    # δRMS ≤ Σ|dᵢ|σᵢ/(n RMS) for any correlation between wavelengths (module docstring).
    rms_mc = float(np.sum(np.abs(d) * s) / (n * rms)) if rms > 0 else float(np.max(s))
    i = int(np.argmax(np.abs(d)))
    return BandError(
        band,
        low_nm,
        high_nm,
        n,
        rms,
        rms_mc,
        float(abs(d[i])),
        float(s[i]),
        float(wl[sel][i]),
        float(np.mean(d)),
        target_rms,
    )


@dataclass(frozen=True)
class ValidationResult:
    """The model against one measured sample.

    Attributes
    ----------
    sample : ValidationSample
    label : str
        What was run: ``"preset <name>"`` or a variant's label.
    wavelengths_nm, model, model_stderr : numpy.ndarray
        Model grid (nm), modelled directional-hemispherical reflectance at normal incidence and
        its Monte Carlo standard error.
    measured : numpy.ndarray
        The measurement on the model grid (:func:`measured_on_grid`), NaN where skipped.
    spectrum : xarray.DataArray
        The full measured spectrum.
    errors : dict[str, BandError]
        Per band of :data:`BANDS_NM`.
    rays, seed : int
    elapsed_s : float
        Wall time of the model run (s).
    sample_values : dict
        What was traced: the description recorded by the engine (a sample's parameters).
    """

    sample: ValidationSample
    label: str
    wavelengths_nm: np.ndarray
    model: np.ndarray
    model_stderr: np.ndarray
    measured: np.ndarray
    spectrum: object
    errors: dict
    rays: int
    seed: int
    elapsed_s: float = 0.0
    sample_values: dict = field(default_factory=dict)

    @property
    def skipped(self) -> int:
        """Model wavelengths without a usable measurement."""
        return int(np.count_nonzero(~np.isfinite(self.measured)))

    def plot(self, path: str | os.PathLike, *, title: str | None = None) -> None:
        """Model (±2 standard errors) and the full-resolution measurement, to a PNG (atomic)."""
        sel = (self.spectrum["wavelength"].values >= 350) & (self.spectrum["wavelength"].values <= 2500)
        meas = self.spectrum[sel]
        errs = ", ".join(f"RMS {b} = {e.rms:.3f}" for b, e in self.errors.items())
        _plot_curves(
            path,
            self.wavelengths_nm,
            self.model,
            self.model_stderr,
            model_label=f"sandlight ({self.label}, {self.rays:,} rays/λ)",
            others=[(meas["wavelength"].values, meas.values, f"measured: USGS {self.sample.spectrum}", "k")],
            title=title or f"{self.sample.name}\n{errs}",
        )


def _plot_curves(
    path: str | os.PathLike,
    wl: np.ndarray,
    values: np.ndarray,
    stderr: np.ndarray,
    *,
    model_label: str,
    others: list,
    title: str,
) -> None:
    # sandlight.plots.plot_spectrum scales the y axis to the model curve only, which would clip a
    # measurement brighter than the model (GDS76 in the near-infrared); hence this plot.
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from sandlight.io import atomic_path

    fig, ax = plt.subplots(figsize=(7.5, 4.2), dpi=120)
    ax.axvspan(400, 700, color="0.93", lw=0, label="400–700 nm")
    ax.plot(wl, values, "-o", ms=2.5, color="C3", label=model_label)
    ax.fill_between(
        wl,
        values - 2 * stderr,
        values + 2 * stderr,
        color="C3",
        alpha=0.3,
        lw=0,
        label="±2 Monte Carlo standard errors",
    )
    top = float(np.nanmax(values + 2 * stderr))
    for w2, v2, lab, colour in others:
        ax.plot(w2, v2, "-", lw=1, color=colour, label=lab)
        top = max(top, float(np.nanmax(v2)))
    ax.set_xlim(350, 2500)
    ax.set_ylim(0, min(1.0, top * 1.08) if top < 0.95 else 1.0)
    ax.set_xlabel("wavelength (nm)")
    ax.set_ylabel("directional-hemispherical reflectance")
    ax.grid(alpha=0.3)
    ax.legend(loc="lower right", fontsize=7)
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png")
    plt.close(fig)


def score(
    sample: ValidationSample, label: str, result: ReflectanceResult, spectrum: xr.DataArray, *, elapsed_s: float = 0.0
) -> ValidationResult:
    """Scores a model run (``result``, from :func:`sandlight.reflectance`) against the measured
    ``spectrum`` of ``sample``, over every band of :data:`BANDS_NM`.

    ``label`` says what was run (``"preset <name>"``, a variant's label); ``elapsed_s`` is the
    wall time of the run (s). The seed and what was traced are taken from ``result``.
    """
    wl = result.wavelengths
    measured = measured_on_grid(spectrum, wl)
    errors = {
        b: band_error(wl, result.values, result.stderr, measured, b, lo, hi, TARGET_RMS.get(b, math.nan))
        for b, (lo, hi) in BANDS_NM.items()
    }
    return ValidationResult(
        sample,
        label,
        wl,
        result.values,
        result.stderr,
        measured,
        spectrum,
        errors,
        result.rays,
        result.seed,
        elapsed_s,
        result.sample,
    )
