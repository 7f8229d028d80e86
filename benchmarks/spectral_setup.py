"""Set-up cost of shared spectral runs (docs/performance.md, "Set-up of a shared run"): a
benchmark script, not a test.

Before a shared run traces a ray it builds a native medium per wavelength and the group's
stack tables. For short runs — the training samples of the spectral predictors — that set-up
can cost more than the tracing. This prints, 1 thread, wall-clock and process CPU seconds:

* ``training``: ``--samples`` broad dry samples (``Domain.default().restrict(saturation=0.0,
  film_saturation=0.15).draw(n, 9, 'random')``), 16 wavelengths 400–700 nm, 1000 rays each,
  through ``sandlight.predictor.training.engine_simulate`` (seed 1), per sample; then, for as
  many other samples of the domain (drawn with seeds 11 and 10), the set-up alone: building the
  media (``traced.medium(λ)``), and the media with the native ``SpectralGroup`` of each group
  (what happens before the first ray is traced);
* ``red-dune``: the preset at the 216 wavelengths 350–2500 nm step 10, 1 ray and 2000 rays.

The parts run in this order in one process, so whatever a build remembers from one sample to
the next (optical constants at the training wavelengths) is remembered as in a training job.
Each timed line ends with a digest of the results (values and standard errors, bit for bit),
so two builds timed with this script can be seen to give the same numbers. Nothing is
asserted; other load on the machine shows in the wall-clock times, less in the CPU times, so
run it a few times.

Usage::

    python benchmarks/spectral_setup.py [--samples 20]
"""

from __future__ import annotations

import argparse
import hashlib
import os
import time

import numpy as np

import sandlight
from sandlight import _native
from sandlight.physics.media import as_traceable
from sandlight.physics.spectral_groups import spectral_groups
from sandlight.predictor import Domain
from sandlight.predictor.training import engine_simulate


def load_average() -> str:
    try:
        return "{:.2f} {:.2f} {:.2f}".format(*os.getloadavg())
    except OSError:
        return "n/a"


def digest(results) -> str:
    h = hashlib.sha256()
    for r in results:
        h.update(np.ascontiguousarray(r.values, dtype=float).tobytes())
        h.update(np.ascontiguousarray(r.stderr, dtype=float).tobytes())
    return h.hexdigest()[:16]


def timed(fn):
    """(result, wall s, CPU s) of one call."""
    w, c = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - w, time.process_time() - c


def training(n_samples: int) -> None:
    wl = np.linspace(400.0, 700.0, 16)
    payloads = Domain.default().restrict(saturation=0.0, film_saturation=0.15).draw(n_samples, 9, "random")

    def run():
        return [engine_simulate(p, wl, rays=1000, seed=1) for p in payloads]

    results, wall, cpu = timed(run)
    print(
        f"training, {n_samples} samples × 16 λ, 1000 rays: {wall / n_samples:.3f} s/sample wall, "
        f"{cpu / n_samples:.3f} CPU s/sample  [{digest(results)}]"
    )

    # The set-up alone, for other samples (each part its own: nothing of theirs remembered yet),
    # the media of every wavelength, and those with the native groups.
    def others(seed: int) -> list[dict]:
        return Domain.default().restrict(saturation=0.0, film_saturation=0.15).draw(n_samples, seed, "random")

    def setup():
        for p in others(10):
            traced = as_traceable(sandlight.SandSample(**p))
            for idx in spectral_groups(traced.composition, wl):
                _native.SpectralGroup([traced.medium(float(wl[i])) for i in idx])

    def media():
        for p in others(11):
            traced = as_traceable(sandlight.SandSample(**p))
            for lam in wl:
                traced.medium(float(lam))

    _, wall_m, cpu_m = timed(media)
    _, wall_s, cpu_s = timed(setup)
    print(
        f"set-up of {n_samples} other samples: media (16 per sample) {wall_m / n_samples:.4f} s/sample wall, "
        f"{cpu_m / n_samples:.4f} CPU s/sample; media and SpectralGroups {wall_s / n_samples:.4f} s/sample wall, "
        f"{cpu_s / n_samples:.4f} CPU s/sample"
    )


def red_dune() -> None:
    wl = np.arange(350.0, 2501.0, 10.0)
    for rays in (1, 2000):
        r, wall, cpu = timed(
            lambda rays=rays: sandlight.reflectance("red-dune", wl, rays=rays, seed=1, threads=1, progress=False)
        )
        print(
            f"red-dune, {wl.size} λ, {rays} rays, {len(r.groups)} groups: {wall:.2f} s wall, {cpu:.2f} CPU s  "
            f"[{digest([r])}]"
        )


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--samples", type=int, default=20, help="training samples (broad, dry)")
    args = parser.parse_args(argv)
    print(f"sandlight {sandlight.__version__} ({os.path.dirname(sandlight.__file__)}), load average {load_average()}")
    training(args.samples)
    red_dune()
    print(f"load average after: {load_average()}")


if __name__ == "__main__":
    main()
