"""Speed and memory of the virtual goniophotometer (prints figures; asserts nothing).

    python3 benchmarks/gonio.py [--rays 1e6] [--preset NAME]

Prints trials per second with 1 and 2 threads for the default sample (``SandSample()``) at
550 nm on the paper's 901-patch hemisphere, the projected time for 10⁸ trials, the memory of one
counter set and the process's peak resident memory.
"""

from __future__ import annotations

import argparse
import os
import platform
import resource
import time

import sandlight
from sandlight.gonio.measure import brdf
from sandlight.sample import SandSample


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--rays", type=float, default=1e6)
    ap.add_argument("--preset", default=None, help="a preset instead of the default sample")
    args = ap.parse_args()
    sample = SandSample.preset(args.preset) if args.preset else SandSample()
    n = int(args.rays)
    print(
        f"sandlight {sandlight.__version__} on {platform.processor() or platform.machine()}, "
        f"{os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f}"
    )
    print(f"sample: {args.preset or 'default SandSample()'}, 550 nm, 31 × 30 = 901 patches, {n:,} trials")
    rates = {}
    for threads in (1, 2):
        best = float("inf")
        for _ in range(2):
            t0 = time.perf_counter()
            result = brdf(sample, 550.0, rays=n, seed=1, threads=threads, progress=False)
            best = min(best, time.perf_counter() - t0)
        rates[threads] = n / best
        print(f"  {threads} thread(s): {rates[threads]:,.0f} trials/s (best of 2: {best:.2f} s)")
    r = result.hemisphere.n_patches
    counter_mb = (r * r + 3 * r) * 8 / 1e6
    print(f"1 → 2 threads speed-up: {rates[2] / rates[1]:.2f}×")
    print(f"projected time for 1e8 trials with 2 threads: {1e8 / rates[2] / 60:.1f} min")
    print(f"one counter set: {counter_mb:.1f} MB ({r}×{r} uint64 + 3 per-patch counters)")
    print(f"peak resident memory of this process: {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MB")
    print(f"normal-incidence reflectance of the last run: {result.normal_reflectance:.4f}")


if __name__ == "__main__":
    main()
