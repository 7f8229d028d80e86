"""The engine as a forward model at one seed (docs/retrieval.md, "Forward models").

Prints (1) the standard errors at 2·10⁴ rays per wavelength of a red sand (2 % iron oxide,
hematite ratio 0.6, saturation 0.05) with spectral path sharing and without (``share=False``,
what the retrieval's engine forward model uses), and (2) the engine's reflectance at 400, 560,
640 and 700 nm at one seed (5000 rays, ``share=False``) for saturation 0.35 … 0.55 next to the
predictor bank's: how rough the one-seed engine is in saturation.

Usage::

    nice -n 10 python3 scripts/studies/retrieval_engine_roughness.py
"""

from __future__ import annotations

import numpy as np

import sandlight
from sandlight.predictor import default_model

WAVELENGTHS = np.arange(400.0, 701.0, 20.0)
SHOWN = [0, 8, 12, 15]  # 400, 560, 640, 700 nm


def main() -> None:
    bank = default_model()
    red = sandlight.SandSample(iron_oxide=0.02, hematite_ratio=0.6, saturation=0.05)
    for share in (True, False):
        r = sandlight.reflectance(red, WAVELENGTHS, rays=20_000, seed=3, share=share, progress=False, threads=1)
        print(f"share={share}: standard error at 400/560/700 nm {r.stderr[0]:.4f} {r.stderr[8]:.4f} {r.stderr[15]:.4f}")
    print("\nsaturation | engine (seed 0, 5000 rays) at 400, 560, 640, 700 nm | predictor")
    for s in (0.35, 0.40, 0.45, 0.47, 0.50, 0.55):
        sample = sandlight.SandSample(iron_oxide=0.0095, hematite_ratio=0.32, saturation=s)
        e = sandlight.reflectance(sample, WAVELENGTHS, rays=5000, seed=0, share=False, progress=False, threads=1)
        p = bank.predict([sample])[0]
        print(f"{s:.2f} | {' '.join(f'{v:.4f}' for v in e.values[SHOWN])} | {' '.join(f'{v:.4f}' for v in p[SHOWN])}")


if __name__ == "__main__":
    main()
