#!/usr/bin/env python3
"""Pure hematite powders through the explicit packing against the on-the-fly engine.

Which engine should calibrate the iron-oxide constants (docs/optical-constants.md, "Inclusions
and fractures in the powders' grains")? For a sieve fraction of hematite
(:class:`sandlight.physics.powder.Powder`, shipped optical constants) and each grain
scattering σ it traces the classic model (``memory='none'``), the path memory ``'packed'`` and
the explicit reference (:class:`sandlight.physics.media.PackedSand`, one packing, seed 1), and
prints the directional-hemispherical reflectance at normal incidence with its standard error.

Usage::

    python3 scripts/studies/powder_geometry.py [--rays 20000] [--sizes 104-150] [--sigmas 0 30]
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

WAVELENGTHS_NM = np.array([450.0, 600.0, 650.0, 750.0, 900.0, 1200.0, 2000.0])


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rays", type=int, default=20000, help="rays per wavelength (default 20000)")
    parser.add_argument("--sizes", nargs="+", default=["104-150"], help="sieve fractions in µm, as lo-hi")
    parser.add_argument("--sigmas", nargs="+", type=float, default=[0.0, 30.0], help="grain scattering, mm⁻¹")
    parser.add_argument("--seed", type=int, default=2, help="engine seed (default 2)")
    args = parser.parse_args(argv)
    if args.rays < 1:
        parser.error(f"--rays = {args.rays!r} is not allowed: an integer >= 1")
    try:
        sizes = [tuple(float(x) for x in s.split("-")) for s in args.sizes]
    except ValueError:
        parser.error(f"--sizes = {args.sizes!r} is not allowed: sieve fractions as lo-hi in µm")

    import sandlight
    from sandlight.physics.media import PackedSand
    from sandlight.physics.powder import Powder

    head = " | ".join(f"ρ {w:.0f} nm" for w in WAVELENGTHS_NM)
    print(f"Hematite powders, {args.rays:,} rays per wavelength, seed {args.seed}, normal incidence.\n")
    print(f"| fraction (µm) | σ (mm⁻¹) | engine | {head} |")
    print("|---|---|---|" + "---|" * WAVELENGTHS_NM.size)
    for d in sizes:
        for sigma in args.sigmas:
            start = time.perf_counter()
            traced = {
                memory: Powder("hematite", d, memory=memory, scattering_per_mm=sigma) for memory in ("none", "packed")
            }
            traced["explicit"] = PackedSand.generate(Powder("hematite", d, scattering_per_mm=sigma).composition, seed=1)
            for engine, medium in traced.items():
                r = sandlight.reflectance(medium, WAVELENGTHS_NM, rays=args.rays, seed=args.seed, progress=False)
                cells = " | ".join(f"{v:.3f} ± {e:.3f}" for v, e in zip(r.values, r.stderr))
                print(f"| {d[0]:g}–{d[1]:g} | {sigma:g} | {engine} | {cells} |", flush=True)
            print(f"<!-- {time.perf_counter() - start:.0f} s -->", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
