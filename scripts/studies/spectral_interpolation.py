"""How well ``sandlight.predict`` interpolates between the spectral models' wavelengths.

Each measured USGS spectrum below (sands, the GDS76 mixture, pure iron-oxide powders: the
steepest edges a sand spectrum has) is sampled at the models' wavelengths (``--grid``: the
paper's bank, 400–700 nm every 20 nm, by default; the full-range bank's is 350:2500:25),
interpolated back to every nm of that range by
:func:`sandlight.predictor.prediction.interpolate_spectra` (what ``sandlight.predict`` does), and
compared with the measurement itself (linearly brought to the same 1 nm grid from its own 1–2 nm
sampling). Prints the RMS and largest error per spectrum (docs/spectral-predictor.md,
"Any wavelength"); the measurement's own noise is part of the figures (it sets Ottawa's 0.003),
and so are the channels a file deletes (the wet sand's 1800–1950 nm), bridged linearly in both.

Usage::

    python3 scripts/studies/spectral_interpolation.py [--grid 400:700:20] [--spectra STEM ...]
"""

from __future__ import annotations

import argparse

import numpy as np

from sandlight.measured import read_usgs, usgs_library
from sandlight.predictor.prediction import interpolate_spectra
from sandlight.predictor.training import wavelength_grid

SPECTRA = (
    "Hematite.02+Quartz.98_GDS76_BECKa_AREF",
    "Quartz_GDS74_Sand_Ottawa_BECKc_AREF",
    "Sand_DWO-3-DEL2c_no_vis.oil_ASDFRa_AREF",
    "Sand_DWO-3-DEL2d_wet_no_oil_ASDFRa_AREF",
    "Goethite_WS222_Medium_Gr._BECKa_AREF",
    "Goethite_HS36.3_BECKb_AREF",
    "Hematite_GDS27_BECKa_AREF",
)


def interpolation_error(stem: str, nodes: np.ndarray) -> tuple[float, float, float]:
    """RMS and largest absolute error (reflectance) of the spectrum ``stem`` interpolated from
    ``nodes`` (nm) to every nm between them, and the wavelength of the largest."""
    spectrum = read_usgs(usgs_library(stem)).dropna("wavelength")
    wl, r = spectrum["wavelength"].values, spectrum.values
    fine = np.arange(nodes[0], nodes[-1] + 0.5, 1.0)
    truth = np.interp(fine, wl, r)
    error = interpolate_spectra(nodes, np.interp(nodes, wl, r), fine) - truth
    worst = int(np.argmax(np.abs(error)))
    return float(np.sqrt(np.mean(error**2))), float(abs(error[worst])), float(fine[worst])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--spectra", nargs="+", default=list(SPECTRA), help="USGS splib07a spectrum names")
    parser.add_argument("--grid", default="400:700:20", help="the models' wavelengths, nm, start:stop:step")
    args = parser.parse_args()
    nodes = wavelength_grid(args.grid)
    print(f"nodes {args.grid} nm ({nodes.size}), interpolated to every nm\n")
    print("| spectrum | RMS | largest (at nm) |\n|---|---|---|")
    for stem in args.spectra:
        rms, largest, at = interpolation_error(stem, nodes)
        print(f"| {stem} | {rms:.4f} | {largest:.4f} ({at:g}) |")


if __name__ == "__main__":
    main()
