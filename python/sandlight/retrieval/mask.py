"""Band masks: wavelength intervals left out of a fit (e.g. the water-vapour absorption bands).

Public objects
--------------
BandMask
    Closed wavelength intervals (nm) to drop; ``keep(wavelengths)`` says which points stay.
WATER_VAPOUR_NM
    The default intervals of ``BandMask.water_vapour()``: the strong atmospheric water-vapour
    bands near 940, 1130, 1400 and 1900 nm and the 2.5 µm edge, where field and airborne
    spectra are unreliable. The limits are the usual ones of field spectroscopy (e.g. the ASD
    and USGS practice of removing 1350–1450 nm and 1800–1950 nm); they are rounded, not fitted.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from sandlight.errors import ParameterError

__all__ = ["BandMask", "WATER_VAPOUR_NM"]

WATER_VAPOUR_NM: tuple[tuple[float, float], ...] = (
    (920.0, 970.0),
    (1110.0, 1160.0),
    (1350.0, 1450.0),
    (1800.0, 1950.0),
    (2450.0, 2500.0),
)


@dataclass(frozen=True)
class BandMask:
    """Wavelength intervals [low, high] in nm to leave out.

    Raises
    ------
    ParameterError
        An interval that is not a pair of finite numbers with low < high.
    """

    intervals: tuple[tuple[float, float], ...] = ()

    def __post_init__(self) -> None:
        checked = []
        for item in self.intervals:
            try:
                low, high = (float(v) for v in item)
            except (TypeError, ValueError):
                raise ParameterError("mask", item, "intervals (low_nm, high_nm) of two numbers") from None
            if not (np.isfinite(low) and np.isfinite(high) and low < high):
                raise ParameterError("mask", item, "an interval (low_nm, high_nm) with finite low < high")
            checked.append((low, high))
        object.__setattr__(self, "intervals", tuple(checked))

    @classmethod
    def water_vapour(cls) -> BandMask:
        return cls(WATER_VAPOUR_NM)

    @classmethod
    def parse(cls, mask: BandMask | str | Iterable | None) -> BandMask:
        """A mask from a BandMask, None (nothing masked), 'water-vapour', text such as
        ``"1350-1450,1800-1950"`` or a list of (low, high) pairs."""
        if mask is None:
            return cls()
        if isinstance(mask, BandMask):
            return mask
        if isinstance(mask, str):
            if mask.strip() in ("water-vapour", "water-vapor"):
                return cls.water_vapour()
            pairs = []
            for part in mask.split(","):
                bounds = part.strip().split("-")
                if len(bounds) != 2:
                    raise ParameterError("mask", mask, "'water-vapour' or intervals in nm like '1350-1450,1800-1950'")
                pairs.append(bounds)
            try:
                return cls(tuple((float(a), float(b)) for a, b in pairs))
            except ValueError:
                raise ParameterError("mask", mask, "intervals of numbers in nm like '1350-1450,1800-1950'") from None
        return cls(tuple(mask))

    def keep(self, wavelengths_nm: np.ndarray) -> np.ndarray:
        """True where a wavelength lies in none of the intervals."""
        wl = np.asarray(wavelengths_nm, dtype=float)
        out = np.ones(wl.shape, dtype=bool)
        for low, high in self.intervals:
            out &= ~((wl >= low) & (wl <= high))
        return out
