"""Fits to measured USGS spectra (docs/retrieval.md, "Measured spectra").

- ``Hematite.02+Quartz.98_GDS76``: quartz powder with 2 wt % hematite (USGS splib07a). Read as
  sand with the iron oxide as separate particles (form 'particles'), pure hematite
  (hematite_ratio 1), dry, no silt or clay. Fitted (a) with the predictor bank, iron oxide free,
  and (b) with the engine, iron oxide, its particle size and the quartz grain size free.
- The ``Hematite_GDS69`` series a–g: pure hematite powders sieved to 150–250 µm … < 10 µm.
  Pure hematite is outside the sand model (iron oxide ≤ 10 % of the solids); the closest sample
  is hematite as separate particles in quartz sand. The engine fits the iron oxide (≤ 10 %)
  and the particle size (≤ 50 µm); the sizes should come out in the order of the sieves.

- ``--parts powder``: the case for a powder forward model. Each GDS69 spectrum next to the
  engine's spectrum of pure hematite powder of the sieve's sizes
  (:class:`sandlight.physics.powder.Powder`, equal mass per log size), no fit.

Wavelengths 400–1000 nm every 25 nm for the engine (the bank covers 400–700 nm); the
measurement noise is estimated from the residuals. Prints the tables of docs/retrieval.md and
writes ``retrieval_measured.csv`` to ``--out`` and the figures ``retrieval_gds76.png`` and
``retrieval_gds69.png`` to ``--figures``.

Usage::

    nice -n 10 python3 scripts/studies/retrieval_measured.py [--rays 5000] [--out docs/data]
        [--figures docs/figures] [--parts sand powder]
"""

from __future__ import annotations

import argparse
import csv
import time
from pathlib import Path

import numpy as np

import sandlight
from sandlight.io import write_atomically
from sandlight.measured import usgs_library
from sandlight.retrieval.spectrum import as_spectrum

ENGINE_WAVELENGTHS = np.arange(400.0, 1001.0, 25.0)
PARTICLES = {"saturation": 0.0, "hematite_ratio": 1.0, "iron_oxide_form": "particles", "silt": 0.0, "clay": 0.0}
#: Sieve label in the file name, nominal size (µm, the sieve's centre) and sieve range (µm; the
#: < 10 µm fraction taken as 2–10 µm).
GDS69 = {
    "a": ("150-250u", 200.0, (150.0, 250.0)),
    "b": ("104-150u", 127.0, (104.0, 150.0)),
    "c": ("60-104um", 82.0, (60.0, 104.0)),
    "d": ("30-45um", 37.5, (30.0, 45.0)),
    "e": ("20-30um", 25.0, (20.0, 30.0)),
    "f": ("10-20um", 15.0, (10.0, 20.0)),
    "g": ("lt10um", 5.0, (2.0, 10.0)),
}
POWDER_WAVELENGTHS = np.array([450.0, 550.0, 650.0, 750.0, 900.0, 1000.0])


def row(label: str, result, nominal: float | None = None) -> dict:
    out = {"spectrum": label, "method": result.method, "model": result.model, "sigma": result.sigma}
    out["residual_rms"] = float(np.sqrt(np.mean(result.optimum.residual**2)))
    if nominal is not None:
        out["nominal_size_um"] = nominal
    for name in result.free:
        out[name] = result.estimate[name]
        if result.identifiable(name):
            out[f"{name}_low"], out[f"{name}_high"] = result.interval(name)
        else:
            out[f"{name}_low"] = out[f"{name}_high"] = "not identifiable"
    return out


def show(r: dict, names) -> str:
    parts = []
    for n in names:
        lo = r[f"{n}_low"]
        parts.append(
            f"{n} = {r[n]:.4g} (not identifiable)"
            if isinstance(lo, str)
            else f"{n} = {r[n]:.4g} ({lo:.4g}–{r[f'{n}_high']:.4g})"
        )
    return "; ".join(parts)


