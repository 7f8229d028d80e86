"""Classes of patch pairs whose BRDF values are equal by isotropy and reciprocity (paper §3.2.1).

Public objects
--------------
EquivalenceClasses
    The partition of the r × r (incoming, outgoing) patch pairs into the m classes of values
    known to be equal; class means, exact compression to the m unique values, and expansion.
PatchClasses
    Base of the BRDF objects: their hemisphere and classes, built once per object.

Definition of the classes
-------------------------
Write a patch as (band, slice): band 0 is the cap (slice 0), bands 1 … B = stacks − 1 run from
the top down and slices s = 0 … L − 1 (L = slices) by increasing azimuth. All bands are sliced
at the same azimuths, so a rotation about the normal by 2π/L maps every patch (b, s) to
(b, s + 1 mod L) and the cap to itself: it maps patch pairs onto patch pairs exactly.

- **Isotropy** (invariance under rotation about the normal): f[i, j] depends only on the
  incoming band b_i, the outgoing band b_j and, when both are bands, the slice difference
  Δ = (s_j − s_i) mod L. A pair with the cap on either side does not depend on the other
  patch's slice (the cap is invariant under every rotation).
- **Helmholtz reciprocity** f[i, j] = f[j, i]: (b_i, b_j, Δ) ≡ (b_j, b_i, −Δ mod L).

Each class is labelled by its canonical triple (band_in, band_out, delta):

- (0, 0, 0): cap → cap, 1 pair;
- (0, b, 0), b = 1 … B: cap → band b and band b → cap, 2L pairs;
- (b, b', Δ), 1 ≤ b < b' ≤ B, Δ ∈ 0 … L − 1: the L pairs b → b' with slice difference Δ and
  the L pairs b' → b with difference −Δ, 2L pairs;
- (b, b, Δ), 0 ≤ Δ ≤ L/2: pairs within one band with difference Δ or −Δ; 2L pairs, or L
  when Δ ≡ −Δ (Δ = 0, and Δ = L/2 for even L).

Their number is m = 1 + B + (B²L + B·e)/2 with e = 2 for even L and 1 for odd L: 13 561 for the
paper's 31 × 30 (against 811 801 pairs). The classes are ordered by their triple
(lexicographically), so the cap → cap class is first and the cap classes follow.

Mirror symmetry about the plane of incidence (Δ ≡ −Δ for b ≠ b') is *not* imposed: the paper
names isotropy and reciprocity only, and a rotation-invariant medium need not be mirror
symmetric.
"""

from __future__ import annotations

import functools

import numpy as np
from numpy.typing import ArrayLike

from sandlight.errors import ParameterError
from sandlight.gonio.hemisphere import CollectorHemisphere

__all__ = ["EquivalenceClasses", "PatchClasses"]


def _canonical_key(b_in: ArrayLike, b_out: ArrayLike, delta: ArrayLike, stacks: int, slices: int) -> np.ndarray:
    """Integer key of the canonical triple of each (band_in, band_out, Δ) (arrays broadcast)."""
    b_in, b_out, delta = np.broadcast_arrays(b_in, b_out, delta)
    neg = (-delta) % slices
    lo = np.minimum(b_in, b_out)
    hi = np.maximum(b_in, b_out)
    # Reciprocity: b_in > b_out is read as the reversed pair, whose slice difference is −Δ.
    d = np.where(b_in < b_out, delta, np.where(b_in > b_out, neg, np.minimum(delta, neg)))
    d = np.where(lo == 0, 0, d)  # a pair with the cap does not depend on the slices
    return (lo.astype(np.int64) * stacks + hi) * slices + d


@functools.lru_cache(maxsize=4)
def _classes(stacks: int, slices: int) -> dict[str, np.ndarray]:
    h = CollectorHemisphere(stacks, slices)
    band, sl = h.band, h.slice
    delta = (sl[None, :] - sl[:, None]) % slices
    keys = _canonical_key(band[:, None], band[None, :], delta, stacks, slices)
    # representative: the first cell (row-major) of each class.
    unique_keys, representative, class_of = np.unique(keys.ravel(), return_index=True, return_inverse=True)
    class_of = class_of.astype(np.int64).ravel()
    m = unique_keys.size
    r = h.n_patches
    # Groups of cells sharing a class and an incoming row, for the multinomial covariances.
    row = np.repeat(np.arange(r, dtype=np.int64), r)
    group_keys, group_of = np.unique(class_of * r + row, return_inverse=True)
    # Class id of every canonical (band_in, band_out, Δ) for the continuous BRDF table.
    bi, bo, dd = np.meshgrid(np.arange(stacks), np.arange(stacks), np.arange(slices), indexing="ij")
    table = np.searchsorted(unique_keys, _canonical_key(bi, bo, dd, stacks, slices))
    out = {
        "class_of": class_of.reshape(r, r),
        "sizes": np.bincount(class_of, minlength=m),
        "band_in": unique_keys // slices // stacks,
        "band_out": unique_keys // slices % stacks,
        "delta": unique_keys % slices,
        "representative": representative,
        "group_of": group_of.reshape(r, r).astype(np.int64),
        "group_class": group_keys // r,
        "group_row": group_keys % r,
        "table": table,
    }
    for array in out.values():
        array.setflags(write=False)
    return out


