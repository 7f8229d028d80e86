"""Speed and memory of the virtual goniophotometer (prints figures; asserts nothing).

    python3 benchmarks/gonio.py [--rays 1e6] [--preset NAME] [--spectral-rays 1e6]

Prints trials per second with 1 and 2 threads for the default sample (``SandSample()``) at
550 nm on the paper's 901-patch hemisphere, the projected time for 10⁸ trials, the memory of one
counter set and the process's peak resident memory; then the time of 16 wavelengths 400–700 nm
measured with shared paths and wavelength by wavelength (``share=False``), side by side (one run
each, 2 threads) with their ratio and the memory of the shared sums: with uniform incidence
(``brdf``), then with light from 30° (``fixed_incidence``, the classic instrument).
"""

from __future__ import annotations

import argparse
import os
import platform
import resource
import time

import numpy as np

import sandlight
from sandlight.gonio.measure import MAX_GONIO_GROUP, _zero_sums, brdf, fixed_incidence
from sandlight.sample import SandSample

#: Settings of every 16-wavelength run.
SPECTRAL = {"seed": 1, "threads": 2, "progress": False}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--rays", type=float, default=1e6)
    ap.add_argument("--preset", default=None, help="a preset instead of the default sample")
    ap.add_argument("--spectral-rays", type=float, default=1e6, help="trials per wavelength of the 16-wavelength runs")
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
    n = int(args.spectral_rays)
    spectral("uniform incidence", lambda wl, share: brdf(sample, wl, rays=n, share=share, **SPECTRAL), n, r * r)
    fixed = {"incidence_deg": 30.0, "rays": n, **SPECTRAL}
    spectral("fixed incidence 30°", lambda wl, share: fixed_incidence(sample, wl, share=share, **fixed), n, r)


def spectral(instrument: str, measure, n: int, cells: int) -> None:
    """Shared and independent measurements ``measure(wavelengths, share)`` of 16 wavelengths
    400–700 nm, side by side; ``cells`` (incoming, outgoing) patch pairs per wavelength."""
    wl = np.linspace(400.0, 700.0, 16)
    print(f"{instrument}: 16 wavelengths 400–700 nm, {n:,} trials each, 2 threads, one run each:")
    seconds = {}
    for share in (True, False):
        t0 = time.perf_counter()
        results = measure(wl, share)
        seconds[share] = time.perf_counter() - t0
        shared = results[0].squares is not None
        rate = 16 * n / seconds[share]
        print(f"  share={share}: {seconds[share]:.1f} s ({rate:,.0f} wavelength-trials/s, shared: {shared})")
    ratio = seconds[True] / seconds[False]
    print(f"shared / independent time: {ratio:.2f} (speed-up {1 / ratio:.2f}×)")
    group = min(16, MAX_GONIO_GROUP)
    one = _zero_sums(1, 1, 1)  # the arrays of one (incoming, outgoing, wavelength) cell
    per_cell = one["escaped"].nbytes + one["squares"].nbytes
    print(
        f"shared sums of a group of {group}: {per_cell * cells * group / 1e6:.2f} MB "
        f"({per_cell} bytes per in × out × wavelength)"
    )
    print(f"peak resident memory of this process: {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MB")


if __name__ == "__main__":
    main()
