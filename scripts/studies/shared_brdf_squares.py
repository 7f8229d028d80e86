#!/usr/bin/env python3
"""Do the shared goniophotometer's standard errors hold for a dark wavelength behind bright heroes?

Measures yellow-dune's BRDF at 450 nm twice with 4·10⁶ trials: shared with 550, 700 and 1000 nm
(one group: 450 nm's weights behind brighter heroes are small) and with trials of its own
(``share=False``), and prints, for each, how many unique values pass a 10 % relative standard
error and their smallest and median value, how many passing shared values lie below a tenth of
the smallest passing unshared one, then the five smallest passing shared values with their
standard errors and the unshared values in the same cells. A shared value far below
anything the unshared run counts, yet "measured" to better than 10 %, is a standard error that
has collapsed (docs/transport.md, the goniophotometer's sums of squares).

Usage::

    python3 scripts/studies/shared_brdf_squares.py [--rays 4e6] [--seed 3]
"""

from __future__ import annotations

import argparse

import numpy as np


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rays", type=float, default=4_000_000, help="trials per measurement")
    parser.add_argument("--seed", type=int, default=3, help="goniophotometer seed")
    args = parser.parse_args(argv)

    import sandlight

    sample = sandlight.SandSample.preset("yellow-dune")
    common = dict(rays=args.rays, seed=args.seed, threads=1, progress=False)
    shared = sandlight.brdf(sample, [450.0, 550.0, 700.0, 1000.0], **common)[0]
    own = sandlight.brdf(sample, 450.0, share=False, **common)
    for name, m in (("shared", shared), ("own trials", own)):
        v, e = m.unique_values, m.unique_stderr
        with np.errstate(all="ignore"):
            keep = (v > 0) & (e / v < 0.1)
        low, mid = (f"{v[keep].min():.3g}", f"{np.median(v[keep]):.3g}") if keep.any() else ("-", "-")
        print(
            f"{name}: r = {m.normal_reflectance:.4f}; {keep.sum()} values to better than 10 %, "
            f"smallest {low}, median {mid} sr⁻¹"
        )
    v, e = shared.unique_values, shared.unique_stderr
    with np.errstate(all="ignore"):
        keep = np.flatnonzero((v > 0) & (e / v < 0.1))
    with np.errstate(all="ignore"):
        own_keep = (own.unique_values > 0) & (own.unique_stderr / own.unique_values < 0.1)
    floor = own.unique_values[own_keep].min() if own_keep.any() else np.inf
    print(
        f"passing shared values below a tenth of the smallest passing own-trial value: {(v[keep] < 0.1 * floor).sum()}"
    )
    smallest = keep[np.argsort(v[keep])[:5]]
    print("five smallest passing shared values:", np.array2string(v[smallest], precision=3))
    print("their standard errors:             ", np.array2string(e[smallest], precision=3))
    print("own trials in the same cells:      ", np.array2string(own.unique_values[smallest], precision=3))


if __name__ == "__main__":
    main()
