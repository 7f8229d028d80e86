"""Speed of sandlight.fit (prints figures; asserts nothing).

    python3 benchmarks/fit.py [--engine]

Prints wall-clock and CPU seconds (best of ``--repeat``) of, on one core (``threads=1``):

- a bank fit of three parameters (iron oxide, hematite ratio, saturation) of a noisy predictor
  spectrum, noise estimated, Laplace posterior, no engine check (target ≤ 1 s);
- the same with the engine check at the optimum (2·10⁴ rays per wavelength);
- the full posterior by emcee (3000 steps, noise estimated: four dimensions; target ≤ 30 s);
- with ``--engine``: an engine fit of the same three parameters at 5000 rays per wavelength.
"""

from __future__ import annotations

import argparse
import os
import platform

import numpy as np
from _timing import best_of

import sandlight
from sandlight.predictor import default_model

FREE = ["iron_oxide", "hematite_ratio", "saturation"]


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--engine", action="store_true", help="Also time an engine fit (about a minute).")
    args = parser.parse_args(argv)
    bank = default_model()
    truth = sandlight.SandSample(iron_oxide=0.01, hematite_ratio=0.3, saturation=0.4)
    wl = bank.wavelengths_
    spectrum = (wl, bank.predict([truth])[0] + np.random.default_rng(0).normal(0.0, 0.005, wl.size))
    sandlight.fit(spectrum, FREE, check_rays=0)  # imports, model loading
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} CPUs (threads=1 here)")
    cases = [
        ("bank fit, Laplace, no engine check", dict(check_rays=0)),
        ("bank fit, Laplace, engine check 2e4 rays", dict(check_rays=20_000, threads=1)),
        ("bank fit, emcee posterior (3000 steps)", dict(check_rays=0, posterior="emcee")),
    ]
    if args.engine:
        cases.append(("engine fit, 5000 rays, Laplace", dict(method="engine", rays=5000, threads=1)))
    for label, kw in cases:
        repeat = 1 if kw.get("method") == "engine" else args.repeat
        wall, cpu = best_of(lambda kw=kw: sandlight.fit(spectrum, FREE, **kw), repeat)
        print(f"{label:45s} {wall:7.2f} s wall, {cpu:7.2f} s CPU (best of {repeat})")


if __name__ == "__main__":
    main()
