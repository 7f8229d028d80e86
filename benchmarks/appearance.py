"""Speed of the explicit BRDF (prints figures; asserts nothing).

    python3 benchmarks/appearance.py [--pairs 1e6] [--preset wet-beach]

Prints, for `SandAppearance` on the shipped models (or, where a model is not installed yet, a
synthetic stand-in of the same size, which runs the same code):

- model load: `SpatialModel.load` of the spatial model file, construction of `SandAppearance`
  (prediction, grid, sampling tables), and a cold start in a fresh interpreter (imports included);
- BRDF evaluations per second, batched: direction pairs per second at 1 and at 16 wavelengths,
  per core (CPU time of this process) and per wall-clock second, with 1 and 2 threads;
- sampling and pdf rates of both samplers;
- the cost of a shape per wavelength (``shape='reflectance'`` against ``'fixed'``, side by side)
  on the shipped model that covers ``--shape-preset`` (default yellow-dune: the dune family,
  which interpolates in log r₀): construction and BRDF rate at the spectral model's wavelengths.

"Per core" divides by the process's CPU time, so it is meaningful on a shared machine; the wall
rate depends on what else runs.
"""

from __future__ import annotations

import argparse
import os
import platform
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
from _timing import best_of


def synthetic_spatial_model(path: Path) -> Path:
    """A 31 × 30 SpatialModel from synthetic counts (Chandrasekhar media), same size as the real one."""
    from sandlight.gonio import CollectorHemisphere, MeasuredBRDF
    from sandlight.spatial import Mesh, SpatialModel
    from sandlight.testing import synthetic_brdf

    h = CollectorHemisphere()
    mesh = Mesh.beach(4)
    nodes = []
    for i, x in enumerate(mesh.nodes[:, 0]):
        p = synthetic_brdf.chandrasekhar_probabilities(h, 0.95 - 0.5 * x, order=4)
        nodes.append(MeasuredBRDF.from_counts(**synthetic_brdf.sample_counts(h, p, 10**8, seed=i), wavelength_nm=550.0))
    return SpatialModel(n_components=3).fit(nodes, mesh).save(path)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--pairs", type=float, default=1e6)
    ap.add_argument("--preset", default="wet-beach")
    ap.add_argument("--shape-preset", default="yellow-dune")
    args = ap.parse_args()

    import sandlight
    from sandlight.appearance import SandAppearance
    from sandlight.spatial import SpatialModel
    from sandlight.spatial.model import default_model_path

    print(
        f"sandlight {sandlight.__version__} on {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
        f"load average {os.getloadavg()[0]:.2f}"
    )
    spatial_path = default_model_path()
    tmp = Path(tempfile.mkdtemp())
    if not spatial_path.is_file():
        print("spatial model not installed: using a synthetic 31 × 30 stand-in")
        spatial_path = synthetic_spatial_model(tmp / "spatial.npz")
    try:
        from sandlight.predictor import default_model

        default_model()
        spectral, spectral_label = None, "shipped spectral model"
    except sandlight.ModelFileError:
        wl = np.arange(400.0, 701.0, 20.0)
        spectral, spectral_label = (lambda s: (wl, np.linspace(0.2, 0.5, wl.size))), "flat stand-in spectrum (16 wl)"
    print(f"sample: {args.preset}; {spectral_label}; spatial model {spatial_path}")

    wall, _ = best_of(lambda: SpatialModel.load(spatial_path), repeat=5)
    print(f"SpatialModel.load: {wall * 1e3:.1f} ms ({spatial_path.stat().st_size / 1e6:.2f} MB)")
    model = SpatialModel.load(spatial_path)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        wall, _ = best_of(lambda: SandAppearance(args.preset, spectral, model), repeat=3)
        app = SandAppearance(args.preset, spectral, model)
    print(f"SandAppearance construction (prediction, grid, sampling tables): {wall * 1e3:.1f} ms")
    stand_in = "None" if spectral is None else "lambda s: (np.arange(400.0, 701.0, 20.0), np.full(16, 0.3))"
    code = (
        "import time, warnings; t = time.perf_counter(); warnings.simplefilter('ignore'); import numpy as np; "
        "from sandlight.appearance import SandAppearance; "
        f"SandAppearance({args.preset!r}, {stand_in}, {str(spatial_path)!r}); "
        "print(time.perf_counter() - t)"
    )
    cold = float(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout)
    print(f"cold start in a fresh interpreter (imports, models, construction): {cold:.2f} s")

    n = int(args.pairs)
    rng = np.random.default_rng(1)
    wi, wo = rng.normal(size=(n, 3)), rng.normal(size=(n, 3))
    wi[:, 2], wo[:, 2] = np.abs(wi[:, 2]), np.abs(wo[:, 2])
    for wavelengths in ([550.0], app.wavelengths_nm):
        for threads in (None, 2):

            def run(wavelengths=wavelengths, threads=threads):
                return app.brdf(wi, wo, wavelengths, threads=threads)

            wall, cpu = best_of(run)
            print(
                f"brdf, {len(wavelengths):2d} wavelength(s), {threads or 1} thread(s): {n / cpu / 1e6:6.1f} M pairs/s "
                f"per core (CPU time), {n / wall / 1e6:6.1f} M pairs/s wall"
            )
    m = min(n, 200_000)
    u1, u2 = rng.random(m), rng.random(m)
    for method in ("brdf", "cosine"):
        wall, cpu = best_of(lambda method=method: app.sample(wi[:m], u1, u2, 550.0, method=method))
        print(f"sample ({method}): {m / cpu / 1e6:.2f} M/s per core")
    wall, cpu = best_of(lambda: app.pdf(wi[:m], wo[:m]))
    print(f"pdf (brdf): {m / cpu / 1e6:.2f} M/s per core")

    from sandlight.spatial.shipped import model_for

    covering = model_for(sandlight.SandSample.preset(args.shape_preset))
    rates = {}
    for shape in ("fixed", "reflectance"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            build = lambda shape=shape: SandAppearance(args.shape_preset, spectral, covering, shape=shape)  # noqa: E731
            wall, _ = best_of(build, repeat=3)
            app = build()
        _, cpu = best_of(lambda app=app: app.brdf(wi, wo))
        rates[shape] = n / cpu
        print(
            f"{args.shape_preset}, shape={shape!r} ({len(app.shapes.shapes)} shapes): "
            f"construction {wall * 1e3:.1f} ms, "
            f"brdf at {len(app.wavelengths_nm)} wavelengths {rates[shape] / 1e6:.1f} M pairs/s per core"
        )
    print(f"shape per wavelength costs {rates['fixed'] / rates['reflectance']:.1f}× the time of one shape")


if __name__ == "__main__":
    main()
