"""The measured samples of the validation, and running the model for them.

Public objects
--------------
ValidationSample, SAMPLES
    A USGS spectrum with the preset set from the sample's written description (or any medium);
    the validation samples.
sample_by_name
    A validation sample by its name, spectrum stem or preset.
run_and_score
    Traces a medium and scores it against a sample's measurement.
validate
    Runs the model for the validation samples and scores it: a list of ``ValidationResult``.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy.typing as npt

from sandlight.errors import ParameterError
from sandlight.validation.scoring import ValidationResult, model_wavelengths_nm, score

if TYPE_CHECKING:
    import xarray as xr

    from sandlight.physics.medium import Traceable

__all__ = ["ValidationSample", "SAMPLES", "sample_by_name", "run_and_score", "validate"]


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
        The :meth:`sandlight.SandSample.preset` set from the sample description; with
        ``medium``, the sample's short name in labels and file names.
    description : str
        What the USGS description says about the sample.
    medium : Traceable, optional
        What to trace instead of the preset (any ``sandlight.physics.medium.Traceable``, e.g.
        a ``sandlight.physics.powder.Powder`` for a pure mineral).
    """

    name: str
    spectrum: str
    preset: str
    description: str
    medium: Traceable | None = None

    @property
    def label(self) -> str:
        """What is traced, for tables: ``"preset <preset>"``, or the medium's type and the short name."""
        return f"preset {self.preset}" if self.medium is None else f"{type(self.medium).__name__} {self.preset}"

    def traced(self) -> Traceable:
        """The medium traced for this sample: ``medium``, or the preset on the fly."""
        from sandlight.physics.media import as_traceable

        return self.medium if self.medium is not None else as_traceable(self.preset)

    def measured_spectrum(self) -> xr.DataArray:
        """The measured reflectance (``sandlight.measured.read_usgs`` of the shipped library)."""
        from sandlight.measured import read_usgs, usgs_library

        return read_usgs(usgs_library(self.spectrum))


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


def sample_by_name(name: str) -> ValidationSample:
    """The sample of :data:`SAMPLES` with this name, spectrum stem or preset name."""
    for s in SAMPLES:
        if name in (s.name, s.spectrum, s.preset):
            return s
    raise ParameterError("samples", name, "names of validation samples: " + ", ".join(s.name for s in SAMPLES))


def run_and_score(
    sample: ValidationSample,
    traced: Traceable,
    label: str,
    spectrum: xr.DataArray,
    *,
    rays: int,
    wavelengths_nm: npt.ArrayLike,
    seed: int = 0,
    progress: bool = False,
) -> ValidationResult:
    """Traces ``traced`` at normal incidence (:func:`sandlight.reflectance`) and scores it against
    ``spectrum``, the measurement of ``sample`` (:func:`sandlight.validation.scoring.score`)."""
    from sandlight.engine import reflectance

    start = time.perf_counter()
    result = reflectance(traced, wavelengths_nm, rays=rays, seed=seed, progress=progress)
    return score(sample, label, result, spectrum, elapsed_s=time.perf_counter() - start)


def validate(
    samples: Sequence[str | ValidationSample] | None = None,
    *,
    rays: int,
    wavelengths_nm: npt.ArrayLike | None = None,
    seed: int = 0,
    progress: bool = False,
) -> list[ValidationResult]:
    """Runs the model for measured samples and scores it against their spectra.

    Parameters
    ----------
    samples : sequence of str or ValidationSample, optional
        Names of :data:`SAMPLES` (sample name, spectrum stem or preset name), or samples of
        one's own (e.g. with a ``medium``); default all of :data:`SAMPLES`.
    rays : int
        Rays per wavelength (≥ 1).
    wavelengths_nm : array_like, optional
        Model wavelengths in nm within [350, 2500]; default
        :func:`~sandlight.validation.scoring.default_wavelengths_nm`. Each band of
        :data:`~sandlight.validation.scoring.BANDS_NM` needs at least one of them.
    seed : int
        Master seed of the Monte Carlo engine.
    progress : bool
        Show the engine's progress bars.

    Returns
    -------
    list of ValidationResult
        One per sample, each with RMS and maximum absolute errors per band and their Monte
        Carlo error bars. Plot with :meth:`ValidationResult.plot`; report with
        :func:`sandlight.validation.report.write_report`.
    """
    if samples is None:
        chosen = SAMPLES
    else:
        chosen = tuple(s if isinstance(s, ValidationSample) else sample_by_name(s) for s in samples)
    wl = model_wavelengths_nm(wavelengths_nm)
    return [
        run_and_score(
            s, s.traced(), s.label, s.measured_spectrum(), rays=rays, wavelengths_nm=wl, seed=seed, progress=progress
        )
        for s in chosen
    ]
