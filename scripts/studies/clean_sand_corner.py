#!/usr/bin/env python3
"""The broad models at the clean-sand corner of their domains, against fresh Monte Carlo.

Clean quartz sand (iron oxide, magnetite, silt and clay all 0, like the ``ottawa-quartz``
preset) is a corner of the broad domains where few training draws lie, so the hold-out sets
(random draws) say little about it. This draws ``--random`` samples from each broad model's
domain with those four parameters set to 0, adds ``ottawa-quartz`` (dry for ``broad-dry``,
saturation 0.5 for ``broad-wet``), runs the default engine at ``--rays`` rays per wavelength and
prints, per sample and over all, the RMS of prediction − Monte Carlo next to the reference's
noise (docs/spectral-predictor.md, "Broad models", "Corners of the domain")::

    python3 scripts/studies/clean_sand_corner.py [--rays 20000] [--random 24] [--seed 78] [--models broad-dry]
"""

from __future__ import annotations

import argparse

import numpy as np

import sandlight
from sandlight.predictor.bank import default_model
from sandlight.predictor.domain import CLEAN_SAND
from sandlight.predictor.training import engine_simulate

CLEAN = {**CLEAN_SAND, "sand": 1.0}
#: The broad models and the saturation of their ottawa-quartz.
SATURATION = {"broad-dry": 0.0, "broad-wet": 0.5}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rays", type=int, default=20_000, help="rays per wavelength of the reference")
    parser.add_argument("--random", type=int, default=24, help="random clean samples per model")
    parser.add_argument("--seed", type=int, default=78, help="seed of the draws and of the engine")
    parser.add_argument(
        "--models", nargs="+", choices=list(SATURATION), default=list(SATURATION), help="the broad models to check"
    )
    args = parser.parse_args()
    for name in ("rays", "random"):
        if getattr(args, name) < 1:
            parser.error(f"--{name} = {getattr(args, name)!r} is not allowed: an integer >= 1")

    bank = default_model()
    print(f"reference: {args.rays} rays per wavelength, seed {args.seed}\n")
    print("| model | sample | form | grain size (mm) | saturation | RMS | reference noise |")
    print("|---|---|---|---|---|---|---|")
    for name in args.models:
        saturation, model = SATURATION[name], bank.model(name)
        rows = [{**r, **CLEAN} for r in model.domain_.draw(args.random, seed=args.seed, design="random")]
        ottawa = sandlight.SandSample.preset("ottawa-quartz").replace(saturation=saturation)
        samples = [(f"random {i}", sandlight.SandSample.from_dict(r)) for i, r in enumerate(rows)]
        samples.append(("ottawa-quartz", ottawa))
        errors, noises = [], []
        for label, sample in samples:
            mc = engine_simulate(sample.to_dict(), model.wavelengths_, rays=args.rays, seed=args.seed)
            predicted = model.predict([sample], extrapolate=True)[0]
            errors.append(float(np.sqrt(np.mean((predicted - mc.values) ** 2))))
            noises.append(float(np.sqrt(np.mean(mc.stderr**2))))
            print(
                f"| {name} | {label} | {sample.iron_oxide_form} | {sample.grain_size:.3f} | {sample.saturation:.2f} "
                f"| {errors[-1]:.4f} | {noises[-1]:.4f} |",
                flush=True,
            )
        rms, noise = float(np.sqrt(np.mean(np.square(errors)))), float(np.sqrt(np.mean(np.square(noises))))
        print(
            f"\n{name}: {len(samples)} clean samples, RMS {rms:.4f} (model error alone "
            f"{np.sqrt(max(rms**2 - noise**2, 0.0)):.4f}), largest {max(errors):.4f}; ottawa-quartz "
            f"{errors[-1]:.4f}\n"
        )


if __name__ == "__main__":
    main()
