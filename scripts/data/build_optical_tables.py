#!/usr/bin/env python3
"""Regenerate sandlight's shipped optical-constant tables from the shared source data.

Reads the refractiveindex.info conversions in ``<shared>/data/optical/csv`` (CC0) and writes
``python/sandlight/data/optical/<material>.csv`` for quartz, hematite, goethite, magnetite,
kaolinite and water. Running it twice gives byte-identical files; ``tests/test_optics.py`` checks
that the shipped tables are exactly what this script produces.

The minerals in ``CALIBRATED`` (the quartz host of natural sand grains and goethite) have an
effective k derived by calibration on their pure end-member powders (issue 17 §1):
``docs/calibration/<mineral>/<mineral>-k.csv``, the output of
``scripts/data/calibrate_optical_constants.py``, interpolated log-linearly onto the 5 nm grid
(docs/optical-constants.md). The shipped tables take it for the minerals in
``SHIPPED_CALIBRATED`` (all of ``CALIBRATED``; the predictor bank is trained with it);
``build_all(src, calibrated=())`` builds the PROVISIONAL literature k below instead (quartz:
Crystran plus a power law; goethite: ``sandlight.calibration.priors``), kept for comparison
(``scripts/studies/preset_chroma.py``). Either way n is the same (measured for quartz; for goethite the Handbook
dispersion, converted with the literature k, so that n — and with it the calibration's cached
tables — stay as they were). Kaolinite's k is PROVISIONAL, defined below with its
justification.

Usage::

    python3 scripts/data/build_optical_tables.py                # write the tables
    python3 scripts/data/build_optical_tables.py --check        # exit 1 if shipped tables differ
    python3 scripts/data/build_optical_tables.py --report       # cross-check tables (Markdown)
    python3 scripts/data/build_optical_tables.py --plot         # docs/img/optical-constants.png

``--source DIR`` points at the shared ``data/optical`` folder (default: found by walking up
from the repository to a ``shared/data/optical`` folder).
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from sandlight.calibration import priors
from sandlight.calibration.priors import goethite_literature_k
from sandlight.calibration.report import read_k_table

REPO = Path(__file__).resolve().parents[2]
CALIBRATION_DIR = REPO / "docs" / "calibration"
#: Minerals with a calibrated k: their calibration output (CalibratedK) exists.
CALIBRATED = ("quartz", "goethite")
#: The calibrated minerals whose *shipped* table takes that k: all of them. The shipped predictor
#: bank is trained with these tables (scripts/data/train_default_spectral.py); changing this
#: tuple means retraining it (docs/optical-constants.md).
SHIPPED_CALIBRATED: tuple[str, ...] = CALIBRATED
OUT_DIR = REPO / "python" / "sandlight" / "data" / "optical"
PLOT_PATH = REPO / "docs" / "img" / "optical-constants.png"

LAMBDA_MIN_NM = 350.0
LAMBDA_MAX_NM = 2500.0
GRID_5NM = np.arange(350.0, 2500.0 + 0.5, 5.0)
SODIUM_D_NM = 589.3  # wavelength at which mineralogical indices are quoted (Na D line)
HC_EV_NM = 1239.84198  # h c in eV nm: photon energy E = HC_EV_NM / lambda

RII_COMMIT = "ff11b5897ef0754b15d939d921eb6c745693cbd1"
RII_ORIGIN = (
    f"refractiveindex.info database, GitHub polyanskiy/refractiveindex.info-database, "
    f"commit {RII_COMMIT} (2026-06-14), database/data/"
)
RII_LICENCE = "CC0 1.0 (refractiveindex.info database: public domain dedication)"
UNITS = (
    "wavelength_nm = wavelength in vacuum [nm]; n, k dimensionless, complex index m = n + i k; "
    "absorption coefficient alpha = 4 pi k / lambda"
)
BUILT_BY = "scripts/data/build_optical_tables.py (sandlight); do not edit by hand"
# Licence of values that sandlight itself computed (provisional parameterisations, averages).
SANDLIGHT_LICENCE = "MIT (sandlight project) for the provisional parameterisation"


@dataclass
class Table:
    """One material's table: ordered header entries and the columns."""

    material: str
    header: list[tuple[str, str]]
    wavelength_nm: np.ndarray
    n: np.ndarray
    k: np.ndarray


# --------------------------------------------------------------------------------------------
# Source readers and interpolation
# --------------------------------------------------------------------------------------------


