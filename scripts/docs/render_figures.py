#!/usr/bin/env python3
"""Render the two shipped animations at a preview resolution, time them, and write the strips of
frames shown in docs/rendering.md (``render_desert_day.png``, ``render_beach_drying.png``).

    python3 scripts/docs/render_figures.py [--out docs/figures] [--work build/render-figures]

Each animation is rendered by the same command a user runs (``sandlight render SCENE -o DIR
--video FILE.mp4 --width 320 --height 180``, every other setting from the scene file), in a
subprocess timed from start to end (MP4 included); the strip is a row of chosen frames with
their solar time underneath.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

#: Scene, frames shown (0-based) and their labels; the scene files give 25 desert frames from
#: 06:00 to 18:00 and 21 beach frames from 08:00 to 18:00.
FIGURES = {
    "desert-day": ((0, 6, 12, 18, 24), ("06:00", "09:00", "12:00", "15:00", "18:00")),
    "beach-drying": ((0, 10, 20), ("08:00", "13:00", "18:00")),
}


def render(scene: str, work: Path) -> float:
    """Render ``scene`` into ``work/scene`` with the CLI; the wall time in seconds."""
    out = work / scene
    start = time.perf_counter()
    subprocess.run(
        [
            sys.executable,
            "-m",
            "sandlight",
            "render",
            scene,
            "-o",
            str(out),
            "--video",
            str(work / f"{scene}.mp4"),
            "--width",
            "320",
            "--height",
            "180",
            "--no-progress",
        ],
        check=True,
    )
    return time.perf_counter() - start


def strip(scene: str, work: Path, target: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from PIL import Image

    frames, labels = FIGURES[scene]
    fig, axes = plt.subplots(1, len(frames), figsize=(3.2 * len(frames), 2.1), dpi=100)
    for ax, index, label in zip(axes, frames, labels):
        ax.imshow(Image.open(work / scene / f"frame_{index:04d}.png"))
        ax.set_axis_off()
        ax.set_title(label, fontsize=10, y=-0.16)
    fig.subplots_adjust(left=0.005, right=0.995, top=0.99, bottom=0.1, wspace=0.02)
    fig.savefig(target)
    plt.close(fig)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, default=ROOT / "docs" / "figures")
    ap.add_argument("--work", type=Path, default=ROOT / "build" / "render-figures")
    args = ap.parse_args()
    args.work.mkdir(parents=True, exist_ok=True)
    for scene in FIGURES:
        seconds = render(scene, args.work)
        target = args.out / f"render_{scene.replace('-', '_')}.png"
        strip(scene, args.work, target)
        print(
            f"{scene}: {len(list((args.work / scene).glob('frame_*.png')))} frames at 320×180 "
            f"with MP4 in {seconds / 60:.1f} min; wrote {target}"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
