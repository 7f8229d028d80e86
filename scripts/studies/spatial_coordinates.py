"""In which coordinates to interpolate a spatial model (docs/spatial-predictor.md, "Interpolation
coordinates").

Reads the node and held-out measurements of a finished training run of
``scripts/data/train_default_spatial.py`` (default: the dune family's work directory) and prints

1. the held-out relative RMS (`sandlight.spatial.evaluate`, values measured to better than 2 %)
   of models fitted to the same nodes with different interpolation coordinates: the paper's
   (the mesh parameters), log r₀ in place of the absorbers, and log grain size;
2. how close each node's own BRDF is to the held-out one, next to its normal reflectance r₀:
   whether samples that share r₀ share their shape, whatever their composition.

Usage::

    python scripts/studies/spatial_coordinates.py [--work-dir build/train-default-spatial-dune]
        [--absorbers iron_oxide hematite_ratio] [--log grain_size]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from sandlight.gonio import CollectorHemisphere, EquivalenceClasses
from sandlight.spatial import Mesh, SpatialModel, evaluate, node_brdfs

ROOT = Path(__file__).resolve().parents[2]


def relative_rms(values: np.ndarray, measured, sizes: np.ndarray) -> float:
    """Relative RMS of ``values`` against ``measured`` over its values known to better than 2 %,
    weighted by the patch pairs each unique value stands for (as `evaluate` scores)."""
    keep = measured.unique_stderr < 0.02 * np.abs(measured.unique_values)
    e = (values[keep] - measured.unique_values[keep]) / measured.unique_values[keep]
    return float(np.sqrt(np.sum(sizes[keep] * e**2) / np.sum(sizes[keep])))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--work-dir", type=Path, default=ROOT / "build" / "train-default-spatial-dune")
    ap.add_argument("--absorbers", nargs="+", default=["iron_oxide", "hematite_ratio"])
    ap.add_argument("--log", nargs="*", default=["grain_size"], help="parameters interpolated in their log")
    ap.add_argument("--method", default="pooled", choices=["average", "pooled"])
    args = ap.parse_args()

    nodes = node_brdfs(args.work_dir / "nodes", args.method)
    held = node_brdfs(args.work_dir / "holdout", args.method)[0]
    names = [n for n in ("saturation", "iron_oxide", "hematite_ratio", "grain_size") if n in nodes[0].sample]
    varied = [n for n in names if len({b.sample[n] for b in nodes}) > 1]
    mesh = Mesh(tuple(varied), [[b.sample[n] for n in varied] for b in nodes], nodes[0].sample)
    print(f"{mesh}; held out at { ({n: held.sample[n] for n in varied}) }, r0 = {held.normal_reflectance:.3f}")

    print("\n| interpolation | ℓ | held-out relative RMS | model error |")
    print("|---|---|---|---|")
    variants = [
        ("mesh parameters (the paper)", {}),
        ("log r0 for " + ", ".join(args.absorbers), {"absorbers": tuple(args.absorbers)}),
        (
            "log r0, log " + ", ".join(args.log),
            {"absorbers": tuple(args.absorbers), "log_parameters": tuple(args.log)},
        ),
    ]
    for label, params in variants:
        model = SpatialModel(**params).fit(nodes, mesh)
        report = evaluate(model, held)
        print(f"| {label} | {model.n_components_} | {report.relative_rms:.1%} | {report.model_error:.1%} |")

    sizes = EquivalenceClasses(CollectorHemisphere(held.stacks, held.slices)).sizes
    print("\n| node | " + " | ".join(varied) + " | r0 | its BRDF against the held-out one |")
    print("|---|" + "---|" * len(varied) + "---|---|")
    order = np.argsort([abs(b.normal_reflectance - held.normal_reflectance) for b in nodes])
    for k in order:
        b = nodes[k]
        coords = " | ".join(f"{b.sample[n]:g}" for n in varied)
        print(f"| {k} | {coords} | {b.normal_reflectance:.3f} | {relative_rms(b.unique_values, held, sizes):.1%} |")


if __name__ == "__main__":
    main()
