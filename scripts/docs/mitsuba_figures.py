#!/usr/bin/env python3
"""Render the figures of docs/mitsuba.md: the two XML examples and the two animations through
Mitsuba, timed.

    python3 scripts/docs/mitsuba_figures.py [--out docs/figures] [--work build/mitsuba-figures]

- ``mitsuba_examples.png``: ``desert.xml`` and ``beach.xml`` (sandlight/data/mitsuba/, 320 × 180,
  64 spp, llvm_ad_spectral), exposed as the animations are.
- ``mitsuba_desert_day.png``, ``mitsuba_beach_drying.png``: ``sandlight render SCENE -o DIR
  --video FILE.mp4 --renderer mitsuba --width 240 --height 135 --spp 64 --frames N`` (5 desert
  frames, 06:00–18:00; 3 beach frames, 08:00–18:00), every other setting from the scene file.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
ANIMATIONS = {
    "desert-day": (5, ("06:00", "09:00", "12:00", "15:00", "18:00")),
    "beach-drying": (3, ("08:00", "13:00", "18:00")),
}
SIZE, SPP = (240, 135), 64


def strip(images: list, labels: list[str], target: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(images), figsize=(3.2 * len(images), 2.1), dpi=100)
    for ax, image, label in zip(axes, images, labels):
        ax.imshow(image)
        ax.set_axis_off()
        ax.set_title(label, fontsize=10, y=-0.16)
    fig.subplots_adjust(left=0.005, right=0.995, top=0.99, bottom=0.1, wspace=0.02)
    fig.savefig(target)
    plt.close(fig)


def examples(target: Path) -> None:
    import numpy as np

    import sandlight.mitsuba as sm
    from sandlight.mitsuba.animation import tonemap, white_luminance
    from sandlight.mitsuba.scenes import example_xml_path, sunsky
    from sandlight.render import Scene

    mi = sm.load_mitsuba("llvm_ad_spectral")
    images, labels = [], []
    for name, scene_name, hour in (("desert.xml", "desert-day", 9.0), ("beach.xml", "beach-drying", 13.0)):
        start = time.perf_counter()
        image = np.array(mi.render(mi.load_file(str(example_xml_path(name)))))[..., :3]
        seconds = time.perf_counter() - start
        scene = Scene.load(scene_name)
        white = white_luminance(mi, sunsky(scene.sun_direction(hour), scene.sun.turbidity))
        images.append(tonemap(image, white))
        labels.append(f"{name} ({seconds:.1f} s incl. set-up)")
        print(f"{name}: {image.shape[1]}×{image.shape[0]}, {seconds:.1f} s with loading and compilation")
    strip(images, labels, target)


def animation(scene: str, frames: int, labels: tuple[str, ...], work: Path, target: Path) -> None:
    from PIL import Image

    out = work / scene
    start = time.perf_counter()
    subprocess.run(
        [sys.executable, "-m", "sandlight", "render", scene, "-o", str(out), "--video", str(work / f"{scene}.mp4")]
        + ["--renderer", "mitsuba", "--width", str(SIZE[0]), "--height", str(SIZE[1])]
        + ["--spp", str(SPP), "--frames", str(frames), "--no-progress"],
        check=True,
    )
    seconds = time.perf_counter() - start
    strip([Image.open(out / f"frame_{k:04d}.png") for k in range(frames)], list(labels), target)
    print(f"{scene}: {frames} frames at {SIZE[0]}×{SIZE[1]}, {SPP} spp, with MP4 in {seconds:.0f} s; wrote {target}")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, default=ROOT / "docs" / "figures")
    ap.add_argument("--work", type=Path, default=ROOT / "build" / "mitsuba-figures")
    args = ap.parse_args()
    args.work.mkdir(parents=True, exist_ok=True)
    examples(args.out / "mitsuba_examples.png")
    for scene, (frames, labels) in ANIMATIONS.items():
        animation(scene, frames, labels, args.work, args.out / f"mitsuba_{scene.replace('-', '_')}.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
