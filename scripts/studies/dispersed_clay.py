"""Where the clay of a coated sand sits, and what it does to its colour (issue 17, a diagnostic).

The composition (docs/transport.md, "From the sample to the particles") disperses the clay
fraction as separate kaolinite particles of 0.2–2 µm in the pore space, each carrying the iron
oxide coating; being small, they are most of the particles a ray meets. In red and yellow dune
sands the clay a particle-size analysis reports sits mostly in the grain coatings (Walker 1979,
USGS Prof. Paper 1052; Folk 1976, J. Sediment. Petrol. 46, 604), and the analysis disperses it
first. This script traces each sample three ways, everything else equal:

* ``dispersed``: the model as it is;
* ``clay as sand``: the clay mass moved to the sand grains (the clay's optics removed);
* ``clay in coating``: the clay mass added to the coating's kaolinite matrix (``clay`` 0, the
  sand takes its share of the separates, ``coating_iron_share`` lowered so that the coating
  holds the iron oxide, its own kaolinite and the clay).

and prints L*, C*ab, h° (D50, 10°, 400–700 nm) and the reflectance at 450 and 700 nm. It is a
diagnostic, not a model option: nothing here is fitted, and no default changes.

Usage::

    python3 scripts/studies/dispersed_clay.py [--rays 4000] [--seed 1]
"""

from __future__ import annotations

import argparse

import numpy as np

import sandlight
from sandlight.colour.lch import lch_with_chroma_error
from sandlight.optics import DENSITY_G_CM3

WAVELENGTHS_NM = np.arange(400.0, 701.0, 20.0)


def clay_in_coating(sample: sandlight.SandSample) -> sandlight.SandSample:
    """``sample`` with its clay added to the coating's kaolinite matrix (same masses)."""
    rho = DENSITY_G_CM3
    v_fe = sample.iron_oxide * (sample.hematite_ratio / rho["hematite"] + (1 - sample.hematite_ratio) / rho["goethite"])
    v_coat = v_fe / sample.coating_iron_share + sample.clay / rho["kaolinite"]
    return sample.replace(clay=0.0, sand=sample.sand + sample.clay, coating_iron_share=v_fe / v_coat)


def variants(sample: sandlight.SandSample) -> dict[str, sandlight.SandSample]:
    out = {"dispersed": sample, "clay as sand": sample.replace(clay=0.0, sand=sample.sand + sample.clay)}
    if sample.iron_oxide > 0:  # without iron oxide there is no coating to hold the clay
        out["clay in coating"] = clay_in_coating(sample)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rays", type=int, default=4000)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    samples = {
        "red-dune": sandlight.SandSample.preset("red-dune"),
        "yellow-dune": sandlight.SandSample.preset("yellow-dune"),
        "red-dune, no iron oxide": sandlight.SandSample.preset("red-dune").replace(iron_oxide=0.0),
        "reference, 0.5 % goethite": sandlight.SandSample(iron_oxide=0.005, hematite_ratio=0.0),
        "reference, 2 % hematite": sandlight.SandSample(iron_oxide=0.02, hematite_ratio=1.0),
    }
    print(f"default engine, {args.rays} rays per wavelength, seed {args.seed}; CIELAB D50/10° over 400–700 nm\n")
    print("| sample (clay %) | clay | L* | C*ab ± se | h° | r 450 | r 700 |\n|---|---|---|---|---|---|---|")
    for name, base in samples.items():
        for how, sample in variants(base).items():
            r = sandlight.reflectance(sample, WAVELENGTHS_NM, rays=args.rays, seed=args.seed, progress=False)
            lightness, chroma, hue, se = lch_with_chroma_error(r.wavelengths, r.values, r.covariance)
            at = dict(zip(WAVELENGTHS_NM, r.values))
            print(
                f"| {name} ({100 * base.clay:g}) | {how} | {lightness:.1f} | {chroma:.1f} ± {se:.1f} | {hue:.0f} "
                f"| {np.interp(450.0, WAVELENGTHS_NM, r.values):.3f} | {at[700.0]:.3f} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