def plot_fits(results: list[tuple[str, object]], path: Path, title: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 5), dpi=110)
    for k, (label, result) in enumerate(results):
        obs = result.observation
        colour = f"C{k % 10}"
        ax.plot(obs.centres_nm, obs.values, "o", ms=3, color=colour)
        ax.plot(obs.centres_nm, result.optimum.model, "-", color=colour, label=label)
    ax.set_xlabel("wavelength (nm)")
    ax.set_ylabel("reflectance (dots: measured, lines: fitted)")
    ax.set_title(title, fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    write_atomically(path, lambda tmp: fig.savefig(tmp, format="png"))
    plt.close(fig)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rays", type=int, default=5000)
    parser.add_argument("--out", type=Path, default=Path("docs/data"))
    parser.add_argument("--figures", type=Path, default=Path("docs/figures"))
    parser.add_argument("--parts", nargs="+", choices=("sand", "powder"), default=["sand", "powder"])
    args = parser.parse_args(argv)
    if "sand" in args.parts:
        sand_fits(args)
    if "powder" in args.parts:
        powder_check(args)


def powder_check(args) -> None:
    """GDS69 against the engine's pure hematite powder of the sieve sizes (no fit)."""
    from sandlight.physics.powder import Powder

    print(f"\nGDS69 against pure hematite powder (engine, {args.rays} rays), reflectance at {POWDER_WAVELENGTHS} nm")
    print("| spectrum | sieve (µm) | measured | powder model |")
    print("|---|---|---|---|")
    for letter, (sieve, _, sizes) in GDS69.items():
        measured = as_spectrum(usgs_library(f"Hematite_GDS69.{letter}_{sieve}")).interp(wavelength=POWDER_WAVELENGTHS)
        model = sandlight.reflectance(Powder("hematite", sizes), POWDER_WAVELENGTHS, rays=args.rays, progress=False)
        fmt = ", ".join
        print(
            f"| GDS69.{letter} | {sieve} | {fmt(f'{v:.3f}' for v in measured.values)} | "
            f"{fmt(f'{v:.3f}' for v in model.values)} |",
            flush=True,
        )


def sand_fits(args) -> None:
    """GDS76 and GDS69 fitted with the sand model (bank and engine)."""
    engine = {"method": "engine", "rays": args.rays, "wavelengths": ENGINE_WAVELENGTHS, "threads": 1}
    rows = []
    t0 = time.perf_counter()

    gds76 = as_spectrum(usgs_library("Hematite.02+Quartz.98_GDS76"))
    bank = sandlight.fit(gds76, ["iron_oxide"], PARTICLES, threads=1)
    rows.append(row("GDS76", bank))
    free = ["iron_oxide", "iron_oxide_particle_size_um", "grain_size"]
    eng = sandlight.fit(gds76, free, PARTICLES, **engine)
    rows.append(row("GDS76", eng))
    print(f"GDS76 (2 wt % hematite), {time.perf_counter() - t0:.0f} s")
    print(f"  bank: {show(rows[0], ['iron_oxide'])}; {bank.model}; {bank.engine_check.summary()}")
    print(f"  engine ({args.rays} rays): {show(rows[1], free)}; residual RMS {rows[1]['residual_rms']:.4f}")
    plot_fits(
        [(f"predictor bank ({bank.model.split(chr(39))[1]})", bank), (f"engine, {args.rays} rays", eng)],
        args.figures / "retrieval_gds76.png",
        "Hematite.02+Quartz.98 GDS76 (USGS splib07a): 2 wt % hematite; fitted iron oxide "
        f"{bank.estimate['iron_oxide']:.3%} (bank), {eng.estimate['iron_oxide']:.3%} (engine)",
    )

    series = []
    print("\nGDS69 hematite powders (outside the sand model: hematite particles in quartz, size free)")
    print("| spectrum | sieve (µm) | fitted particle size (µm), 95 % | fitted iron oxide | residual RMS |")
    print("|---|---|---|---|---|")
    fixed = {**PARTICLES}
    for letter, (sieve, nominal, _) in GDS69.items():
        spectrum = as_spectrum(usgs_library(f"Hematite_GDS69.{letter}_{sieve}"))
        result = sandlight.fit(spectrum, ["iron_oxide", "iron_oxide_particle_size_um"], fixed, **engine)
        r = row(f"GDS69.{letter}", result, nominal)
        rows.append(r)
        series.append((f"GDS69.{letter} {sieve}", result))
        size = show(r, ["iron_oxide_particle_size_um"]).split(" = ", 1)[1]
        print(f"| GDS69.{letter} | {sieve} | {size} | {r['iron_oxide']:.4f} | {r['residual_rms']:.4f} |", flush=True)
    sizes = [r["iron_oxide_particle_size_um"] for r in rows if r["spectrum"].startswith("GDS69")]
    ordered = all(a >= b for a, b in zip(sizes, sizes[1:], strict=False))
    print(f"fitted sizes in the sieves' order: {ordered} ({time.perf_counter() - t0:.0f} s in all)")
    plot_fits(
        series,
        args.figures / "retrieval_gds69.png",
        "Hematite GDS69 powders: engine fits (hematite particles ≤ 10 % in quartz sand)",
    )

    keys = sorted({k for r in rows for k in r}, key=lambda k: (k != "spectrum", k != "method", k))

    def write(tmp: Path) -> None:
        with open(tmp, "w", newline="") as f:
            w = csv.DictWriter(f, keys)
            w.writeheader()
            w.writerows(rows)

    write_atomically(args.out / "retrieval_measured.csv", write)


if __name__ == "__main__":
    main()
