"""Validation of the model against measured reflectance spectra (issue 3 §3).

The model is run, with the shipped optical constants and the shipped presets, for laboratory
samples whose reflectance the USGS Spectral Library measured. Each preset was set from the
sample's written description, never fitted to its spectrum; the comparison is therefore a test
of the physics and the optical constants, not of a fit.

Public objects
--------------
SAMPLES
    The validation samples: USGS spectrum, preset, what the description says.
TARGET_RMS
    The accuracy targets of issue 3: RMS ≤ 0.02 over 400–700 nm and ≤ 0.03 over 400–2500 nm.
default_wavelengths_nm
    The model grid: every 10 nm in 400–700 nm, every 50 nm in 750–2500 nm.
measured_on_grid
    A measured spectrum brought to the model's wavelengths (window average, else interpolation).
validate
    Runs the model for the validation samples and scores it: a list of :class:`ValidationResult`.
Variant, DIAGNOSTIC_VARIANTS, run_variants
    What-if runs (one physical change at a time) used to find the cause of a miss.
powder_reflectance
    Reflectance of a powder of one pure material (an iron-oxide end-member, which a
    :class:`~sandlight.SandSample` cannot describe).
figure3_spectra, plot_figure3
    The paper's Figure 3 from the model: quartz vs iron oxide vs the 98/2 mixture.
write_report
    Writes (or updates) the Markdown report ``docs/validation.md``.

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

import contextlib
import math
import os
import re
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from sandlight.errors import ParameterError

__all__ = [
    "SAMPLES",
    "TARGET_RMS",
    "BANDS_NM",
    "ValidationSample",
    "BandError",
    "ValidationResult",
    "default_wavelengths_nm",
    "measured_on_grid",
    "band_error",
    "validate",
    "Variant",
    "DIAGNOSTIC_VARIANTS",
    "run_variants",
    "powder_reflectance",
    "figure3_spectra",
    "plot_figure3",
    "write_report",
]

# Issue 3 §3: RMS reflectance error targets per band (band limits in nm, inclusive).
BANDS_NM: dict[str, tuple[float, float]] = {"400–700 nm": (400.0, 700.0), "400–2500 nm": (400.0, 2500.0)}
TARGET_RMS: dict[str, float] = {"400–700 nm": 0.02, "400–2500 nm": 0.03}

# See "Comparing a model grid with a measured spectrum" in the module docstring.
HALF_WINDOW_NM = 5.0
MAX_GAP_NM = 50.0


@dataclass(frozen=True)
class ValidationSample:
    """A measured sample and the preset that describes it.

    Attributes
    ----------
    name : str
        The name used in reports and on the command line (the USGS sample name).
    spectrum : str
        The splib07a spectrum (file stem) holding its measured reflectance.
    preset : str
        The :meth:`sandlight.SandSample.preset` set from the sample description.
    description : str
        What the USGS description says about the sample.
    """

    name: str
    spectrum: str
    preset: str
    description: str


SAMPLES: tuple[ValidationSample, ...] = (
    ValidationSample(
        "Hematite.02+Quartz.98_GDS76",
        "Hematite.02+Quartz.98_GDS76_BECKa_AREF",
        "gds76-hematite-quartz",
        "Hematite GDS27 2 wt% + 98 wt% pure crystal quartz (< 250 µm), intimate laboratory mixture",
    ),
    ValidationSample(
        "Quartz_GDS74_Sand_Ottawa",
        "Quartz_GDS74_Sand_Ottawa_BECKc_AREF",
        "ottawa-gds74",
        "pure commercial quartz sand, Ottawa; grain size not stated",
    ),
)


def _sample_by_name(name: str) -> ValidationSample:
    for s in SAMPLES:
        if name in (s.name, s.spectrum, s.preset):
            return s
    raise ParameterError("samples", name, "names of validation samples: " + ", ".join(s.name for s in SAMPLES))


def default_wavelengths_nm() -> np.ndarray:
    """The model grid (nm): 400–700 every 10 nm, then 750–2500 every 50 nm (67 wavelengths)."""
    return np.concatenate([np.arange(400.0, 701.0, 10.0), np.arange(750.0, 2501.0, 50.0)])


def measured_on_grid(
    spectrum, wavelengths_nm, *, half_window_nm: float = HALF_WINDOW_NM, max_gap_nm: float = MAX_GAP_NM
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
    wavelengths_nm, model, stderr, measured, band: str, low_nm: float, high_nm: float, target_rms: float = math.nan
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

    def plot(self, path, *, title: str | None = None) -> None:
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


def _plot_curves(path, wl, values, stderr, *, model_label, others, title) -> None:
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


def _score(sample, label, wl, model, stderr, spectrum, rays, seed, elapsed, sample_values) -> ValidationResult:
    measured = measured_on_grid(spectrum, wl)
    errors = {
        b: band_error(wl, model, stderr, measured, b, lo, hi, TARGET_RMS.get(b, math.nan))
        for b, (lo, hi) in BANDS_NM.items()
    }
    return ValidationResult(
        sample, label, wl, model, stderr, measured, spectrum, errors, rays, seed, elapsed, sample_values
    )


def _measured_spectrum(sample: ValidationSample):
    from sandlight.measured import read_usgs, usgs_library

    return read_usgs(usgs_library(sample.spectrum))


def validate(
    samples: Sequence[str] | None = None, *, rays, wavelengths_nm=None, seed: int = 0, progress: bool = False
) -> list[ValidationResult]:
    """Runs the model for measured samples and scores it against their spectra.

    Parameters
    ----------
    samples : sequence of str, optional
        Names of :data:`SAMPLES` (sample name, spectrum stem or preset name); default all.
    rays : int
        Rays per wavelength (≥ 1).
    wavelengths_nm : array_like, optional
        Model wavelengths in nm within [350, 2500]; default :func:`default_wavelengths_nm`.
        Each band of :data:`BANDS_NM` needs at least one of them.
    seed : int
        Master seed of the Monte Carlo engine.
    progress : bool
        Show the engine's progress bars.

    Returns
    -------
    list of ValidationResult
        One per sample, each with RMS and maximum absolute errors per band and their Monte
        Carlo error bars. Plot with :meth:`ValidationResult.plot`; report with
        :func:`write_report`.
    """
    from sandlight.engine import reflectance
    from sandlight.sample import SandSample

    chosen = SAMPLES if samples is None else tuple(_sample_by_name(s) for s in samples)
    wl = default_wavelengths_nm() if wavelengths_nm is None else np.atleast_1d(np.asarray(wavelengths_nm, dtype=float))
    results = []
    for s in chosen:
        sample = SandSample.preset(s.preset)
        spectrum = _measured_spectrum(s)
        start = time.perf_counter()
        r = reflectance(sample, wl, rays=rays, seed=seed, progress=progress)
        results.append(
            _score(
                s,
                f"preset {s.preset}",
                r.wavelengths,
                r.values,
                r.stderr,
                spectrum,
                r.rays,
                seed,
                time.perf_counter() - start,
                sample.to_dict(),
            )
        )
    return results


# --- Diagnostic variants: one physical change at a time ---------------------------------------


@dataclass(frozen=True)
class Variant:
    """A what-if run of a validation sample: the preset with one physical change.

    Variants are diagnostics, not fits: each tests whether one candidate cause can move the
    model by the size of the observed miss.

    Attributes
    ----------
    sample : str
        Name of the validation sample (:data:`SAMPLES`).
    label : str
        Short name for tables.
    hypothesis : str
        The physics the variant probes.
    changes : Mapping[str, object]
        Sample parameters replaced in the preset (:meth:`SandSample.replace`).
    k_factor : Mapping[str, float]
        Factor applied to a material's extinction coefficient k at λ ≥ ``k_factor_from_nm``.
    k_factor_from_nm : float
        Lower wavelength limit (nm) of ``k_factor``.
    extra_alpha_per_cm : Mapping[str, float]
        Absorption coefficient added to a material at every wavelength (cm⁻¹).
    """

    sample: str
    label: str
    hypothesis: str
    changes: Mapping = field(default_factory=dict)
    k_factor: Mapping = field(default_factory=dict)
    k_factor_from_nm: float = 0.0
    extra_alpha_per_cm: Mapping = field(default_factory=dict)

    @property
    def changes_optics(self) -> bool:
        return bool(self.k_factor or self.extra_alpha_per_cm)


_GDS76 = SAMPLES[0].name
_OTTAWA = SAMPLES[1].name

DIAGNOSTIC_VARIANTS: tuple[Variant, ...] = (
    Variant(
        _GDS76,
        "no hematite (the quartz host alone)",
        "ceiling: what the quartz host gives with no absorber",
        {"iron_oxide": 0.0},
    ),
    Variant(
        _GDS76,
        "hematite k × 0.2 at λ ≥ 580 nm",
        "hematite's absorption edge is steeper than the log-linear join of Querry and Longtin",
        k_factor={"hematite": 0.2},
        k_factor_from_nm=580.0,
    ),
    Variant(
        _GDS76,
        "hematite particles 1 µm",
        "finer primary hematite grains (more cross-section per mass)",
        {"iron_oxide_particle_size_um": 1.0},
    ),
    Variant(
        _GDS76,
        "hematite particles 10 µm",
        "partial aggregation of the 2–3 µm hematite grains",
        {"iron_oxide_particle_size_um": 10.0},
    ),
    Variant(
        _GDS76,
        "hematite as a uniform coating",
        "the hematite smeared over the quartz grains instead of separate particles",
        {"iron_oxide_form": "coating", "coating_iron_share": 1.0},
    ),
    Variant(_GDS76, "no silt (fines)", "fewer quartz fines", {"sand": 1.0, "silt": 0.0}),
    Variant(
        _GDS76, "quartz host + 1 cm⁻¹", "absorption of the quartz host (impurities)", extra_alpha_per_cm={"quartz": 1.0}
    ),
    Variant(_OTTAWA, "grain size 0.2 mm", "the unknown grade: finer sand", {"grain_size": 0.2}),
    Variant(_OTTAWA, "grain size 0.8 mm", "the unknown grade: coarser sand", {"grain_size": 0.8}),
    Variant(_OTTAWA, "depth 5 mm over a black bottom", "a shallow sample cup", {"depth_mm": 5.0}),
    Variant(
        _OTTAWA,
        "quartz host + 1 cm⁻¹",
        "grey absorption of the quartz host (inclusions, impurities)",
        extra_alpha_per_cm={"quartz": 1.0},
    ),
    Variant(
        _OTTAWA,
        "0.01 wt% iron oxide coating",
        "trace iron staining (hematite/goethite 1:1 in the default kaolinite coating)",
        {"iron_oxide": 0.0001, "hematite_ratio": 0.5, "iron_oxide_form": "coating"},
    ),
)


@contextlib.contextmanager
def _adjusted_optics(variant: Variant):
    """Temporarily changes the optical constants the engine's medium builder reads.

    The shipped tables stay untouched: only the name ``complex_index`` that
    ``sandlight.physics.medium`` looks up is replaced for the duration, so the variant runs
    through exactly the same physics code as the validation.
    """
    if not variant.changes_optics:
        yield
        return
    from sandlight.physics import medium

    original = medium.complex_index

    def adjusted(material, wavelength_nm):
        m = complex(original(material, wavelength_nm))
        k = m.imag
        if material in variant.k_factor and float(wavelength_nm) >= variant.k_factor_from_nm:
            k *= variant.k_factor[material]
        if material in variant.extra_alpha_per_cm:
            # α = 4πk/λ, so an added α (cm⁻¹) is k = αλ/(4π) with λ in cm (nm × 1e-7).
            k += variant.extra_alpha_per_cm[material] * float(wavelength_nm) * 1e-7 / (4.0 * math.pi)
        return complex(m.real, k)

    medium.complex_index = adjusted
    try:
        yield
    finally:
        medium.complex_index = original


def run_variants(
    variants: Sequence[Variant] = DIAGNOSTIC_VARIANTS,
    *,
    rays,
    wavelengths_nm=None,
    seed: int = 0,
    progress: bool = False,
) -> list[ValidationResult]:
    """Runs and scores diagnostic variants (:class:`Variant`) like :func:`validate` does."""
    from sandlight.engine import reflectance
    from sandlight.sample import SandSample

    wl = default_wavelengths_nm() if wavelengths_nm is None else np.atleast_1d(np.asarray(wavelengths_nm, dtype=float))
    spectra = {}
    results = []
    for v in variants:
        s = _sample_by_name(v.sample)
        if s.name not in spectra:
            spectra[s.name] = _measured_spectrum(s)
        sample = SandSample.preset(s.preset).replace(**dict(v.changes))
        start = time.perf_counter()
        with _adjusted_optics(v):
            r = reflectance(sample, wl, rays=rays, seed=seed, progress=progress)
        results.append(
            _score(
                s,
                v.label,
                r.wavelengths,
                r.values,
                r.stderr,
                spectra[s.name],
                r.rays,
                seed,
                time.perf_counter() - start,
                sample.to_dict(),
            )
        )
    return results


# --- Pure powders and the paper's Figure 3 ------------------------------------------------------


def powder_reflectance(
    material: str,
    diameter_um: float | tuple[float, float],
    wavelengths_nm,
    *,
    rays: int,
    porosity: float = 0.45,
    aspect_ratio: float = 1.0,
    seed: int = 0,
    progress: bool = False,
):
    """Directional-hemispherical reflectance at normal incidence of a dry powder of one pure
    material: :func:`sandlight.reflectance` of a :class:`sandlight.physics.powder.Powder`.

    Parameters
    ----------
    material : str
        A name of :data:`sandlight.optics.MATERIALS`.
    diameter_um : float or (float, float)
        Volume-equivalent particle diameter in µm (all equal), or a sieve fraction
        (d_min, d_max) in µm, taken as equal mass per logarithmic size interval.
    wavelengths_nm : array_like
        Vacuum wavelengths (nm) in [350, 2500].
    rays : int
        Rays per wavelength.
    porosity : float
        Pore volume fraction in (0, 1); only the free-path scale depends on it.
    aspect_ratio : float
        Prolate spheroid aspect ratio in [1, 20].
    seed : int
        Master seed.

    Returns
    -------
    sandlight.ReflectanceResult
        Its ``sample`` attribute records the powder's description.
    """
    from sandlight.engine import reflectance
    from sandlight.physics.powder import Powder

    powder = Powder(material, diameter_um, porosity, aspect_ratio)
    return reflectance(powder, wavelengths_nm, rays=rays, seed=seed, progress=progress)


FIGURE3_PARTICLE_UM = 2.5


def figure3_spectra(*, rays, wavelengths_nm=None, seed: int = 0, progress: bool = False) -> dict:
    """Model spectra of the paper's Figure 3: pure quartz, pure iron oxide and the 98/2 mixture.

    The quartz is the host of the ``gds76-hematite-quartz`` preset (that preset with no iron
    oxide); the mixtures are that preset with 2 wt% hematite or 2 wt% goethite as separate
    particles of 2.5 µm; the pure iron oxides are powders of the same 2.5 µm particles at the
    preset's porosity (:func:`powder_reflectance`).

    Returns
    -------
    dict
        ``{"wavelengths_nm": ndarray, "quartz": result, "hematite": {"powder": result,
        "mixture": result}, "goethite": {...}}`` with :class:`sandlight.ReflectanceResult` values.
    """
    from sandlight.engine import reflectance
    from sandlight.sample import SandSample

    wl = default_wavelengths_nm() if wavelengths_nm is None else np.atleast_1d(np.asarray(wavelengths_nm, dtype=float))
    base = SandSample.preset("gds76-hematite-quartz").replace(iron_oxide_particle_size_um=FIGURE3_PARTICLE_UM)
    out = {
        "wavelengths_nm": wl,
        "quartz": reflectance(base.replace(iron_oxide=0.0), wl, rays=rays, seed=seed, progress=progress),
    }
    for mineral, ratio in (("hematite", 1.0), ("goethite", 0.0)):
        out[mineral] = {
            "powder": powder_reflectance(
                mineral, FIGURE3_PARTICLE_UM, wl, rays=rays, porosity=base.porosity, seed=seed, progress=progress
            ),
            "mixture": reflectance(
                base.replace(iron_oxide=0.02, hematite_ratio=ratio), wl, rays=rays, seed=seed, progress=progress
            ),
        }
    return out


# Measured counterparts drawn in grey (USGS splib07a), where the library has them.
FIGURE3_MEASURED = {
    "hematite": {
        "quartz": "Quartz_HS32.4B_BECKa_AREF",
        "powder": "Hematite_GDS27_BECKa_AREF",
        "mixture": "Hematite.02+Quartz.98_GDS76_BECKa_AREF",
    },
    "goethite": {"quartz": "Quartz_HS32.4B_BECKa_AREF", "powder": "Goethite_WS222_Medium_Gr._BECKa_AREF"},
}


def plot_figure3(spectra: dict, path, *, measured: bool = True) -> None:
    """Two panels (hematite, goethite) in the style of the paper's Figure 3, to a PNG (atomic).

    Dotted: pure quartz; dashed: pure iron oxide; solid: 98 wt% quartz + 2 wt% iron oxide.
    Coloured: model; grey: the USGS measurements of :data:`FIGURE3_MEASURED` when ``measured``
    and the spectra are found (:func:`sandlight.measured.usgs_library`).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from sandlight.io import atomic_path
    from sandlight.measured import read_usgs, usgs_library

    wl = spectra["wavelengths_nm"]
    styles = {"quartz": ":", "powder": "--", "mixture": "-"}
    names = {"quartz": "pure quartz", "powder": "pure {m} (2.5 µm)", "mixture": "98 wt% quartz + 2 wt% {m}"}
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), dpi=120, sharey=True)
    for ax, mineral, colour in zip(axes, ("hematite", "goethite"), ("C3", "C1")):
        curves = {"quartz": spectra["quartz"], **spectra[mineral]}
        for key, r in curves.items():
            ax.plot(wl, r.values, styles[key], color=colour, lw=1.6, label="model: " + names[key].format(m=mineral))
        if measured:
            for key, stem in FIGURE3_MEASURED[mineral].items():
                try:
                    m = read_usgs(usgs_library(stem))
                except (FileNotFoundError, ParameterError):
                    continue
                m = m[(m["wavelength"].values >= 350) & (m["wavelength"].values <= 2500)]
                ax.plot(
                    m["wavelength"].values,
                    m.values,
                    styles[key],
                    color="0.55",
                    lw=1,
                    label=f"measured: {stem.replace('_AREF', '')}",
                )
        ax.set_title(
            f"iron oxide = {mineral}" + (" (provisional optical constants)" if mineral == "goethite" else ""),
            fontsize=9,
        )
        ax.set_xlabel("wavelength (nm)")
        ax.set_xlim(350, 2500)
        ax.set_ylim(0, 1)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="lower right")
    axes[0].set_ylabel("directional-hemispherical reflectance")
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png")
    plt.close(fig)


