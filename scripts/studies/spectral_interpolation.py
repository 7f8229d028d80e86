"""How well ``sandlight.predict`` interpolates between the spectral models' wavelengths.

Each measured USGS spectrum below (sands, the GDS76 mixture, pure iron-oxide powders: the
steepest edges a sand spectrum has) is sampled at the shipped models' wavelengths (400–700 nm
every 20 nm), interpolated back to every nm of 400–700 nm by
:func:`sandlight.predictor.prediction.interpolate_spectra` (what ``sandlight.predict`` does), and
compared with the measurement itself (linearly brought to the same 1 nm grid from its own 1–2 nm
sampling). Prints the RMS and largest error per spectrum (docs/spectral-predictor.md,
"Any wavelength"); the measurement's own noise is part of the figures (it sets Ottawa's 0.003).

Usage::

    python3 scripts/studies/spectral_interpolation.py [--spectra STEM ...]
"""

from __future__ import annotations

import argparse

import numpy as np

from sandlight.measured import read_usgs, usgs_library
from sandlight.predictor.prediction import interpolate_spectra

NODES_NM = np.arange(400.0, 701.0, 20.0)
FINE_NM = np.arange(400.0, 701.0, 1.0)
SPECTRA = (
    "Hematite.02+Quartz.98_GDS76_BECKa_AREF",
    "Quartz_GDS74_Sand_Ottawa_BECKc_AREF",
    "Sand_DWO-3-DEL2c_no_vis.oil_ASDFRa_AREF",
    "Sand_DWO-3-DEL2d_wet_no_oil_ASDFRa_AREF",
    "Goethite_WS222_Medium_Gr._BECKa_AREF",
    "Goethite_HS36.3_BECKb_AREF",
    "Hematite_GDS27_BECKa_AREF",
)


def interpolation_error(stem: str) -> tuple[float, float]:
    """RMS and largest absolute error (reflectance) of the interpolated spectrum ``stem``."""
    spectrum = read_usgs(usgs_library(stem)).dropna("wavelength")
    wl, r = spectrum["wavelength"].values, spectrum.values
    truth = np.interp(FINE_NM, wl, r)
    error = interpolate_spectra(NODES_NM, np.interp(NODES_NM, wl, r), FINE_NM) - truth
    return float(np.sqrt(np.mean(error**2))), float(np.max(np.abs(error)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--spectra", nargs="+", default=list(SPECTRA), help="USGS splib07a spectrum names")
    args = parser.parse_args()
    print("| spectrum | RMS | largest |\n|---|---|---|")
    for stem in args.spectra:
        rms, largest = interpolation_error(stem)
        print(f"| {stem} | {rms:.4f} | {largest:.4f} |")


if __name__ == "__main__":
    main()
