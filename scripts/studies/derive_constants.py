"""Prototype of issue 3 §2: derive k(λ) by inverting powder spectra with sandlight's own engine,
proved first on hematite, whose k Querry (1985) measured.

For each wavelength λ, the USGS hematite grain-size series (GDS69.a–.g, wet-sieved fractions of
one specular-hematite rock: 150–250, 104–150, 60–104, 30–45, 20–30, 10–20 and < 10 µm) is
modelled as dry powders of pure hematite particles (sizes log-uniform by mass within each sieve
fraction, spheres, porosity 0.45, n from the shipped table) for a grid of trial k. Two answers
are reported:

* per fraction, the k at which the model reproduces that fraction's measured reflectance (linear
  interpolation in log k; a bound when the measurement lies outside what any k on the grid gives);
* k_median, the median of the per-fraction values that were found (not bounds), with their range;
* jointly, the single k minimising the RMS reflectance residual over all fractions.

If one k explains every size, the method is self-consistent; the derived k is then compared with
Querry's (figure of merit: RMS of log10(k_derived / k_Querry) over the wavelengths). As an
independent check, the validation mixture GDS76 (never used in the derivation) is modelled with
k_median at each wavelength. Nothing here is shipped: the script prints a Markdown report and
draws a figure.

Usage::

    python3 scripts/studies/derive_constants.py --rays 4000 --plot docs/img/hematite-inversion.png

Needs the native engine and the shared USGS library (``shared/data/measured/usgs_splib07a``).
"""

from __future__ import annotations

import argparse
import contextlib
import math
import sys
import time
from pathlib import Path

import numpy as np

# The inversion reads Querry's hematite tables the way the data builder does: reuse its readers.
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "data"))
from build_optical_tables import find_shared_optical, hematite_sources  # noqa: E402

from sandlight import validation as v
from sandlight.measured import read_usgs, usgs_library

# Sieve fractions of GDS69 (µm), from the USGS sample description. "< 10 µm" has no stated lower
# bound; we assume 1 µm (geometric optics is in any case doubtful below a few µm).
FRACTIONS = {
    "Hematite_GDS69.a_150-250u_BECKb_AREF": (150.0, 250.0),
    "Hematite_GDS69.b_104-150u_BECKb_AREF": (104.0, 150.0),
    "Hematite_GDS69.c_60-104um_BECKb_AREF": (60.0, 104.0),
    "Hematite_GDS69.d_30-45um_BECKb_AREF": (30.0, 45.0),
    "Hematite_GDS69.e_20-30um_BECKb_AREF": (20.0, 30.0),
    "Hematite_GDS69.f_10-20um_BECKb_AREF": (10.0, 20.0),
    "Hematite_GDS69.g_lt10um_BECKb_AREF": (1.0, 10.0),
}
DEFAULT_WAVELENGTHS_NM = (450, 550, 600, 650, 700, 750, 800, 900, 1000, 1200, 1500, 2000, 2400)
LOG10_K_GRID = np.arange(-5.0, 0.5001, 0.125)
POROSITY = 0.45
#: The acceptance test of the method (docs/optical-constants.md): recover Querry's k within this
#: factor where Querry is trustworthy (the charge-transfer region, 450-600 nm).
ACCEPT_FACTOR = 1.5
ACCEPT_NM = (450.0, 600.0)


@contextlib.contextmanager
def hematite_k(k: float):
    """Runs the engine with hematite's k set to ``k`` (n unchanged), as the validation variants
    do: the name the medium builder looks up (``shipped_index``, which remembers the shipped
    constants) is replaced for the duration only."""
    from sandlight.physics import medium

    original = medium.shipped_index

    def replaced(material, wavelength_nm):
        m = original(material, wavelength_nm)
        return complex(m.real, k) if material == "hematite" else m

    medium.shipped_index = replaced
    try:
        yield
    finally:
        medium.shipped_index = original


def model_grid(wavelength_nm: float, rays: int, seed: int) -> np.ndarray:
    """Modelled reflectance, shape (fractions, k grid), at one wavelength."""
    out = np.empty((len(FRACTIONS), LOG10_K_GRID.size))
    for j, lk in enumerate(LOG10_K_GRID):
        with hematite_k(10.0**lk):
            for i, sizes in enumerate(FRACTIONS.values()):
                out[i, j] = v.powder_reflectance(
                    "hematite", sizes, [wavelength_nm], rays=rays, porosity=POROSITY, seed=seed
                ).values[0]
    return out


