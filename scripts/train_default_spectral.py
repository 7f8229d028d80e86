#!/usr/bin/env python3
"""Train the spectral model shipped with sandlight, and print the figures for the docs.

This is the documented command behind ``python/sandlight/data/models/spectral-default.npz``
(see docs/spectral-predictor.md). It needs the native engine (a built sandlight)::

    python scripts/train_default_spectral.py                      # local pool, one worker/CPU
    python scripts/train_default_spectral.py --dask-local 8
    python scripts/train_default_spectral.py --scheduler tcp://head:8786

It is resumable: interrupted (Ctrl-C, kill, a lost node), the same command continues from the
stored samples in ``--work-dir``. At the end it copies the model into the package data and
prints: the settings, k and the explained variance, the hold-out RMS and maximum error per
wavelength next to the Monte Carlo noise, the time taken, the machine, and the speed-up of
prediction over Monte Carlo at equal accuracy.
"""

from __future__ import annotations

import argparse
import shutil
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE_MODEL = ROOT / "python" / "sandlight" / "data" / "models" / "spectral-default.npz"


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--samples", type=int, default=3000, help="training samples (paper: 3000)")
    p.add_argument("--holdout", type=int, default=300, help="hold-out samples")
    p.add_argument("--rays", type=int, default=100_000, help="rays per sample and wavelength")
    p.add_argument("--wavelengths", default="400:700:20", help="nm, start:stop:step")
    p.add_argument("--seed", type=int, default=20240601, help="master seed")
    p.add_argument("--ridge", type=float, default=0.0, help="ridge penalty")
    p.add_argument("--forms", default="separate", choices=["separate", "onehot"])
    p.add_argument("--work-dir", type=Path, default=ROOT / "build" / "train-default-spectral",
                   help="job stores and intermediate files (resumable)")
    ex = p.add_mutually_exclusive_group()
    ex.add_argument("--workers", type=int, help="local worker processes")
    ex.add_argument("--dask-local", type=int, help="start a Dask LocalCluster of N workers")
    ex.add_argument("--scheduler", help="Dask scheduler address tcp://HOST:PORT")
    p.add_argument("--no-install", action="store_true",
                   help=f"do not copy the model to {PACKAGE_MODEL.relative_to(ROOT)}")
    return p.parse_args(argv)


def time_per_call(fn, repeat: int) -> float:
    best = float("inf")
    for _ in range(3):
        start = time.perf_counter()
        for _ in range(repeat):
            fn()
        best = min(best, (time.perf_counter() - start) / repeat)
    return best


def main(argv=None) -> int:
    args = parse_args(argv)
    import numpy as np

    import sandlight
    from sandlight.jobs import make_executor
    from sandlight.predictor import Domain, SpectralModel, train_spectral
    from sandlight.machine import describe as describe_machine
    from sandlight.predictor.training import engine_simulate, wavelength_grid

    executor = make_executor(args.workers, args.dask_local, args.scheduler)
    print(f"sandlight {sandlight.__version__}; machine: {describe_machine()}")
    print(f"training {args.samples} samples + {args.holdout} hold-out, {args.rays} rays, "
          f"wavelengths {args.wavelengths} nm, seed {args.seed}, executor "
          f"{executor.describe()}, work dir {args.work_dir}")
    start = time.perf_counter()
    run = train_spectral(args.work_dir, args.samples, args.rays, args.wavelengths, args.seed,
                         n_holdout=args.holdout, executor=executor,
                         model_params={"ridge": args.ridge, "forms": args.forms})
    total_s = time.perf_counter() - start
    model, report = run.model, run.report

    k = model.n_components_
    ratio, signal = model.explained_variance_ratio_, model.signal_variance_ratio_
    print(f"\nprincipal components: k = {k}")
    print("  explained variance (raw):    " + ", ".join(f"{r:.5%}" for r in ratio[:k])
          + f"  -> {ratio[:k].sum():.4%}")
    if signal is not None:
        print("  explained variance (signal): " + ", ".join(f"{r:.5%}" for r in signal[:k])
              + f"  -> {signal[:k].sum():.4%}")
    print(f"training RMS error {model.training_rms_:.5f} (PCA truncation floor "
          f"{model.reconstruction_rms_:.5f})\n")
    print(report.table())
    print(f"\nwall time of this run: {total_s:.0f} s (generation {run.generation_s:.0f} s, fit "
          f"{run.fit_s:.1f} s); a resumed run counts only its own part")

    # Speed-up at equal accuracy: Monte Carlo noise falls as 1/√rays, so reaching the model's
    # error ε needs rays·(σ/ε)² rays, σ the noise at `rays`, and its cost scales with the rays.
    # ε is the hold-out RMS error against Monte Carlo, an upper bound of the model's error
    # (it includes the reference's noise): the speed-up printed is a lower bound.
    wl = wavelength_grid(args.wavelengths)
    samples = Domain.default().draw(3, seed=args.seed + 1, design="random")
    mc_s = time_per_call(lambda: [engine_simulate(s, wl, rays=args.rays, seed=1)
                                  for s in samples], 1) / len(samples)
    error = report.rms_error_overall
    noise = float(np.sqrt(np.mean(report.mc_noise_rms**2)))
    rays_equal = args.rays * (noise / error) ** 2
    mc_equal_s = mc_s * rays_equal / args.rays
    one = samples[0]
    single_s = time_per_call(lambda: model.predict(one), 2000)
    print(f"\nMonte Carlo: {mc_s:.3f} s per sample at {args.rays} rays (noise {noise:.5f}); "
          f"hold-out RMS error {error:.5f} (model error alone ≈ "
          f"{float(np.sqrt(np.mean(report.model_error_estimate**2))):.5f})")
    print(f"equal accuracy needs ≈ {rays_equal:.3g} rays, {mc_equal_s:.3g} s per sample; "
          f"prediction takes {single_s * 1e6:.0f} µs per call: speed-up ≥ "
          f"{mc_equal_s / single_s:.3g}×")

    if not args.no_install:
        from sandlight.io import write_atomically

        write_atomically(PACKAGE_MODEL, lambda tmp: shutil.copyfile(run.model_path, tmp))
        SpectralModel.load(PACKAGE_MODEL)  # the installed file reads back
        print(f"\ninstalled {PACKAGE_MODEL}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
