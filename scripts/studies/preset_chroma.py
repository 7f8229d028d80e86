"""Preset chroma check (issue 17): no preset with iron oxide ≤ 5 % more chromatic than C*ab 50.

Traces every shipped preset (400–700 nm, CIELAB D50/10°) with the chosen coating optics, film
model, path memory, particle optics (``--particle-optics``: how the separate iron-oxide particles
of the ``particles`` form are traced, docs/model.md §2.4 item 8) and coating coverage
(``--coating-coverage F``: ``SandSample.coating_coverage`` set to F in every preset,
docs/model.md §2.4) and inclusions in the host grains (``--host-scattering S``:
``SandSample.host_scattering`` set to S mm⁻¹ in every preset), each by default the engine's default, with the
shipped optical constants (the calibrated k of the quartz host and goethite), and prints
L*, C*ab ± its Monte Carlo standard error and h°; a preset with iron_oxide ≤ 0.05 whose C*ab
exceeds 50 by more than 4 standard errors fails the check, and the script then exits with
status 1.

Usage::

    python scripts/studies/preset_chroma.py [--coating-optics uniform|mie] [--films pendular|uniform]
        [--memory packed|none|...] [--particle-optics geometric|mie] [--coating-coverage 1]
        [--host-scattering 0] [--rays 4000] [--seed 1]
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

import sandlight
from sandlight.colour.lch import lch_with_chroma_error
from sandlight.physics.composition import DEFAULT_FILMS, FILM_MODELS
from sandlight.physics.fine_particles import DEFAULT_PARTICLE_OPTICS, PARTICLE_OPTICS
from sandlight.physics.media import DEFAULT_MEMORY, MEMORIES, SandMedium
from sandlight.physics.medium import COATING_OPTICS
from sandlight.physics.pigment import PIGMENT_DIAMETER_UM

WAVELENGTHS_NM = np.arange(400.0, 701.0, 20.0)
CHROMA_LIMIT = 50.0
IRON_OXIDE_LIMIT = 0.05


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--coating-optics", choices=COATING_OPTICS, default="uniform")
    ap.add_argument("--films", choices=FILM_MODELS, default=DEFAULT_FILMS)
    ap.add_argument("--memory", choices=MEMORIES, default=DEFAULT_MEMORY)
    ap.add_argument("--particle-optics", choices=PARTICLE_OPTICS, default=DEFAULT_PARTICLE_OPTICS)
    ap.add_argument(
        "--coating-coverage", type=float, default=1.0, help="SandSample.coating_coverage of every preset (0, 1]"
    )
    ap.add_argument(
        "--host-scattering", type=float, default=0.0, help="SandSample.host_scattering of every preset, mm⁻¹"
    )
    ap.add_argument("--rays", type=int, default=4000)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    print(
        f"coating_optics {args.coating_optics!r} (pigment {PIGMENT_DIAMETER_UM} µm), films {args.films!r}, "
        f"memory {args.memory!r}, particle_optics {args.particle_optics!r}, "
        f"coating_coverage {args.coating_coverage:g}, host_scattering {args.host_scattering:g} mm⁻¹, "
        f"shipped optical constants, "
        f"{args.rays} rays\n"
    )
    print("| preset | iron oxide | L* | C*ab | h° | check |\n|---|---|---|---|---|---|")
    failed = []
    for name in sandlight.SandSample.presets():
        sample = sandlight.SandSample.preset(name).replace(
            coating_coverage=args.coating_coverage, host_scattering=args.host_scattering
        )
        medium = SandMedium.from_sample(
            sample,
            args.memory,
            coating_optics=args.coating_optics,
            films=args.films,
            particle_optics=args.particle_optics,
        )
        r = sandlight.reflectance(medium, WAVELENGTHS_NM, rays=args.rays, seed=args.seed, progress=False)
        L, C, h, se = lch_with_chroma_error(r.wavelengths, r.values, r.covariance)
        # Without path sharing (a medium that cannot share, or --no-share runs) the covariance
        # between wavelengths is not known (NaN): then C*ab itself is compared with the limit.
        margin = 4 * se if np.isfinite(se) else 0.0
        over = sample.iron_oxide <= IRON_OXIDE_LIMIT and margin < C - CHROMA_LIMIT
        failed += [name] if over else []
        print(
            f"| {name} | {sample.iron_oxide:g} | {L:.1f} | {C:.1f} ± {se:.1f} | {h:.0f} | {'FAIL' if over else 'ok'} |"
        )
    print(f"\n{len(failed)} preset(s) above C*ab {CHROMA_LIMIT:g}: {', '.join(failed) or 'none'}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
