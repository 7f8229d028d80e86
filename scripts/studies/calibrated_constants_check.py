#!/usr/bin/env python3
"""The validation samples and the preset colours with the shipped optical constants (issue 17 §1).

For docs/optical-constants.md ("What the calibrated constants change"): run it once with the
tables before the calibration and once after, and compare.

* Each validation sample of :data:`sandlight.validation.SAMPLES` (GDS76 hematite + quartz, never
  fitted; Ottawa GDS74, in the quartz host fit): RMS of model − measured over 400–700 and
  400–2500 nm with its Monte Carlo error, and ΔE2000 (D50, CIE 1964 10°, 400–700 nm) between the
  model and the measured spectrum.
* With ``--hematite-k CSV`` (a calibration output, docs/calibration/hematite/hematite-k.csv),
  the samples with hematite again, with that k instead of the shipped one: why hematite is not
  recalibrated (docs/optical-constants.md).
* Each preset: CIELAB L*, C*ab and h° from the engine (not the predictor bank, which was trained
  with the constants of its day), same illuminant and observer.

Uses only what the package had before the calibration, so the same file runs against an older
checkout (``PYTHONPATH=<checkout>/python python3 scripts/studies/calibrated_constants_check.py``).

Usage::

    python3 scripts/studies/calibrated_constants_check.py --rays 20000 --out check.md
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

import colour

VISIBLE_NM = np.arange(400.0, 701.0, 10.0)


def lab_of(wavelengths_nm, values) -> np.ndarray:
    """CIELAB (D50, 10°) of a reflectance spectrum (sandlight.colour)."""
    from sandlight.colour.spectrum import spectrum_to_xyz
    from sandlight.colour.srgb import xyz_to_lab

    return xyz_to_lab(spectrum_to_xyz(np.asarray(wavelengths_nm, float), np.asarray(values, float)))


def chroma_hue(lab) -> tuple[float, float]:
    """C*ab and h° (degrees in [0, 360)) of CIELAB values."""
    return float(math.hypot(lab[1], lab[2])), float(math.degrees(math.atan2(lab[2], lab[1])) % 360.0)


def with_k(material: str, path: Path):
    """The shipped optical constants with ``material``'s k from a calibration csv (log-linear)."""
    from sandlight.calibration import with_calibrated_k

    return with_calibrated_k({material: path})


def as_medium(preset: str, index):
    """A preset traced with other optical constants."""
    from sandlight import SandSample
    from sandlight.physics.media import SandMedium

    return SandMedium.from_sample(SandSample.preset(preset), optical_constants=index)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rays", type=int, default=20000, help="rays per wavelength (default 20000)")
    parser.add_argument("--seed", type=int, default=0, help="engine seed (default 0)")
    parser.add_argument(
        "--hematite-k", type=Path, default=None, help="also run the hematite samples with this calibrated k csv"
    )
    parser.add_argument("--out", type=Path, default=None, help="also write the Markdown here")
    args = parser.parse_args(argv)
    if args.rays < 1:
        parser.error(f"--rays = {args.rays!r} is not allowed: an integer >= 1")

    from sandlight import SandSample, reflectance
    from sandlight.validation import SAMPLES
    from sandlight.validation.samples import run_and_score
    from sandlight.validation.scoring import measured_on_grid, model_wavelengths_nm

    start = time.perf_counter()
    out = [f"Engine, {args.rays:,} rays per wavelength, seed {args.seed}; colours D50, CIE 1964 10°, 400–700 nm.\n"]
    out.append(
        "| sample | RMS 400–700 ± MC | RMS 400–2500 ± MC | bias 400–700 | ΔE2000 model vs measured "
        "| ρ 450 / 600 / 700 nm, model (measured) |"
    )
    out.append("|---|---|---|---|---|---|")
    runs = [(s, s.name, s.traced()) for s in SAMPLES]
    if args.hematite_k is not None:
        index = with_k("hematite", args.hematite_k)
        runs += [
            (s, f"{s.name}, hematite k of {args.hematite_k.name}", as_medium(s.preset, index))
            for s in SAMPLES
            if SandSample.preset(s.preset).iron_oxide > 0 and SandSample.preset(s.preset).hematite_ratio > 0
        ]
    for s, name, traced in runs:
        spectrum = s.measured_spectrum()
        result = run_and_score(
            s, traced, name, spectrum, rays=args.rays, wavelengths_nm=model_wavelengths_nm(), seed=args.seed
        )
        visible = reflectance(traced, VISIBLE_NM, rays=args.rays, seed=args.seed, progress=False)
        de = colour.delta_E(
            lab_of(VISIBLE_NM, visible.values),
            lab_of(VISIBLE_NM, measured_on_grid(spectrum, VISIBLE_NM)),
            method="CIE 2000",
        )
        vis, full = result.errors["400–700 nm"], result.errors["400–2500 nm"]
        at = [int(np.argmin(abs(VISIBLE_NM - w))) for w in (450.0, 600.0, 700.0)]
        measured = measured_on_grid(spectrum, VISIBLE_NM)
        rho = " / ".join(f"{visible.values[i]:.3f} ({measured[i]:.3f})" for i in at)
        out.append(
            f"| {name} | {vis.rms:.4f} ± {vis.rms_mc:.4f} | {full.rms:.4f} ± {full.rms_mc:.4f} | "
            f"{vis.bias:+.4f} | {float(de):.1f} | {rho} |"
        )
    out.append("\n| preset | L* | a* | b* | C*ab | h° |")
    out.append("|---|---|---|---|---|---|")
    for name in SandSample.presets():
        r = reflectance(SandSample.preset(name), VISIBLE_NM, rays=args.rays, seed=args.seed, progress=False)
        lab = lab_of(VISIBLE_NM, r.values)
        c, h = chroma_hue(lab)
        out.append(f"| {name} | {lab[0]:.1f} | {lab[1]:.1f} | {lab[2]:.1f} | {c:.1f} | {h:.0f} |")
    out.append(f"\n{time.perf_counter() - start:.0f} s wall.")
    text = "\n".join(out) + "\n"
    print(text)
    if args.out is not None:
        args.out.write_text(text, encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
