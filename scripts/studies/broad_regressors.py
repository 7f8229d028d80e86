#!/usr/bin/env python3
"""The broad dry model's regression: the paper's cubic against networks, on the same data.

Fits each regressor on the stored training set of ``broad-dry`` (made by
``scripts/data/train_default_spectral.py --only broad-dry``) and scores it on that model's
hold-out set; prints, per regressor, the hold-out RMS error, the model error alone (the hold-out
set's own Monte Carlo noise removed), the largest error, the mean bias at 400 and 700 nm and the
fit time (docs/spectral-predictor.md, "Broad models"; prediction speed: benchmarks/predict.py)::

    python scripts/studies/broad_regressors.py --work-dir build/train-default-spectral
    python scripts/studies/broad_regressors.py --work-dir DIR --ensembles 1 4 --no-cubic
    python scripts/studies/broad_regressors.py --work-dir DIR --ensembles 1 --no-cubic --samples 2500 5000
    python scripts/studies/broad_regressors.py --work-dir DIR --ensembles 1 4 --no-cubic --layers 3

``--samples`` fits on the first N training samples only (how the error falls with the set's size);
``--layers`` and ``--units`` set the networks' depth and width (default 2 × 128, the shipped ones).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--work-dir", type=Path, default=ROOT / "build" / "train-default-spectral")
    p.add_argument("--ensembles", type=int, nargs="*", default=[1, 4], help="network ensemble sizes to fit")
    p.add_argument("--no-cubic", action="store_true", help="skip the cubic")
    p.add_argument("--layers", type=int, default=2, help="hidden layers of the networks (default 2)")
    p.add_argument("--units", type=int, default=128, help="units per hidden layer (default 128)")
    p.add_argument("--samples", type=int, nargs="*", default=[], help="also fit on the first N training samples")
    args = p.parse_args()
    for name in ("layers", "units"):
        if getattr(args, name) < 1:
            p.error(f"--{name} = {getattr(args, name)!r} is not allowed: an integer >= 1")
    if any(n < 2 for n in args.samples):
        p.error(f"--samples = {args.samples!r} is not allowed: integers >= 2")

    import xarray as xr

    from sandlight.predictor import SpectralModel, evaluate

    store = args.work_dir / "broad-dry"
    candidates = [] if args.no_cubic else [("cubic (degree 3, k = 8)", {"degree": 3, "n_components": 8})]
    network = {"regressor": "network", "n_components": 8, "hidden_units": args.units, "hidden_layers": args.layers}
    candidates += [
        (f"network {args.layers} × {args.units} tanh, ensemble {e} (k = 8)", {**network, "ensemble": e})
        for e in args.ensembles
    ]
    print(f"training set {store / 'training'}; hold-out set {store / 'holdout'}")
    print("| regression | training samples | hold-out RMS | model error alone | max | bias 400 / 700 nm | fit |")
    print("|---|---|---|---|---|---|---|")
    with xr.open_dataset(store / "training" / "dataset.nc") as ds:
        training = ds.load()
    total = training.sizes["sample"]
    sizes = sorted({n for n in args.samples if n < total}) + [total]
    for label, params in candidates:
        for n in sizes:
            start = time.perf_counter()
            model = SpectralModel(**params).fit(training.isel(sample=slice(0, n)), name="broad-dry")
            fit_s = time.perf_counter() - start
            report = evaluate(model, store / "holdout" / "dataset.nc")
            alone = float(np.sqrt(max(np.mean(report.rms_error**2 - report.mc_noise_rms**2), 0.0)))
            print(
                f"| {label} | {n} | {report.rms_error_overall:.4f} | {alone:.4f} | {report.max_error_overall:.3f} | "
                f"{report.mean_error[0]:+.4f} / {report.mean_error[-1]:+.4f} | {fit_s:.0f} s |",
                flush=True,
            )


if __name__ == "__main__":
    main()
