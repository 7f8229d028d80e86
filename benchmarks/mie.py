"""Cost of the Lorenz–Mie solver (docs/transport.md, "Fine particles: Lorenz–Mie"): a benchmark
script, not a test.

For size parameters x = 10, 100 and 1000 and two indices (quartz 1.54 + 1e-8i, hematite
3.0 + 0.5i, in air) it prints, on one thread,

* the time of one efficiency evaluation (Q_ext, Q_sca, Q_abs, g, albedo), from a vectorised call
  over many identical spheres, so the Python overhead is spread over them;
* the time to build the phase-function sampling table (``sandlight.physics.mie.phase_table``:
  the series, the table's nodes and values, the cumulative distribution) and its node count;
* the time of one phase-function evaluation at one angle.

Every figure is the best of ``--repeats`` runs (other processes may share the machine); the
machine and load average are printed. Nothing is asserted.

Usage::

    python benchmarks/mie.py [--repeats 5]
"""

from __future__ import annotations

import argparse
import os
import platform
import time

import numpy as np

import sandlight
from sandlight.machine import cpu_model
from sandlight.physics import mie

SIZES = (10.0, 100.0, 1000.0)
INDICES = {"quartz": 1.54 + 1e-8j, "hematite": 3.0 + 0.5j}
TARGET_SECONDS = 0.2
ANGLES = np.linspace(-1.0, 1.0, 4096)


def load_average() -> str:
    try:
        return "{:.2f} {:.2f} {:.2f}".format(*os.getloadavg())
    except OSError:
        return "n/a"


def best_time(call, repeats: int) -> float:
    """Shortest wall time of ``repeats`` calls, in s."""
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        call()
        times.append(time.perf_counter() - t0)
    return min(times)


def per_item(make_call, repeats: int) -> float:
    """Seconds per item of ``make_call(n)``, with n grown until one call takes TARGET_SECONDS."""
    n = 1
    while True:
        t = best_time(make_call(n), 1)
        if t >= TARGET_SECONDS:
            return best_time(make_call(n), repeats) / n
        n *= 4


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    print(f"sandlight {sandlight.__version__}, {platform.python_implementation()} {platform.python_version()}")
    print(f"CPU: {cpu_model()}, {os.cpu_count()} logical cores; load average {load_average()}")
    print(f"{'material':<10}{'x':>7}{'terms':>7}{'efficiencies':>15}{'table':>12}{'nodes':>8}{'p(mu)':>12}")
    for name, m in INDICES.items():
        for x in SIZES:
            eff = per_item(lambda n, m=m, x=x: lambda: mie.mie_efficiencies(np.full(n, m), x), args.repeats)
            table = best_time(lambda m=m, x=x: mie.phase_table(m, x), args.repeats)
            nodes = mie.phase_table(m, x).mu.size
            # Phase function per angle: the cost of solving the series once subtracted.
            p_time = best_time(lambda m=m, x=x: mie.phase_function(m, x, ANGLES), args.repeats)
            p_time = (p_time - eff) / ANGLES.size
            terms = int(x + 6 * x ** (1 / 3) + 3)
            print(
                f"{name:<10}{x:>7g}{terms:>7d}{eff * 1e6:>12.1f} µs{table * 1e3:>9.2f} ms{nodes:>8d}"
                f"{p_time * 1e6:>9.2f} µs"
            )
    print(f"load average after: {load_average()}")


if __name__ == "__main__":
    main()