def invert_one(r_model: np.ndarray, r_meas: float) -> tuple[float, str]:
    """log10 k at which a (decreasing in k) model curve meets ``r_meas``, and a flag:
    '' (found), '<' (brighter than any k gives: k below the grid), '>' (darker than the opaque
    limit: no k fits, k ≥ the value where the curve flattens)."""
    if r_meas >= r_model[0]:
        return LOG10_K_GRID[0], "<"
    if r_meas <= r_model.min():
        return LOG10_K_GRID[int(np.argmin(r_model))], ">"
    j = int(np.flatnonzero(r_model <= r_meas)[0])
    x0, x1, y0, y1 = LOG10_K_GRID[j - 1], LOG10_K_GRID[j], r_model[j - 1], r_model[j]
    return x0 + (r_meas - y0) * (x1 - x0) / (y1 - y0), ""


def invert_joint(models: np.ndarray, meas: np.ndarray) -> tuple[float, float]:
    """log10 k minimising the RMS residual over all fractions (parabola through the grid minimum
    and its neighbours), and that minimum RMS."""
    rms = np.sqrt(np.mean((models - meas[:, None]) ** 2, axis=0))
    j = int(np.argmin(rms))
    if 0 < j < rms.size - 1:
        y0, y1, y2 = rms[j - 1 : j + 2]
        denom = y0 - 2 * y1 + y2
        shift = 0.5 * (y0 - y2) / denom if denom > 0 else 0.0
        best = LOG10_K_GRID[j] + shift * (LOG10_K_GRID[1] - LOG10_K_GRID[0])
        return best, float(np.interp(best, LOG10_K_GRID, rms))
    return LOG10_K_GRID[j], float(rms[j])


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rays", type=int, default=4000, help="rays per wavelength and trial k")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument(
        "--wavelengths", default=",".join(map(str, DEFAULT_WAVELENGTHS_NM)), help="comma-separated wavelengths (nm)"
    )
    parser.add_argument("--plot", default=None, help="write the figure (PNG) here")
    args = parser.parse_args(argv)
    wl = [float(x) for x in args.wavelengths.split(",")]

    spectra = {stem: read_usgs(usgs_library(stem)) for stem in FRACTIONS}
    meas = np.array([v.measured_on_grid(s, wl) for s in spectra.values()])  # (fractions, λ)
    # The references: Querry's own k (issue 3's), and Longtin's beyond the edge (shipped there).
    _, _, k_querry, k_longtin = hematite_sources(find_shared_optical(), wl)
    start = time.perf_counter()
    per_sample, flags, joint, joint_rms, models_at_best, median, spread = [], [], [], [], [], [], []
    sensitivity = []
    for i, lam in enumerate(wl):
        models = model_grid(lam, args.rays, args.seed)
        sensitivity.append(resolution(models, math.log10(k_querry[i])))
        res = [invert_one(models[f], meas[f, i]) for f in range(len(FRACTIONS))]
        per_sample.append([r[0] for r in res])
        flags.append([r[1] for r in res])
        found = [r[0] for r in res if r[1] == ""]
        median.append(float(np.median(found)) if found else math.nan)
        spread.append((min(found), max(found)) if found else (math.nan, math.nan))
        best, rms = invert_joint(models, meas[:, i])
        joint.append(best)
        joint_rms.append(rms)
        models_at_best.append([np.interp(best, LOG10_K_GRID, models[f]) for f in range(len(FRACTIONS))])
        print(f"λ = {lam:g} nm done ({time.perf_counter() - start:.0f} s)", file=sys.stderr)
    per_sample, joint, joint_rms, median = np.array(per_sample), np.array(joint), np.array(joint_rms), np.array(median)
    models_at_best = np.array(models_at_best)

    names = [s.split("_")[1] for s in FRACTIONS]
    print(
        f"Hematite grain-size inversion: {args.rays:,} rays per run, seed {args.seed}, "
        f"log10 k grid {LOG10_K_GRID[0]:g}..{LOG10_K_GRID[-1]:g} step {LOG10_K_GRID[1] - LOG10_K_GRID[0]:g}, "
        f"{time.perf_counter() - start:.0f} s\n"
    )
    print(
        "| λ (nm) | k Querry | k Longtin | k median (range) | k joint | joint RMS residual | "
        + " | ".join(f"k {n}" for n in names)
        + " |"
    )
    print("|---|---|---|---|---|---|" + "---|" * len(names))
    for i, lam in enumerate(wl):
        cells = [f"{flags[i][f]}{10 ** per_sample[i, f]:.2g}" for f in range(len(FRACTIONS))]
        lo, hi = spread[i]
        longtin = f"{k_longtin[i]:.3g}" if lam >= 633.0 else "–"
        print(
            f"| {lam:g} | {k_querry[i]:.3g} | {longtin} | {10 ** median[i]:.2g} ({10**lo:.2g}–{10**hi:.2g}) | "
            f"{10 ** joint[i]:.3g} | {joint_rms[i]:.3f} | " + " | ".join(cells) + " |"
        )
    print(
        "\n'<' : the fraction is brighter than the model with the smallest k on the grid (an upper bound);"
        " '>' : darker than the model's opaque limit (no k reproduces it).\n"
    )
    print("Measured reflectance / model at the joint k:\n")
    print("| λ (nm) | " + " | ".join(names) + " |")
    print("|---|" + "---|" * len(names))
    for i, lam in enumerate(wl):
        print(
            f"| {lam:g} | "
            + " | ".join(f"{meas[f, i]:.3f} / {models_at_best[i, f]:.3f}" for f in range(len(FRACTIONS)))
            + " |"
        )
    beyond = np.asarray(wl) >= 633.0
    for ref_label, ref, where in (("k_Querry", k_querry, np.ones(len(wl), bool)), ("k_Longtin", k_longtin, beyond)):
        for label, derived in (("k_median", median), ("k_joint", joint)):
            log_ratio = np.where(where, derived - np.log10(ref), np.nan)
            ok = np.isfinite(log_ratio)
            print(
                f"\nFigure of merit, RMS of log10({label} / {ref_label}) over {ok.sum()} wavelengths: "
                f"{math.sqrt(np.mean(log_ratio[ok] ** 2)):.2f} (per λ: "
                + ", ".join(f"{lam:g}: {r:+.2f}" for lam, r, o in zip(wl, log_ratio, ok) if o)
                + ")"
            )
    identifiability(wl, k_querry, np.array(sensitivity), joint_rms, names)
    check_gds76(wl, median, args.rays, args.seed)

    if args.plot:
        plot(args.plot, wl, joint, median, per_sample, flags, names, meas, models_at_best)
        print(f"wrote {args.plot}", file=sys.stderr)
    return 0


