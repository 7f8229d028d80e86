"""What a fit compares with the forward model: values, the map from a model spectrum to them, noise.

Public objects
--------------
Observation
    ``values`` (n,) measured, ``operator`` (n, n_grid) mapping a forward-model spectrum on
    ``grid`` (nm) to those values (a selection of wavelengths, or sensor band integrals),
    ``labels`` and ``centres_nm`` of the channels, and the measurement noise ``sigma`` (n,) if
    known.
observe
    An Observation from a measured spectrum: on the forward model's wavelengths, or in the
    bands of a sensor.

In wavelength space the measured spectrum is linearly interpolated at the forward model's
wavelengths that lie inside the measured range and outside the band mask (measured channels
inside the mask are dropped first). In band space each band value is the SRF-weighted integral of
the measured spectrum (:func:`sandlight.retrieval.sensors.bands`), and the forward model's
spectrum is mapped through the same responses (linear interpolation between its wavelengths).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike

from sandlight.errors import ParameterError
from sandlight.retrieval.mask import BandMask
from sandlight.retrieval.sensors import SpectralResponse, load_sensor

__all__ = ["Observation", "observe"]


@dataclass(frozen=True)
class Observation:
    values: np.ndarray
    operator: np.ndarray
    grid: np.ndarray
    labels: tuple[str, ...]
    centres_nm: np.ndarray
    sigma: np.ndarray | None
    space: str = "wavelength"
    sensor: str = ""

    @property
    def size(self) -> int:
        return self.values.size


def _noise(
    noise: ArrayLike | xr.DataArray | None, n: int, what: str, at: np.ndarray | None = None
) -> np.ndarray | None:
    """Measurement standard deviations: None (estimate), one number, or one per channel."""
    if noise is None:
        return None
    if isinstance(noise, xr.DataArray) and at is not None:
        noise = np.interp(at, noise["wavelength"].values, noise.values)
    sigma = np.asarray(noise, dtype=float)
    if sigma.ndim == 0:
        sigma = np.full(n, float(sigma))
    if sigma.shape != (n,) or not np.all(np.isfinite(sigma)) or np.any(sigma <= 0):
        raise ParameterError(
            "noise",
            noise if np.size(noise) < 20 else f"an array of shape {np.shape(noise)}",
            f"None (estimated from the residuals), one standard deviation > 0, or one per {what} ({n})",
        )
    return sigma


def observe(
    spectrum: xr.DataArray,
    grid_nm: np.ndarray,
    *,
    mask: BandMask | None = None,
    sensor: str | SpectralResponse | None = None,
    noise: ArrayLike | xr.DataArray | None = None,
    min_channels: int = 1,
) -> Observation:
    """The observation of ``spectrum`` (checked, nm) by a forward model on ``grid_nm``.

    ``noise`` is the measurement standard deviation (reflectance): None to estimate it from the
    residuals, a number for every channel, or an array with one value per channel of the
    observation (per band in band space); a DataArray on ``wavelength`` is interpolated.

    Raises
    ------
    ParameterError
        Fewer than ``min_channels`` channels left (the mask, the measured range and the forward
        model's range leave too few), or bad ``noise``.
    """
    mask = mask or BandMask()
    grid = np.asarray(grid_nm, dtype=float)
    keep = mask.keep(spectrum["wavelength"].values)
    spectrum = spectrum[keep]
    wl, r = spectrum["wavelength"].values, spectrum.values
    if sensor is None:
        inside = (grid >= (wl[0] if wl.size else np.inf)) & (grid <= (wl[-1] if wl.size else -np.inf)) & mask.keep(grid)
        rows = np.flatnonzero(inside)
        _enough(rows.size, min_channels, "wavelengths", grid, wl, mask)
        at = grid[rows]
        return Observation(
            values=np.interp(at, wl, r),
            operator=np.eye(grid.size)[rows],
            grid=grid,
            labels=tuple(f"{w:g} nm" for w in at),
            centres_nm=at,
            sigma=_noise(noise, rows.size, "wavelength", at),
        )
    srf = load_sensor(sensor)
    low, high = (max(wl[0], grid[0]), min(wl[-1], grid[-1])) if wl.size else (np.inf, -np.inf)
    which = np.flatnonzero(srf.covered(low, high)) if low < high else np.array([], dtype=int)
    # A band reaching into a masked interval is dropped as a whole.
    which = np.array([b for b in which if mask.keep(srf.wavelengths[srf.response[b] > 0]).all()], dtype=int)
    _enough(which.size, min_channels, f"bands of {srf.name}", grid, wl, mask)
    values = srf.weights(wl)[which] @ r
    return Observation(
        values=values,
        operator=srf.operator(grid, which),
        grid=grid,
        labels=tuple(srf.band_names[b] for b in which),
        centres_nm=srf.centres[which],
        sigma=_noise(noise, which.size, "band"),
        space="band",
        sensor=srf.name,
    )


def _enough(n: int, needed: int, what: str, grid: np.ndarray, wl: np.ndarray, mask: BandMask) -> None:
    if n >= needed:
        return
    measured = f"{wl[0]:g}–{wl[-1]:g} nm" if wl.size else "nothing (all masked)"
    raise ParameterError(
        f"{what} left to fit",
        n,
        f"at least {needed} (one more than the free parameters); the forward model covers "
        f"{grid[0]:g}–{grid[-1]:g} nm, the measured spectrum {measured}, the mask removes {list(mask.intervals)}",
    )
