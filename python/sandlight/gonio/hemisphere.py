"""The collector hemisphere of the virtual goniophotometer (paper §3.2.1).

Public objects
--------------
CollectorHemisphere
    Equal-solid-angle patches of the upper hemisphere: geometry arrays and direction → patch.

The patch maths lives in the Rust core (``sandlight-core/src/gonio/hemisphere.rs``); this module
only holds the arrays it returns, so Python and the transport engine agree to the last bit.

Layout (docs/model.md §3): with r = 1 + (stacks − 1)·slices patches, patch 0 is the cap
cos θ ∈ [1 − 1/r, 1]; bands 1 … stacks − 1 follow from the top down, each of height slices/r in
cos θ, cut into ``slices`` azimuth slices φ ∈ [2πs/slices, 2π(s + 1)/slices); patch
1 + (band − 1)·slices + s is slice s of a band. Every patch subtends 2π/r sr.
"""

from __future__ import annotations

import functools

import numpy as np
import numpy.typing as npt

from sandlight.checks import check_whole_number
from sandlight.errors import ParameterError

__all__ = ["CollectorHemisphere"]

# Tolerance for directions that fall below the horizon by rounding only: z/|d| ≥ −1e-9 counts as
# horizontal (the transport's unit vectors carry errors of a few 1e-16).
_HORIZON_TOLERANCE = 1e-9


@functools.lru_cache(maxsize=8)
def _geometry(stacks: int, slices: int) -> dict[str, np.ndarray]:
    from sandlight import _native

    geometry = _native.hemisphere_geometry(stacks, slices)
    for array in geometry.values():
        array.setflags(write=False)
    return geometry


class CollectorHemisphere:
    """Upper hemisphere divided into patches of equal solid angle.

    Parameters
    ----------
    stacks : int, default 31
        Polar stacks, 2 ≤ stacks ≤ 10000; the top stack is the undivided cap.
    slices : int, default 30
        Azimuthal slices of every stack below the cap, 1 ≤ slices ≤ 10000.

    Attributes
    ----------
    n_patches : int
        r = 1 + (stacks − 1)·slices (901 for the paper's 31 × 30).
    centroids : numpy.ndarray, shape (r, 3)
        Unit vector of each patch's centroid: the centre of the patch in the equal-area
        coordinates (cos θ, φ), i.e. cos θ_c = (z0 + z1)/2 (the solid-angle mean of cos θ) and
        φ_c = (φ0 + φ1)/2; the pole for the cap. It always lies in its own patch; the normalised
        mean direction would lean towards the pole (at 31 × 30 by 0.52° in the top band, which
        spans 2.7°–15.1° in zenith, and by less than 0.12° below it).
    bounds : numpy.ndarray, shape (r, 4)
        Columns z0, z1 (cos θ) and φ0, φ1 (rad) of each patch; the patch holds z0 ≤ cos θ < z1
        (≤ 1 for the cap) and φ0 ≤ φ < φ1.
    solid_angles : numpy.ndarray, shape (r,)
        Solid angle of each patch in sr, 2π/r.
    projected_solid_angles : numpy.ndarray, shape (r,)
        ω_p = ∫ cos θ dΩ of each patch in sr; they sum to π.
    band, slice : numpy.ndarray of int64, shape (r,)
        Band (0 = cap, then 1 … stacks − 1 from the top down) and slice (0 … slices − 1; 0 for
        the cap) of each patch.
    band_cos_theta : numpy.ndarray, shape (stacks,)
        cos θ of the centroids of each band (1 for the cap), decreasing.

    Examples
    --------
    >>> h = CollectorHemisphere()
    >>> h.n_patches
    901
    >>> int(h.patch_index([0.0, 0.0, 1.0]))
    0
    """

    cap = 0
    """Index of the cap patch (normal incidence / exit)."""

    def __init__(self, stacks: int = 31, slices: int = 30):
        self.stacks = check_whole_number("stacks", stacks, 2, 10_000)
        self.slices = check_whole_number("slices", slices, 1, 10_000)
        geometry = _geometry(self.stacks, self.slices)
        self.centroids = geometry["centroids"]
        self.bounds = geometry["bounds"]
        self.solid_angles = geometry["solid_angles"]
        self.projected_solid_angles = geometry["projected_solid_angles"]
        self.band = geometry["band"]
        self.slice = geometry["slice"]

    @property
    def n_patches(self) -> int:
        return 1 + (self.stacks - 1) * self.slices

    @property
    def n_bands(self) -> int:
        """Number of bands below the cap, stacks − 1."""
        return self.stacks - 1

    @property
    def band_cos_theta(self) -> np.ndarray:
        first = np.concatenate([[0], 1 + self.slices * np.arange(self.n_bands)])
        return self.centroids[first, 2]

    def patch_index(self, dirs: npt.ArrayLike) -> np.ndarray:
        """Patch holding each direction.

        Parameters
        ----------
        dirs : array_like, shape (..., 3)
            Directions in the upper hemisphere (z ≥ 0), any positive length.

        Returns
        -------
        numpy.ndarray of int64, shape (...)
            Patch index in [0, r).

        Raises
        ------
        sandlight.errors.ParameterError
            If the last axis is not of length 3, or a direction is zero, not finite, or below
            the horizon (cos θ < −1e-9; smaller negative values are rounding and count as
            horizontal).
        """
        from sandlight import _native

        d = np.asarray(dirs, dtype=float)
        if d.ndim == 0 or d.shape[-1] != 3:
            raise ParameterError("dirs", f"an array of shape {d.shape}", "must have shape (..., 3)")
        flat = np.ascontiguousarray(d.reshape(-1, 3))
        norm = np.linalg.norm(flat, axis=1)
        bad = ~np.isfinite(flat).all(axis=1) | ~(norm > 0)
        if bad.any():
            raise ParameterError("dirs", flat[bad][0].tolist(), "directions must be finite and non-zero")
        below = flat[:, 2] < -_HORIZON_TOLERANCE * norm
        if below.any():
            raise ParameterError(
                "dirs", flat[below][0].tolist(), "directions must point into the upper hemisphere (z ≥ 0)"
            )
        return _native.hemisphere_patch_index(self.stacks, self.slices, flat).reshape(d.shape[:-1])

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, CollectorHemisphere):
            return NotImplemented
        return (self.stacks, self.slices) == (other.stacks, other.slices)

    def __hash__(self) -> int:
        return hash((CollectorHemisphere, self.stacks, self.slices))

    def __repr__(self) -> str:
        return f"CollectorHemisphere(stacks={self.stacks}, slices={self.slices})"
