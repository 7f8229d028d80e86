#!/usr/bin/env python3
"""A shipped model against a fresh hold-out set at many rays (issue 23's proof: 10⁵+ rays).

The hold-out sets made with the models (``scripts/data/train_default_spectral.py``) run at a few
thousand rays, so their own Monte Carlo noise is part of the RMS they print and the model's error
is estimated by subtracting it. This draws ``--samples`` new samples at random from the model's
own domain (``--seed``, one the training never used), runs the default engine at ``--rays`` rays
per wavelength at the model's wavelengths, and prints the model's errors against them per
wavelength with the reference noise beside, and over the whole grid. The set is stored in
``--work-dir`` and is resumable: interrupted (Ctrl-C), the same command continues; run again after
a refit, it only re-evaluates. Figures in docs/spectral-predictor.md ("Broad models")::

    python scripts/studies/precise_holdout.py --model broad-dry --samples 200 --rays 100000
    python scripts/studies/precise_holdout.py --model broad-wet --model-file WORK/broad-wet/spectral-model.npz
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--model", default="broad-dry", help="name of the shipped model (default broad-dry)")
    p.add_argument("--model-file", type=Path, help="evaluate this model file instead of the shipped one")
    p.add_argument("--samples", type=int, default=200, help="hold-out samples (default 200)")
    p.add_argument("--rays", type=int, default=100_000, help="rays per wavelength (default 10⁵)")
    p.add_argument("--seed", type=int, default=31, help="seed of the draws and of the engine (default 31)")
    p.add_argument("--workers", type=int, default=None, help="worker processes (default: one per CPU)")
    p.add_argument("--work-dir", type=Path, default=ROOT / "build" / "precise-holdout")
    args = p.parse_args()
    for name in ("samples", "rays"):
        if getattr(args, name) < 1:
            p.error(f"--{name} = {getattr(args, name)!r} is not allowed: an integer >= 1")

    from sandlight.jobs.executors import LocalExecutor
    from sandlight.predictor import SpectralModel, evaluate, generate_training_set
    from sandlight.predictor.bank import default_model_dir

    path = args.model_file or default_model_dir() / f"spectral-{args.model}.npz"
    if not path.is_file():
        p.error(f"--model = {args.model!r}: no model file {path}")
    model = SpectralModel.load(path)
    store = args.work_dir / f"{model.name_}-{args.samples}x{args.rays}-seed{args.seed}"
    start = time.perf_counter()
    status = generate_training_set(
        store,
        args.samples,
        model.wavelengths_,
        args.rays,
        args.seed,
        LocalExecutor(args.workers),
        domain=model.domain_,
        design="random",
        memory=model.memory_,
    )
    if status.dataset_path is None:
        raise SystemExit(f"the hold-out set in {store} is not complete; run the same command again to continue")
    report = evaluate(model, status.dataset_path)
    rms, noise = report.rms_error_overall, float(np.sqrt(np.mean(report.mc_noise_rms**2)))
    print(f"{model.name_} ({path}) against {args.samples} samples at {args.rays} rays, seed {args.seed}")
    print(report.table())
    print(
        f"over {model.wavelengths_[0]:g}–{model.wavelengths_[-1]:g} nm: RMS {rms:.4f}, reference noise {noise:.4f}, "
        f"model error alone {np.sqrt(max(rms**2 - noise**2, 0.0)):.4f}; "
        f"largest error {report.max_error_overall:.3f}; wall time {time.perf_counter() - start:.0f} s"
    )


if __name__ == "__main__":
    main()
