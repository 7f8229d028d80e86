#!/usr/bin/env python3
"""Does one hematite k serve both the pure GDS27 powder and the GDS76 mixture made from it?

USGS made the mixture Hematite.02+Quartz.98 GDS76 from the reagent powder Hematite GDS27. If the
engine described both, one k(λ) would reproduce both measurements. This study asks the engine,
at each wavelength beyond the absorption edge, which k it needs for each:

* the pure powder: the GDS27 end-member of sandlight/data/calibration/end_members.toml (2–3 µm
  grains, porosity 0.45, spheres; ``sandlight.physics.powder.Powder``), traced with the default
  memory;
* the mixture: the ``gds76-hematite-quartz`` preset (its hematite as separate 2.5 µm particles),
  traced with the default engine;

each with hematite's k set to one trial value at every wavelength (n as shipped), on a log grid of
k with one seed for every k (common random numbers: ρ(k) is then smooth in k). The k at which the
model equals the measurement is read off by linear interpolation of log k against ρ (ρ falls with
k). Nothing is fitted and nothing shipped changes; the output is the table in
docs/optical-constants.md ("One k for the powder and its mixture?").

Usage::

    python scripts/studies/hematite_k_consistency.py [--rays 4000] [--seed 1]

Needs the native engine and the shared USGS library; run it from the repository root.
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

WAVELENGTHS_NM = (560.0, 580.0, 600.0, 620.0, 650.0, 700.0, 750.0, 860.0, 1000.0)
LOG10_K = np.arange(-5.0, 0.01, 0.25)


def k_at(rho: np.ndarray, measured: float) -> float:
    """The k at which the tabulated ρ(k) (over LOG10_K) equals ``measured``: log k interpolated
    linearly in ρ between the bracketing grid points; NaN where the measurement lies outside the
    tabulated range (the model cannot reach it with any k)."""
    order = np.argsort(rho)
    r, lk = rho[order], LOG10_K[order]
    if not (r[0] <= measured <= r[-1]):
        return float("nan")
    return float(10.0 ** np.interp(measured, r, lk))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rays", type=int, default=4000, help="rays per wavelength and k (default 4000)")
    parser.add_argument("--seed", type=int, default=1, help="engine seed (default 1)")
    args = parser.parse_args(argv)
    if args.rays < 1:
        parser.error(f"--rays = {args.rays!r} is not allowed: an integer >= 1")

    from sandlight import SandSample
    from sandlight.calibration import end_members, measured_reflectance, with_trial_k
    from sandlight.engine import reflectance
    from sandlight.optics import complex_index
    from sandlight.physics.media import DEFAULT_MEMORY, SandMedium
    from sandlight.physics.powder import Powder
    from sandlight.validation import SAMPLES
    from sandlight.validation.scoring import measured_on_grid

    start = time.perf_counter()
    wl = np.asarray(WAVELENGTHS_NM)
    gds27 = next(m for m in end_members("hematite") if m.id == "GDS27")
    powder_measured, _ = measured_reflectance(gds27, wl)
    gds76 = next(s for s in SAMPLES if s.preset == "gds76-hematite-quartz")
    mixture_measured = measured_on_grid(gds76.measured_spectrum(), wl)
    sample = SandSample.preset(gds76.preset)

    powder = np.empty((LOG10_K.size, wl.size))
    mixture = np.empty((LOG10_K.size, wl.size))
    for i, lk in enumerate(LOG10_K):
        index = with_trial_k("hematite", 10.0**lk)
        traced = Powder("hematite", gds27.size_um, 0.45, 1.0, index, memory=DEFAULT_MEMORY)
        powder[i] = reflectance(traced, wl, rays=args.rays, seed=args.seed, progress=False, share=False).values
        traced = SandMedium.from_sample(sample, optical_constants=index)
        mixture[i] = reflectance(traced, wl, rays=args.rays, seed=args.seed, progress=False, share=False).values

    print(
        f"Engine (memory {DEFAULT_MEMORY!r}), {args.rays:,} rays per wavelength and k, seed {args.seed}; "
        f"k grid 10^{LOG10_K[0]:g} … 10^{LOG10_K[-1]:g} every {LOG10_K[1] - LOG10_K[0]:g} decade.\n"
    )
    print(
        "| λ (nm) | GDS27 powder measured | k it needs | GDS76 mixture measured | k it needs | "
        "powder k / mixture k | shipped k | ρ range of the mixture over k |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for j, w in enumerate(wl):
        kp = k_at(powder[:, j], powder_measured[j])
        km = k_at(mixture[:, j], mixture_measured[j])
        ratio = kp / km if np.isfinite(kp) and np.isfinite(km) else float("nan")
        shipped = complex(complex_index("hematite", w)).imag
        print(
            f"| {w:.0f} | {powder_measured[j]:.3f} | {kp:.2g} | {mixture_measured[j]:.3f} | {km:.2g} | "
            f"{ratio:.1f} | {shipped:.2g} | {mixture[:, j].min():.3f}–{mixture[:, j].max():.3f} |"
        )
    print(f"\n{time.perf_counter() - start:.0f} s wall.")
    return 0


if __name__ == "__main__":
    sys.exit(main())
