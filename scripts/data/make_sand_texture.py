#!/usr/bin/env python3
"""Generate sandlight's demo sand texture, python/sandlight/data/textures/sand.png.

A close-up of loose sand seen from above, made procedurally so the colourisation demo needs no
photograph and no download: grains are rounded domes of random size and albedo on a jittered
grid, lit from the upper left, with dark pores between them and a little fine-scale speckle,
stored as a 128-colour palette PNG.
The output is deterministic for a given seed and numpy version. Released under CC0 1.0 (public
domain dedication); see the README beside the image.

Usage: python3 scripts/data/make_sand_texture.py [--size 256] [--seed 2024] [-o PATH]
"""

from __future__ import annotations

import argparse
import os
import tempfile
from pathlib import Path

import numpy as np
from PIL import Image
from scipy.ndimage import gaussian_filter
from scipy.spatial import cKDTree

DEFAULT_OUTPUT = Path(__file__).resolve().parents[2] / "python" / "sandlight" / "data" / "textures" / "sand.png"

# Encoded sRGB albedos of the grain populations and their shares: mostly tan quartz with iron
# staining, some clear quartz, a few dark (heavy mineral) and reddish grains.
GRAIN_TYPES = (
    # (share, mean colour)
    (0.70, (0.78, 0.68, 0.52)),
    (0.17, (0.90, 0.87, 0.80)),
    (0.07, (0.30, 0.27, 0.24)),
    (0.06, (0.72, 0.52, 0.38)),
)
MEAN_GRAIN_RADIUS_PX = 6.5
PALETTE_COLOURS = 128
SPECKLE = 0.02  # relative amplitude of the fine speckle on grain surfaces
LIGHT_DIRECTION = np.array([-0.45, -0.55, 0.70])  # towards the light: from the upper left


def sand_texture(size: int, seed: int) -> np.ndarray:
    """Encoded sRGB image (size, size, 3) in [0, 1] of procedural sand."""
    rng = np.random.default_rng(seed)
    spacing = 2.0 * MEAN_GRAIN_RADIUS_PX * 0.9  # grains overlap slightly, as packed sand does
    n = int(np.ceil(size / spacing)) + 2
    gx, gy = np.meshgrid(np.arange(n) - 1.0, np.arange(n) - 1.0)
    centres = (np.stack([gx.ravel(), gy.ravel()], axis=1) + 0.5) * spacing
    centres += rng.uniform(-0.4, 0.4, centres.shape) * spacing
    radii = MEAN_GRAIN_RADIUS_PX * rng.lognormal(0.0, 0.25, len(centres))

    shares = np.array([t[0] for t in GRAIN_TYPES])
    palette = np.array([t[1] for t in GRAIN_TYPES])
    kinds = rng.choice(len(GRAIN_TYPES), size=len(centres), p=shares / shares.sum())
    albedo = palette[kinds] * rng.lognormal(0.0, 0.08, (len(centres), 1))

    yy, xx = np.mgrid[0:size, 0:size].astype(float) + 0.5
    pixels = np.stack([xx.ravel(), yy.ravel()], axis=1)
    # Nearest grain by distance relative to its radius approximates which dome is on top.
    dist, idx = cKDTree(centres).query(pixels, k=4)
    rel = dist / radii[idx]
    top = np.argmin(rel, axis=1)
    rows = np.arange(len(pixels))
    grain = idx[rows, top]
    rel_top = rel[rows, top]

    # Dome height and its normal: z = sqrt(1 - ρ²) on a unit sphere scaled to the grain.
    offset = (pixels - centres[grain]) / radii[grain][:, None]
    z = np.sqrt(np.clip(1.0 - rel_top**2, 0.0, 1.0))
    normal = np.column_stack([offset, np.maximum(z, 0.15)])
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    light = LIGHT_DIRECTION / np.linalg.norm(LIGHT_DIRECTION)
    shade = 0.35 + 0.75 * np.clip(normal @ light, 0.0, 1.0)

    image = albedo[grain] * shade[:, None]
    # Pores: pixels outside every dome see into the dark gaps between grains.
    pore = rel_top > 1.0
    image[pore] *= 0.35
    image = image.reshape(size, size, 3)
    speckle = gaussian_filter(rng.normal(0.0, SPECKLE, (size, size)), 0.7)
    image *= (1.0 + speckle)[..., None]
    return np.clip(image, 0.0, 1.0)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=256, help="width = height in pixels")
    parser.add_argument("--seed", type=int, default=2024)
    parser.add_argument("-o", "--output", type=Path, default=DEFAULT_OUTPUT)
    args = parser.parse_args()
    if not 16 <= args.size <= 4096:
        parser.error(f"--size {args.size} is not allowed: use 16–4096 pixels")

    rgb8 = np.rint(sand_texture(args.size, args.seed) * 255.0).astype(np.uint8)
    args.output.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=args.output.parent, suffix=".part")
    os.close(fd)
    try:
        # A 128-colour palette (median cut, no dithering) keeps the file at a few tens of kB
        # with no visible banding: the texture's gradients are short, within single grains.
        image = Image.fromarray(rgb8, mode="RGB").quantize(
            PALETTE_COLOURS, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE
        )
        image.save(tmp, format="PNG", optimize=True)
        os.chmod(tmp, 0o644)
        os.replace(tmp, args.output)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    print(f"wrote {args.output} ({args.output.stat().st_size} bytes)")


if __name__ == "__main__":
    main()
