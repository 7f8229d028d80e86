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
loading) is excluded and reported. Noise: on the crop of rows 22–61 of 180 (scaled to the
height; for beach-drying the wet sand 0.3°–8° below the horizon, as benchmarks/render.py), the
relative standard deviation of one render's luminance, σ/Y = rms(A − B)/(√2 Ȳ) from two renders
with independent seeds; efficiency = samples/s ÷ (σ/Y)² (higher is better), relative to sandlight.

Then the cost of the plugin's shapes per wavelength, side by side: ``eval`` + ``pdf`` of 10⁶
random direction pairs in ``llvm_ad_rgb`` for ``--shape-preset`` (default yellow-dune, the dune
family's blended shapes) with ``shape="reflectance"`` and ``"fixed"`` (best of 3 after a
warm-up). ``--shapes-only`` skips the frame.
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import time
import warnings
from pathlib import Path

import numpy as np

# This file is named like the package it measures: keep its folder off the path so that
# `import mitsuba` finds Mitsuba, not this script.
sys.path = [p for p in sys.path if Path(p or ".").resolve() != Path(__file__).resolve().parent]


LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def crop_noise(a, b):
    """σ/Y of one render on the benchmark crop, from two renders' luminance images a, b."""
    h = a.shape[0]
    rows = slice(round(22 * h / 180), round(62 * h / 180))
    a, b = a[rows], b[rows]
    return float(np.sqrt(np.mean((a - b) ** 2) / 2) / np.mean(0.5 * (a + b)))


def sandlight_frame(scene, frame):
    import dataclasses

    from sandlight.render import post, render_image

    t0 = time.perf_counter()
    terrain = scene.build_terrain()
    camera = scene.build_camera(terrain)
    table = scene.build_table()
    lighting = scene.build_lighting(float(scene.times_h()[frame]))
    material = scene.build_material(float(scene.day_fractions()[frame]))
    setup = time.perf_counter() - t0
    ys, seconds = [], []
    for seed in range(2):
        settings = dataclasses.replace(scene.settings, seed=seed)
        image = render_image(camera, terrain, table, lighting, material, settings, frame=frame)
        ys.append(post.spectral_to_xyz(image.radiance, scene.wavelength_nm)[..., 1])
        seconds.append(image.elapsed_s)
    return setup, min(seconds), crop_noise(*ys)


def mitsuba_frame(scene, frame, variant):
    import sandlight.mitsuba as sm
    from sandlight.mitsuba.scenes import scene_dict

    mi = sm.load_mitsuba(variant)
    t0 = time.perf_counter()
    loaded = mi.load_dict(scene_dict(mi, scene, frame))
    setup = time.perf_counter() - t0
    times, ys = [], []
    for seed in range(3):  # the first render compiles the kernels
        t0 = time.perf_counter()
        image = np.array(mi.render(loaded, seed=seed))  # (waits for the kernels)
        times.append(time.perf_counter() - t0)
        ys.append(image[..., :3] @ LUMINANCE)
    return setup, times[0], min(times[1:]), crop_noise(ys[1], ys[2])


def plugin_eval_rates(preset: str, n: int = 1_000_000) -> None:
    """Pairs per second of the plugin's eval + pdf for ``preset`` with either shape option."""
    import drjit as dr

    import sandlight.mitsuba as sm

    mi = sm.load_mitsuba("llvm_ad_rgb")
    rng = np.random.default_rng(1)
    wi, wo = rng.normal(size=(2, n, 3))
    wi[:, 2], wo[:, 2] = np.abs(wi[:, 2]) + 1e-3, np.abs(wo[:, 2]) + 1e-3
    wi /= np.linalg.norm(wi, axis=1, keepdims=True)
    wo /= np.linalg.norm(wo, axis=1, keepdims=True)
    si = dr.zeros(mi.SurfaceInteraction3f, n)
    si.wi = mi.Vector3f(wi.T.astype(np.float32))
    out, ctx = mi.Vector3f(wo.T.astype(np.float32)), mi.BSDFContext()
    rates = {}
    for shape in ("fixed", "reflectance"):
        bsdf = mi.load_dict({"type": "sand", "preset": preset, "shape": shape})
        times = []
        for _ in range(4):  # the first compiles the kernel
            t0 = time.perf_counter()
            value, pdf = bsdf.eval_pdf(ctx, si, out)
            dr.eval(value, pdf)
            dr.sync_thread()  # the kernels run asynchronously: wait for them
            times.append(time.perf_counter() - t0)
        rates[shape] = n / min(times[1:])
        shapes = sm.bsdf.plugin_tables(bsdf.spec).shapes
        print(f"plugin eval + pdf, {preset}, shape={shape!r} ({shapes} shapes): {rates[shape] / 1e6:.1f} M pairs/s")
    print(f"shape per wavelength costs {rates['fixed'] / rates['reflectance']:.1f}× the time of one shape")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", default="beach-drying")
    ap.add_argument("--frame", type=int, default=10)
    ap.add_argument("--width", type=int, default=320)
    ap.add_argument("--height", type=int, default=180)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--shape-preset", default="yellow-dune")
    ap.add_argument("--shapes-only", action="store_true")
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    if args.shapes_only:
        plugin_eval_rates(args.shape_preset)
        return 0
    from sandlight.render import Scene

    scene = Scene.load(args.scene).with_overrides(width=args.width, height=args.height, spp=args.spp)
    samples = args.width * args.height * args.spp
    print(f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores; {args.scene} frame {args.frame}")
    print(f"{args.width}×{args.height} px, {args.spp} spp = {samples:,} camera samples")
    print(f"load average before: {os.getloadavg()[0]:.2f}")
    setup, seconds, noise = sandlight_frame(scene, args.frame)
    base = samples / seconds
    base_eff = base / noise**2
    print(
        f"sandlight (Rust, 16 bands, MIS): {seconds:.2f} s = {base / 1e6:.3f} M samples/s, crop σ/Y {noise:.4f} "
        f"(set-up {setup:.1f} s)"
    )
    for variant in ("llvm_ad_rgb", "llvm_ad_spectral"):
        setup, first, steady, noise = mitsuba_frame(scene, args.frame, variant)
        rate = samples / steady
        print(
            f"Mitsuba {variant}: {steady:.2f} s = {rate / 1e6:.3f} M samples/s, {rate / base:.2f}× sandlight; "
            f"crop σ/Y {noise:.4f}, efficiency {rate / noise**2 / base_eff:.2f}× sandlight "
            f"(first render with compilation {first:.1f} s; scene loading {setup:.1f} s)"
        )
    plugin_eval_rates(args.shape_preset)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
