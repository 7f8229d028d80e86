"""Fingerprint of sandlight's results on a fixed set of runs, to prove a refactor bit-identical.

Runs the engine (every preset and memory, explicit geometry, BRDF counts, fixed incidence, the
isotropic reference), the shipped spectral and spatial models, the appearance, colour, sky and a
small render, and records a SHA-256 per result. Run it before and after a change:

    python scripts/dev/fingerprint.py -o before.json
    python scripts/dev/fingerprint.py --compare before.json

``--compare`` prints every entry that differs and exits 1 if any does. About a minute on 2 cores.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np


def _digest(*arrays) -> str:
    h = hashlib.sha256()
    for a in arrays:
        a = np.ascontiguousarray(np.asarray(a))
        h.update(str(a.dtype).encode() + str(a.shape).encode())
        h.update(a.tobytes())
    return h.hexdigest()[:16]


def fingerprint() -> dict[str, str]:
    import sandlight
    from sandlight.colour import sample_lab
    from sandlight.predictor import default_model
    from sandlight.sample import SandSample
    from sandlight.sky.preetham import PreethamSky
    from sandlight.spatial import model as spatial_model

    out: dict[str, str] = {}
    presets = ["red-dune", "yellow-dune", "wet-beach", "gds76-hematite-quartz", "ottawa-gds74", "ottawa-quartz"]
    wl = [450.0, 650.0, 1450.0]
    for name in presets:
        for memory in ("none", "channel", "cut", "packed"):
            if memory in ("cut", "packed") and name == "wet-beach":
                continue
            r = sandlight.reflectance(name, wl, rays=3000, seed=7, progress=False, memory=memory)
            out[f"reflectance/{name}/{memory}"] = _digest(*[r.counts[k] for k in sorted(r.counts)])
    spheres = SandSample.preset("ottawa-quartz").replace(aspect_ratio=1.0)
    for memory in ("none", "cut", "packed"):
        r = sandlight.reflectance(spheres, wl, rays=3000, seed=7, progress=False, memory=memory)
        out[f"reflectance/spheres/{memory}"] = _digest(*[r.counts[k] for k in sorted(r.counts)])
    r = sandlight.reflectance("red-dune", [550.0], rays=400, seed=3, progress=False, geometry="explicit")
    out["reflectance/red-dune/explicit"] = _digest(*[r.counts[k] for k in sorted(r.counts)])
    r = sandlight.reflectance("yellow-dune", [600.0], rays=2000, seed=5, incidence_deg=60, progress=False)
    out["reflectance/yellow-dune/60deg"] = _digest(*[r.counts[k] for k in sorted(r.counts)])
    out["isotropic_halfspace"] = _digest(sandlight.isotropic_halfspace(0.9, rays=5000, seed=1))

    b = sandlight.brdf("red-dune", 650.0, rays=20000, stacks=7, slices=6, seed=2, progress=False)
    out["brdf/red-dune"] = _digest(b.counts, b.values)
    b = sandlight.brdf("wet-beach", 550.0, rays=10000, stacks=7, slices=6, seed=2, progress=False, memory="cut")
    out["brdf/wet-beach/cut"] = _digest(b.counts)
    f = sandlight.fixed_incidence(
        "yellow-dune", 550.0, incidence_deg=40, rays=20000, stacks=7, slices=6, seed=4, progress=False
    )
    out["fixed_incidence/yellow-dune"] = _digest(f.values)

    bank = default_model()
    samples = [SandSample.preset(p) for p in presets]
    for p, s in zip(presets, samples):
        out[f"predict/{p}"] = _digest(bank.predict(s))
    rng = np.random.default_rng(0)
    batch = {"iron_oxide": rng.uniform(0.0, 0.05, 50), "saturation": rng.uniform(0, 1, 50)}
    try:
        out["predict/batch"] = _digest(bank.predict(batch))
    except Exception as e:  # noqa: BLE001 - a partial dict is refused today (issue 24); record what happens
        out["predict/batch"] = type(e).__name__

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        spatial = spatial_model.default_model()
        for p in ("wet-beach", "red-dune"):
            out[f"spatial/{p}"] = _digest(spatial.brdf(SandSample.preset(p)).grid())
            app = sandlight.SandAppearance(p)
            wi = np.array([[0.0, 0.0, 1.0], [0.5, 0.0, np.sqrt(0.75)], [0.9, 0.1, np.sqrt(1 - 0.82)]])
            wo = np.array([[0.3, 0.2, np.sqrt(1 - 0.13)], [-0.5, 0.0, np.sqrt(0.75)], [0.0, 0.0, 1.0]])
            out[f"appearance/{p}/brdf"] = _digest(app.brdf(wi, wo))
            out[f"appearance/{p}/albedo"] = _digest(app.albedo(wi))
            u = rng.random((2, 64))
            s = app.sample(wi[np.arange(64) % 3], u[0], u[1])
            out[f"appearance/{p}/sample"] = _digest(*[np.asarray(x) for x in (s if isinstance(s, tuple) else (s,))])
            out[f"appearance/{p}/pdf"] = _digest(app.pdf(wi, wo))
            out[f"appearance/{p}/table"] = _digest(app.table(n_mu=6, n_dphi=5).f)
        out["colour/lab"] = _digest(sample_lab(samples))

    sky = PreethamSky.from_location(3.0, 30.0, 172, 10.5)
    d = np.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [0.0, 0.96, 0.28]])
    out["sky/radiance"] = _digest(sky.radiance(d, [400.0, 550.0, 700.0]))

    from sandlight.render.animation import render_scene
    from sandlight.render.scene import Scene

    with tempfile.TemporaryDirectory() as tmp, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for name in ("desert-day", "beach-drying"):
            scene = Scene.load(name).with_overrides(
                width=32, height=18, frames=2, spp=2, seed=0, threads=None, write_linear="xyz"
            )
            run = render_scene(scene, Path(tmp) / name, video=None, progress=False)
            out[f"render/{name}"] = _digest(*[np.frombuffer(Path(p).read_bytes(), np.uint8) for p in run.pngs])
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-o", "--output", type=Path, help="write the fingerprint (JSON) here")
    ap.add_argument("--compare", type=Path, help="compare with a fingerprint written before")
    args = ap.parse_args()
    fp = fingerprint()
    if args.output:
        args.output.write_text(json.dumps(fp, indent=1, sort_keys=True) + "\n")
        print(f"{len(fp)} entries written to {args.output}")
    if args.compare:
        old = json.loads(args.compare.read_text())
        diff = sorted(k for k in set(old) | set(fp) if old.get(k) != fp.get(k))
        for k in diff:
            print(f"DIFFERS {k}: {old.get(k)} -> {fp.get(k)}")
        print(f"{len(fp) - len(diff)} of {len(set(old) | set(fp))} entries identical")
        return 1 if diff else 0
    if not args.output:
        json.dump(fp, sys.stdout, indent=1, sort_keys=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