def resolution(models: np.ndarray, log10_k: float) -> np.ndarray:
    """Per fraction, how much the model's reflectance changes when k is multiplied or divided
    by ACCEPT_FACTOR around ``log10_k``: the larger of the two changes."""
    step = math.log10(ACCEPT_FACTOR)
    at = [np.interp(log10_k + s, LOG10_K_GRID, row) for row in models for s in (-step, 0.0, step)]
    at = np.array(at).reshape(len(models), 3)
    return np.maximum(np.abs(at[:, 0] - at[:, 1]), np.abs(at[:, 2] - at[:, 1]))


def identifiability(wl, k_querry, sensitivity, joint_rms, names) -> None:
    """Whether the series can determine k within ACCEPT_FACTOR at all: a fraction is informative
    at λ when changing Querry's k by that factor moves its modelled reflectance by more than the
    model's own error, estimated by the joint fit's RMS residual at the shortest wavelength, where
    every fraction is opaque and k does not matter."""
    sigma = float(joint_rms[0])
    print(
        f"\nIdentifiability: |ΔR| of the model when Querry's k is changed by a factor "
        f"{ACCEPT_FACTOR:g}, against the model error σ = {sigma:.3f} (joint RMS residual at "
        f"{wl[0]:g} nm, where every fraction is opaque). Informative: |ΔR| > σ.\n"
    )
    print("| λ (nm) | k Querry | " + " | ".join(f"|ΔR| {n}" for n in names) + " | informative |")
    print("|---|---|" + "---|" * len(names) + "---|")
    blind = []
    for i, lam in enumerate(wl):
        good = sensitivity[i] > sigma
        if ACCEPT_NM[0] <= lam <= ACCEPT_NM[1] and not good.any():
            blind.append(lam)
        print(
            f"| {lam:g} | {k_querry[i]:.3g} | "
            + " | ".join(f"{x:.4f}" for x in sensitivity[i])
            + f" | {int(good.sum())} of {len(names)} |"
        )
    window = [lam for lam in wl if ACCEPT_NM[0] <= lam <= ACCEPT_NM[1]]
    print(
        f"\nIn the acceptance window {ACCEPT_NM[0]:g}-{ACCEPT_NM[1]:g} nm, {len(blind)} of "
        f"{len(window)} wavelengths have no informative fraction"
        + (f" ({', '.join(f'{x:g}' for x in blind)} nm)" if blind else "")
        + "."
    )


