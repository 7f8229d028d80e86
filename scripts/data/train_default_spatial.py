#!/usr/bin/env python3
"""Train the spatial model shipped with sandlight, and print the figures for the docs.

This is the documented command behind ``python/sandlight/data/models/spatial-beach.npz`` (see
docs/spatial-predictor.md): the paper's beach-scene mesh (§4.2.2), 16 degrees of saturation
evenly spaced over [0, 1] at the default mineralogy (``SandSample()``), each measured with the
virtual goniophotometer (31 × 30 patches, uniform incidence) at 550 nm, plus a held-out
measurement at saturation 0.5 (between the nodes 7/15 and 8/15). It needs the native engine::

    python scripts/data/train_default_spatial.py                  # in-process, engine threads = CPUs
    python scripts/data/train_default_spatial.py --rays 1e8 --dask-local 8 --threads 1

Resumable: interrupted, the same command continues from the stored nodes (and from each
running node's checkpoint) in ``--work-dir``. At the end it copies the model into the package
data and prints the settings, the time, ℓ and the explained variance, the reconstruction error
next to the noise, and the held-out error.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PACKAGE_MODEL = ROOT / "python" / "sandlight" / "data" / "models" / "spatial-beach.npz"


def count(text: str) -> int:
    value = float(text)
    if value < 1 or value != int(value):
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number >= 1")
    return int(value)


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--nodes", type=int, default=16, help="saturation levels over [0, 1] (paper: 16)")
    p.add_argument("--rays", type=count, default=50_000_000, help="goniophotometer trials per node")
    p.add_argument("--holdout-rays", type=count, default=400_000_000, help="trials of the held-out measurement")
    p.add_argument("--holdout", type=float, default=0.5, help="saturation of the held-out point")
    p.add_argument("--wavelength", type=float, default=550.0, help="nm")
    p.add_argument(
        "--method",
        default="pooled",
        choices=["average", "pooled"],
        help="class estimator of the reduction (pooled: minimum variance)",
    )
    p.add_argument("--variance", type=float, default=0.999, help="signal-variance threshold for ℓ")
    p.add_argument("--components", type=int, default=None, help="force ℓ")
    p.add_argument(
        "--scaling",
        default="relative",
        choices=["relative", "none", "noise"],
        help="scaling of the values before the PCA (none: the paper)",
    )
    p.add_argument("--seed", type=int, default=20261122, help="master seed")
    p.add_argument(
        "--work-dir",
        type=Path,
        default=ROOT / "build" / "train-default-spatial",
        help="job stores and intermediate files (resumable)",
    )
    p.add_argument(
        "--threads",
        type=int,
        default=None,
        help="engine threads per node (default: all CPUs in-process, 1 with --workers/--dask-*)",
    )
    ex = p.add_mutually_exclusive_group()
    ex.add_argument(
        "--workers",
        type=int,
        help="local worker processes (default: nodes run one after the other in this process, each on all CPUs)",
    )
    ex.add_argument("--dask-local", type=int, help="start a Dask LocalCluster of N workers")
    ex.add_argument("--scheduler", help="Dask scheduler address tcp://HOST:PORT (no checkpoints)")
    p.add_argument(
        "--no-install", action="store_true", help=f"do not copy the model to {PACKAGE_MODEL.relative_to(ROOT)}"
    )
    p.add_argument(
        "--figure",
        type=Path,
        default=ROOT / "docs" / "img" / "spatial-holdout.png",
        help="principal-plane plot of the held-out prediction against the measurement ('' for none)",
    )
    return p.parse_args(argv)


def leave_one_out(nodes_dataset, mesh, method: str) -> dict:
    """Mean leave-one-out scores of the interior nodes for each scaling and ℓ (choosing them).

    The node measurements have fewer trials than the held-out one, so values are scored when
    measured to better than 5 % (not 2 %) relative standard error."""
    import numpy as np

    from sandlight.spatial import cross_validate, node_brdfs

    brdfs = node_brdfs(nodes_dataset, method)
    table = {}
    for scaling in ("none", "relative", "noise"):
        for ell in (1, 2, 3, 4, 5, 6, 8, 10):
            results = [
                r
                for _, r in cross_validate(
                    brdfs, mesh, {"n_components": ell, "scaling": scaling}, max_relative_stderr=0.05
                )
            ]
            table[f"{scaling} l={ell}"] = {
                "relative_rms": round(float(np.mean([r.relative_rms for r in results])), 5),
                "noise_rms": round(float(np.mean([r.noise_rms for r in results])), 5),
                "model_error": round(float(np.mean([r.model_error for r in results])), 5),
                "normalised_rms": round(float(np.mean([r.normalised_rms for r in results])), 4),
                "n_values": int(np.mean([r.n_values for r in results])),
            }
    return table


def plot_holdout(model, holdout_dataset, method: str, path: Path) -> None:
    """Normalised BRDF in the principal plane at the held-out point: measured (patch centroids,
    with ±2 standard errors) against predicted (continuous interpolant)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    from sandlight.spatial import node_brdfs

    measured = node_brdfs(holdout_dataset, method)[0]
    predicted = model.brdf(measured.sample)
    h = measured.hemisphere
    fig, ax = plt.subplots(figsize=(7, 4.2))
    for zenith, colour in ((0.0, "C0"), (30.0, "C1"), (60.0, "C2"), (80.0, "C3")):
        t = np.radians(zenith)
        wi = np.array([np.sin(t), 0.0, np.cos(t)])
        i = int(h.patch_index(wi))
        wi_c = h.centroids[i]
        # Outgoing patches whose centroid lies in the plane of incidence (Δφ = 0 or π); at normal
        # incidence, the plane through the centroids of slice 0.
        az = np.arctan2(wi_c[1], wi_c[0]) if i != h.cap else np.arctan2(h.centroids[1, 1], h.centroids[1, 0])
        dphi = np.mod(np.arctan2(h.centroids[:, 1], h.centroids[:, 0]) - az, 2 * np.pi)
        plane = (
            np.isclose(dphi, 0, atol=1e-9) | np.isclose(dphi, np.pi, atol=1e-9) | np.isclose(dphi, 2 * np.pi, atol=1e-9)
        ) | (h.band == 0)
        signed = np.degrees(np.arccos(np.clip(h.centroids[plane, 2], -1, 1))) * np.where(
            np.isclose(dphi[plane], np.pi, atol=1e-9), -1, 1
        )
        order = np.argsort(signed)
        value, err = measured.values[i, plane][order], measured.stderr[i, plane][order]
        ax.errorbar(
            signed[order],
            value,
            yerr=2 * err,
            fmt="o",
            ms=2.5,
            color=colour,
            alpha=0.6,
            label=f"measured, θi = {np.degrees(np.arccos(wi_c[2])):.0f}°",
        )
        theta = np.radians(np.linspace(-89, 89, 357))
        wo = np.stack([np.sin(theta), np.zeros_like(theta), np.cos(theta)], 1)  # positive θ: the light's side
        rot = np.array([[np.cos(az), -np.sin(az), 0], [np.sin(az), np.cos(az), 0], [0, 0, 1]])
        ax.plot(np.degrees(theta), predicted.f(np.broadcast_to(wi_c, wo.shape), wo @ rot.T), color=colour, lw=1.2)
    ax.set(
        xlabel="outgoing zenith angle in the plane of incidence (°; positive: the light's side)",
        ylabel="normalised BRDF (sr⁻¹)",
        yscale="log",
        title=f"held-out saturation {measured.sample['saturation']:g}: prediction (lines) vs measurement",
    )
    ax.legend(fontsize=7, ncol=2)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None) -> int:
    args = parse_args(argv)
    import sandlight
    from sandlight.errors import Cancelled
    from sandlight.jobs import make_executor
    from sandlight.machine import describe as describe_machine
    from sandlight.spatial import Mesh, train_spatial

    mesh = Mesh.beach(args.nodes)
    pooled = any(v is not None for v in (args.workers, args.dask_local, args.scheduler))
    executor = make_executor(args.workers, args.dask_local, args.scheduler) if pooled else make_executor(workers=1)
    threads = args.threads or (1 if pooled else os.cpu_count() or 1)
    print(f"sandlight {sandlight.__version__} on {describe_machine()}")
    print(
        f"mesh: {mesh}; base: default SandSample(); {args.wavelength:g} nm; 31 x 30 patches; "
        f"{args.rays:,} trials per node; held-out saturation {args.holdout:g} with {args.holdout_rays:,} trials; "
        f"reduction {args.method}; {threads} engine thread(s) per node"
    )
    cpu0, start = time.process_time(), time.perf_counter()
    try:
        run = train_spatial(
            args.work_dir,
            mesh,
            args.rays,
            args.wavelength,
            args.seed,
            holdout=[[args.holdout]],
            holdout_rays=args.holdout_rays,
            method=args.method,
            executor=executor,
            threads=threads,
            checkpoint=args.scheduler is None,
            model_params={
                "n_components": args.components,
                "variance_threshold": args.variance,
                "scaling": args.scaling,
            },
        )
    except Cancelled as exc:
        print(f"interrupted: {exc}", file=sys.stderr)
        return 130
    wall = time.perf_counter() - start
    if not run.complete:
        print("not complete: run the same command again to continue", file=sys.stderr)
        return 1
    model = run.model
    model.training_set_["measurement_wall_s_last_run"] = round(run.measurement_s, 1)
    model.training_set_["machine"] = describe_machine()
    model.save(run.model_path)
    ratio, signal = model.explained_variance_ratio_, model.signal_variance_ratio_
    ell = model.n_components_
    summary = {
        "nodes": mesh.n_nodes,
        "rays_per_node": args.rays,
        "holdout_rays": args.holdout_rays,
        "wavelength_nm": args.wavelength,
        "method": args.method,
        "wall_s_this_run": round(wall, 1),
        "measurement_s_this_run": round(run.measurement_s, 1),
        "fit_s": round(run.fit_s, 2),
        "parent_cpu_s": round(time.process_time() - cpu0, 1),
        "n_components": ell,
        "variance_threshold": args.variance,
        "explained_variance_ratio": [round(float(x), 6) for x in ratio[:6]],
        "signal_variance_ratio": None if signal is None else [round(float(x), 6) for x in signal[:6]],
        "explained_variance_kept": float(ratio[:ell].sum()),
        "signal_variance_kept": None if signal is None else float(signal[:ell].sum()),
        "reconstruction_rms_sr-1": model.reconstruction_rms_,
        "node_noise_rms_sr-1": model.node_noise_rms_,
        "node_normal_reflectance": [round(float(x), 5) for x in model.node_normal_reflectance_],
        "holdout": [r.to_dict() for r in run.reports],
        "leave_one_out": leave_one_out(run.nodes.dataset_path, mesh, args.method),
    }
    print(json.dumps(summary, indent=1))
    for r in run.reports:
        print(r.table())
    (args.work_dir / "summary.json").write_text(json.dumps(summary, indent=1) + "\n", encoding="utf-8")
    if str(args.figure):
        plot_holdout(model, run.holdout.dataset_path, args.method, args.figure)
        print(f"wrote {args.figure}")
    if not args.no_install:
        from sandlight.io import write_atomically

        write_atomically(PACKAGE_MODEL, lambda tmp: shutil.copyfile(run.model_path, tmp))
        print(f"installed {PACKAGE_MODEL} ({PACKAGE_MODEL.stat().st_size / 1e6:.2f} MB)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
