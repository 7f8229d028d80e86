"""GDS76 (2 wt% hematite + 98 % quartz) with the hematite particles in geometric optics and as
Lorenz–Mie volume scatterers (``particle_optics``, docs/model.md §2.4 item 8).

Traces the validation sample ``Hematite.02+Quartz.98_GDS76`` (preset ``gds76-hematite-quartz``)
on the validation grid (:func:`sandlight.validation.scoring.default_wavelengths_nm`, 400–2500 nm)
with ``particle_optics`` 'geometric' and 'mie' at each hematite diameter given: the preset's
2.5 µm (the primary grains of the Baker reagent GDS27, per its USGS record) and smaller ones
(reagent hematite crystallites are often sub-micron). Nothing is fitted: GDS76 is a validation
case. For each run it prints the RMS error against the measurement over 400–700 and 400–2500 nm
with its Monte Carlo error bar (:func:`sandlight.validation.scoring.band_error`), the red edge
(where the reflectance first rises through the midpoint of its values at 450 and 750 nm, linear
interpolation, ± from the standard errors over the local slope) against the measured one, and
CIELAB L*, C*ab ± its standard error and h° (D50/10°, 400–700 nm, :mod:`sandlight.colour.lch`).

Usage::

    python scripts/studies/mie_particles_gds76.py [--diameters 2.5 1.0 0.5 0.2] [--rays 4000]
        [--seed 1] [--memory packed|none]
"""

from __future__ import annotations

import argparse

import numpy as np

import sandlight
from sandlight.colour.lch import lch, lch_with_chroma_error
from sandlight.physics.fine_particles import PARTICLE_OPTICS
from sandlight.physics.media import DEFAULT_MEMORY, SandMedium
from sandlight.validation.samples import sample_by_name
from sandlight.validation.scoring import BANDS_NM, band_error, default_wavelengths_nm, measured_on_grid

PRESET = "gds76-hematite-quartz"
EDGE_FROM_NM, EDGE_TO_NM = 450.0, 750.0
VISIBLE_NM = (400.0, 700.0)


def red_edge_nm(wl: np.ndarray, r: np.ndarray, se: np.ndarray | None = None) -> tuple[float, float]:
    """(λ, σ_λ) where ``r`` first rises through (r(450) + r(750))/2 between 450 and 750 nm
    (linear between the samples); σ_λ from ``se`` at the two samples over the slope (NaN without)."""
    sel = (wl >= EDGE_FROM_NM) & (wl <= EDGE_TO_NM) & np.isfinite(r)
    w, v = wl[sel], r[sel]
    mid = 0.5 * (v[0] + v[-1])
    k = int(np.argmax(v >= mid))
    if k == 0:
        return float("nan"), float("nan")
    slope = (v[k] - v[k - 1]) / (w[k] - w[k - 1])
    edge = w[k - 1] + (mid - v[k - 1]) / slope
    if se is None:
        return float(edge), float("nan")
    s = se[sel]
    # The crossing moves with the value there and with the midpoint (both ends' errors).
    sigma = np.sqrt(max(s[k - 1], s[k]) ** 2 + 0.25 * (s[0] ** 2 + s[-1] ** 2)) / slope
    return float(edge), float(sigma)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--diameters", type=float, nargs="+", default=[2.5, 1.0, 0.5, 0.2], help="hematite diameters, µm")
    ap.add_argument("--rays", type=int, default=4000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--memory", choices=("none", "packed"), default=DEFAULT_MEMORY)
    args = ap.parse_args()

    case = sample_by_name(PRESET)
    spectrum = case.measured_spectrum()
    wl = default_wavelengths_nm()
    measured = measured_on_grid(spectrum, wl)
    fine = spectrum.dropna("wavelength").sel(wavelength=slice(EDGE_FROM_NM - 10, EDGE_TO_NM + 10))
    edge_measured, _ = red_edge_nm(fine.wavelength.values, fine.values)
    vis = (wl >= VISIBLE_NM[0]) & (wl <= VISIBLE_NM[1])
    L, C, h = lch(wl[vis], measured[vis])
    print(
        f"{case.name}, preset {PRESET!r}, memory {args.memory!r}, {args.rays} rays, seed {args.seed}, "
        f"{wl.size} wavelengths 400–2500 nm\nmeasured: red edge {edge_measured:.0f} nm, "
        f"L* {L:.1f} C*ab {C:.1f} h° {h:.0f}\n"
    )
    bands = list(BANDS_NM)
    print(
        "| d (µm) | particle optics | "
        + " | ".join(f"RMS {b}" for b in bands)
        + " | red edge (nm) | L* | C*ab | h° |\n|---|---|"
        + "---|" * (len(bands) + 4)
    )
    base = sandlight.SandSample.preset(PRESET)
    for d in args.diameters:
        sample = base.replace(iron_oxide_particle_size_um=d)
        for optics in PARTICLE_OPTICS:
            medium = SandMedium.from_sample(sample, args.memory, particle_optics=optics)
            r = sandlight.reflectance(medium, wl, rays=args.rays, seed=args.seed, progress=False)
            errs = [band_error(wl, r.values, r.stderr, measured, b, *BANDS_NM[b]) for b in bands]
            edge, edge_se = red_edge_nm(wl, r.values, r.stderr)
            L, C, h, se = lch_with_chroma_error(wl[vis], r.values[vis], r.covariance[np.ix_(vis, vis)])
            print(
                f"| {d:g} | {optics} | "
                + " | ".join(f"{e.rms:.4f} ± {e.rms_mc:.4f}" for e in errs)
                + f" | {edge:.0f} ± {edge_se:.0f} | {L:.1f} | {C:.1f} ± {se:.1f} | {h:.0f} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