def check_gds76(wl, median, rays, seed) -> None:
    """The validation mixture GDS76 with hematite's k set to k_median, against the shipped k and
    the measurement (a check only: GDS76 is never used in the derivation)."""
    import sandlight
    from sandlight.sample import SandSample

    sample = SandSample.preset("gds76-hematite-quartz")
    spectrum = read_usgs(usgs_library("Hematite.02+Quartz.98_GDS76_BECKa_AREF"))
    measured = v.measured_on_grid(spectrum, wl)
    shipped = sandlight.reflectance(sample, wl, rays=rays, seed=seed, progress=False).values
    derived = []
    for lam, lk in zip(wl, median):
        if not math.isfinite(lk):
            derived.append(math.nan)
            continue
        with hematite_k(10.0**lk):
            derived.append(sandlight.reflectance(sample, [lam], rays=rays, seed=seed, progress=False).values[0])
    derived = np.array(derived)
    print("\nCheck on the validation mixture GDS76 (preset gds76-hematite-quartz), not used above:\n")
    print("| λ (nm) | measured | model, shipped k | model, k_median |")
    print("|---|---|---|---|")
    for i, lam in enumerate(wl):
        print(f"| {lam:g} | {measured[i]:.3f} | {shipped[i]:.3f} | {derived[i]:.3f} |")
    ok = np.isfinite(derived)
    for label, model in (("shipped k", shipped), ("k_median", derived)):
        print(f"RMS over these wavelengths, {label}: {math.sqrt(np.mean((model[ok] - measured[ok]) ** 2)):.3f}")


def plot(path, wl, joint, median, per_sample, flags, names, meas, models_at_best) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from sandlight.io import atomic_path

    wl = np.asarray(wl)
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.2), dpi=120)
    grid, _, querry, longtin = hematite_sources(find_shared_optical(), np.arange(400.0, 2501.0, 10.0))
    a.semilogy(grid, querry, "k-", lw=1.2, label="Querry 1985, (2o+e)/3")
    a.semilogy(
        grid[grid >= 633.0],
        longtin[grid >= 633.0],
        "k:",
        lw=1.2,
        label="Longtin 1988, (2o+e)/3 (shipped beyond the edge)",
    )
    a.semilogy(wl, 10**median, "s-", color="C0", ms=5, label="derived: median of the fractions")
    a.semilogy(wl, 10**joint, "o--", color="C3", ms=4, label="derived: one k for all 7 fractions (joint)")
    for f, name in enumerate(names):
        found = np.array([fl[f] == "" for fl in flags])
        a.semilogy(
            wl[found],
            10 ** per_sample[found, f],
            ".",
            color=plt.cm.viridis(f / 6),
            ms=6,
            label=f"derived from {name} alone" if f in (0, 3, 6) else None,
        )
    a.set_xlabel("wavelength (nm)")
    a.set_ylabel("k")
    a.set_ylim(1e-5, 3)
    a.grid(alpha=0.3, which="both")
    a.legend(fontsize=7)
    a.set_title("hematite k: inversion of the GDS69 grain-size series", fontsize=9)
    for f, name in enumerate(names):
        colour = plt.cm.viridis(f / 6)
        b.plot(wl, meas[f], "-", color=colour, lw=1, label=f"measured {name}")
        b.plot(wl, models_at_best[:, f], "o", color=colour, ms=3)
    b.set_xlabel("wavelength (nm)")
    b.set_ylabel("reflectance")
    b.set_title("measured (lines) vs model at the joint k (dots)", fontsize=9)
    b.grid(alpha=0.3)
    b.legend(fontsize=6, ncol=2)
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png")
    plt.close(fig)


if __name__ == "__main__":
    raise SystemExit(main())
