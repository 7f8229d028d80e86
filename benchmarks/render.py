"""Speed and noise of the renderer (prints figures; asserts nothing).

    python3 benchmarks/render.py [--spp 64] [--time-h 9] [--figures docs/figures]

1. One 640×360 frame of the shipped ``desert-day`` scene at 64 samples per pixel (the issue's
   target: ≤ 10 s on the 2-core machine): seconds of native rendering with 1 and 2 threads,
   samples per second, and the seconds of colour conversion and writing.
2. Noise against samples per pixel on a small crop (a 48 × 48 telephoto view of the same dunes):
   the standard deviation of one render, from the difference of two renders with independent
   seeds (σ = rms(A − B)/√2 of the luminance Y), for 4 … 256 spp, and the fitted log–log slope
   (Monte Carlo: −1/2).
3. Wet sand at grazing angles (where the mirror reflection of saturated sand peaks at 10³–10⁴
   sr⁻¹): a 320 × 180 ``beach-drying`` frame at 13:00 and 08:00, crop of rows 22–61 (the wet
   sand towards the horizon, seen 0.3°–8° below it), relative noise σ/Y and the largest pixel
   over the median at 8, 32 and 128 spp.
4. With ``--figures DIR``: ``render_noise.png`` (noise against spp) and ``render_benchmark_frame.png``.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import platform
import time
from pathlib import Path

import numpy as np

import sandlight
from sandlight.render import Camera, Scene, post, render_image


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--time-h", type=float, default=9.0, help="solar time of the benchmark frame")
    ap.add_argument("--figures", type=Path, default=None, help="folder for the PNG figures")
    args = ap.parse_args()
    print(
        f"sandlight {sandlight.__version__} on {platform.processor() or platform.machine()}, "
        f"{os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f}"
    )

    scene = Scene.load("desert-day").with_overrides(width=640, height=360, spp=args.spp)
    t0 = time.perf_counter()
    terrain = scene.build_terrain()
    camera = scene.build_camera(terrain)
    table = scene.build_table()
    lighting = scene.build_lighting(args.time_h)
    setup = time.perf_counter() - t0
    print(
        f"desert-day frame at {args.time_h:g} h (sun {lighting.sun_elevation_deg:.1f}° up), 640×360, "
        f"{args.spp} spp, {scene.settings.max_bounces} bounce(s), estimator {scene.settings.estimator}/"
        f"{scene.settings.sampling}; scene set-up (dunes, table, sky) {setup:.2f} s"
    )
    samples = 640 * 360 * args.spp
    image = None
    for threads in (1, 2):
        settings = dataclasses.replace(scene.settings, threads=threads)
        cpu0 = time.process_time()
        image = render_image(camera, terrain, table, lighting, None, settings)
        cpu = time.process_time() - cpu0
        # CPU seconds (all threads of this process) hardly depend on other jobs sharing the cores:
        # on idle cores the wall time would be about cpu / threads.
        print(
            f"  {threads} thread(s): {image.elapsed_s:.2f} s wall, {cpu:.2f} s CPU, "
            f"{samples / image.elapsed_s / 1e6:.2f} M samples/s, {cpu / samples * 1e9:.0f} ns CPU per sample; "
            f"load average now {os.getloadavg()[0]:.2f}"
        )
    t0 = time.perf_counter()
    xyz = post.spectral_to_xyz(image.radiance, scene.wavelength_nm)
    rgb = post.to_srgb(xyz, post.white_level("auto", lighting, scene.wavelength_nm))
    colour_s = time.perf_counter() - t0
    print(f"  colour (spectrum → XYZ → sRGB) {colour_s:.2f} s; ground {image.coverage.mean():.0%} of the frame")

    # Noise on a crop: a 5° telephoto view of the dunes seen by the benchmark camera.
    f, _, _ = camera.basis()
    crop = Camera(camera.position, f + np.array([0.05, 0.0, -0.08]), 5.0, 48, 48)
    spps = [4, 16, 64, 256]
    sigmas = []
    wl = scene.wavelength_nm
    for spp in spps:
        ys = []
        for seed in (11, 12):
            s = dataclasses.replace(scene.settings, spp=spp, seed=seed)
            img = render_image(crop, terrain, table, lighting, None, s)
            ys.append(post.spectral_to_xyz(img.radiance, wl)[..., 1])
        sigma = float(np.sqrt(np.mean((ys[0] - ys[1]) ** 2) / 2.0) / np.mean(ys[0]))
        sigmas.append(sigma)
        print(f"  crop 48×48 at {spp:4d} spp: relative noise σ/Y = {sigma:.4f}  (σ·√spp = {sigma * np.sqrt(spp):.3f})")
    slope = np.polyfit(np.log(spps), np.log(sigmas), 1)[0]
    print(f"  log–log slope of noise against spp: {slope:.3f} (Monte Carlo: −0.5)")

    beach_crop()

    if args.figures is not None:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        args.figures.mkdir(parents=True, exist_ok=True)
        fig, ax = plt.subplots(figsize=(4.5, 3.2), dpi=120)
        ax.loglog(spps, sigmas, "o-", label=f"measured (slope {slope:.2f})")
        ax.loglog(spps, sigmas[0] * np.sqrt(spps[0] / np.asarray(spps)), "k--", label=r"$1/\sqrt{\mathrm{spp}}$")
        ax.set_xlabel("samples per pixel")
        ax.set_ylabel("relative noise σ/Y")
        ax.set_title("desert-day crop, 48×48")
        ax.legend()
        fig.tight_layout()
        fig.savefig(args.figures / "render_noise.png")
        post.write_png(args.figures / "render_benchmark_frame.png", rgb)
        print(f"  figures in {args.figures}")


def beach_crop() -> None:
    """Section 3 of the module docstring: noise on the wet sand of ``beach-drying`` at grazing angles."""
    scene = Scene.load("beach-drying").with_overrides(width=320, height=180)
    terrain = scene.build_terrain()
    camera = scene.build_camera(terrain)
    table = scene.build_table()
    rows = slice(22, 62)
    below = -np.degrees(np.arcsin(camera.directions()[rows, :, 2]))
    print(
        f"beach-drying, 320×180, crop rows {rows.start}–{rows.stop - 1} (view {below.min():.1f}°–{below.max():.1f}° "
        f"below the horizon), BRDF {table.source!r}, {table.n_levels} levels"
    )
    wl = scene.wavelength_nm
    for time_h in (13.0, 8.0):
        lighting = scene.build_lighting(time_h)
        material = scene.build_material((time_h - scene.sun.start_h) / (scene.sun.end_h - scene.sun.start_h))
        sigmas, spps = [], [8, 32, 128]
        for spp in spps:
            ys = []
            for seed in (21, 22):
                img = render_image(
                    camera, terrain, table, lighting, material, dataclasses.replace(scene.settings, spp=spp, seed=seed)
                )
                ys.append(post.spectral_to_xyz(img.radiance, wl)[rows, :, 1])
            sigma = float(np.sqrt(np.mean((ys[0] - ys[1]) ** 2) / 2.0) / np.mean(ys[0]))
            sigmas.append(sigma)
            print(
                f"  {time_h:4.1f} h (sun {lighting.sun_elevation_deg:4.1f}° up), {spp:3d} spp: σ/Y = {sigma:.4f}, "
                f"largest pixel / median = {ys[0].max() / np.median(ys[0]):.2f}"
            )
        print(f"  log–log slope: {np.polyfit(np.log(spps), np.log(sigmas), 1)[0]:.3f}")


if __name__ == "__main__":
    main()
