"""``sandlight.predict`` over 350–2500 nm against fresh Monte Carlo (issue 23's proof).

Predicts every preset and ``--random`` samples drawn at random from each full-range model's
own domain (a seed the training never used) with the shipped full-range bank, runs the default
engine on the same samples at ``--rays`` rays per wavelength at the models' nodes, and prints,
per sample and per band, the RMS difference next to the Monte Carlo noise of the reference, and
the model error alone (√(RMS² − noise²), the part Monte Carlo cannot explain). The figures go to
docs/spectral-predictor.md, "Full range".

``--models NAME ...`` limits the random draws to those models, ``--no-presets`` leaves the presets
out: with ``--random 100 --rays 4000`` and a new ``--seed`` that is a fresh hold-out set of a
model, drawn independently of the one its configuration was chosen on.

Usage::

    python3 scripts/studies/full_range_check.py [--rays 10000] [--random 20] [--seed 7] [--models full-wet]
        [--no-presets]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import sandlight
from sandlight.predictor.bank import full_range_model
from sandlight.predictor.training import engine_simulate

BANDS_NM = ((350.0, 700.0), (700.0, 1300.0), (1300.0, 2500.0), (350.0, 2500.0))


def _rms(x: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.square(x))))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rays", type=int, default=10_000, help="rays per wavelength of the reference")
    parser.add_argument("--random", type=int, default=20, help="random samples from the model's domain")
    parser.add_argument("--seed", type=int, default=7, help="seed of the random draws and of the engine")
    parser.add_argument("--models", nargs="+", default=None, help="draw only from these models (default: all)")
    parser.add_argument("--no-presets", action="store_true", help="leave the presets out")
    args = parser.parse_args()

    bank = full_range_model()
    wl = bank.wavelengths_
    names = [m.name_ for m in bank.models]
    if args.models is not None and not set(args.models) <= set(names):
        parser.error(f"--models = {args.models!r} is not allowed: names among {names}")
    presets = {}
    if not args.no_presets:
        presets = {n: sandlight.SandSample.preset(n).to_dict() for n in sandlight.SandSample.presets()}
    drawn = {
        f"{model.name_} random {i}": s
        for model in bank.models
        if args.models is None or model.name_ in args.models
        for i, s in enumerate(model.domain_.draw(args.random, seed=10_000 + args.seed, design="random"))
    }
    print(
        f"full-range bank {[m.name_ for m in bank.models]}, {wl.size} wavelengths {wl[0]:g}–{wl[-1]:g} nm; "
        f"reference {args.rays} rays per wavelength, seed {args.seed}\n"
    )
    for model in bank.models:
        scores = model.holdout_scores_
        rms, noise = np.asarray(scores["rms_error"]), np.asarray(scores["mc_noise_rms"])
        cells = []
        for lo, hi in BANDS_NM:
            band = (wl >= lo) & (wl <= hi)
            total, floor = _rms(rms[band]), _rms(noise[band])
            cells.append(f"{lo:g}–{hi:g} nm {total:.4f} ({np.sqrt(max(total**2 - floor**2, 0.0)):.4f})")
        print(f"{model.name_} hold-out ({scores['n_samples']} samples), RMS (model error alone): " + "; ".join(cells))
    print()
    head = " | ".join(f"{lo:g}–{hi:g} nm" for lo, hi in BANDS_NM)
    print(f"| sample | model | RMS (model error alone): {head} | noise |\n|---|---|{'---|' * len(BANDS_NM)}---|")
    rows, start = [], time.perf_counter()
    for label, params in {**presets, **drawn}.items():
        ds = sandlight.predict(params, wl, mode="full-range", extrapolate=True)
        mc = engine_simulate(params, wl, rays=args.rays, seed=args.seed)
        diff = ds["reflectance"].values - mc.values
        cells = []
        for lo, hi in BANDS_NM:
            band = (wl >= lo) & (wl <= hi)
            rms, noise = _rms(diff[band]), _rms(mc.stderr[band])
            cells.append(f"{rms:.4f} ({np.sqrt(max(rms**2 - noise**2, 0.0)):.4f})")
        rows.append((label, diff, mc.stderr))
        flag = " (extrapolated)" if bool(ds["extrapolated"]) else ""
        print(f"| {label} | {ds['model'].values}{flag} | {' | '.join(cells)} | {_rms(mc.stderr):.4f} |", flush=True)
    for model in bank.models:
        mine = [(d, n) for label, d, n in rows if label.startswith(f"{model.name_} random")]
        if not mine:
            continue
        rms, noise = _rms(np.array([d for d, _ in mine])), _rms(np.array([n for _, n in mine]))
        print(
            f"\n{len(mine)} random samples of {model.name_}: RMS {rms:.4f}, reference noise {noise:.4f}, model "
            f"error alone {np.sqrt(max(rms**2 - noise**2, 0.0)):.4f}; largest |difference| "
            f"{max(np.max(np.abs(d)) for d, _ in mine):.3f}"
        )
    print(f"wall time {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
