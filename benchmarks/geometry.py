"""Cost of explicit geometry and of path memory against the on-the-fly engine (issue 9, item 5):
a benchmark, not a test.

For each sample (default: issue 9's monodisperse spheres at α = 5 cm⁻¹, and the ``red-dune``
preset) and, for a preset, each of ``--wavelengths`` (default 450, 550, 650 and 850 nm: dark to
bright sand, 1 to 65 grains met per ray), it traces the same rays (same seed, normal incidence)
with

* the on-the-fly engine, ``memory="none"`` (the classic model), ``memory="cut"`` and
  ``memory="packed"``,
* the explicit reference (packing generated with the default box and seed 1),

each in a fresh Python process, and prints rays per second (best of ``--repeats`` runs), grains
met per ray, nanoseconds per grain met, the time to generate the packing, the packing's own size
and the peak resident memory the process gained over its state after ``import sandlight``
(``ru_maxrss``). Ratios are printed per ray (the cost of a reflectance at equal rays) and per
grain met (the cost of the transport step alone: path memory changes how many grains a ray meets,
towards the explicit count), and for a preset over the whole sweep (total time of the same rays
at every wavelength, as a spectrum costs). Other processes may share the machine: the load
average is printed before and after. Nothing is asserted.

Usage::

    python benchmarks/geometry.py [--rays 200000] [--repeats 3] [--threads 2]
                                  [--samples spheres red-dune] [--wavelengths 450 550 650 850]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys

from sandlight.machine import describe

CHILD = r"""
import json, resource, sys, time
import sandlight
from sandlight.physics.packing import generate_packing, grain_medium, reference_grain_mm
from sandlight.physics.composition import compose
from sandlight.physics.medium import native_medium
sample, mode, threads = sys.argv[1], sys.argv[2], sys.argv[5]
rays, repeats, nm = int(sys.argv[3]), int(sys.argv[4]), float(sys.argv[6])
threads = None if threads == "all" else int(threads)
base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
memory = "none" if mode == "explicit" else mode
if sample == "spheres":
    medium = grain_medium([0.25], alpha_per_mm=0.5, memory=memory)
    make_packing = lambda: generate_packing(grain_medium([0.25]), reference_mm=0.25, seed=1)
else:
    comp = compose(sandlight.SandSample.preset(sample))
    medium = native_medium(comp, nm, memory=memory)
    make_packing = lambda: generate_packing(native_medium(comp, nm), reference_mm=reference_grain_mm(comp), seed=1)
out = {"packing_s": 0.0, "grains": 0, "scene_bytes": 0}
if mode == "explicit":
    t = time.perf_counter()
    pk = make_packing()
    out.update(packing_s=time.perf_counter() - t, grains=pk.n_particles, scene_bytes=pk.memory_bytes)
    medium = medium.explicit(pk)
best = float("inf")
for _ in range(repeats):
    t = time.perf_counter()
    c = medium.dhr(0.0, 1, 0, 0, rays, 10_000_000, 10_000, threads)
    best = min(best, time.perf_counter() - t)
out.update(seconds=best, rays_per_s=rays / best, reflectance=c[1] / c[0], events_per_ray=c[5] / c[0],
           peak_rss_gain_mb=(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - base) / 1024.0)
print(json.dumps(out))
"""


def load_average() -> str:
    try:
        return "{:.2f} {:.2f} {:.2f}".format(*os.getloadavg())
    except OSError:
        return "n/a"


MODES = ("none", "cut", "packed", "explicit")


def run(sample, mode, rays, repeats, threads, nm):
    res = subprocess.run(
        [sys.executable, "-c", CHILD, sample, mode, str(rays), str(repeats), threads, str(nm)],
        capture_output=True,
        text=True,
        check=True,
    )
    return json.loads(res.stdout.strip().splitlines()[-1])


def ns_per_event(r):
    return 1e9 / (r["rays_per_s"] * max(r["events_per_ray"], 1e-9))


def report(label, rows):
    """Print one sample at one wavelength: each mode, then its ratios to the classic model."""
    print(f"\n{label}")
    for mode, r in rows.items():
        name = "explicit" if mode == "explicit" else f"on-the-fly (memory {mode})"
        extra = (
            f", packing {r['packing_s']:.1f} s, {r['grains']} grains, scene {r['scene_bytes'] / 2**20:.1f} MiB"
            if mode == "explicit"
            else ""
        )
        print(
            f"  {name:26s} {r['rays_per_s']:12,.0f} rays/s  ρ = {r['reflectance']:.4f}  "
            f"{r['events_per_ray']:5.1f} grains/ray  {ns_per_event(r):5.0f} ns/grain  "
            f"peak RSS +{r['peak_rss_gain_mb']:.1f} MB{extra}"
        )
    n, e = rows["none"], rows["explicit"]
    ratios = ", ".join(
        f"{m} {rows[m]['rays_per_s'] / n['rays_per_s']:.2f} per ray, "
        f"{ns_per_event(n) / ns_per_event(rows[m]):.2f} per grain"
        for m in ("cut", "packed")
    )
    print(
        f"  speed on-the-fly / explicit: {n['rays_per_s'] / e['rays_per_s']:.2f}; "
        f"speed with memory / none: {ratios}; "
        f"peak RSS gain explicit / on-the-fly: {e['peak_rss_gain_mb'] / max(n['peak_rss_gain_mb'], 0.1):.1f}"
    )


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rays", type=int, default=200_000)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--threads", default="2", help="worker threads, or 'all'")
    ap.add_argument("--samples", nargs="+", default=["spheres", "red-dune"])
    ap.add_argument(
        "--wavelengths",
        nargs="+",
        type=float,
        default=[450.0, 550.0, 650.0, 850.0],
        help="wavelengths (nm) for presets; the spheres have a fixed α",
    )
    args = ap.parse_args(argv)
    print(f"machine: {describe()}; load average before: {load_average()}")
    print(f"rays per run: {args.rays}, best of {args.repeats}, threads: {args.threads}")
    for sample in args.samples:
        spheres = sample == "spheres"
        total = dict.fromkeys(MODES, 0.0)
        for nm in [550.0] if spheres else args.wavelengths:
            rows = {mode: run(sample, mode, args.rays, args.repeats, args.threads, nm) for mode in MODES}
            report(
                "monodisperse spheres d = 0.25 mm, φ = 0.40, α = 5 cm⁻¹" if spheres else f"{sample}, {nm:g} nm", rows
            )
            for mode in MODES:
                total[mode] += rows[mode]["seconds"]
        if not spheres and len(args.wavelengths) > 1:
            print(
                f"  {sample} over {', '.join(f'{w:g}' for w in args.wavelengths)} nm (total time of the same rays): "
                + ", ".join(f"{m}/none {total['none'] / total[m]:.2f}" for m in ("cut", "packed"))
                + f"; on-the-fly / explicit {total['explicit'] / total['none']:.1f}"
            )
    print(f"\nload average after: {load_average()}")


if __name__ == "__main__":
    main()
