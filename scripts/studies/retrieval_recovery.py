"""Synthetic recovery of sample parameters (docs/retrieval.md, "Synthetic recovery").

Draws samples in the predictor bank's reference domain (iron oxide log-uniform in 0.1–5 %,
hematite ratio uniform in [0, 1], saturation uniform in [0.001, 1]; the reference sand
otherwise, iron oxide as a coating), traces each with the Monte Carlo engine (independent
seeds, ``--rays`` rays per wavelength, 400–700 nm every 20 nm), adds Gaussian noise of standard
deviation ``--sigma`` and fits the noisy spectrum blind (the noise is estimated from the
residuals) with the bank, the default of ``sandlight.fit`` (Laplace posterior, or emcee with
``--posterior emcee``: then the files are named ``retrieval_recovery_emcee.*``). Optionally the
first ``--engine-fits`` spectra are fitted again with the engine as forward model.

It prints, per parameter, how often the true value lies inside the 95 % interval (a parameter
flagged not identifiable counts as covered by its whole range, and the count of such flags is
printed), the mean bias and the median interval width, and writes the per-sample table
``retrieval_recovery.csv`` to ``--out`` and the figure ``retrieval_recovery.png`` to
``--figures``.

Usage::

    nice -n 10 python3 scripts/studies/retrieval_recovery.py [--samples 50] [--rays 20000]
        [--sigma 0.005] [--engine-fits 0] [--out docs/data] [--figures docs/figures]
"""

from __future__ import annotations

import argparse
import csv
import time
from pathlib import Path

import numpy as np
from scipy.stats import qmc

import sandlight
from sandlight.io import write_atomically

FREE = ("iron_oxide", "hematite_ratio", "saturation")
WAVELENGTHS = np.arange(400.0, 701.0, 20.0)


def draw(n: int, seed: int) -> list[sandlight.SandSample]:
    u = qmc.LatinHypercube(d=3, seed=seed).random(n)
    iron = np.exp(np.log(0.001) + u[:, 0] * (np.log(0.05) - np.log(0.001)))
    return [
        sandlight.SandSample(iron_oxide=float(a), hematite_ratio=float(b), saturation=float(0.001 + c * 0.999))
        for a, b, c in zip(iron, u[:, 1], u[:, 2], strict=True)
    ]


def one_fit(truth, spectrum, method: str, args) -> dict:
    t0 = time.perf_counter()
    kw = {"method": method, "threads": 1, "seed": 1, "posterior": args.posterior}
    if method == "engine":
        kw.update(rays=args.engine_rays, posterior="laplace")
    else:
        kw.update(check_rays=args.check_rays)
    result = sandlight.fit(spectrum, list(FREE), **kw)
    row = {"method": method, "model": result.model, "sigma": result.sigma, "seconds": time.perf_counter() - t0}
    if result.engine_check is not None:
        row["engine_check_rms"] = result.engine_check.rms_error
    for i, name in enumerate(FREE):
        true = getattr(truth, name)
        ok = result.identifiable(name)
        lo, hi = result.interval(name) if ok else (result.space.low[i], result.space.high[i])
        row.update(
            {
                f"{name}_true": true,
                f"{name}_estimate": result.estimate[name],
                f"{name}_low": lo,
                f"{name}_high": hi,
                f"{name}_identifiable": ok,
                f"{name}_covered": bool(lo <= true <= hi),
            }
        )
    return row


def summary(rows: list[dict], label: str) -> None:
    print(f"\n{label}: {len(rows)} fits, median {np.median([r['seconds'] for r in rows]):.2f} s per fit")
    print(
        "| parameter | coverage of the 95 % interval | not identifiable | coverage where identifiable "
        "| mean bias | median width |"
    )
    print("|---|---|---|---|---|---|")
    for name in FREE:
        cov = np.mean([r[f"{name}_covered"] for r in rows])
        flat = sum(not r[f"{name}_identifiable"] for r in rows)
        shown = [r[f"{name}_covered"] for r in rows if r[f"{name}_identifiable"]]
        bias = np.mean([r[f"{name}_estimate"] - r[f"{name}_true"] for r in rows])
        width = np.median([r[f"{name}_high"] - r[f"{name}_low"] for r in rows if r[f"{name}_identifiable"]] or [np.nan])
        print(f"| {name} | {cov:.0%} | {flat} | {np.mean(shown):.0%} of {len(shown)} | {bias:+.4f} | {width:.4f} |")
    models = {}
    for r in rows:
        models[r["model"]] = models.get(r["model"], 0) + 1
    print("answered by: " + "; ".join(f"{k}: {v}" for k, v in sorted(models.items())))


