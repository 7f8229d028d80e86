#!/usr/bin/env python3
"""Speed of the spectral predictor: spectra per second (batched) and single-call latency.

Targets (issue 5): ≥ 1 million spectra per second on one core for batched input, ≤ 1 ms for a
single call. Run on one core::

    python benchmarks/predict.py                       # every shipped model, and the bank
    python benchmarks/predict.py --model out/spectral-model.npz
    python benchmarks/predict.py --bank-only --models-dir DIR  # the bank of DIR's spectral-*.npz
    python benchmarks/predict.py --synthetic           # no model needed: a model of the
                                                       # broad model's shape (13 parameters,
                                                       # 3 forms, k = 6, 16 wavelengths)
"""

from __future__ import annotations

import os

# One core: BLAS must not spread the matrix products over threads (set before numpy loads).
for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402


def synthetic_model():
    """A model fitted to smooth synthetic spectra over the default domain (shape only)."""
    import numpy as np

    from sandlight.predictor import Domain, SpectralModel

    domain = Domain.default()
    values, codes = domain.draw_arrays(3000, seed=1)
    X = domain.scaled(values)
    wl = np.arange(400.0, 701.0, 20.0)
    B = np.random.default_rng(0).standard_normal((X.shape[1], 6))
    R = 0.4 + 0.05 * np.tanh(X @ B) @ np.random.default_rng(1).standard_normal((6, wl.size))
    return SpectralModel(n_components=6).fit(values, R, wavelengths_nm=wl, domain=domain, forms=codes, name="synthetic")


def best_time(fn, repeat: int, rounds: int = 5) -> float:
    """Best mean time per call over a few rounds (least disturbed by other load)."""
    best = float("inf")
    for _ in range(rounds):
        start = time.perf_counter()
        for _ in range(repeat):
            fn()
        best = min(best, (time.perf_counter() - start) / repeat)
    return best


def bench_model(model, batch: int) -> None:
    """Batched and single-call speed of one SpectralModel on draws from its own domain."""
    import numpy as np

    domain = model.domain_
    X, codes = domain.draw_arrays(batch, seed=7, design="random")
    regression = (
        f"network {model.ensemble} × {model.hidden_layers} × {model.hidden_units} "
        f"({model.network_.n_parameters} weights)"
        if model.regressor == "network"
        else f"({model.forms}), degree {model.degree}, {model.powers_.shape[0]} monomials"
    )
    print(
        f"model {model.name_}: {len(model.parameter_names_)} parameters, forms {model.forms_} {regression}, "
        f"k = {model.n_components_}, {model.wavelengths_.size} wavelengths"
    )
    batched = best_time(lambda: model.predict(X, codes), 1, rounds=3)
    one_form = best_time(lambda: model.predict(X, np.zeros_like(codes)), 1, rounds=3)
    print(f"  batched ({batch} spectra, mixed forms): {batch / batched:,.0f} spectra/s")
    print(f"  batched ({batch} spectra, one form):    {batch / one_form:,.0f} spectra/s")
    row, code = X[:1], codes[:1]
    print(f"  single call, array input:  {best_time(lambda: model.predict(row, code), 2000) * 1e6:.0f} µs")
    sample = domain.draw(1, seed=8)[0]
    print(f"  single call, dict input:   {best_time(lambda: model.predict(sample), 2000) * 1e6:.0f} µs")


def bench_bank(bank, batch: int) -> None:
    """The bank: routing plus prediction, for named input drawn from each model's domain."""
    import numpy as np

    print(f"bank {[m.name_ for m in bank.models]}:")
    per_model = -(-batch // len(bank.models))
    columns: dict = {}
    for m in bank.models:  # equal shares of samples inside each model's domain
        draws = m.domain_.draw(per_model, seed=9, design="random")
        for key in draws[0]:
            columns.setdefault(key, []).extend(d[key] for d in draws)
    names = sorted(columns)
    table = np.empty(len(columns[names[0]]), dtype=[(n, "U16" if n == "iron_oxide_form" else "f8") for n in names])
    for n in names:
        table[n] = columns[n]
    n = table.shape[0]
    batched = best_time(lambda: bank.predict(table), 1, rounds=3)
    print(f"  batched ({n} spectra as a structured array, every model): {n / batched:,.0f} spectra/s")
    try:
        from sandlight.sample import SandSample
    except ImportError:
        return
    for m in bank.models:
        sand = SandSample(**m.domain_.draw(1, seed=8)[0])
        seconds = best_time(lambda sand=sand: bank.predict(sand), 2000)
        print(f"  single call, SandSample of {m.name_}: {seconds * 1e6:.0f} µs")


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    source = p.add_mutually_exclusive_group()
    source.add_argument("--model", help="model file (default: the shipped models)")
    source.add_argument("--synthetic", action="store_true", help="fit a synthetic model")
    p.add_argument("--batch", type=int, default=1_000_000, help="spectra per batched call")
    p.add_argument("--bank-only", action="store_true", help="time the bank only, not each of its models")
    p.add_argument(
        "--models-dir",
        type=Path,
        help="bank the spectral-*.npz files of this directory instead of the shipped ones (e.g. another commit's)",
    )
    args = p.parse_args(argv)

    from sandlight.predictor import SpectralModel, default_model
    from sandlight.predictor.bank import banks_by_grid

    if args.synthetic or args.model:
        bench_model(synthetic_model() if args.synthetic else SpectralModel.load(args.model), args.batch)
        return 0
    if args.models_dir is None:
        bank = default_model()
    else:
        paths = sorted(args.models_dir.glob("spectral-*.npz"))
        if not paths:
            p.error(f"--models-dir = {str(args.models_dir)!r}: no spectral-*.npz file there")
        bank = banks_by_grid(SpectralModel.load(path) for path in paths)[0]  # the paper's 16 wavelengths
    if not args.bank_only:
        for model in bank.models:
            bench_model(model, args.batch)
    bench_bank(bank, args.batch)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
