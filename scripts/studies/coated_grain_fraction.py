#!/usr/bin/env python3
"""What if only a fraction of the grains carries the coating? (issue 17 §2, a what-if for the notes)

The shipped model coats every host particle uniformly. Here a fraction c of each coated
population carries all of its coating (thickness t/c, so the iron mass is unchanged) and the rest
is clean: stained and clean grains side by side, the coarsest form of a patchy coating. The
populations are split after `sandlight.physics.composition.compose`; nothing in the package
changes. Prints L*, C*ab ± its Monte Carlo error and h° (D50, 10°, 400–700 nm) of the red-dune and
yellow-dune presets for a few c, with the shipped or (``--calibrated``) the calibrated optical
constants of the quartz host and goethite (docs/calibration), and ``--coating-optics``.

Usage::

    python scripts/studies/coated_grain_fraction.py [--calibrated] [--coating-optics uniform|mie]
        [--fractions 1 0.5 0.25] [--rays 3000] [--seed 1]
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
from pathlib import Path

import numpy as np

import sandlight
from sandlight.calibration import with_calibrated_k
from sandlight.colour.lch import lch_with_chroma_error
from sandlight.physics.composition import Composition, compose
from sandlight.physics.media import SandMedium
from sandlight.physics.medium import COATING_OPTICS

WAVELENGTHS_NM = np.arange(400.0, 701.0, 20.0)
CALIBRATION = Path(__file__).resolve().parents[2] / "docs" / "calibration"
PRESETS = ("red-dune", "yellow-dune")


def coated_fraction(comp: Composition, c: float) -> Composition:
    """``comp`` with each coated population split: a fraction ``c`` of its volume coated t/c thick,
    the rest clean."""
    if not 0.0 < c <= 1.0:
        raise ValueError(f"coated fraction {c}: need 0 < c <= 1")
    pops = []
    for p in comp.populations:
        if p.coating and p.coating_thickness_mm > 0 and c < 1.0:
            pops.append(
                dataclasses.replace(
                    p, volume_fraction=p.volume_fraction * c, coating_thickness_mm=p.coating_thickness_mm / c
                )
            )
            clean = p.volume_fraction * (1 - c)
            pops.append(dataclasses.replace(p, volume_fraction=clean, coating={}, coating_thickness_mm=0.0))
        else:
            pops.append(p)
    return dataclasses.replace(comp, populations=tuple(pops))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--calibrated", action="store_true", help="calibrated k of the quartz host and goethite")
    ap.add_argument("--coating-optics", choices=COATING_OPTICS, default="uniform")
    ap.add_argument("--fractions", type=float, nargs="+", default=[1.0, 0.5, 0.25])
    ap.add_argument("--rays", type=int, default=3000)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args(argv)
    constants = (
        with_calibrated_k({m: CALIBRATION / m / f"{m}-k.csv" for m in ("quartz", "goethite")})
        if args.calibrated
        else None
    )
    print(
        f"{'calibrated' if args.calibrated else 'shipped'} constants, coating_optics {args.coating_optics!r}, "
        f"{args.rays} rays, seed {args.seed}\n"
    )
    print("| preset | coated fraction | L* | C*ab | h° | R(400) | R(700) |\n|---|---|---|---|---|---|---|")
    for name in PRESETS:
        for c in args.fractions:
            comp = coated_fraction(compose(sandlight.SandSample.preset(name)), c)
            medium = SandMedium(comp, "none", optical_constants=constants, coating_optics=args.coating_optics)
            r = sandlight.reflectance(medium, WAVELENGTHS_NM, rays=args.rays, seed=args.seed, progress=False)
            L, C, h, se = lch_with_chroma_error(r.wavelengths, r.values, r.covariance)
            row = f"| {name} | {c:g} | {L:.1f} | {C:.1f} ± {se:.1f} | {h:.0f} |"
            print(f"{row} {r.values[0]:.3f} | {r.values[-1]:.3f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
