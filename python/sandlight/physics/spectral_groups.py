"""Which wavelengths the engine traces together (spectral path sharing, docs/transport.md).

A shared path takes its refraction directions from the hero wavelength's indices, so the
wavelengths of one group must have nearly equal real indices n(λ) wherever an index sets a
direction: every population's (mixed) core, and the pore water when pores fill with water.
Films and coatings are thin layers whose index changes only probabilities (the direction
through parallel layers is set by the media on either side, see ``layers`` in the core), so
they do not limit a group. :func:`spectral_groups` cuts the sorted wavelengths into runs whose
index spread stays within a tolerance. The bias this costs is measured by
``scripts/spectral_sharing_check.py`` and reported in docs/transport.md.
"""

from __future__ import annotations

import numpy as np

from sandlight.optics import complex_index
from sandlight.physics.composition import Composition
from sandlight.physics.medium import OpticalConstants, shipped_index

__all__ = ["DISPERSION_TOLERANCE", "MAX_GROUP", "direction_indices", "spectral_groups"]

#: Default largest spread max n − min n of any material's real index within a group.
DISPERSION_TOLERANCE = 0.02
#: Most wavelengths in one group (the native ``SpectralGroup`` accepts up to 256).
MAX_GROUP = 128


def direction_indices(comp: Composition, wavelength_nm: float, index: OpticalConstants = complex_index) -> np.ndarray:
    """The real indices that set refraction directions at ``wavelength_nm`` (nm): each
    population's core (volume-weighted mean of its materials, as the engine mixes them,
    :mod:`sandlight.physics.medium`), then water if pores fill with water."""
    cores = [sum(v * complex(index(m, wavelength_nm)).real for m, v in p.core.items()) for p in comp.populations]
    water = [complex(index("water", wavelength_nm)).real] if comp.water_filled_probability > 0 else []
    return np.array(cores + water)


def spectral_groups(
    comp: Composition,
    wavelengths_nm: np.ndarray,
    tolerance: float = DISPERSION_TOLERANCE,
    *,
    optical_constants: OpticalConstants | None = None,
) -> list[np.ndarray]:
    """Indices into ``wavelengths_nm`` of each group, in increasing wavelength.

    Greedy over the sorted wavelengths: a wavelength joins the current group while, for every
    index of :func:`direction_indices`, max n − min n over the group stays ≤ ``tolerance`` and the group has fewer than
    :data:`MAX_GROUP` members. ``tolerance`` 0 puts wavelengths of different index apart.
    """
    index = shipped_index if optical_constants is None else optical_constants
    wl = np.asarray(wavelengths_nm, dtype=float)
    order = np.argsort(wl, kind="stable")
    n = np.array([direction_indices(comp, float(lam), index) for lam in wl[order]])
    groups: list[list[int]] = []
    lo = hi = None
    for k, i in enumerate(order):
        if groups and len(groups[-1]) < MAX_GROUP:
            new_lo, new_hi = np.minimum(lo, n[k]), np.maximum(hi, n[k])
            if np.all(new_hi - new_lo <= tolerance):
                groups[-1].append(int(i))
                lo, hi = new_lo, new_hi
                continue
        groups.append([int(i)])
        lo = hi = n[k]
    return [np.array(g, dtype=np.intp) for g in groups]