class EquivalenceClasses:
    """Partition of the r × r patch pairs into classes of equal BRDF values.

    Parameters
    ----------
    hemisphere : CollectorHemisphere
        The collector hemisphere (incoming and outgoing patches alike).

    Attributes
    ----------
    n_classes : int
        m, the number of unique values.
    class_of : numpy.ndarray of int64, shape (r, r)
        Class of each (incoming, outgoing) pair.
    sizes : numpy.ndarray of int64, shape (m,)
        Number of pairs in each class.
    band_in, band_out, delta : numpy.ndarray of int64, shape (m,)
        Canonical triple of each class (see the module docstring); band_in ≤ band_out.
    table : numpy.ndarray of int64, shape (stacks, stacks, slices)
        Class of (band_in, band_out, Δ) for every triple, canonical or not.
    """

    def __init__(self, hemisphere: CollectorHemisphere):
        if not isinstance(hemisphere, CollectorHemisphere):
            raise ParameterError("hemisphere", hemisphere, "must be a CollectorHemisphere")
        self.hemisphere = hemisphere
        data = _classes(hemisphere.stacks, hemisphere.slices)
        self.class_of = data["class_of"]
        self.sizes = data["sizes"]
        self.band_in = data["band_in"]
        self.band_out = data["band_out"]
        self.delta = data["delta"]
        self.table = data["table"]
        self._representative = data["representative"]
        self._group_of = data["group_of"]
        self._group_class = data["group_class"]
        self._group_row = data["group_row"]

    @property
    def n_classes(self) -> int:
        return self.sizes.size

    @property
    def cap_classes(self) -> np.ndarray:
        """Boolean mask (m,) of the classes that involve the cap (band_in = 0)."""
        return self.band_in == 0

    def _check_full(self, name: str, full: ArrayLike) -> np.ndarray:
        a = np.asarray(full, dtype=float)
        r = self.hemisphere.n_patches
        if a.shape != (r, r):
            raise ParameterError(name, f"an array of shape {a.shape}", f"must have shape ({r}, {r})")
        return a

    def mean(self, full: ArrayLike, mask: ArrayLike | None = None) -> np.ndarray:
        """Unweighted mean of the entries of each class.

        Parameters
        ----------
        full : array_like, shape (r, r)
            Values per (incoming, outgoing) pair.
        mask : array_like of bool, shape (r, r), optional
            Entries to include (default all). A class with no included entry gives NaN.

        Returns
        -------
        numpy.ndarray, shape (m,)
        """
        a = self._check_full("full", full)
        m = self.n_classes
        if mask is None:
            return np.bincount(self.class_of.ravel(), weights=a.ravel(), minlength=m) / self.sizes
        keep = np.broadcast_to(np.asarray(mask, dtype=bool), a.shape)
        n = np.bincount(self.class_of[keep], minlength=m)
        total = np.bincount(self.class_of[keep], weights=a[keep], minlength=m)
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(n > 0, total / np.maximum(n, 1), np.nan)

    def compress(self, full: ArrayLike, *, rtol: float = 0.0) -> np.ndarray:
        """The m unique values of an array that is constant on every class.

        Exact: the value of each class is read from one of its entries, so
        ``compress(expand(u))`` returns ``u`` bit for bit.

        Parameters
        ----------
        full : array_like, shape (r, r)
            A symmetrised array (e.g. the reduced BRDF).
        rtol : float, default 0
            Allowed relative spread within a class; NaN entries must be NaN throughout their class.

        Raises
        ------
        sandlight.errors.ParameterError
            If an entry differs from its class value by more than ``rtol`` (the array is not
            symmetric: use `mean` to symmetrise it).
        """
        a = self._check_full("full", full)
        values = a.ravel()[self._representative]
        spread = np.abs(a - values[self.class_of])
        limit = rtol * np.abs(values[self.class_of])
        nan_mismatch = np.isnan(a) != np.isnan(values[self.class_of])
        off = (spread > limit) | nan_mismatch
        if off.any():
            i, j = np.argwhere(off)[0]
            raise ParameterError(
                "full",
                f"entry [{i}, {j}] = {a[i, j]!r} in a class of value {values[self.class_of[i, j]]!r}",
                f"must be constant on every class of isotropy and reciprocity (rtol = {rtol})",
            )
        return values.copy()

    def expand(self, values: ArrayLike) -> np.ndarray:
        """The r × r array whose every entry is the value of its class.

        Parameters
        ----------
        values : array_like, shape (m,)

        Returns
        -------
        numpy.ndarray, shape (r, r)
        """
        v = np.asarray(values)
        if v.shape != (self.n_classes,):
            raise ParameterError("values", f"an array of shape {v.shape}", f"must have shape ({self.n_classes},)")
        return v[self.class_of]

    def row_group_sums(self, cell_values: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Sums of ``cell_values`` over the entries sharing a class and an incoming row.

        Returns ``(sums, group_class, group_row)``, one entry per (class, row) group. Used for
        the multinomial covariances of the reduction.
        """
        a = self._check_full("cell_values", cell_values)
        sums = np.bincount(self._group_of.ravel(), weights=a.ravel(), minlength=self._group_class.size)
        return sums, self._group_class, self._group_row


class PatchClasses:
    """Base of the BRDFs on a collector hemisphere of ``stacks`` × ``slices``: the hemisphere and
    its :class:`EquivalenceClasses`, built once per object (the classes take ~0.1 s at 901 patches
    and every array property uses them)."""

    stacks: int
    slices: int

    @functools.cached_property
    def hemisphere(self) -> CollectorHemisphere:
        return CollectorHemisphere(self.stacks, self.slices)

    @functools.cached_property
    def classes(self) -> EquivalenceClasses:
        return EquivalenceClasses(self.hemisphere)
