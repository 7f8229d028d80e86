"""GDS69 grain sizes with the powder forward model (docs/retrieval.md, "Measured spectra").

The USGS ``Hematite_GDS69`` series a–g (pure specular hematite, wet sieved to 150–250 µm …
< 10 µm; sieve ranges in ``retrieval_measured.GDS69``) fitted with ``sandlight.fit(...,
forward='powder', material='hematite')``: a dry hematite powder traced by the engine with the
shipped optical constants, the diameter free (fitted in log10 µm), porosity 0.45, measurement
noise estimated from the residuals. The same settings for all seven fractions:

- window 600–1000 nm every 25 nm (the fit's wavelength grid): where the model's size signal
  lives. Below 600 nm hematite absorbs so strongly that the model's reflectance is the grains'
  first-surface reflection, the same for every size (0.05); beyond 1000 nm the shipped k is at
  its 10⁻⁵ floor and the model is 0.5–0.96 for every size against the measured 0.12–0.46.
- three variants (``--variants``, default the first two): ``diameter``: diameter alone;
  ``diameter+scale``: diameter and a multiplicative scale on the model spectrum (0.25–4), the
  nuisance for the model's known error in absolute level; ``diameter+scattering``: diameter and
  the scattering inside the grains (0–1000 mm⁻¹, the fractures of these "anhedrally fractured"
  crystals; docs/model.md §2.4 item 9).

``--parts recovery``: the synthetic check of the intervals: hematite powders of 5, 20 and 80 µm,
eight each, truth traced at 40000 rays (seeds 200 …), Gaussian noise σ = 0.005 added, fitted
(diameter free, noise given) at 2000 rays with seeds 10 …; prints the share of 95 % intervals
holding the truth and the standard deviation of (fitted − true log10 d) / posterior sd.

``--parts correlation``: the correlation of the Monte Carlo errors over wavelength of a 20 µm
hematite powder at 2000 rays (20 seeds, 600–1000 nm every 50 nm), the reason the fit estimates
the Monte Carlo covariance from replicates.

Prints one table per variant (fitted diameter and 95 % interval against the sieve range), the
Spearman rank correlation of the fitted diameters with the sieve midpoints and the pairs whose
order is swapped; writes ``retrieval_powder.csv`` to ``--out`` and ``retrieval_powder.png`` to
``--figures`` (``retrieval_powder_packed.*`` with ``--memory packed``, and so on).

``--memory``: the engine's path memory for the powders (default 'none', the classic model).

Usage::

    nice -n 10 python3 scripts/studies/retrieval_powder.py [--rays 8000] [--out docs/data]
        [--figures docs/figures] [--parts gds69 recovery correlation]
        [--variants diameter diameter+scale diameter+scattering]
"""

from __future__ import annotations

import argparse
import csv
import sys
import time
from itertools import combinations
from pathlib import Path

import numpy as np
from scipy.stats import spearmanr

import sandlight
from sandlight.io import write_atomically
from sandlight.measured import usgs_library
from sandlight.physics.media import MEMORIES
from sandlight.retrieval.spectrum import as_spectrum

sys.path.insert(0, str(Path(__file__).resolve().parent))
from retrieval_measured import GDS69  # noqa: E402

WINDOW_NM = np.arange(600.0, 1001.0, 25.0)
VARIANTS = {
    "diameter": ["diameter_um"],
    "diameter+scale": ["diameter_um", "scale"],
    "diameter+scattering": ["diameter_um", "scattering_per_mm"],
}


def swapped_pairs(letters: list[str], fitted: list[float]) -> list[str]:
    """Pairs (coarser sieve, finer sieve) whose fitted diameters are not in that order."""
    return [f"{a}–{b}" for (i, a), (j, b) in combinations(enumerate(letters), 2) if fitted[i] <= fitted[j]]


