"""Speed of the `sand` plugin in Mitsuba against sandlight's renderer on the same frame (prints
figures; asserts nothing).

    python3 benchmarks/mitsuba.py [--width 320] [--height 180] [--spp 64] [--scene beach-drying] [--frame 10]

The frame: the shipped scene's camera, terrain and sand at that frame's hour (default
``beach-drying`` at 13:00: the flat beach with its 16 saturation levels and the waterline map).
sandlight's renderer shades it under its Preetham sky with 16 bands (400–700 nm) and MIS, all
cores; Mitsuba under ``sunsky`` with the ``path`` integrator (MIS), ``max_depth`` = the scene's
bounces + 1, in ``llvm_ad_rgb`` and ``llvm_ad_spectral`` (4 wavelengths per sample), all cores.
Both estimate the same direct lighting on the same plane. For each: the wall time of one render
after a warm-up render (Mitsuba compiles its kernels once; the first render is reported
separately), and samples (camera paths) per second. Set-up (BRDF tables, sky texture, scene
loading) is excluded and reported.
"""

from __future__ import annotations

import argparse
import os
import platform
import time
import warnings

import numpy as np


def sandlight_frame(scene, frame):
    from sandlight.render import render_image

    t0 = time.perf_counter()
    terrain = scene.build_terrain()
    camera = scene.build_camera(terrain)
    table = scene.build_table()
    lighting = scene.build_lighting(float(scene.times_h()[frame]))
    material = scene.build_material(float(scene.day_fractions()[frame]))
    setup = time.perf_counter() - t0
    image = render_image(camera, terrain, table, lighting, material, scene.settings, frame=frame)
    return setup, image.elapsed_s


def mitsuba_frame(scene, frame, variant):
    import sandlight.mitsuba as sm
    from sandlight.mitsuba.scenes import scene_dict

    mi = sm.load_mitsuba(variant)
    t0 = time.perf_counter()
    loaded = mi.load_dict(scene_dict(mi, scene, frame))
    setup = time.perf_counter() - t0
    times = []
    for seed in range(2):  # the first render compiles the kernels
        t0 = time.perf_counter()
        image = mi.render(loaded, seed=seed)
        np.array(image)  # wait for the kernels
        times.append(time.perf_counter() - t0)
    return setup, times[0], times[1]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", default="beach-drying")
    ap.add_argument("--frame", type=int, default=10)
    ap.add_argument("--width", type=int, default=320)
    ap.add_argument("--height", type=int, default=180)
    ap.add_argument("--spp", type=int, default=64)
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    from sandlight.render import Scene

    scene = Scene.load(args.scene).with_overrides(width=args.width, height=args.height, spp=args.spp)
    samples = args.width * args.height * args.spp
    print(f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores; {args.scene} frame {args.frame}")
    print(f"{args.width}×{args.height} px, {args.spp} spp = {samples:,} camera samples")
    setup, seconds = sandlight_frame(scene, args.frame)
    base = samples / seconds
    print(f"sandlight (Rust, 16 bands, MIS): {seconds:.2f} s = {base / 1e6:.3f} M samples/s (set-up {setup:.1f} s)")
    for variant in ("llvm_ad_rgb", "llvm_ad_spectral"):
        setup, first, steady = mitsuba_frame(scene, args.frame, variant)
        rate = samples / steady
        print(
            f"Mitsuba {variant}: {steady:.2f} s = {rate / 1e6:.3f} M samples/s, {rate / base:.2f}× sandlight "
            f"(first render with compilation {first:.1f} s; scene loading {setup:.1f} s)"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
