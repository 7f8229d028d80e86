"""Sensor bands: spectral response functions (SRF) and band reflectances.

Public objects
--------------
SpectralResponse
    The relative spectral response of each band of a sensor on a wavelength grid (nm).
load_sensor
    A shipped sensor by name (``landsat-oli``, ``sentinel2-msi``) or a user SRF file.
bands
    Band reflectances of a spectrum: ρ_b = ∫ ρ(λ) S_b(λ) dλ / ∫ S_b(λ) dλ (trapezoid rule on the
    spectrum's own wavelengths).
SHIPPED_SENSORS
    The names of the shipped sensors.

The shipped sensors are **Gaussian approximations** built from the published band centres and
full widths at half maximum (``sandlight/data/sensors/*.csv``; sources and licence in the README
there): S_b(λ) = exp(−4 ln 2 (λ − c_b)² / FWHM_b²), cut at ±1.5 FWHM (S = 2⁻⁹). Real SRFs are
flatter-topped with steeper edges; band values differ from those of the true SRFs by a fraction
of the spectrum's curvature across the band (small for the smooth spectra of sand).

A user SRF file is a CSV: a header ``wavelength_nm,<band>,<band>,...`` (lines starting with ``#``
are comments), then one row per wavelength, strictly increasing, responses ≥ 0 (any scale; each
band is normalised by its integral).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr

from sandlight.errors import ModelFileError, ParameterError

__all__ = ["SpectralResponse", "load_sensor", "bands", "SHIPPED_SENSORS", "OUTSIDE_TOLERANCE"]

_SENSOR_DIR = Path(__file__).resolve().parent.parent / "data" / "sensors"
SHIPPED_SENSORS: tuple[str, ...] = ("landsat-oli", "sentinel2-msi")
#: A band is usable on a wavelength range when at most this share of its response integral lies
#: outside it (the rest is renormalised).
OUTSIDE_TOLERANCE = 0.01
#: Gaussian SRFs are cut where the response falls to 2⁻⁹: at ±1.5 FWHM.
_GAUSSIAN_HALF_SPAN_FWHM = 1.5
_GRID_STEP_NM = 1.0


@dataclass(frozen=True)
class SpectralResponse:
    """Relative spectral responses of a sensor's bands.

    Attributes
    ----------
    name : str
    band_names : tuple of str
    wavelengths : ndarray (n_wl,)
        nm, strictly increasing.
    response : ndarray (n_bands, n_wl)
        Relative response of each band (≥ 0, peak 1 for the shipped ones).
    description : str
        Where the responses come from (for the shipped sensors: "Gaussian approximation …").
    """

    name: str
    band_names: tuple[str, ...]
    wavelengths: np.ndarray
    response: np.ndarray
    description: str = ""

    @property
    def centres(self) -> np.ndarray:
        """Response-weighted mean wavelength of each band, nm."""
        w = self.weights(self.wavelengths)
        return w @ self.wavelengths

    def weights(self, wl: np.ndarray) -> np.ndarray:
        """Quadrature weights (n_bands, len(wl)) of the normalised band integral on ``wl`` (trapezoid)."""
        s = np.stack([np.interp(wl, self.wavelengths, r, left=0.0, right=0.0) for r in self.response])
        # Trapezoid weights: half the neighbouring steps at each point.
        trap = np.empty_like(wl)
        steps = np.diff(wl)
        trap[0], trap[-1] = steps[0] / 2, steps[-1] / 2
        trap[1:-1] = (steps[:-1] + steps[1:]) / 2
        w = s * trap
        total = w.sum(axis=1, keepdims=True)
        return np.divide(w, total, out=np.zeros_like(w), where=total > 0)

    def covered(self, low_nm: float, high_nm: float) -> np.ndarray:
        """Which bands have at most `OUTSIDE_TOLERANCE` of their response outside [low, high]."""
        wl = self.wavelengths
        trap = np.gradient(wl)
        total = (self.response * trap).sum(axis=1)
        inside = (self.response * trap * ((wl >= low_nm) & (wl <= high_nm))).sum(axis=1)
        return inside >= (1 - OUTSIDE_TOLERANCE) * total

    def operator(self, grid_nm: np.ndarray, which: np.ndarray) -> np.ndarray:
        """Matrix (n_which, len(grid)) mapping a spectrum on ``grid`` (linear interpolation in
        between) to the band values of the bands ``which``."""
        grid = np.asarray(grid_nm, dtype=float)
        fine = np.arange(grid[0], grid[-1] + _GRID_STEP_NM / 2, _GRID_STEP_NM)
        interp = np.stack([np.interp(fine, grid, e) for e in np.eye(grid.size)], axis=1)  # (fine, grid)
        w = self.weights(fine)[which]
        return w @ interp


def _gaussian(name: str, table: Path) -> SpectralResponse:
    rows = _read_table(table)
    header, data = rows[0], rows[1:]
    if header[:3] != ["band", "centre_nm", "fwhm_nm"]:
        raise ModelFileError(f"{table}: expected the header band,centre_nm,fwhm_nm, found {','.join(header)}")
    names = tuple(r[0] for r in data)
    centre = np.array([float(r[1]) for r in data])
    fwhm = np.array([float(r[2]) for r in data])
    lo = math.floor((centre - _GAUSSIAN_HALF_SPAN_FWHM * fwhm).min())
    hi = math.ceil((centre + _GAUSSIAN_HALF_SPAN_FWHM * fwhm).max())
    wl = np.arange(lo, hi + _GRID_STEP_NM, _GRID_STEP_NM)
    d = wl[None, :] - centre[:, None]
    response = np.exp(-4 * math.log(2) * d**2 / fwhm[:, None] ** 2)
    response[np.abs(d) > _GAUSSIAN_HALF_SPAN_FWHM * fwhm[:, None]] = 0.0
    return SpectralResponse(
        name, names, wl, response, f"Gaussian approximation from published band centres and FWHM ({table.name})"
    )


def _read_table(path: Path) -> list[list[str]]:
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise ModelFileError(f"{path}: not a text file") from None
    rows = [
        [f.strip() for f in line.split(",")] for line in text.splitlines() if line.strip() and not line.startswith("#")
    ]
    if len(rows) < 2:
        raise ModelFileError(f"{path}: expected a header line and at least one row")
    width = len(rows[0])
    for i, row in enumerate(rows[1:], start=2):
        if len(row) != width:
            raise ModelFileError(f"{path}: data row {i - 1} has {len(row)} fields, the header {width}")
    return rows


def _srf_file(path: Path) -> SpectralResponse:
    rows = _read_table(path)
    header = rows[0]
    if header[0].lower() not in ("wavelength_nm", "wavelength") or len(header) < 2:
        raise ModelFileError(
            f"{path}: expected a header 'wavelength_nm,<band>,...' (one column per band), found {','.join(header)}"
        )
    try:
        data = np.array([[float(f) for f in row] for row in rows[1:]])
    except ValueError:
        raise ModelFileError(f"{path}: every field below the header must be a number") from None
    wl, response = data[:, 0], data[:, 1:].T
    if not np.all(np.isfinite(data)):
        raise ModelFileError(f"{path}: non-finite value")
    if wl.size < 2 or np.any(np.diff(wl) <= 0):
        raise ModelFileError(f"{path}: wavelengths must be strictly increasing (at least two rows)")
    if wl[-1] < 100:
        raise ModelFileError(f"{path}: wavelengths end at {wl[-1]:g}: these look like micrometres; use nm")
    if np.any(response < 0) or np.any(response.max(axis=1) <= 0):
        raise ModelFileError(f"{path}: responses must be >= 0 with a positive peak in every band")
    return SpectralResponse(path.stem, tuple(header[1:]), wl, response, f"spectral response file {path}")


def load_sensor(sensor: str | os.PathLike | SpectralResponse) -> SpectralResponse:
    """A shipped sensor (`SHIPPED_SENSORS`) by name, or a user SRF CSV file by path.

    Raises
    ------
    ParameterError
        An unknown name that is not a file either.
    sandlight.errors.ModelFileError
        A malformed SRF file (the message says what is wrong).
    """
    if isinstance(sensor, SpectralResponse):
        return sensor
    if isinstance(sensor, str) and sensor in SHIPPED_SENSORS:
        return _gaussian(sensor, _SENSOR_DIR / f"{sensor}.csv")
    path = Path(os.fspath(sensor))
    if not path.is_file():
        raise ParameterError("sensor", str(sensor), f"one of {', '.join(SHIPPED_SENSORS)} or an SRF CSV file")
    return _srf_file(path)


def bands(spectrum: object, sensor: str | os.PathLike | SpectralResponse) -> xr.DataArray:
    """Band reflectances of a spectrum seen by a sensor.

    Parameters
    ----------
    spectrum : anything :func:`sandlight.retrieval.spectrum.as_spectrum` accepts
    sensor : name, SRF file or SpectralResponse

    Returns
    -------
    xarray.DataArray
        Along ``band`` (coordinates: band names, ``centre_nm``), the bands whose response lies
        within the spectrum's wavelengths (`OUTSIDE_TOLERANCE`); ``attrs["bands_outside"]``
        lists the others.

    Raises
    ------
    ParameterError
        No band of the sensor lies within the spectrum's wavelengths.
    """
    from sandlight.retrieval.spectrum import as_spectrum

    s = as_spectrum(spectrum)
    srf = load_sensor(sensor)
    wl = s["wavelength"].values
    which = np.flatnonzero(srf.covered(wl[0], wl[-1]))
    if not which.size:
        raise ParameterError(
            "spectrum wavelengths", f"{wl[0]:g}–{wl[-1]:g} nm", f"a range covering at least one band of {srf.name}"
        )
    values = srf.weights(wl)[which] @ s.values
    names = [srf.band_names[i] for i in which]
    return xr.DataArray(
        values,
        dims="band",
        coords={"band": names, "centre_nm": ("band", srf.centres[which], {"units": "nm"})},
        name="band_reflectance",
        attrs={
            "sensor": srf.name,
            "response": srf.description,
            "bands_outside": ",".join(b for i, b in enumerate(srf.band_names) if i not in set(which.tolist())),
        },
    )