def fit_series(variant: str, rays: int, fractions: str, memory: str = "none") -> list[dict]:
    rows = []
    print(
        f"\nvariant {variant!r}: free {VARIANTS[variant]}, {rays} rays, {WINDOW_NM[0]:g}–{WINDOW_NM[-1]:g} nm, "
        f"memory {memory!r}"
    )
    print("| spectrum | sieve (µm) | fitted diameter (µm), 95 % | scale | residual RMS |")
    print("|---|---|---|---|---|")
    for letter, (sieve, midpoint, (lo, hi)) in GDS69.items():
        if letter not in fractions:
            continue
        spectrum = as_spectrum(usgs_library(f"Hematite_GDS69.{letter}_{sieve}"))
        result = sandlight.fit(
            spectrum,
            VARIANTS[variant],
            forward="powder",
            material="hematite",
            memory=memory,
            rays=rays,
            wavelengths=WINDOW_NM,
            threads=1,
        )
        d = result.estimate["diameter_um"]
        ok = result.identifiable("diameter_um")
        d_lo, d_hi = result.interval("diameter_um") if ok else (float("nan"), float("nan"))
        scale = result.estimate.get("scale", 1.0)
        rms = float(np.sqrt(np.mean(result.optimum.residual**2)))
        rows.append(
            {
                "variant": variant,
                "spectrum": f"GDS69.{letter}",
                "sieve_low_um": lo,
                "sieve_high_um": hi,
                "sieve_midpoint_um": midpoint,
                "diameter_um": d,
                "diameter_low_95": d_lo,
                "diameter_high_95": d_hi,
                "scale": scale,
                "residual_rms": rms,
                "sigma": result.sigma,
                "fitted": result.optimum.model.tolist(),
                "measured": result.observation.values.tolist(),
            }
        )
        interval = f"{d:.3g} ({d_lo:.3g}–{d_hi:.3g})" if ok else f"{d:.3g} (not identifiable)"
        print(f"| GDS69.{letter} | {sieve} | {interval} | {scale:.2f} | {rms:.4f} |", flush=True)
    fitted = [r["diameter_um"] for r in rows]
    rho = spearmanr([r["sieve_midpoint_um"] for r in rows], fitted).statistic
    swaps = swapped_pairs([r["spectrum"][-1] for r in rows], fitted)
    print(f"Spearman ρ (fitted vs sieve midpoint) = {rho:.3f}; pairs out of order: {', '.join(swaps) or 'none'}")
    for r in rows:
        r["spearman"] = rho
    return rows


def correlation() -> None:
    """Correlation of the Monte Carlo errors over wavelength (see the module)."""
    from sandlight.physics.powder import Powder

    grid = np.arange(600.0, 1001.0, 50.0)
    runs = np.array(
        [
            sandlight.reflectance(Powder("hematite", 20.0), grid, rays=2000, seed=s, share=False, progress=False).values
            for s in range(20)
        ]
    )
    corr = np.corrcoef(runs, rowvar=False)
    i, j = list(grid).index(700.0), list(grid).index(900.0)
    print(f"\nMonte Carlo error correlation, 20 µm hematite, 2000 rays, 20 seeds, {grid[0]:g}–{grid[-1]:g} nm:")
    print("mean ρ:", np.round(runs.mean(axis=0), 3))
    print(np.round(corr, 2))
    print(f"700 nm – 900 nm: {corr[i, j]:.2f} (Gaussian kernel ℓ = 100 nm: {np.exp(-(200.0**2) / (2 * 100.0**2)):.2f})")


def recovery() -> None:
    """Coverage of the 95 % intervals on synthetic powders (see the module)."""
    from sandlight.physics.powder import Powder

    inside, z = [], []
    for d in (5.0, 20.0, 80.0):
        for k in range(8):
            truth = sandlight.reflectance(
                Powder("hematite", d), WINDOW_NM, rays=40_000, seed=200 + k, share=False, progress=False, threads=1
            )
            y = truth.values + 0.005 * np.random.default_rng(k).standard_normal(WINDOW_NM.size)
            result = sandlight.fit(
                (WINDOW_NM, y),
                ["diameter_um"],
                forward="powder",
                material="hematite",
                rays=2000,
                wavelengths=WINDOW_NM,
                noise=0.005,
                threads=1,
                seed=10 + k,
            )
            lo, hi = result.interval("diameter_um")
            inside.append(lo <= d <= hi)
            z.append(np.log10(result.estimate["diameter_um"] / d) / result.posterior.sd[0])
    print(
        f"\nrecovery: {len(z)} synthetic powders (5, 20, 80 µm), 2000 rays: truth inside the 95 % interval "
        f"{np.mean(inside):.0%}; (fitted − true log10 d)/sd: mean {np.mean(z):.2f}, sd {np.std(z, ddof=1):.2f}"
    )


