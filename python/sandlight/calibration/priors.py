"""Weak literature priors on log10 k(λ) for the calibration (issue 17 §1).

Public objects
--------------
literature_k
    The literature k(λ) of a mineral: the calibration's prior, or its reports' reference.
goethite_literature_k
    Goethite: a charge-transfer edge and two crystal-field bands placed where the literature
    puts them, with magnitudes of the quoted order.
quartz_literature_k
    The absorption of natural quartz grains as a power law in wavelength.

Why a prior. Where no end-member powder constrains k (all opaque, or all transparent), the fit's
curvature penalty alone sets it, and a penalty interpolates straight lines in log k across the
gap: for goethite below ~490 nm, where every powder is opaque, the penalty alone carried k down
to 0.06, ten times below the charge-transfer absorption every goethite study reports. A weak
prior (σ = 1 decade by default, :class:`sandlight.calibration.KFit`) decides k only there; where
a powder sees k, the data outweigh it by orders of magnitude. The curves here were the shipped
PROVISIONAL tables before the calibration replaced them (scripts/data/build_optical_tables.py
still uses the goethite curve for the shape of goethite's n dispersion, so that n — and the
calibration tables' cache keys — stay as they were).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from sandlight.errors import ParameterError

__all__ = ["literature_k", "goethite_literature_k", "quartz_literature_k", "LITERATURE_MINERALS"]

HC_EV_NM = 1239.84198  # h c in eV nm: photon energy E = HC_EV_NM / λ
LAMBDA_MAX_NM = 2500.0

# Goethite k(E), E = photon energy in eV. Terms, with the band assignments of Sherman & Waite
# (1985) and band positions of Scheinost et al. (1998):
#   edge: Fe3+ ligand-to-metal charge transfer plus the 6A1+6A1 -> 4T1+4T1 pair excitation
#         (~480 nm) make a strong absorption edge; a logistic step in energy of height 0.6,
#         centre 2.39 eV (519 nm) and width 0.08 eV puts k(550 nm) at ~0.09 (Bedidi & Cervelle
#         1993, as quoted by Conny et al. 2017), an edge ~80 nm bluer than hematite's (Querry);
#   4T2:  6A1 -> 4T2 crystal-field band at 1.91 eV (~650 nm), Gaussian, peak 1.5e-3;
#   4T1:  6A1 -> 4T1 crystal-field band at 1.34 eV (~925 nm), Gaussian, peak 2.5e-3;
#   OH:   the wing of the strong O-H stretching band near 3 µm, 1e-3 at 2500 nm, e-folding 150 nm;
#   floor 1.5e-4.
# References: D. M. Sherman, T. D. Waite, Am. Mineral. 70, 1262-1269 (1985); A. C. Scheinost et
# al., Clays Clay Miner. 46, 528-536 (1998); A. Bedidi, B. Cervelle, J. Geophys. Res. 98(B7),
# 11941-11952 (1993); R. A. Conny et al., J. Geophys. Res. Atmos. 122 (2017),
# doi:10.1002/2017JD026488.
GOETHITE_EDGE_K, GOETHITE_EDGE_EV, GOETHITE_EDGE_WIDTH_EV = 0.6, 2.39, 0.08
GOETHITE_BANDS = ((1.5e-3, 1.91, 0.12), (2.5e-3, 1.34, 0.15))  # (peak k, centre eV, sigma eV)
GOETHITE_OH_K_2500, GOETHITE_OH_EFOLD_NM = 1.0e-3, 150.0
GOETHITE_K_FLOOR = 1.5e-4

# Natural quartz grains absorb through trace Fe3+, Ti and fluid/mineral inclusions; optical-grade
# quartz has k < ~1e-8 in the visible. The prior takes α = 0.1 /cm at 550 nm, the upper end of
# the 0.01-0.1 /cm expected for such grains, rising to the UV as α ∝ λ^-3.566 (the exponent with
# which this law met Crystran's ordinary-ray k at 1270 nm in the former provisional table).
QUARTZ_ALPHA_550_PER_CM = 0.1
QUARTZ_ALPHA_EXPONENT = 3.566


def _wavelengths(wavelength_nm: ArrayLike) -> np.ndarray:
    try:
        wl = np.asarray(wavelength_nm, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError("wavelength_nm", wavelength_nm, "wavelengths in nm, finite and > 0") from None
    if not np.all(np.isfinite(wl) & (wl > 0)):
        raise ParameterError("wavelength_nm", wavelength_nm, "wavelengths in nm, finite and > 0")
    return wl


def goethite_literature_k(wavelength_nm: ArrayLike) -> np.ndarray:
    """Literature k of goethite at vacuum wavelengths (nm): the parameter block above."""
    wl = _wavelengths(wavelength_nm)
    energy = HC_EV_NM / wl
    k = GOETHITE_EDGE_K / (1.0 + np.exp(-(energy - GOETHITE_EDGE_EV) / GOETHITE_EDGE_WIDTH_EV))
    for peak, centre, sigma in GOETHITE_BANDS:
        k = k + peak * np.exp(-0.5 * ((energy - centre) / sigma) ** 2)
    k = k + GOETHITE_OH_K_2500 * np.exp((wl - LAMBDA_MAX_NM) / GOETHITE_OH_EFOLD_NM)
    return k + GOETHITE_K_FLOOR


def quartz_literature_k(wavelength_nm: ArrayLike) -> np.ndarray:
    """Literature k of natural quartz grains: α = 0.1 /cm (550 nm/λ)^3.566, k = αλ/(4π)."""
    wl = _wavelengths(wavelength_nm)
    alpha_per_cm = QUARTZ_ALPHA_550_PER_CM * (550.0 / wl) ** QUARTZ_ALPHA_EXPONENT
    return alpha_per_cm * wl * 1e-7 / (4.0 * math.pi)


_PRIORS = {"goethite": goethite_literature_k, "quartz": quartz_literature_k}
#: Minerals with a literature k (a prior, or the reference the reports compare with).
LITERATURE_MINERALS = tuple(sorted(_PRIORS))


def literature_k(mineral: str, wavelength_nm: ArrayLike) -> np.ndarray:
    """The literature k(λ) of ``mineral`` (one of :data:`LITERATURE_MINERALS`) at ``wavelength_nm``."""
    if mineral not in _PRIORS:
        raise ParameterError("mineral", mineral, "one with a literature prior: " + ", ".join(LITERATURE_MINERALS))
    return _PRIORS[mineral](wavelength_nm)
