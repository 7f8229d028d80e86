#!/usr/bin/env python3
"""The broad models' regression: the paper's cubic against networks, on the same data.

Fits each regressor on the stored training set of a broad or full-range model (``--model``,
default ``broad-dry``; made by ``scripts/data/train_default_spectral.py --only NAME``) and scores
it on that model's hold-out set; prints, per regressor, the hold-out RMS error, the model error
alone (the hold-out set's own Monte Carlo noise removed), the largest error, the mean bias at the
first and last wavelength and the fit time (docs/spectral-predictor.md, "Broad models" and "Full
range"; prediction speed: benchmarks/predict.py)::

    python scripts/studies/broad_regressors.py --work-dir build/train-default-spectral
    python scripts/studies/broad_regressors.py --work-dir DIR --ensembles 1 4 --no-cubic
    python scripts/studies/broad_regressors.py --work-dir DIR --ensembles 1 --no-cubic --samples 2500 5000
    python scripts/studies/broad_regressors.py --work-dir DIR --ensembles 1 4 --no-cubic --layers 3
    python scripts/studies/broad_regressors.py --work-dir DIR --model full-wet --ensembles 4 --no-cubic \
        --layers 3 --components 8 12 16 --rates 1e-3 1e-4 1e-5 --truncation

``--samples`` fits on the first N training samples only (how the error falls with the set's size);
``--layers`` and ``--units`` set the networks' depth and width (default 2 × 128, the broad models'
recipe before 2026-12-07; now 3 × 128 with stepped rates, stopping on the error); ``--components``
the numbers k of principal components to try (default 8); ``--rates`` Adam's learning rate per
stage (default one stage at 10⁻³); ``--validation`` what early stopping follows (``r2``, the
default, or ``error``; ``SpectralModel.network_validation``); ``--physical no yes`` fits the
networks without and with the physical inputs (``SpectralModel.physical_inputs``); ``--truncation`` also prints the RMS
that keeping k components alone leaves on the hold-out spectra, with the part of it the Monte Carlo
noise explains removed.
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
    p.add_argument("--model", default="broad-dry", help="the stored model whose sets to use (default broad-dry)")
    p.add_argument("--components", type=int, nargs="+", default=[8], help="numbers k of components (default 8)")
    p.add_argument("--rates", type=float, nargs="+", default=[1e-3], help="Adam's rate per stage (default 1e-3)")
    p.add_argument(
        "--validation",
        choices=("r2", "error"),
        nargs="+",
        default=["r2"],
        help="what the networks' early stopping follows (SpectralModel.network_validation; default r2)",
    )
    p.add_argument(
        "--physical",
        choices=("no", "yes"),
        nargs="+",
        default=["no"],
        help="networks without and/or with the physical inputs (SpectralModel.physical_inputs; default no)",
    )
    p.add_argument("--truncation", action="store_true", help="print the PCA truncation error per k first")
    args = p.parse_args()
    for name in ("layers", "units"):
        if getattr(args, name) < 1:
            p.error(f"--{name} = {getattr(args, name)!r} is not allowed: an integer >= 1")
    if any(n < 2 for n in args.samples):
        p.error(f"--samples = {args.samples!r} is not allowed: integers >= 2")

    import xarray as xr

    from sandlight.predictor import SpectralModel, evaluate
    from sandlight.predictor.physical_inputs import PHYSICAL_INPUTS

    store = args.work_dir / args.model
    network = {
        "regressor": "network",
        "hidden_units": args.units,
        "hidden_layers": args.layers,
        "learning_rates": tuple(args.rates),
    }
    rates = "" if len(args.rates) == 1 else f", rates {' → '.join(f'{r:g}' for r in args.rates)}"
    candidates = []
    for k in args.components:
        if not args.no_cubic:
            candidates.append((f"cubic (degree 3, k = {k})", {"degree": 3, "n_components": k}))
        candidates += [
            (
                f"network {args.layers} × {args.units} tanh{', physical inputs' if f == 'yes' else ''}, "
                f"ensemble {e} (k = {k}{rates}, stopping on {v})",
                {
                    **network,
                    "ensemble": e,
                    "n_components": k,
                    "network_validation": v,
                    "physical_inputs": PHYSICAL_INPUTS if f == "yes" else (),
                },
            )
            for f in args.physical
            for e in args.ensembles
            for v in args.validation
        ]
    print(f"training set {store / 'training'}; hold-out set {store / 'holdout'}")
    with xr.open_dataset(store / "training" / "dataset.nc") as ds:
        training = ds.load()
    if args.truncation:
        print_truncation(training, store / "holdout" / "dataset.nc", args.components)
    wl = training["wavelength"].values
    print(
        f"| regression | training samples | hold-out RMS | model error alone | max | bias {wl[0]:g} / {wl[-1]:g} nm "
        "| fit |"
    )
    print("|---|---|---|---|---|---|---|")
    total = training.sizes["sample"]
    sizes = sorted({n for n in args.samples if n < total}) + [total]
    for label, params in candidates:
        for n in sizes:
            start = time.perf_counter()
            model = SpectralModel(**params).fit(training.isel(sample=slice(0, n)), name=args.model)
            fit_s = time.perf_counter() - start
            report = evaluate(model, store / "holdout" / "dataset.nc")
            alone = float(np.sqrt(max(np.mean(report.rms_error**2 - report.mc_noise_rms**2), 0.0)))
            print(
                f"| {label} | {n} | {report.rms_error_overall:.4f} | {alone:.4f} | {report.max_error_overall:.3f} | "
                f"{report.mean_error[0]:+.4f} / {report.mean_error[-1]:+.4f} | {fit_s:.0f} s |",
                flush=True,
            )


def print_truncation(training, holdout_path: Path, components: list[int]) -> None:
    """RMS left on the hold-out spectra by their projection on the training set's first k
    principal directions, and that RMS with the hold-out noise the projection keeps removed:
    of a noise of variance σ² per value, k of the W dimensions stay, so the part of the
    residual that is truncated signal is √(RMS² − σ²(1 − k/W))."""
    import xarray as xr

    R = training["reflectance"].values
    with xr.open_dataset(holdout_path) as ds:
        H, noise = ds["reflectance"].values, float(np.mean(ds["stderr"].values ** 2))
    mean = R.mean(axis=0)
    directions = np.linalg.svd(R - mean, full_matrices=False)[2]
    print("| k | RMS left by k components | truncated signal |\n|---|---|---|")
    for k in sorted({*components, 4, 6, 8, 10, 12, 16, 20}):
        V = directions[:k]
        left = float(np.sqrt(np.mean(((H - mean) @ V.T @ V + mean - H) ** 2)))
        signal = np.sqrt(max(left**2 - noise * (1 - k / H.shape[1]), 0.0))
        print(f"| {k} | {left:.4f} | {signal:.4f} |")
    print()


if __name__ == "__main__":
    main()
