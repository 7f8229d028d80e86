"""Build the pair-correlation table of sandlight's random packings, which the on-the-fly
engine's neighbour memory (``memory="packed"``, docs/geometry.md) uses to place the next grain
a ray meets relative to the grain it left.

For each packing fraction η of the grid, packings of monodisperse spheres (d = 0.25 mm, the
default box of ``generate_packing``, seeds 1 and 2) are generated with sandlight's own packing
generator, and the centre distances r of all pairs (minimum image) are histogrammed in units of
the contact distance σ = d:

* ``z_contact``: contacts per grain, pairs at |x − 1| < 10⁻³ (x = r/σ; the generator leaves
  overlaps up to 10⁻³ σ), the delta peak of g at contact;
* ``g``: the pair correlation function g(x) = (pairs in [x, x + dx)) / (ideal-gas pairs) on
  x = 1.001 + dx·k, dx = 0.005, k = 0 … 399 (x up to 3.001), without the contacts.

Written to ``crates/sandlight-core/data/pair_correlation.txt`` (plain text, atomically) with its
provenance. Run time: about 2 minutes on 2 CPUs.

Usage::

    python3 scripts/data/build_pair_correlation.py [--etas 0.40 0.45 0.50 0.55 0.60 0.62] [--seeds 1 2]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

from sandlight.io import write_atomically
from sandlight.machine import describe
from sandlight.physics.packing import generate_packing, grain_medium

ROOT = Path(__file__).resolve().parents[2]
OUT = ROOT / "crates" / "sandlight-core" / "data" / "pair_correlation.txt"
D_MM = 0.25
X0, DX, BINS = 1.001, 0.005, 400
CONTACT = 1e-3


def pair_statistics(eta, seeds):
    """(contacts per grain, g on the grid, grains, sweeps) over packings of the given seeds."""
    edges = X0 + DX * np.arange(BINS + 1)
    counts, contacts, grains, sweeps, volume = np.zeros(BINS), 0, 0, [], 0.0
    for seed in seeds:
        pk = generate_packing(grain_medium([D_MM], porosity=1.0 - eta), reference_mm=D_MM, seed=seed)
        centres, _ = pk.particles()
        period = np.array(pk.period_mm)
        tree = cKDTree(np.mod(centres, period), boxsize=period)
        pairs = tree.query_pairs(edges[-1] * D_MM, output_type="ndarray")
        rel = centres[pairs[:, 0]] - centres[pairs[:, 1]]
        rel -= period * np.round(rel / period)
        x = np.linalg.norm(rel, axis=1) / D_MM
        contacts += int(np.count_nonzero(np.abs(x - 1.0) < CONTACT))
        counts += np.histogram(x, bins=edges)[0]
        grains += len(centres)
        volume += float(np.prod(period))
        sweeps.append(pk.sweeps)
    # Ideal-gas pairs in a shell: N·ρ·(shell volume)/2 summed over the packings (each has its ρ).
    rho = grains / volume
    shell = 4.0 / 3.0 * np.pi * (edges[1:] ** 3 - edges[:-1] ** 3) * D_MM**3
    g = counts / (0.5 * grains * rho * shell)
    return 2.0 * contacts / grains, g, grains, sweeps


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--etas", type=float, nargs="+", default=[0.40, 0.45, 0.50, 0.55, 0.60, 0.62])
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2])
    args = ap.parse_args(argv)
    started = time.perf_counter()
    rows = []
    for eta in args.etas:
        z, g, grains, sweeps = pair_statistics(eta, args.seeds)
        rows.append(f"{eta:.4f} {z:.4f} " + " ".join(f"{v:.4f}" for v in g))
        print(
            f"η = {eta:.2f}: {grains} grains, sweeps {sweeps}, contacts per grain {z:.3f}, "
            f"g(1.001–1.006) {g[0]:.2f}, g max beyond {g[1:].max():.2f}",
            flush=True,
        )
    header = [
        "# Pair correlation of sandlight's random packings of monodisperse spheres.",
        f"# Source: scripts/data/build_pair_correlation.py (this repository), sandlight_core::packing, d = {D_MM} mm,",
        f"#   default box, seeds {' '.join(map(str, args.seeds))}; "
        f"generated on {describe()}, {time.strftime('%Y-%m-%d')}.",
        "# Licence: MIT (computed by this project's own code).",
        "# Units: x = centre distance / contact distance (dimensionless); z_contact = contacts per grain",
        f"#   (pairs with |x - 1| < {CONTACT:g}); g = pair correlation (dimensionless, 1 for an ideal gas),",
        "#   without the contacts, averaged over bins [x0 + dx k, x0 + dx (k + 1)).",
        "# Lines: 'grid x0 dx bins', then one line per packing fraction: 'eta z_contact g_0 ... g_{bins-1}'.",
        f"grid {X0} {DX} {BINS}",
    ]
    write_atomically(OUT, lambda p: p.write_text("\n".join(header + rows) + "\n", encoding="utf-8"))
    print(f"wrote {OUT.relative_to(ROOT)} in {time.perf_counter() - started:.0f} s")


if __name__ == "__main__":
    main()
