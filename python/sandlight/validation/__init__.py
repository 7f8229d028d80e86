"""Validation of the model against measured reflectance spectra (issue 3 §3).

The model is run, with the shipped optical constants and the shipped presets, for laboratory
samples whose reflectance the USGS Spectral Library measured. Each preset was set from the
sample's written description, never fitted to its spectrum; the comparison is therefore a test
of the physics and the optical constants, not of a fit.

Modules
-------
scoring
    The model grid, the measurement brought to it (``measured_on_grid``), the error per band
    with its Monte Carlo error bar (``band_error``), ``ValidationResult``. Its docstring says how
    a grid is compared with a measured spectrum and how the error bars are bounded.
samples
    The validation samples (``SAMPLES``: USGS spectrum, preset, what the description says) and
    ``validate``, which runs the model for them and scores it; any Traceable medium can be
    validated as a ``ValidationSample(..., medium=...)``.
variants
    What-if runs, one physical change at a time (``Variant``, ``DIAGNOSTIC_VARIANTS``,
    ``run_variants``), used to find the cause of a miss.
figure3
    The paper's Figure 3 from the model: quartz vs iron oxide vs the 98/2 mixture
    (``figure3_spectra``, ``plot_figure3``), with ``powder_reflectance`` for the pure iron oxide
    (a :class:`sandlight.physics.powder.Powder`).
report
    ``write_report``: writes (or updates) the Markdown report ``docs/validation.md``.

Every public name of these modules is also importable from ``sandlight.validation``.
"""

from sandlight.validation.figure3 import (
    FIGURE3_MEASURED,
    FIGURE3_PARTICLE_UM,
    figure3_spectra,
    plot_figure3,
    powder_reflectance,
)
from sandlight.validation.report import REPORT_BLOCKS, write_report
from sandlight.validation.samples import SAMPLES, ValidationSample, run_and_score, sample_by_name, validate
from sandlight.validation.scoring import (
    BANDS_NM,
    HALF_WINDOW_NM,
    MAX_GAP_NM,
    TARGET_RMS,
    BandError,
    ValidationResult,
    band_error,
    default_wavelengths_nm,
    measured_on_grid,
    model_wavelengths_nm,
    score,
)
from sandlight.validation.variants import DIAGNOSTIC_VARIANTS, Variant, run_variants

__all__ = [
    "SAMPLES",
    "TARGET_RMS",
    "BANDS_NM",
    "HALF_WINDOW_NM",
    "MAX_GAP_NM",
    "ValidationSample",
    "BandError",
    "ValidationResult",
    "default_wavelengths_nm",
    "model_wavelengths_nm",
    "measured_on_grid",
    "band_error",
    "score",
    "sample_by_name",
    "run_and_score",
    "validate",
    "Variant",
    "DIAGNOSTIC_VARIANTS",
    "run_variants",
    "powder_reflectance",
    "FIGURE3_PARTICLE_UM",
    "FIGURE3_MEASURED",
    "figure3_spectra",
    "plot_figure3",
    "REPORT_BLOCKS",
    "write_report",
]