def read_source_csv(path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Read a shared ``csv/*.csv`` file (``wavelength_nm,n,k``; blank cell = not given -> NaN).

    Exact duplicate rows (the Querry 1985 e-ray table lists 1950 nm twice) are dropped; any
    other repeated or decreasing wavelength is an error.
    """
    rows = []
    with open(path, encoding="utf-8") as f:
        for line in f:
            line = line.strip()
            if not line or line.startswith("#") or line.startswith("wavelength"):
                continue
            fields = line.split(",")
            rows.append(tuple(float(x) if x else math.nan for x in fields[:3]))
    deduplicated = [r for i, r in enumerate(rows) if i == 0 or not _same_row(r, rows[i - 1])]
    data = np.array(deduplicated, dtype=float)
    if np.any(np.diff(data[:, 0]) <= 0):
        raise ValueError(f"{path}: wavelengths are not strictly increasing")
    return data[:, 0], data[:, 1], data[:, 2]


def _same_row(a, b) -> bool:
    return all((x == y) or (math.isnan(x) and math.isnan(y)) for x, y in zip(a, b))


def interp_linear(x_new, x, y):
    """Linear interpolation, NaN outside the source range (never extrapolates)."""
    return np.interp(x_new, x, y, left=np.nan, right=np.nan)


def interp_loglinear(x_new, x, y):
    """Interpolation linear in log(y): the same rule sandlight.optics uses for k > 0."""
    return np.exp(np.interp(x_new, x, np.log(y), left=np.nan, right=np.nan))


@dataclass(frozen=True)
class CalibratedK:
    """A mineral's k derived by calibration: ``docs/calibration/<m>/<m>-k.csv``, the output of
    scripts/data/calibrate_optical_constants.py (``# key: value`` header, ``wavelength_nm,n,k``)."""

    mineral: str
    path: Path
    header: dict[str, str]
    wavelength_nm: np.ndarray
    k: np.ndarray

    @classmethod
    def read(cls, mineral: str, directory: Path = CALIBRATION_DIR) -> CalibratedK:
        path = directory / mineral / f"{mineral}-k.csv"
        header, wavelength_nm, _, k = read_k_table(path)
        if header.get("material") != mineral or wavelength_nm[0] > LAMBDA_MIN_NM or wavelength_nm[-1] < LAMBDA_MAX_NM:
            raise ValueError(f"{path}: not a calibrated k table of {mineral} covering 350-2500 nm")
        return cls(mineral, path, header, wavelength_nm, k)

    def on(self, grid: np.ndarray) -> np.ndarray:
        """k on ``grid``, interpolated linearly in log k (the rule sandlight.optics uses)."""
        return interp_loglinear(grid, self.wavelength_nm, self.k)

    @property
    def status(self) -> str:
        return self.header["status"]

    @property
    def source(self) -> str:
        return self.header["source"]

    @property
    def licence(self) -> str:
        return self.header["licence"]

    @property
    def origin(self) -> str:
        return f"{self.path.relative_to(REPO)} (inputs: {self.header['origin']})"

    def method_lines(self) -> list[tuple[str, str]]:
        return [
            ("method", f"k: calibration, {self.header['method']}"),
            (
                "method",
                f"k: from the calibration grid ({self.header['sampling'].removeprefix('the calibration grid, ')}), "
                "log-linear interpolation onto the 5 nm grid",
            ),
        ]


def bracket(wavelength_nm: np.ndarray) -> np.ndarray:
    """Mask of the source points that cover [350, 2500] nm: all points inside plus the nearest
    point outside on each side, so that interpolation reaches both ends without extrapolating."""
    inside = (wavelength_nm >= LAMBDA_MIN_NM) & (wavelength_nm <= LAMBDA_MAX_NM)
    lo = np.searchsorted(wavelength_nm, LAMBDA_MIN_NM, side="right") - 1
    hi = np.searchsorted(wavelength_nm, LAMBDA_MAX_NM, side="left")
    if lo < 0 or hi >= wavelength_nm.size:
        raise ValueError("source table does not cover 350-2500 nm")
    inside[lo] = True
    inside[hi] = True
    return inside


def gaussian(x, centre, sigma):
    return np.exp(-0.5 * ((x - centre) / sigma) ** 2)


# --------------------------------------------------------------------------------------------
# Quartz
# --------------------------------------------------------------------------------------------

# PROVISIONAL absorption of natural quartz grains in 350-1270 nm, where no measured k exists
# (Crystran gives k only from 1270 nm; optical-grade quartz has k < ~1e-8 there). Natural sand
# grains absorb through trace Fe3+, Ti and fluid/mineral inclusions; we take an absorption
# coefficient alpha = 0.1 /cm at 550 nm, the upper end of the 0.01-0.1 /cm range expected for
# such grains: a reading of the USGS quartz powder spectra with Hapke's (2012) equivalent-slab
# model gives apparent values near 1 /cm even for very pure crystal quartz, so the lower end
# would be implausibly transparent. alpha rises toward the UV as a power law
# alpha = alpha_550 (550/lambda)^p, with p fixed so that alpha joins Crystran's first tabulated
# value at 1270 nm continuously. The calibration on the pure quartz powders (CALIBRATED) replaces
# this in the shipped table.
QUARTZ_ALPHA_550_PER_CM = 0.1
QUARTZ_JOIN_NM = 1270.0


def literature_quartz_k(src: Path, grid: np.ndarray) -> tuple[np.ndarray, float]:
    """Crystran's k from 1270 nm, the PROVISIONAL power law below (see the block above); and
    the power law's exponent."""
    w_c, _, k_c = read_source_csv(src / "csv" / "quartz_SiO2_Crystran_o_nk.csv")
    has_k = np.isfinite(k_c) & (k_c > 0)
    w_k, k_k = w_c[has_k], k_c[has_k]
    in_ir = grid >= QUARTZ_JOIN_NM
    k = np.empty_like(grid)
    k[in_ir] = interp_loglinear(grid[in_ir], w_k, k_k)
    k_join = float(interp_loglinear(QUARTZ_JOIN_NM, w_k, k_k))
    alpha_join = 4.0 * math.pi * k_join / (QUARTZ_JOIN_NM * 1e-7)  # per cm
    exponent = math.log(QUARTZ_ALPHA_550_PER_CM / alpha_join) / math.log(QUARTZ_JOIN_NM / 550.0)
    alpha = QUARTZ_ALPHA_550_PER_CM * (550.0 / grid[~in_ir]) ** exponent  # per cm
    k[~in_ir] = alpha * grid[~in_ir] * 1e-7 / (4.0 * math.pi)
    return k, exponent


def build_quartz(src: Path, calibrated: bool = "quartz" in SHIPPED_CALIBRATED) -> Table:
    csv = src / "csv"
    w_ro, n_ro, _ = read_source_csv(csv / "quartz_SiO2_Radhakrishnan1951_o.csv")
    w_re, n_re, _ = read_source_csv(csv / "quartz_SiO2_Radhakrishnan1951_e.csv")
    w_go, n_go, _ = read_source_csv(csv / "quartz_SiO2_Ghosh1999_o.csv")
    w_ge, n_ge, _ = read_source_csv(csv / "quartz_SiO2_Ghosh1999_e.csv")

    grid = GRID_5NM
    # Orientation average for randomly oriented uniaxial grains (see docs/optical-constants.md):
    # unpolarised light sees n_o for one polarisation and n_e(theta) ~ n_o cos^2 + n_e sin^2 for
    # the other; averaging over isotropic directions (<sin^2 theta> = 2/3) gives (2 n_o + n_e)/3.
    n_o = interp_linear(grid, w_ro, n_ro)
    n_e = interp_linear(grid, w_re, n_re)
    n = (2.0 * n_o + n_e) / 3.0

    # Agreement of the two dispersion formulas where both are valid (Ghosh stops at 2053 nm).
    both = (grid >= LAMBDA_MIN_NM) & (grid <= w_go.max())
    n_ghosh = (2.0 * interp_linear(grid, w_go, n_go) + interp_linear(grid, w_ge, n_ge)) / 3.0
    max_dn = float(np.max(np.abs(n_ghosh[both] - n[both])))
    if max_dn > 2e-4:
        raise ValueError(f"Ghosh and Radhakrishnan quartz disagree by {max_dn:.1e}")

    if calibrated:
        cal = CalibratedK.read("quartz")
        k = cal.on(grid)
        k_status = cal.status
        k_sources = [cal.source + " [k]"]
        k_origin, k_licence = cal.origin, cal.licence + " [k]"
        k_methods = cal.method_lines()
    else:
        k, exponent = literature_quartz_k(src, grid)
        k_status = (
            "measured (Crystran) in 1270-2500 nm; PROVISIONAL in 350-1270 nm "
            "(natural-grain impurity absorption, to be replaced by the calibrated k)"
        )
        k_sources = [
            "Crystran Ltd., The Crystran handbook of infra-red and ultra-violet optical "
            "materials, 5th ed. (2023) [k, ordinary ray, 1270-2500 nm]"
        ]
        k_origin, k_licence = "specs/crystran/optical/quartz-o.yml", SANDLIGHT_LICENCE + " of k in 350-1270 nm"
        k_methods = [
            (
                "method",
                "k >= 1270 nm: Crystran ordinary-ray k, log-linear interpolation onto the grid, used for both rays",
            ),
            (
                "method",
                f"k < 1270 nm PROVISIONAL: alpha = {QUARTZ_ALPHA_550_PER_CM} /cm * "
                f"(550 nm/lambda)^{exponent:.3f}, the exponent making alpha continuous with "
                f"Crystran at 1270 nm; k = alpha lambda/(4 pi)",
            ),
        ]

    header = [
        ("material", "quartz"),
        ("description", "alpha-quartz SiO2 (uniaxial positive), randomly oriented natural grains"),
        ("status", "n: measured. k: " + k_status),
        (
            "source",
            "T. Radhakrishnan, Further studies on the temperature variation of the refractive "
            "index of crystals, Proc. Indian Acad. Sci. A 31, 22-34 (1951), "
            "doi:10.1007/BF03172255; and The dispersion, birefringence and optical activity "
            "of quartz, Proc. Indian Acad. Sci. A 25, 260-265 (1947), doi:10.1007/BF03171408 "
            "[n_o, n_e, 18 C]",
        ),
        *(("source", text) for text in k_sources),
        (
            "source",
            "cross-check: G. Ghosh, Dispersion-equation coefficients for the refractive index "
            "and birefringence of calcite and quartz crystals, Opt. Commun. 163, 95-102 "
            "(1999), doi:10.1016/S0030-4018(99)00091-7",
        ),
        (
            "origin",
            RII_ORIGIN + "main/SiO2/nk/Radhakrishnan-o.yml, Radhakrishnan-e.yml, "
            "Ghosh-o.yml, Ghosh-e.yml [n]; " + k_origin,
        ),
        ("licence", RII_LICENCE + " [n]; " + k_licence),
        ("units", UNITS),
        ("sampling", "5 nm grid, 350-2500 nm"),
        (
            "method",
            "n = (2 n_o + n_e)/3, orientation average for randomly oriented grains; "
            "Radhakrishnan formula evaluated on the 5 nm grid; birefringence n_e - n_o = "
            f"{np.min(n_e - n_o):.4f}-{np.max(n_e - n_o):.4f} over the range",
        ),
        ("method", f"Ghosh 1999 agrees with Radhakrishnan within {max_dn:.1e} in n over 350-2050 nm"),
        *k_methods,
        ("built_by", BUILT_BY),
    ]
    return Table("quartz", header, grid, n, k)


# --------------------------------------------------------------------------------------------
# Hematite (Querry 1985, Longtin 1988) and magnetite (Querry 1985)
# --------------------------------------------------------------------------------------------

QUERRY_1985 = (
    "M. R. Querry, Optical constants, Contractor Report CRDC-CR-85034, US Army "
    "Chemical Research and Development Center, Aberdeen Proving Ground (1985), "
    "https://apps.dtic.mil/sti/citations/ADA158623"
)


LONGTIN_1988 = (
    "D. R. Longtin, E. P. Shettle, J. R. Hummel, J. D. Pryce, A wind dependent desert "
    "aerosol model: radiative properties, Air Force Geophysics Laboratory report "
    "AFGL-TR-88-0112 (1988)"
)
ARIA_ORIGIN = (
    "ARIA (Aerosol Refractive Index Archive, University of Oxford EODG) as bundled in the "
    "PyPI package srfm, GitHub eodg-oxford/srfm, commit "
    "f8841cd3e64675c45448590892b3d15980c51f2d, src/srfm/data/ARIA/"
)
# Where the hematite table switches source: Querry's k up to the end of the charge-transfer
# region, where Querry and Triaud agree within 20 %; Longtin's from its first point beyond the
# absorption edge; between the two, k is log-linear (one straight line in log k).
HEMATITE_QUERRY_UNTIL_NM = 550.0
HEMATITE_LONGTIN_FROM_NM = 633.0


def orientation_average(w_o, v_o, w_e, v_e, grid, log: bool):
    """(2 o + e)/3 on `grid`: for weak absorption the mean absorption coefficient of unpolarised
    light over random orientations is (2 alpha_o + alpha_e)/3; n is averaged the same way."""
    if not log:
        return (2.0 * interp_linear(grid, w_o, v_o) + interp_linear(grid, w_e, v_e)) / 3.0
    # Querry's far-infrared rows (beyond 47 um) have k < 0; they are far outside any grid here.
    o, e = v_o > 0, v_e > 0
    return (2.0 * interp_loglinear(grid, w_o[o], v_o[o]) + interp_loglinear(grid, w_e[e], v_e[e])) / 3.0


def hematite_sources(src: Path, grid=None):
    """The two hematite sources before joining, orientation-averaged: (grid, n Querry,
    k Querry, k Longtin), on Querry's source wavelengths in 350-2500 nm unless ``grid`` (nm) is
    given. Longtin's table starts at 633 nm; below it its first value is repeated."""
    csv = src / "csv"
    w_o, n_o, k_o = read_source_csv(csv / "hematite_Fe2O3_Querry1985_o.csv")
    w_e, n_e, k_e = read_source_csv(csv / "hematite_Fe2O3_Querry1985_e.csv")
    w_lo, _, k_lo = read_source_csv(csv / "hematite_O_Longtin_1988.csv")
    w_le, _, k_le = read_source_csv(csv / "hematite_E_Longtin_1988.csv")
    grid = w_o[bracket(w_o)] if grid is None else np.asarray(grid, dtype=float)
    # The Querry e-ray table has no 1930 nm row (it lists 1950 nm twice); interpolating it onto
    # the o-ray wavelengths fills that one point and is the identity everywhere else.
    n = orientation_average(w_o, n_o, w_e, n_e, grid, log=False)
    k_querry = orientation_average(w_o, k_o, w_e, k_e, grid, log=True)
    k_longtin = orientation_average(w_lo, k_lo, w_le, k_le, np.clip(grid, w_lo[0], None), log=True)
    return grid, n, k_querry, k_longtin


def build_hematite(src: Path) -> Table:
    grid, n, k_querry, k_longtin = hematite_sources(src)
    # Querry's k beyond the edge (0.02-0.04 in the near-infrared) comes from the reflectance of
    # pressed pellets, where scattering losses read as absorption; the hematite grain-size
    # series (GDS69) and the transparency of hematite powders beyond 1000 nm say it is 20-3000
    # times too high (docs/optical-constants.md). Longtin's k is used there instead.
    _, _, (k_a,), _ = hematite_sources(src, [HEMATITE_QUERRY_UNTIL_NM])
    _, _, _, (k_b,) = hematite_sources(src, [HEMATITE_LONGTIN_FROM_NM])
    t = (grid - HEMATITE_QUERRY_UNTIL_NM) / (HEMATITE_LONGTIN_FROM_NM - HEMATITE_QUERRY_UNTIL_NM)
    k_edge = k_a * (k_b / k_a) ** np.clip(t, 0.0, 1.0)
    k = np.where(
        grid <= HEMATITE_QUERRY_UNTIL_NM, k_querry, np.where(grid >= HEMATITE_LONGTIN_FROM_NM, k_longtin, k_edge)
    )
    header = [
        ("material", "hematite"),
        ("description", "alpha-Fe2O3 (uniaxial), randomly oriented grains"),
        ("status", "measured (two sources joined across the absorption edge)"),
        ("source", QUERRY_1985 + " [hematite, ordinary and extraordinary rays: n at all wavelengths, k up to 550 nm]"),
        ("source", LONGTIN_1988 + " [hematite, ordinary and extraordinary rays: k from 633 nm]"),
        ("origin", RII_ORIGIN + "main/Fe2O3/nk/Querry-o.yml, Querry-e.yml"),
        ("origin", ARIA_ORIGIN + "Minerals/Hematite/o-ray_(Longtin_et_al._1988), e-ray_(Longtin_et_al._1988)"),
        ("licence", RII_LICENCE + " for Querry; MIT (srfm package, which bundles ARIA) for Longtin"),
        ("units", UNITS),
        ("sampling", "Querry's source points, 10 nm, 350-2500 nm"),
        (
            "method",
            "n = (2 n_o + n_e)/3 and k = (2 k_o + k_e)/3: orientation average for randomly "
            "oriented grains (exact for the mean absorption coefficient when absorption is "
            "weak); k interpolated linearly in log k",
        ),
        (
            "method",
            f"k: Querry up to {HEMATITE_QUERRY_UNTIL_NM:g} nm, Longtin from "
            f"{HEMATITE_LONGTIN_FROM_NM:g} nm, log-linear between the two end values",
        ),
        ("built_by", BUILT_BY),
    ]
    return Table("hematite", header, grid, n, k)


def build_magnetite(src: Path) -> Table:
    w, n, k = read_source_csv(src / "csv" / "magnetite_Fe3O4_Querry1985.csv")
    keep = bracket(w)
    header = [
        ("material", "magnetite"),
        ("description", "Fe3O4 (cubic, optically isotropic)"),
        ("status", "measured"),
        ("source", QUERRY_1985 + " [magnetite]"),
        ("origin", RII_ORIGIN + "main/Fe3O4/nk/Querry.yml"),
        ("licence", RII_LICENCE),
        ("units", UNITS),
        ("sampling", "source points, 10 nm, 350-2500 nm"),
        ("method", "source values unchanged (isotropic: no orientation averaging)"),
        ("built_by", BUILT_BY),
    ]
    return Table("magnetite", header, w[keep], n[keep], k[keep])


# --------------------------------------------------------------------------------------------
# Water (Segelstein 1981)
# --------------------------------------------------------------------------------------------


def build_water(src: Path) -> Table:
    w, n, k = read_source_csv(src / "csv" / "water_H2O_Segelstein1981.csv")
    keep = bracket(w)
    header = [
        ("material", "water"),
        ("description", "liquid water, 25 C"),
        ("status", "measured (compilation)"),
        (
            "source",
            "D. J. Segelstein, The complex refractive index of water, MSc thesis, "
            "University of Missouri-Kansas City (1981), http://hdl.handle.net/10355/11599 "
            "(continuation of G. M. Hale and M. R. Querry, Appl. Opt. 12, 555-563 (1973), "
            "doi:10.1364/AO.12.000555)",
        ),
        ("origin", RII_ORIGIN + "main/H2O/nk/Segelstein.yml"),
        ("licence", RII_LICENCE),
        ("units", UNITS),
        (
            "sampling",
            "source points (3.5-25 nm apart), first point at or below 350 nm to first point at or above 2500 nm",
        ),
        (
            "method",
            "source values unchanged; n and k from one compilation; n differs from "
            "Daimon & Masumura 2007 (20 C) by +0.009 at 350 nm, +0.001 at 550 nm and "
            "-0.004 at 1000 nm; visible k (below ~500 nm) is higher than Pope & Fry 1997, "
            "irrelevant for mm-scale water paths in sand",
        ),
        ("built_by", BUILT_BY),
    ]
    return Table("water", header, w[keep], n[keep], k[keep])


# --------------------------------------------------------------------------------------------
# Goethite: PROVISIONAL
# --------------------------------------------------------------------------------------------

# Refractive indices of goethite (biaxial negative) at the Na D line, Handbook of Mineralogy:
# alpha = 2.260-2.275, beta = 2.393-2.409, gamma = 2.398-2.515. Mean of the range midpoints.
GOETHITE_N_PRINCIPAL = ((2.260 + 2.275) / 2, (2.393 + 2.409) / 2, (2.398 + 2.515) / 2)
GOETHITE_N_589 = sum(GOETHITE_N_PRINCIPAL) / 3.0

# Specular reflectance R1-R2 [%] of polished goethite in air, 400-700 nm, same Handbook entry
# (IMA/COM Quantitative Data File values). Used only for the *shape* of the dispersion.
GOETHITE_R_WAVELENGTH_NM = np.arange(400.0, 700.0 + 1.0, 20.0)
GOETHITE_R1_PERCENT = np.array(
    [17.5, 16.7, 15.9, 15.2, 14.6, 14.1, 13.7, 13.3, 13.0, 12.8, 12.5, 12.4, 12.2, 12.0, 12.0, 11.9]
)
GOETHITE_R2_PERCENT = np.array(
    [19.2, 18.3, 17.4, 16.7, 16.0, 15.5, 15.0, 14.6, 14.3, 14.0, 13.7, 13.5, 13.4, 13.2, 13.1, 13.0]
)
# The dispersion law is fitted where the provisional k is small enough (< 0.15) that the
# reflectance-to-n conversion hardly depends on it; below this wavelength n is held constant.
GOETHITE_N_FIT_FROM_NM = 540.0


def index_from_normal_reflectance(reflectance, k):
    """Real index n from normal-incidence reflectance R in air and k.

    Inverts R = ((n-1)^2 + k^2)/((n+1)^2 + k^2) (Fresnel, normal incidence), i.e. the root n > 1
    of (1-R) n^2 - 2(1+R) n + (1-R)(1+k^2) = 0.
    """
    r = np.asarray(reflectance, dtype=float)
    return ((1 + r) + np.sqrt((1 + r) ** 2 - (1 - r) ** 2 * (1 + k**2))) / (1 - r)


def goethite_dispersion():
    """Single-oscillator Sellmeier n^2 = 1 + S lambda^2/(lambda^2 - lambda0^2) for goethite.

    The Handbook reflectance spectrum gives n_R(lambda) (with the provisional k); scaled so that
    n(589.3 nm) equals the mean mineralogical index, it is fitted for lambda >= 540 nm via the
    linear form 1/(n^2 - 1) = a + b/lambda^2 (a = 1/S, b = -lambda0^2/S). Returns (S, lambda0_nm,
    max_residual).
    """
    lam = GOETHITE_R_WAVELENGTH_NM
    r = (GOETHITE_R1_PERCENT + GOETHITE_R2_PERCENT) / 200.0
    n_r = index_from_normal_reflectance(r, goethite_literature_k(lam))
    n_scaled = n_r * GOETHITE_N_589 / np.interp(SODIUM_D_NM, lam, n_r)
    sel = lam >= GOETHITE_N_FIT_FROM_NM
    design = np.column_stack([np.ones(sel.sum()), 1.0 / lam[sel] ** 2])
    (a, b), *_ = np.linalg.lstsq(design, 1.0 / (n_scaled[sel] ** 2 - 1.0), rcond=None)
    strength, lambda0 = 1.0 / a, math.sqrt(-b / a)
    fitted = np.sqrt(1.0 + strength * lam[sel] ** 2 / (lam[sel] ** 2 - lambda0**2))
    return strength, lambda0, float(np.max(np.abs(fitted - n_scaled[sel])))


def goethite_n(wavelength_nm):
    """Provisional real index of goethite: the fitted Sellmeier law above 540 nm, constant below."""
    strength, lambda0, _ = goethite_dispersion()
    lam = np.maximum(np.asarray(wavelength_nm, dtype=float), GOETHITE_N_FIT_FROM_NM)
    return np.sqrt(1.0 + strength * lam**2 / (lam**2 - lambda0**2))


def build_goethite(src: Path, calibrated: bool = "goethite" in SHIPPED_CALIBRATED) -> Table:
    grid = GRID_5NM
    strength, lambda0, resid = goethite_dispersion()
    n = goethite_n(grid)
    if calibrated:
        cal = CalibratedK.read("goethite")
        k = cal.on(grid)
        k_status, k_sources, k_origin, k_licence = cal.status, [cal.source + " [k]"], cal.origin, cal.licence
        k_methods = cal.method_lines()
    else:
        k = goethite_literature_k(grid)
        k_status = "PROVISIONAL, the literature parameterisation (to be replaced by the calibrated k)"
        k_sources = []
        k_origin = "parameterisation sandlight.calibration.priors.goethite_literature_k"
        k_licence = SANDLIGHT_LICENCE
        bands = " + ".join(f"{p:g} exp(-(E-{c:g} eV)^2/(2 ({s:g} eV)^2))" for p, c, s in priors.GOETHITE_BANDS)
        k_methods = [
            (
                "method",
                f"k(E) = {priors.GOETHITE_EDGE_K:g}/(1 + exp(-(E - {priors.GOETHITE_EDGE_EV:g} eV)/"
                f"{priors.GOETHITE_EDGE_WIDTH_EV:g} eV)) + {bands} + {priors.GOETHITE_OH_K_2500:g} "
                f"exp((lambda - 2500 nm)/{priors.GOETHITE_OH_EFOLD_NM:g} nm) + {priors.GOETHITE_K_FLOOR:g}, "
                "E = 1239.84 eV nm/lambda: charge-transfer edge, 4T2 (650 nm) and 4T1 "
                "(925 nm) crystal-field bands, O-H wing, floor",
            )
        ]
    header = [
        ("material", "goethite"),
        ("description", "alpha-FeOOH (orthorhombic, biaxial negative), randomly oriented grains"),
        (
            "status",
            "n: PROVISIONAL (no measured n table exists; the Handbook dispersion below). k: " + k_status,
        ),
        *(("source", text) for text in k_sources),
        (
            "source",
            "J. W. Anthony, R. A. Bideaux, K. W. Bladh, M. C. Nichols (eds.), Handbook of "
            "Mineralogy, vol. III, Mineral Data Publishing / Mineralogical Society of "
            "America, goethite entry, http://www.handbookofmineralogy.org/ [principal "
            "indices alpha 2.260-2.275, beta 2.393-2.409, gamma 2.398-2.515; reflectance "
            "R1-R2 400-700 nm]",
        ),
        (
            "source",
            "A. Bedidi and B. Cervelle, Light scattering by spherical particles with "
            "hematite and goethitelike optical properties: effect of water impregnation, "
            "J. Geophys. Res. 98(B7), 11941-11952 (1993), as quoted "
            "by R. A. Conny et al., J. Geophys. Res. Atmos. 122 (2017), "
            "doi:10.1002/2017JD026488, table 4 [k ~ 0.09 mid-visible; in the literature k that "
            "converts the Handbook reflectance to n, sandlight.calibration.priors]",
        ),
        (
            "source",
            "D. M. Sherman and T. D. Waite, Electronic spectra of Fe3+ oxides and oxide "
            "hydroxides in the near IR to near UV, Am. Mineral. 70, 1262-1269 (1985); "
            "A. C. Scheinost, A. Chavernas, V. Barron, J. Torrent, Clays Clay Miner. 46, "
            "528-536 (1998) [band assignments and positions of the literature k]",
        ),
        ("origin", "n: parameterisation in scripts/data/build_optical_tables.py; k: " + k_origin),
        (
            "licence",
            SANDLIGHT_LICENCE + " of n; quoted single values are facts from the cited works; k: " + k_licence,
        ),
        ("units", UNITS),
        ("sampling", "5 nm grid, 350-2500 nm"),
        (
            "method",
            f"n(589.3 nm) = {GOETHITE_N_589:.4f}, mean of the midpoints of the three "
            "principal-index ranges (orientation average of the index ellipsoid)",
        ),
        (
            "method",
            f"n dispersion: Sellmeier n^2 = 1 + {strength:.4f} lambda^2/(lambda^2 - "
            f"({lambda0:.1f} nm)^2) fitted (max residual {resid:.4f}) to the Handbook "
            "reflectance spectrum converted to n with the literature k (sandlight.calibration.priors) and scaled to "
            "n(589.3 nm); lambda0 lies in the charge-transfer UV; held at its 540 nm value "
            "below 540 nm (inside the absorption edge)",
        ),
        *k_methods,
        ("built_by", BUILT_BY),
    ]
    return Table("goethite", header, grid, n, k)


# --------------------------------------------------------------------------------------------
# Kaolinite: PROVISIONAL
# --------------------------------------------------------------------------------------------

# Principal indices of kaolinite (biaxial), mindat: n_alpha 1.553-1.563, n_beta 1.559-1.569,
# n_gamma 1.560-1.570. Mean of the range midpoints.
KAOLINITE_N_589 = ((1.553 + 1.563) / 2 + (1.559 + 1.569) / 2 + (1.560 + 1.570) / 2) / 3.0

# Provisional k of kaolinite; every term is a documented assumption, not a measurement:
#   floor 1e-5 (the low end of the 1e-5..1e-3 literature range for visible k);
#   UV tail (Fe3+/Ti impurities, the tail of the UV edge): k = 5e-5 at 400 nm, e-folding
#     0.28 eV in photon energy (Urbach-like), giving 2.4e-4 at 350 nm;
#   O-H bands: 2nu(OH) doublet 1395/1415 nm with a broad shoulder, weak 1910 nm band of
#     adsorbed water, nu+delta(OH) doublet 2165/2207 nm, and the wing of the 2.7 um O-H
#     fundamental (1e-3 at 2500 nm). Peak heights are of the order an equivalent-slab (Hapke
#     2012) reading of the USGS kaolinite spectra (GDS11 < 63 um, KGa-1) suggests.
KAOLINITE_K_FLOOR = 1.0e-5
KAOLINITE_UV_K_400, KAOLINITE_UV_EFOLD_EV = 5.0e-5, 0.28
KAOLINITE_OH_BANDS_NM = (
    (1.5e-4, 1395.0, 7.0),
    (1.5e-4, 1415.0, 10.0),
    (3.0e-5, 1380.0, 40.0),
    (3.0e-5, 1910.0, 30.0),
    (4.0e-4, 2165.0, 12.0),
    (9.0e-4, 2207.0, 12.0),
)
KAOLINITE_OH_K_2500, KAOLINITE_OH_EFOLD_NM = 1.0e-3, 150.0


def kaolinite_k(wavelength_nm):
    """Provisional imaginary index of kaolinite (see the parameter block above)."""
    wavelength_nm = np.asarray(wavelength_nm, dtype=float)
    energy = HC_EV_NM / wavelength_nm
    k = KAOLINITE_K_FLOOR + KAOLINITE_UV_K_400 * np.exp((energy - HC_EV_NM / 400.0) / KAOLINITE_UV_EFOLD_EV)
    for peak, centre, sigma in KAOLINITE_OH_BANDS_NM:
        k = k + peak * gaussian(wavelength_nm, centre, sigma)
    return k + KAOLINITE_OH_K_2500 * np.exp((wavelength_nm - LAMBDA_MAX_NM) / KAOLINITE_OH_EFOLD_NM)


def build_kaolinite(quartz: Table) -> Table:
    grid = GRID_5NM
    # Weak dispersion borrowed from quartz: both are Si-O/Al-O silicates whose visible-NIR
    # dispersion comes from UV electronic oscillators far above 350 nm; relative dispersion
    # n(lambda)/n(589.3) is taken equal to that of orientation-averaged quartz.
    n_q = np.interp(grid, quartz.wavelength_nm, quartz.n)
    n = KAOLINITE_N_589 * n_q / float(np.interp(SODIUM_D_NM, quartz.wavelength_nm, quartz.n))
    k = kaolinite_k(grid)
    bands = ", ".join(f"{c:g} nm" for _, c, _ in KAOLINITE_OH_BANDS_NM)
    header = [
        ("material", "kaolinite"),
        ("description", "kaolinite Al2Si2O5(OH)4 (triclinic, biaxial), randomly oriented platelets"),
        (
            "status",
            "PROVISIONAL in 350-2500 nm (no visible/NIR n,k table available); to be "
            "replaced by the issue-3 inversion of USGS kaolinite spectra",
        ),
        (
            "source",
            "mindat.org, kaolinite: n_alpha 1.553-1.563, n_beta 1.559-1.569, n_gamma "
            "1.560-1.570, https://www.mindat.org/min-2156.html",
        ),
        (
            "source",
            "k order of magnitude 1e-5..1e-3 in the visible: literature range quoted in "
            "sandlight's shared data README (Egan & Hilgeman 1979; Sokolik & Toon 1999 are "
            "not available to the project); O-H band positions: R. N. Clark et al., "
            "J. Geophys. Res. 95(B8), 12653-12680 (1990), doi:10.1029/JB095iB08p12653",
        ),
        ("origin", "parameterisation in scripts/data/build_optical_tables.py (no external data file)"),
        ("licence", SANDLIGHT_LICENCE),
        ("units", UNITS),
        ("sampling", "5 nm grid, 350-2500 nm"),
        (
            "method",
            f"n = {KAOLINITE_N_589:.4f} (mean of the midpoints of the principal-index "
            "ranges) times the relative dispersion n(lambda)/n(589.3 nm) of the quartz "
            "table",
        ),
        (
            "method",
            f"k = {KAOLINITE_K_FLOOR:g} + {KAOLINITE_UV_K_400:g} exp((E - E(400 nm))/"
            f"{KAOLINITE_UV_EFOLD_EV:g} eV) + Gaussian O-H bands at {bands} + "
            f"{KAOLINITE_OH_K_2500:g} exp((lambda - 2500 nm)/{KAOLINITE_OH_EFOLD_NM:g} nm)",
        ),
        ("built_by", BUILT_BY),
    ]
    return Table("kaolinite", header, grid, n, k)


# --------------------------------------------------------------------------------------------
# Writing, checking, reporting, plotting
# --------------------------------------------------------------------------------------------


def build_all(src: Path, calibrated: tuple[str, ...] = SHIPPED_CALIBRATED) -> dict[str, Table]:
    """Every table, keyed by material name, in sandlight.optics.MATERIALS order; the minerals in
    ``calibrated`` with their calibrated k."""
    unknown = set(calibrated) - set(CALIBRATED)
    if unknown:
        raise ValueError(f"no calibrated k for {sorted(unknown)}; calibrated minerals: {CALIBRATED}")
    quartz = build_quartz(src, "quartz" in calibrated)
    tables = [
        quartz,
        build_hematite(src),
        build_goethite(src, "goethite" in calibrated),
        build_magnetite(src),
        build_kaolinite(quartz),
        build_water(src),
    ]
    for t in tables:
        ok = (
            np.all(np.isfinite(t.n))
            and np.all(t.n > 1.0)
            and np.all(np.isfinite(t.k))
            and np.all(t.k > 0.0)
            and t.wavelength_nm[0] <= LAMBDA_MIN_NM
            and t.wavelength_nm[-1] >= LAMBDA_MAX_NM
            and np.all(np.diff(t.wavelength_nm) > 0)
        )
        if not ok:
            raise ValueError(f"{t.material}: table fails the sanity checks")
    return {t.material: t for t in tables}


def render(table: Table) -> str:
    """The exact text of a table file."""
    lines = ["# sandlight optical-constant table"]
    lines += [f"# {key}: {value}" for key, value in table.header]
    lines.append("wavelength_nm,n,k")
    lines += [f"{w:.4f},{n:.6f},{k:.6e}" for w, n, k in zip(table.wavelength_nm, table.n, table.k)]
    return "\n".join(lines) + "\n"


def write_atomic(path: Path, text: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.name, suffix=".part")
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="\n") as f:
            f.write(text)
        os.chmod(tmp, 0o644)  # mkstemp creates 0600; shipped files must be world-readable
        os.replace(tmp, path)
    except BaseException:
        os.unlink(tmp)
        raise


def find_shared_optical() -> Path | None:
    for parent in [REPO, *REPO.parents]:
        candidate = parent / "shared" / "data" / "optical"
        if (candidate / "csv").is_dir():
            return candidate
    return None


def report(src: Path, tables: dict[str, Table]) -> str:
    """Markdown cross-check tables for docs/optical-constants.md."""
    out = []
    at = np.array([400, 450, 500, 550, 600, 650, 700, 800, 1000, 1500, 2000, 2500], dtype=float)
    csv = src / "csv"
    hem = tables["hematite"]
    w_qo, n_qo, k_qo = read_source_csv(csv / "hematite_Fe2O3_Querry1985_o.csv")
    w_qe, n_qe, k_qe = read_source_csv(csv / "hematite_Fe2O3_Querry1985_e.csv")
    w_t, n_t, k_t = read_source_csv(csv / "hematite_Triaud_2005.csv")
    w_lo, n_lo, k_lo = read_source_csv(csv / "hematite_O_Longtin_1988.csv")
    w_le, n_le, k_le = read_source_csv(csv / "hematite_E_Longtin_1988.csv")
    out.append(
        "| λ (nm) | n Querry (2o+e)/3 | n Triaud | n Longtin (2o+e)/3 "
        "| k Querry (2o+e)/3 | k Triaud | k Longtin (2o+e)/3 | k shipped |"
    )
    out.append("|---|---|---|---|---|---|---|---|")
    for lam in at:
        grid = np.array([lam])
        nq = orientation_average(w_qo, n_qo, w_qe, n_qe, grid, log=False)[0]
        kq = orientation_average(w_qo, k_qo, w_qe, k_qe, grid, log=True)[0]
        nl = orientation_average(w_lo, n_lo, w_le, n_le, grid, log=False)[0]
        kl = orientation_average(w_lo, k_lo, w_le, k_le, grid, log=True)[0]
        out.append(
            f"| {lam:.0f} | {nq:.3f} | {np.interp(lam, w_t, n_t):.3f} | {nl:.3f} "
            f"| {kq:.3g} | {interp_loglinear(lam, w_t, k_t):.3g} | {kl:.3g} "
            f"| {interp_loglinear(lam, hem.wavelength_nm, hem.k):.3g} |"
        )
    out.append("")
    wat = tables["water"]
    wopp = csv / "water_H2O_WOPPv3_Roettgers_absorption_k.csv"
    w_d, n_d, _ = read_source_csv(csv / "water_H2O_DaimonMasumura2007_20C.csv")
    if wopp.exists():  # cross-check only: WOPP has no licence and is never shipped
        w_w, _, k_w = read_source_csv(wopp)
        out.append(
            "| λ (nm) | k Segelstein (shipped) | k WOPP v3 (Pope & Fry) | ratio | n Segelstein | n Daimon & Masumura |"
        )
        out.append("|---|---|---|---|---|---|")
        for lam in [400, 450, 500, 550, 600, 650, 700]:
            ks = interp_loglinear(lam, wat.wavelength_nm, wat.k)
            kw = np.interp(lam, w_w, k_w)
            out.append(
                f"| {lam} | {ks:.3g} | {kw:.3g} | {ks / kw:.2f} "
                f"| {np.interp(lam, wat.wavelength_nm, wat.n):.4f} "
                f"| {np.interp(lam, w_d, n_d):.4f} |"
            )
        out.append("")
    out.append("| material | n 450 | n 550 | n 650 | k 450 | k 550 | k 650 |")
    out.append("|---|---|---|---|---|---|---|")
    for name, t in tables.items():
        n3 = [np.interp(x, t.wavelength_nm, t.n) for x in (450, 550, 650)]
        k3 = [interp_loglinear(x, t.wavelength_nm, t.k) for x in (450, 550, 650)]
        out.append(
            f"| {name} | " + " | ".join(f"{v:.4f}" for v in n3) + " | " + " | ".join(f"{v:.3g}" for v in k3) + " |"
        )
    return "\n".join(out) + "\n"


def plot(tables: dict[str, Table], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax_n, ax_k) = plt.subplots(1, 2, figsize=(11, 4.5), constrained_layout=True)
    for name, t in tables.items():
        provisional = name == "kaolinite"
        style = dict(ls="--" if provisional else "-", lw=1.4)
        label = name + (" (provisional)" if provisional else " (k calibrated)" if name in CALIBRATED else "")
        (line,) = ax_n.plot(t.wavelength_nm, t.n, label=label, **style)
        ax_k.semilogy(t.wavelength_nm, t.k, color=line.get_color(), label=label, **style)
    for ax in (ax_n, ax_k):
        ax.set_xlabel("vacuum wavelength λ (nm)")
        ax.set_xlim(LAMBDA_MIN_NM, LAMBDA_MAX_NM)
        ax.grid(alpha=0.3)
    ax_n.set_ylabel("real index n")
    ax_k.set_ylabel("imaginary index k")
    ax_n.set_title("n(λ)")
    ax_k.set_title("k(λ), log scale; α = 4πk/λ")
    ax_k.legend(fontsize=8, loc="lower right")
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--source", type=Path, default=None, help="the shared data/optical folder (default: found above the repo)"
    )
    parser.add_argument("--out", type=Path, default=OUT_DIR, help="output folder for the tables")
    parser.add_argument("--check", action="store_true", help="do not write; exit 1 if the files in --out differ")
    parser.add_argument("--report", action="store_true", help="print cross-check tables")
    parser.add_argument("--plot", action="store_true", help=f"write {PLOT_PATH.relative_to(REPO)}")
    args = parser.parse_args(argv)

    src = args.source or find_shared_optical()
    if src is None or not (src / "csv").is_dir():
        parser.error("shared data/optical folder not found; pass --source")
    tables = build_all(src)

    if args.check:
        stale = [
            m
            for m, t in tables.items()
            if not (args.out / f"{m}.csv").exists() or (args.out / f"{m}.csv").read_text(encoding="utf-8") != render(t)
        ]
        if stale:
            print("out of date: " + ", ".join(stale), file=sys.stderr)
            return 1
        print("all tables up to date")
    else:
        for material, table in tables.items():
            write_atomic(args.out / f"{material}.csv", render(table))
            print(f"wrote {args.out / (material + '.csv')} ({table.wavelength_nm.size} rows)")
    if args.report:
        print(report(src, tables))
    if args.plot:
        plot(tables, PLOT_PATH)
        print(f"wrote {PLOT_PATH}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
