"""Spectral path sharing against independent runs (docs/transport.md, "Spectral path sharing").

For each sample, the reflectance on a wavelength grid is traced twice with the same number of
rays per wavelength: shared (``share=True``, the default dispersion tolerance unless
``--tolerance``) and independent (``share=False``, one run per wavelength, each with its own
seed so that the independent errors are independent). It prints per wavelength both values,
both standard errors and their ratio, and z = (shared − independent)/√(se_s² + se_i²), then the
mean and spread of z over all wavelengths and seeds and the largest |z|: with no bias, mean ≈ 0
and spread ≈ 1 (z of one shared run are correlated across its group, so the mean scatters by up
to 1/√seeds). Times are wall clock and process CPU (all threads), shared spectrum against the
independent runs. ``--memory`` sets the path memory (default: the engine's, ``DEFAULT_MEMORY``).

Usage::

    python scripts/studies/spectral_sharing_check.py [--samples red-dune ottawa-quartz]
        [--grid validation|visible] [--rays 20000] [--seeds 2] [--tolerance 0.02]
        [--memory none|channel|cut|packed]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import sandlight
from sandlight.physics.media import DEFAULT_MEMORY, MEMORIES
from sandlight.physics.spectral_groups import DISPERSION_TOLERANCE
from sandlight.validation.scoring import default_wavelengths_nm

GRIDS = {"validation": default_wavelengths_nm(), "visible": np.linspace(400.0, 700.0, 16)}


def sample_for(name: str) -> sandlight.SandSample:
    return sandlight.SandSample() if name == "default" else sandlight.SandSample.preset(name)


def compare(sample, wl: np.ndarray, rays: int, seed: int, tolerance: float, memory: str | None) -> dict:
    """Shared and independent spectra of ``sample`` with their wall and CPU times."""
    run = {"rays": rays, "progress": False, "memory": memory}
    t0, c0 = time.perf_counter(), time.process_time()
    shared = sandlight.reflectance(sample, wl, seed=seed, dispersion_tolerance=tolerance, **run)
    t1, c1 = time.perf_counter(), time.process_time()
    # One seed per wavelength: independent errors across wavelengths.
    indep = [
        sandlight.reflectance(sample, [lam], seed=1000 * seed + k + 1, share=False, **run) for k, lam in enumerate(wl)
    ]
    t2, c2 = time.perf_counter(), time.process_time()
    values = np.array([r.values[0] for r in indep])
    stderr = np.array([r.stderr[0] for r in indep])
    z = (shared.values - values) / np.hypot(shared.stderr, stderr)
    times = {"t_shared": t1 - t0, "t_indep": t2 - t1, "cpu_shared": c1 - c0, "cpu_indep": c2 - c1}
    return {"shared": shared, "values": values, "stderr": stderr, "z": z, **times}


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--samples", nargs="+", default=["red-dune", "ottawa-quartz"])
    parser.add_argument("--grid", choices=sorted(GRIDS), default="validation")
    parser.add_argument("--rays", type=int, default=20_000)
    parser.add_argument("--seeds", type=int, default=2)
    parser.add_argument("--tolerance", type=float, default=DISPERSION_TOLERANCE)
    parser.add_argument("--memory", choices=MEMORIES, default=None, help="path memory (default: the engine's)")
    args = parser.parse_args(argv)
    wl = GRIDS[args.grid]
    print(
        f"sandlight {sandlight.__version__}; {wl.size} wavelengths {wl.min():g}–{wl.max():g} nm; "
        f"{args.rays} rays per wavelength; seeds 1..{args.seeds}; dispersion tolerance {args.tolerance:g}; "
        f"memory '{DEFAULT_MEMORY if args.memory is None else args.memory}'"
    )
    for name in args.samples:
        sample = sample_for(name)
        zs, ratios = [], []
        for seed in range(1, args.seeds + 1):
            c = compare(sample, wl, args.rays, seed, args.tolerance, args.memory)
            zs.append(c["z"])
            ratios.append(c["shared"].stderr / c["stderr"])
            sizes = [len(g) for g in c["shared"].groups]
            print(
                f"\n{name}, seed {seed}: {len(sizes)} groups {sizes}; time shared {c['t_shared']:.1f} s, "
                f"independent {c['t_indep']:.1f} s ({c['t_indep'] / c['t_shared']:.1f}×); CPU shared "
                f"{c['cpu_shared']:.1f} s, independent {c['cpu_indep']:.1f} s ({c['cpu_indep'] / c['cpu_shared']:.1f}×)"
            )
            if seed == 1:
                print(f"{'λ nm':>7} {'shared':>8} {'se':>8} {'indep':>8} {'se':>8} {'se ratio':>8} {'z':>6}")
                s = c["shared"]
                for k, lam in enumerate(wl):
                    print(
                        f"{lam:>7g} {s.values[k]:>8.5f} {s.stderr[k]:>8.5f} {c['values'][k]:>8.5f} "
                        f"{c['stderr'][k]:>8.5f} {ratios[-1][k]:>8.2f} {c['z'][k]:>6.2f}"
                    )
        z = np.concatenate(zs)
        r = np.concatenate(ratios)
        print(
            f"{name}: z over {z.size} (wavelength, seed): mean {z.mean():+.3f}, spread {z.std(ddof=1):.3f}, "
            f"max |z| {np.abs(z).max():.2f}; shared/independent standard error at equal rays: "
            f"median {np.median(r):.2f}, range {r.min():.2f}–{r.max():.2f}",
            flush=True,
        )


if __name__ == "__main__":
    main()
