#!/usr/bin/env python3
"""How wrong is one BRDF shape, measured at 550 nm, at the other wavelengths of 350–2500 nm?

The shipped spatial models are measured at 550 nm and their normalised shape f̂ is applied at
every wavelength (paper §4.2.2; docs/spatial-predictor.md). Over 350–2500 nm a sand's
reflectance changes far more than over 400–700 nm (iron-oxide edges, water bands), and with it
the share of multiply scattered light in the BRDF. This study measures the BRDF with the
goniophotometer at several wavelengths and scores, against each measurement's normalised shape
(the same relative RMS as the spatial models' held-out checks, values measured to better than
10 % relative standard error):

* ``550 nm shape``: the spatial model's shape at the sample (r₀ at 550 nm), as shipped with
  ``combination="product"``;
* ``energy, fixed``: what ``SandAppearance(..., shape="fixed")`` (``combination="energy"``)
  gives at that wavelength, divided by its reflectance at normal incidence — the 550 nm shape
  plus the diffuse term it adds where the sand is brighter than at 550 nm;
* ``appearance``: the same for the default ``shape="reflectance"``, which blends the spatial
  model's shapes at the sand's predicted r(λ) (`sandlight.appearance.shapes`);
* ``shape at r(λ)``: for a model that interpolates in log r₀ (the dune family), its shape at the
  sand's own reflectance at that wavelength (the measured one), i.e. "a sand as bright as this
  one is at λ"; the question is whether that is a better approximation than one shape.

The measured normal reflectance is used for r(λ) in the last score, so only shapes are compared;
the two appearance columns use the full-range bank's r(λ), as a user's appearance does.
Output: a Markdown table for docs/spatial-predictor.md ("Over 350–2500 nm").

Usage::

    python3 scripts/studies/spatial_shape_over_range.py [--rays 4e6] [--seed 11] [--threads 2] [--samples 0 2]
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

WAVELENGTHS_NM = (450.0, 550.0, 1000.0, 1450.0, 2200.0)
#: (label, preset, overrides): sands inside the shipped spatial models' meshes.
SAMPLES = (
    ("yellow-dune", "yellow-dune", {}),
    ("dune, 1 % hematite", "yellow-dune", {"iron_oxide": 0.01, "hematite_ratio": 1.0}),
    ("wet sand, saturation 0.5", None, {"saturation": 0.5, "iron_oxide": 0.005}),
)
MAX_RELATIVE_STDERR = 0.10


def relative_rms(predicted: np.ndarray, value: np.ndarray, stderr: np.ndarray, sizes: np.ndarray) -> tuple:
    """Pair-weighted relative RMS of predicted − measured and the measurement's own relative noise,
    over the values measured to better than MAX_RELATIVE_STDERR (as spatial.training.evaluate)."""
    with np.errstate(invalid="ignore", divide="ignore"):
        rel_se = stderr / value
        keep = np.isfinite(rel_se) & (value > 0) & (rel_se < MAX_RELATIVE_STDERR)
        rel = (predicted - value) / value
    w = sizes[keep].astype(float)
    return (
        float(np.sqrt(np.sum(w * rel[keep] ** 2) / w.sum())),
        float(np.sqrt(np.sum(w * rel_se[keep] ** 2) / w.sum())),
    )


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rays", type=float, default=4_000_000, help="goniophotometer trials per wavelength")
    parser.add_argument("--seed", type=int, default=11, help="goniophotometer seed")
    parser.add_argument("--threads", type=int, default=None, help="engine threads (default: all cores)")
    parser.add_argument(
        "--samples", type=int, nargs="+", default=list(range(len(SAMPLES))), help="which sands, by index (default: all)"
    )
    args = parser.parse_args(argv)
    if any(not 0 <= i < len(SAMPLES) for i in args.samples):
        parser.error(f"--samples = {args.samples!r} is not allowed: indices in 0..{len(SAMPLES) - 1}")

    import sandlight
    from sandlight.appearance import SandAppearance
    from sandlight.gonio.symmetry import EquivalenceClasses
    from sandlight.predictor import full_range_model
    from sandlight.spatial.shipped import model_for

    start = time.perf_counter()
    wl = np.asarray(WAVELENGTHS_NM)
    print(
        f"Goniophotometer {args.rays:,.0f} trials per wavelength, seed {args.seed}; spectral part: the shipped "
        f"full-range bank; relative RMS over values measured to better than {MAX_RELATIVE_STDERR:.0%}.\n"
    )
    print(
        "| sand | mesh | λ (nm) | measured r(λ) | 550 nm shape | energy, fixed | appearance | shape at r(λ) | noise |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for label, preset, overrides in (SAMPLES[i] for i in args.samples):
        base = sandlight.SandSample.preset(preset) if preset else sandlight.SandSample()
        sample = base.replace(**overrides)
        model = model_for(sample)
        apps = [SandAppearance(sample, full_range_model(), model, shape=s) for s in ("fixed", "reflectance")]
        # Each wavelength with trials of its own: with shared paths a dark wavelength's weights
        # behind bright heroes are tiny in cells only long paths reach, which a relative score
        # would weigh like any other.
        measured = sandlight.brdf(
            sample,
            wl,
            rays=args.rays,
            seed=args.seed,
            threads=args.threads,
            memory=model.memory_,
            progress=False,
            share=False,
        )
        classes = EquivalenceClasses(measured[0].hemisphere)
        centroids = measured[0].hemisphere.centroids
        wi = np.repeat(centroids[:, None, :], centroids.shape[0], axis=1)
        wo = np.repeat(centroids[None, :, :], centroids.shape[0], axis=0)
        r550 = measured[int(np.argmin(np.abs(wl - 550.0)))].normal_reflectance
        fixed_shape = model.predict(sample, fixed="ignore", normal_reflectance=r550)[0]
        for lam, m in zip(wl, measured):
            r = m.normal_reflectance
            cells = [relative_rms(fixed_shape, m.unique_values, m.unique_stderr, classes.sizes)]
            for app in apps:
                full = app.brdf(wi.reshape(-1, 3), wo.reshape(-1, 3), [lam])[:, 0].reshape(wi.shape[:2])
                shape = classes.mean(full) / float(app.reflectance_at([lam])[0])
                cells.append(relative_rms(shape, m.unique_values, m.unique_stderr, classes.sizes))
            if model.absorbers:
                own = model.predict(sample, fixed="ignore", normal_reflectance=r)[0]
                cells.append(relative_rms(own, m.unique_values, m.unique_stderr, classes.sizes))
            text = [f"{100 * c[0]:.1f} %" for c in cells] + ["–"] * (4 - len(cells))
            mesh = ", ".join(model.mesh_.parameters)
            noise = f"{100 * cells[0][1]:.1f} %"
            print(f"| {label} | {mesh} | {lam:.0f} | {r:.3f} | {' | '.join(text)} | {noise} |", flush=True)
    print(f"\n{time.perf_counter() - start:.0f} s wall.")
    return 0


if __name__ == "__main__":
    sys.exit(main())