# --- The Markdown report ----------------------------------------------------------------------

REPORT_BLOCKS = ("command", "results", "figures", "variants", "figure3")
_BLOCK_RE = r"<!-- BEGIN validation:{name} -->\n.*?<!-- END validation:{name} -->"

_SKELETON = """# Validation against measured spectra

sandlight's reflectance against USGS laboratory spectra of samples whose presets were set from the
sample descriptions, never fitted to the spectra (issue 3 §3). Everything between `BEGIN`/`END`
markers is written by `sandlight validate`; text outside them is kept when the report is updated.

## How to reproduce

{command}

## Results

Targets: RMS ≤ 0.02 over 400–700 nm and ≤ 0.03 over 400–2500 nm.

{results}

## Spectra

{figures}

## Diagnostic variants

Each variant changes one thing in a preset, to see which physics can move the model by the size
of the miss. They are diagnostics, not fits.

{variants}

## The paper's Figure 3, from the model

{figure3}
"""


def _block(name: str, body: str) -> str:
    return f"<!-- BEGIN validation:{name} -->\n{body.rstrip()}\n<!-- END validation:{name} -->"


def _fmt_band(e: BandError) -> str:
    return f"{e.rms:.4f} ± {e.rms_mc:.4f}"


def _results_block(results: Sequence[ValidationResult]) -> str:
    lines = [
        "| sample | band | RMS error ± MC | target | verdict | max abs error ± MC (at λ) | mean bias | points |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in results:
        for e in r.errors.values():
            lines.append(
                f"| {r.sample.name} | {e.band} | {_fmt_band(e)} | ≤ {e.target_rms:g} | **{e.verdict}** | "
                f"{e.max_abs:.4f} ± {e.max_abs_mc:.4f} ({e.max_at_nm:g} nm) | {e.bias:+.4f} | {e.points} |"
            )
    lines.append("")
    lines.append(
        "Mean bias = mean(model − measured): positive means the model is too bright. ± MC is the Monte "
        "Carlo error bar (bound for correlated noise, see `sandlight.validation`)."
    )
    for r in results:
        lines.append(
            f"- **{r.sample.name}**: preset `{r.sample.preset}` ({r.sample.description}); measured "
            f"spectrum `{r.sample.spectrum}`; {r.rays:,} rays per wavelength, seed {r.seed}, "
            f"{r.wavelengths_nm.size} wavelengths, {r.skipped} skipped (no usable measurement), "
            f"model run {r.elapsed_s:.1f} s."
        )
    return "\n".join(lines)


def _figures_block(results, figure_paths, report_dir) -> str:
    lines = []
    for r, p in zip(results, figure_paths):
        rel = os.path.relpath(p, report_dir)
        lines.append(f"![{r.sample.name}: model vs measurement]({rel})\n")
        lines.append(_values_table(r))
        lines.append("")
    return "\n".join(lines)


def _values_table(r: ValidationResult) -> str:
    keep = [lam for lam in (400, 450, 500, 550, 600, 650, 700, 1000, 1500, 2000, 2500) if lam in r.wavelengths_nm]
    idx = [int(np.flatnonzero(r.wavelengths_nm == lam)[0]) for lam in keep]
    head = "| λ (nm) | " + " | ".join(f"{lam:g}" for lam in keep) + " |"
    sep = "|---|" + "---|" * len(keep)
    model = "| model | " + " | ".join(f"{r.model[i]:.3f}" for i in idx) + " |"
    meas = "| measured | " + " | ".join(f"{r.measured[i]:.3f}" for i in idx) + " |"
    return "\n".join([head, sep, model, meas])


def _variants_block(variants: Sequence[ValidationResult] | None, reference: Sequence[ValidationResult]) -> str:
    if not variants:
        return "Not run in this report (`--no-variants`)."
    by_name = {r.sample.name: r for r in reference}
    lines = [
        f"Run at {variants[0].rays:,} rays per wavelength (seed {variants[0].seed}), same grid and scoring as "
        "above; the reference row is the preset.",
        "",
        "| sample | variant | probes | RMS 400–700 | RMS 400–2500 | bias 400–700 | bias 400–2500 | "
        "ρ 450 model / meas | ρ 650 | ρ 1500 |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]

    def row(r, probes):
        vis, full = r.errors["400–700 nm"], r.errors["400–2500 nm"]
        at = []
        for lam in (450.0, 650.0, 1500.0):
            i = np.flatnonzero(r.wavelengths_nm == lam)
            at.append(f"{r.model[i[0]]:.3f} / {r.measured[i[0]]:.3f}" if i.size else "–")
        return (
            f"| {r.sample.name} | {r.label} | {probes} | {_fmt_band(vis)} | {_fmt_band(full)} | {vis.bias:+.3f} | "
            f"{full.bias:+.3f} | " + " | ".join(at) + " |"
        )

    seen = set()
    hypotheses = {v.label: v.hypothesis for v in DIAGNOSTIC_VARIANTS}
    for r in variants:
        if r.sample.name not in seen and r.sample.name in by_name:
            seen.add(r.sample.name)
            lines.append(row(by_name[r.sample.name], "reference"))
        lines.append(row(r, hypotheses.get(r.label, "")))
    return "\n".join(lines)


def _figure3_block(path, report_dir, spectra) -> str:
    if path is None:
        return "Not run in this report."
    rel = os.path.relpath(path, report_dir)
    wl = spectra["wavelengths_nm"]
    keep = [lam for lam in (450, 550, 650, 900, 1500, 2200) if lam in wl]
    idx = [int(np.flatnonzero(wl == lam)[0]) for lam in keep]
    lines = [
        f"![Figure 3 from the model: quartz, iron oxide and the 98/2 mixture]({rel})",
        "",
        f"Model, {spectra['quartz'].rays:,} rays per wavelength. Dotted: pure quartz (the GDS76 preset's "
        "host); dashed: pure iron-oxide powder of 2.5 µm particles; solid: 98 wt% quartz + 2 wt% iron oxide as "
        "separate 2.5 µm particles. Grey: USGS measurements where the library has them.",
        "",
        "| spectrum | " + " | ".join(f"ρ {lam:g}" for lam in keep) + " |",
        "|---|" + "---|" * len(keep),
    ]

    def row(name, r):
        return f"| {name} | " + " | ".join(f"{r.values[i]:.3f}" for i in idx) + " |"

    lines.append(row("pure quartz", spectra["quartz"]))
    for mineral in ("hematite", "goethite"):
        lines.append(row(f"pure {mineral}", spectra[mineral]["powder"]))
        lines.append(row(f"98/2 quartz + {mineral}", spectra[mineral]["mixture"]))
    return "\n".join(lines)


def write_report(
    path,
    results: Sequence[ValidationResult],
    *,
    figure_paths: Sequence,
    command: str,
    variants: Sequence[ValidationResult] | None = None,
    figure3_path=None,
    figure3: dict | None = None,
) -> None:
    """Writes the validation report (Markdown), atomically.

    If ``path`` already holds a report with ``<!-- BEGIN validation:… -->`` /
    ``<!-- END validation:… -->`` blocks, only those blocks are replaced and any hand-written
    text around them (a discussion) is kept; otherwise a new report is written with the sections
    How to reproduce, Results, Spectra, Diagnostic variants and the paper's Figure 3.

    Parameters
    ----------
    path : str or os.PathLike
        The Markdown file.
    results : sequence of ValidationResult
        From :func:`validate`.
    figure_paths : sequence of path
        The PNG of each result, in the same order (linked relative to the report).
    command : str
        The command that produced the report, shown verbatim.
    variants : sequence of ValidationResult, optional
        From :func:`run_variants`.
    figure3_path : path, optional
        The PNG of :func:`plot_figure3`; ``figure3`` the spectra it shows.
    """
    from sandlight.io import atomic_path

    if len(figure_paths) != len(results):
        raise ParameterError("figure_paths", len(figure_paths), f"one path per result ({len(results)})")
    path = Path(path)
    report_dir = path.parent.resolve()
    fig_paths = [Path(p).resolve() for p in figure_paths]
    bodies = {
        "command": f"```\n{command}\n```",
        "results": _results_block(results),
        "figures": _figures_block(results, fig_paths, report_dir),
        "variants": _variants_block(variants, results),
        "figure3": _figure3_block(Path(figure3_path).resolve() if figure3_path else None, report_dir, figure3),
    }
    existing = path.read_text(encoding="utf-8") if path.is_file() else ""
    if existing and all(re.search(_BLOCK_RE.format(name=n), existing, re.S) for n in REPORT_BLOCKS):
        text = existing
        for name, body in bodies.items():
            text = re.sub(_BLOCK_RE.format(name=name), lambda _m, n=name, b=body: _block(n, b), text, flags=re.S)
    else:
        text = _SKELETON.format(**{n: _block(n, b) for n, b in bodies.items()})
    with atomic_path(path) as tmp:
        Path(tmp).write_text(text, encoding="utf-8")