def plot(rows: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(12, 4), dpi=110)
    for ax, name in zip(axes, FREE, strict=True):
        for r in rows:
            if r["method"] != "bank":
                continue
            t, e = r[f"{name}_true"], r[f"{name}_estimate"]
            colour = "C0" if r[f"{name}_covered"] else "C3"
            style = "-" if r[f"{name}_identifiable"] else ":"
            ax.plot([t, t], [r[f"{name}_low"], r[f"{name}_high"]], style, color=colour, lw=1, alpha=0.7)
            ax.plot(t, e, "o", ms=3, color=colour)
        lo, hi = ax.get_xlim()
        ax.plot([lo, hi], [lo, hi], color="0.5", lw=0.8)
        if name == "iron_oxide":
            ax.set_xscale("log")
            ax.set_yscale("log")
        ax.set_xlabel(f"true {name}")
        ax.set_ylabel(f"fitted {name} (95 % interval)")
        ax.grid(alpha=0.3)
    fig.suptitle("blind fits of engine spectra + noise (blue: truth inside the interval; dotted: not identifiable)")
    fig.tight_layout()
    write_atomically(path, lambda tmp: fig.savefig(tmp, format="png"))
    plt.close(fig)


def write_table(rows: list[dict], path: Path) -> None:
    """The per-sample rows as CSV, written atomically."""
    keys = sorted({k for r in rows for k in r}, key=lambda k: (k != "sample", k != "method", k))

    def write(tmp: Path) -> None:
        with open(tmp, "w", newline="") as f:
            w = csv.DictWriter(f, keys)
            w.writeheader()
            w.writerows(rows)

    write_atomically(path, write)


def name(args) -> str:
    """File name of the table and figure: retrieval_recovery, with _emcee for that posterior."""
    return "retrieval_recovery" + ("_emcee" if args.posterior == "emcee" else "")


def read_table(path: Path) -> list[dict]:
    """Rows of a table written by `write_table`, with numbers and booleans parsed."""

    def value(text: str):
        if text in ("True", "False"):
            return text == "True"
        try:
            return float(text)
        except ValueError:
            return text

    with open(path, newline="") as f:
        return [{k: value(v) for k, v in r.items() if v != ""} for r in csv.DictReader(f)]


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--samples", type=int, default=50)
    parser.add_argument("--rays", type=int, default=20_000)
    parser.add_argument("--sigma", type=float, default=0.005)
    parser.add_argument("--seed", type=int, default=2026)
    parser.add_argument("--engine-fits", type=int, default=0)
    parser.add_argument("--engine-rays", type=int, default=5000)
    parser.add_argument("--posterior", choices=("laplace", "emcee"), default="laplace")
    parser.add_argument("--check-rays", type=int, default=20_000, help="Rays of the engine check (0: none).")
    parser.add_argument("--out", type=Path, default=Path("docs/data"))
    parser.add_argument("--figures", type=Path, default=Path("docs/figures"))
    parser.add_argument(
        "--from-csv", type=Path, help="Print the summary and draw the figure of a table written before (no fits)."
    )
    args = parser.parse_args(argv)
    if args.from_csv:
        rows = read_table(args.from_csv)
        report(rows, args)
        return
    rng = np.random.default_rng(args.seed)
    rows = []
    t0 = time.perf_counter()
    for k, truth in enumerate(draw(args.samples, args.seed)):
        engine = sandlight.reflectance(
            truth, WAVELENGTHS, rays=args.rays, seed=args.seed + 100 + k, share=False, progress=False, threads=1
        )
        spectrum = (WAVELENGTHS, engine.values + rng.normal(0.0, args.sigma, WAVELENGTHS.size))
        rows.append({"sample": k, **one_fit(truth, spectrum, "bank", args)})
        if k < args.engine_fits:
            rows.append({"sample": k, **one_fit(truth, spectrum, "engine", args)})
        write_table(rows, args.out / f"{name(args)}.csv")  # after every sample: a long run keeps its rows
        print(f"sample {k + 1}/{args.samples} done ({time.perf_counter() - t0:.0f} s)", flush=True)
    print(f"\n{args.samples} samples, {args.rays} rays per wavelength, noise σ = {args.sigma}, seed {args.seed}")
    report(rows, args)


def report(rows: list[dict], args) -> None:
    """The summary tables and the figure."""
    summary([r for r in rows if r["method"] == "bank"], "predictor bank (default)")
    if any(r["method"] == "engine" for r in rows):
        summary([r for r in rows if r["method"] == "engine"], f"engine forward model, {args.engine_rays} rays")
    checks = [r["engine_check_rms"] for r in rows if "engine_check_rms" in r]
    if checks:
        print(
            f"engine check at the optimum: predictor − engine RMS, median {np.median(checks):.4f}, "
            f"max {max(checks):.4f}"
        )
    plot(rows, args.figures / f"{name(args)}.png")


if __name__ == "__main__":
    main()