def plot(rows: list[dict], path: Path, memory: str = "none") -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.5), dpi=110)
    for k, variant in enumerate(dict.fromkeys(r["variant"] for r in rows)):
        sel = [r for r in rows if r["variant"] == variant]
        mid = np.array([r["sieve_midpoint_um"] for r in sel])
        d = np.array([r["diameter_um"] for r in sel])
        # at a bound the central interval of the truncated posterior can exclude the estimate
        err = np.array(
            [[r["diameter_um"] - r["diameter_low_95"], r["diameter_high_95"] - r["diameter_um"]] for r in sel]
        )
        err = np.clip(err, 0, None).T
        xerr = np.array([[m - r["sieve_low_um"], r["sieve_high_um"] - m] for m, r in zip(mid, sel, strict=True)]).T
        left.errorbar(
            mid * (1 + 0.04 * k), d, yerr=err, xerr=xerr, fmt="o", ms=4, capsize=2, color=f"C{k}",
            label=f"{variant} (Spearman ρ {sel[0]['spearman']:.2f})",
        )  # fmt: skip
    left.plot([1, 1000], [1, 1000], "--", color="0.5", lw=0.8, label="fitted = sieve")
    left.axhline(1000.0, color="0.3", lw=0.8, ls=":", label="upper bound of d (1000 µm)")
    left.set(xscale="log", yscale="log", xlim=(1, 1000), ylim=(1, 2000))
    left.set_xlabel("sieve range (µm; < 10 µm drawn as 2–10)")
    left.set_ylabel("fitted diameter (µm), 95 % interval")
    left.legend(fontsize=7)
    left.grid(alpha=0.3, which="both")
    engine = "classic model" if memory == "none" else f"memory {memory!r}"
    left.set_title(f"GDS69 hematite: powder fits (shipped hematite k, {engine})", fontsize=9)
    for k, r in enumerate(r for r in rows if r["variant"] == "diameter"):
        right.plot(WINDOW_NM, r["measured"], "o", ms=3, color=f"C{k}")
        right.plot(WINDOW_NM, r["fitted"], "-", color=f"C{k}", label=f"{r['spectrum']} ({r['diameter_um']:.3g} µm)")
    right.set_xlabel("wavelength (nm)")
    right.set_ylabel("reflectance (dots: measured, lines: fitted)")
    right.set_title("variant 'diameter': measured and fitted", fontsize=9)
    right.legend(fontsize=7)
    right.grid(alpha=0.3)
    fig.tight_layout()
    write_atomically(path, lambda tmp: fig.savefig(tmp, format="png"))
    plt.close(fig)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rays", type=int, default=8000)
    parser.add_argument("--out", type=Path, default=Path("docs/data"))
    parser.add_argument("--figures", type=Path, default=Path("docs/figures"))
    parser.add_argument("--fractions", default="abcdefg", help="GDS69 fractions to fit (letters a-g)")
    parser.add_argument("--memory", choices=MEMORIES, default="none", help="path memory of the powder engine")
    parser.add_argument(
        "--parts", nargs="+", choices=("gds69", "recovery", "correlation"), default=["gds69", "recovery", "correlation"]
    )
    parser.add_argument(
        "--variants", nargs="+", choices=tuple(VARIANTS), default=["diameter", "diameter+scale"], help="GDS69 fits"
    )
    args = parser.parse_args(argv)
    t0 = time.perf_counter()
    if "correlation" in args.parts:
        correlation()
    if "recovery" in args.parts:
        recovery()
    if "gds69" not in args.parts:
        return
    rows = [r for variant in args.variants for r in fit_series(variant, args.rays, args.fractions, args.memory)]
    print(f"({time.perf_counter() - t0:.0f} s)")
    stem = "retrieval_powder" + ("" if args.memory == "none" else f"_{args.memory}")
    stem += "" if "diameter+scattering" not in args.variants else "_scattering"
    plot(rows, args.figures / f"{stem}.png", args.memory)
    keys = [k for k in rows[0] if k not in ("fitted", "measured")]

    def write(tmp: Path) -> None:
        with open(tmp, "w", newline="") as f:
            w = csv.DictWriter(f, keys, extrasaction="ignore")
            w.writeheader()
            w.writerows(rows)

    write_atomically(args.out / f"{stem}.csv", write)


if __name__ == "__main__":
    main()
