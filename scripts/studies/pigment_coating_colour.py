"""Colour of coated sands with the uniform and the Mie (pigmented) coating (docs/model.md §2.4,
item 6, "Pigmented coating (Mie)").

Prints CIELAB L*, C*ab (± its Monte Carlo standard error) and h° (D50, 10° observer,
400–700 nm) of the presets red-dune, yellow-dune and wet-beach, of a grid iron_oxide ×
hematite_ratio (iron oxide as a coating, other parameters the defaults), and of red-dune and
yellow-dune over the pigment crystal diameter, for ``coating_optics`` 'uniform' and 'mie'; then
red-dune's coating optical depths at 450, 550 and 650 nm, and the 400–700 nm RMS of the
gds76-hematite-quartz preset (iron oxide as separate particles, so both optics must agree)
against its measured spectrum. ``--swatches PATH`` writes the presets' and the grid's sRGB
swatches (uniform left, Mie right) to a PNG.

Usage::

    python scripts/studies/pigment_coating_colour.py [--rays 4000] [--seed 1] [--swatches out.png]
"""

from __future__ import annotations

import argparse

import numpy as np

import sandlight
from sandlight.colour.lch import lch_with_chroma_error
from sandlight.colour.spectrum import spectrum_to_xyz
from sandlight.colour.srgb import srgb_to_uint8, xyz_to_srgb
from sandlight.physics.composition import compose
from sandlight.physics.media import SandMedium
from sandlight.physics.medium import COATING_OPTICS
from sandlight.physics.pigment import PIGMENT_DIAMETER_UM, coating_optics
from sandlight.validation.samples import sample_by_name
from sandlight.validation.scoring import measured_on_grid

WAVELENGTHS_NM = np.arange(400.0, 701.0, 20.0)
PRESETS = ("red-dune", "yellow-dune", "wet-beach")
IRON_OXIDE = (0.005, 0.01, 0.02, 0.05)
HEMATITE_RATIO = (0.0, 0.5, 1.0)
DIAMETERS_UM = (0.05, 0.1, 0.2, 0.3)


def lch_with_error(result) -> tuple[float, float, float, float]:
    """L*, C*ab, h° and σ(C*ab) of a reflectance result."""
    return lch_with_chroma_error(result.wavelengths, result.values, result.covariance)


def trace(sample: sandlight.SandSample, optics: str, rays: int, seed: int, diameter_um: float = PIGMENT_DIAMETER_UM):
    medium = SandMedium.from_sample(sample, coating_optics=optics, pigment_diameter_um=diameter_um)
    return sandlight.reflectance(medium, WAVELENGTHS_NM, rays=rays, seed=seed, progress=False)


def row(label: str, results: dict) -> str:
    cells = []
    for optics in COATING_OPTICS:
        L, C, h, se = lch_with_error(results[optics])
        cells.append(f"{L:5.1f} {C:5.1f}±{se:3.1f} {h:4.0f}")
    return f"| {label} | " + " | ".join(cells) + " |"


def swatch(result) -> np.ndarray:
    return srgb_to_uint8(xyz_to_srgb(spectrum_to_xyz(result.wavelengths, result.values)))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rays", type=int, default=4000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--swatches", default=None, help="PNG of the swatches (uniform left, Mie right)")
    args = ap.parse_args()
    header = "| sample | uniform L* C*ab h° | mie L* C*ab h° |\n|---|---|---|"
    print(
        f"CIELAB D50/10°, 400–700 nm, {args.rays} rays per wavelength, seed {args.seed}, "
        f"pigment diameter {PIGMENT_DIAMETER_UM} µm\n"
    )
    print(header)
    swatches = []
    for name in PRESETS:
        res = {o: trace(sandlight.SandSample.preset(name), o, args.rays, args.seed) for o in COATING_OPTICS}
        print(row(name, res), flush=True)
        swatches.append((name, [swatch(res[o]) for o in COATING_OPTICS]))
    print(f"\nGrid (iron oxide as a coating, other parameters the defaults)\n\n{header}")
    for fe in IRON_OXIDE:
        for hr in HEMATITE_RATIO:
            sample = sandlight.SandSample(iron_oxide=fe, hematite_ratio=hr, iron_oxide_form="coating")
            res = {o: trace(sample, o, args.rays, args.seed) for o in COATING_OPTICS}
            label = f"iron_oxide {fe:g}, hematite_ratio {hr:g}"
            print(row(label, res), flush=True)
            swatches.append((label, [swatch(res[o]) for o in COATING_OPTICS]))
    print("\nMie coating over the pigment diameter\n\n| sample | d (µm) | L* C*ab h° |\n|---|---|---|")
    for name in PRESETS[:2]:
        for d in DIAMETERS_UM:
            L, C, h, se = lch_with_error(trace(sandlight.SandSample.preset(name), "mie", args.rays, args.seed, d))
            print(f"| {name} | {d:g} | {L:5.1f} {C:5.1f}±{se:3.1f} {h:4.0f} |", flush=True)
    coated = compose(sandlight.SandSample.preset("red-dune")).populations[0]
    print("\nred-dune coating optical depths (pigment diameter default)\n")
    for lam in (450.0, 550.0, 650.0):
        c = coating_optics(coated.coating, lam)
        t = coated.coating_thickness_mm
        print(
            f"{lam:.0f} nm: scattering {c.scattering_per_mm * t:.3f}, absorption {c.absorption_per_mm * t:.3f}, "
            f"g {c.asymmetry:.2f} (thickness {t * 1e3:.3f} µm)"
        )
    gds = sample_by_name("gds76-hematite-quartz")
    measured = measured_on_grid(gds.measured_spectrum(), WAVELENGTHS_NM)
    print()
    for optics in COATING_OPTICS:
        r = trace(sandlight.SandSample.preset(gds.preset), optics, args.rays, args.seed)
        rms = float(np.sqrt(np.nanmean((r.values - measured) ** 2)))
        print(f"GDS76 RMS 400–700 nm, coating_optics {optics!r}: {rms:.4f}")
    if args.swatches:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(6, 0.35 * len(swatches) + 0.5))
        ax.imshow(np.array([[s[0], s[1]] for _, s in swatches]), aspect="auto")
        ax.set_yticks(range(len(swatches)), [label for label, _ in swatches], fontsize=7)
        ax.set_xticks([0, 1], list(COATING_OPTICS))
        fig.tight_layout()
        fig.savefig(args.swatches, dpi=120)
        print(f"swatches: {args.swatches}")


if __name__ == "__main__":
    main()
