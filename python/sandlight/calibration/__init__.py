"""Calibration of effective optical constants on pure end-member powders (issue 17 §1).

Public objects
--------------
EndMember, end_members, measured_reflectance, MEASUREMENT_SIGMA
    The inventory of pure powders (``sandlight/data/calibration/end_members.toml``) and their
    measured USGS spectra (:mod:`sandlight.calibration.end_members`).
EnginePowder, with_trial_k
    The forward model: the engine's powder of one mineral with a trial k, and the optical
    constants it uses (:mod:`sandlight.calibration.forward`).
ReflectanceTable, tabulate
    ρ(λᵢ, kⱼ) per end-member on a log-spaced k grid, restartable (:mod:`.tables`).
KFit, holdout
    The penalised least-squares fit of log10 k(λ) and the hold-out check (:mod:`.fit`).
literature_k, goethite_literature_k, quartz_literature_k, LITERATURE_MINERALS
    Weak literature priors on log10 k (:mod:`.priors`).
synthetic_spectra, edge_and_band_log10_k
    Synthetic spectra at a known k(λ), for the round trip (:mod:`.synthetic`).
identifiability, markdown_residuals, markdown_identifiability, plot_calibration, write_k_table
    Reports (:mod:`.report`).
with_calibrated_k
    Optical constants with the calibrated k of some minerals, for runs before it is shipped
    (:mod:`.constants`).

The method, its assumptions and the first results are in docs/optical-constants.md
("Calibration on pure end-members"); the command is ``scripts/data/calibrate_optical_constants.py``.
"""

from sandlight.calibration import report
from sandlight.calibration.constants import with_calibrated_k
from sandlight.calibration.end_members import MEASUREMENT_SIGMA, EndMember, end_members, measured_reflectance
from sandlight.calibration.fit import KFit, holdout
from sandlight.calibration.forward import EnginePowder, with_trial_k
from sandlight.calibration.priors import LITERATURE_MINERALS, goethite_literature_k, literature_k, quartz_literature_k
from sandlight.calibration.report import *  # noqa: F403 - the names of report.__all__, listed there once
from sandlight.calibration.synthetic import edge_and_band_log10_k, synthetic_spectra
from sandlight.calibration.tables import ReflectanceTable, tabulate

__all__ = [
    "EndMember",
    "end_members",
    "measured_reflectance",
    "MEASUREMENT_SIGMA",
    "EnginePowder",
    "with_trial_k",
    "ReflectanceTable",
    "tabulate",
    "KFit",
    "holdout",
    "literature_k",
    "goethite_literature_k",
    "quartz_literature_k",
    "LITERATURE_MINERALS",
    "synthetic_spectra",
    "edge_and_band_log10_k",
    "with_calibrated_k",
    *report.__all__,
]
