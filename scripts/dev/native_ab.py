"""Speed of the tracers' hot loop in two builds of the native module, side by side.

Loads two copies of ``sandlight._native`` (e.g. the build of ``main`` and that of a branch,
each ``_native.abi3.so`` copied somewhere) into one process and alternates their runs of
the same rays, so that other load on the machine slows both alike. Cases: the default sample
and red-dune ('packed' memory, normal incidence, 1 thread) shared (a ``SpectralGroup``) at one
wavelength (550 nm) and at 16 (400–700 nm), and at 550 nm traced on its own (``share=False``:
the ``Medium``). Every table is built before the timing (``exact_fraction`` and a first run of
the same rays), so the loop alone is timed. It prints the particle events per process
CPU-second of each build and the median ratio of paired runs. The two builds must give the
same tallies (checked).

    python scripts/dev/native_ab.py BEFORE.so AFTER.so [--rounds 10]
"""

from __future__ import annotations

import argparse
import importlib.util
import statistics
import time

import numpy as np

import sandlight
import sandlight.physics.medium as physics_medium
from sandlight.physics.media import as_traceable

SIXTEEN = np.linspace(400.0, 700.0, 16).tolist()
#: Case: sample, wavelengths, rays, shared.
CASES = {
    "default, 550 nm": ("default", [550.0], 300_000, True),
    "red-dune, 550 nm": ("red-dune", [550.0], 300_000, True),
    "default, 16 λ": ("default", SIXTEEN, 60_000, True),
    "red-dune, 16 λ": ("red-dune", SIXTEEN, 60_000, True),
    "default, 550 nm, on its own": ("default", [550.0], 300_000, False),
    "red-dune, 550 nm, on its own": ("red-dune", [550.0], 300_000, False),
}


def load(path: str):
    spec = importlib.util.spec_from_file_location("sandlight._native", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def tracer(module, name: str, wavelengths: list[float], shared: bool):
    """The group of the sample's media at ``wavelengths`` (``shared``), or its one medium."""
    # The media are built by the package's Python code through `module`.
    physics_medium._native = module
    sample = sandlight.SandSample() if name == "default" else sandlight.SandSample.preset(name)
    traced = as_traceable(sample)
    media = [traced.medium(w) for w in wavelengths]
    if not shared:
        return media[0]
    g = module.SpectralGroup(media)
    g.exact_fraction()  # every cell built
    return g


def run(tracer, rays: int) -> tuple:
    return tracer.dhr(0.0, 1, 1, 0, rays, 10**6, 100, threads=1)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("before", help="path of the first build's _native.abi3.so")
    parser.add_argument("after", help="path of the second build's _native.abi3.so")
    parser.add_argument("--rounds", type=int, default=10, help="runs of each build per case")
    args = parser.parse_args(argv)
    builds = {"before": load(args.before), "after": load(args.after)}
    for case, (name, wavelengths, rays, shared) in CASES.items():
        tracers = {b: tracer(m, name, wavelengths, shared) for b, m in builds.items()}
        for t in tracers.values():
            run(t, rays)  # the tables the rays meet built (bracket tables, path memory)
        events = 2 if shared else 5  # where the particle events are in the tuple of counts
        speed: dict[str, list[float]] = {b: [] for b in builds}
        tallies = {}
        for r in range(args.rounds):
            for b in ("before", "after") if r % 2 == 0 else ("after", "before"):
                cpu = time.process_time()
                tallies[b] = run(tracers[b], rays)
                speed[b].append(tallies[b][events] / (time.process_time() - cpu) / 1e6)
        if tallies["before"] != tallies["after"]:
            raise SystemExit(f"{case}: the two builds' tallies differ")
        ratio = statistics.median(a / b for a, b in zip(speed["after"], speed["before"]))
        shown = ", ".join(f"{b} {statistics.median(v):.2f} (best {max(v):.2f})" for b, v in speed.items())
        print(f"{case}: M events/CPU-s median {shown}; after/before, median of pairs {ratio:.3f}", flush=True)


if __name__ == "__main__":
    main()
