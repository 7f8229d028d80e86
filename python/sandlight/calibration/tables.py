"""Tabulated forward model: an end-member's reflectance ρ(λᵢ, kⱼ) on a log-spaced k grid.

Public objects
--------------
ReflectanceTable
    ρ and its standard error on (wavelength, log10 k), evaluated at one k per wavelength by
    monotone cubic interpolation in log10 k, with the derivative ∂ρ/∂log10 k.
tabulate
    Builds a table with a forward model, restartable: the table is saved atomically after each
    k column to an ``.npz`` cache and resumed from it.

Why a table. Given n(λ) and k(λ), each wavelength is independent, so ρ at every wavelength
depends on that wavelength's k only. One engine run per trial k (all wavelengths, the same seed
for every k: common random numbers) gives ρ(λᵢ, kⱼ), smooth in k; the fit then needs no engine
run at all. Interpolation is the piecewise cubic Hermite interpolant of Fritsch & Carlson (1980)
(:class:`scipy.interpolate.PchipInterpolator`) in log10 k: it preserves the monotonicity of
the tabulated values between grid points and does not overshoot, so no spurious minimum appears
between two grid values of k. ρ(k) itself need not be monotone: at k ≳ 0.3 the Fresnel reflection
of the grains rises with k.

References
----------
Fritsch, F. N., Carlson, R. E. (1980). Monotone piecewise cubic interpolation. *SIAM J. Numer.
Anal.* 17, 238–246, doi:10.1137/0717021.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike
from scipy.interpolate import PchipInterpolator

from sandlight.errors import ModelFileError, ParameterError
from sandlight.io import atomic_path

if TYPE_CHECKING:
    import os

    from sandlight.calibration.end_members import EndMember
    from sandlight.calibration.forward import ForwardModel

__all__ = ["ReflectanceTable", "tabulate"]

_FORMAT = "sandlight calibration reflectance table 1"


@dataclasses.dataclass(frozen=True, eq=False)
class ReflectanceTable:
    """ρ(λᵢ, kⱼ) of one end-member.

    Attributes
    ----------
    member_id : str
        The end-member's id.
    wavelengths_nm : numpy.ndarray, shape (nλ,)
        Vacuum wavelengths (nm), increasing.
    log10_k : numpy.ndarray, shape (nk,)
        Trial log10 k, strictly increasing.
    rho : numpy.ndarray, shape (nλ, nk)
        Directional-hemispherical reflectance (fraction).
    stderr : numpy.ndarray, shape (nλ, nk)
        Its Monte Carlo standard error.
    settings : dict
        What the table was computed from (end-member, grids, forward model settings).
    """

    member_id: str
    wavelengths_nm: np.ndarray
    log10_k: np.ndarray
    rho: np.ndarray
    stderr: np.ndarray
    settings: dict

    @functools.cached_property
    def _interpolant(self) -> PchipInterpolator:
        return PchipInterpolator(self.log10_k, self.rho.T, axis=0)

    def clip(self, log10_k: ArrayLike) -> np.ndarray:
        """log10 k clipped to the table's grid, as a float array of shape (nλ,)."""
        x = np.broadcast_to(np.asarray(log10_k, dtype=float), self.wavelengths_nm.shape)
        return np.clip(x, self.log10_k[0], self.log10_k[-1])

    def __call__(self, log10_k: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """ρ and ∂ρ/∂log10 k at one log10 k per wavelength.

        Parameters
        ----------
        log10_k : array_like, shape (nλ,) or scalar
            log10 k at each tabulated wavelength; values outside the grid are clipped to it.

        Returns
        -------
        rho, drho : numpy.ndarray, shape (nλ,)
        """
        x = self.clip(log10_k)
        p = self._interpolant
        # Evaluate wavelength i's cubic on the interval holding x[i]: c has shape (4, nk-1, nλ).
        j = np.clip(np.searchsorted(p.x, x, side="right") - 1, 0, p.x.size - 2)
        columns = np.arange(x.size)
        c = p.c[:, j, columns]
        dx = x - p.x[j]
        rho = ((c[0] * dx + c[1]) * dx + c[2]) * dx + c[3]
        drho = (3.0 * c[0] * dx + 2.0 * c[1]) * dx + c[2]
        return rho, drho

    def stderr_at(self, log10_k: ArrayLike) -> np.ndarray:
        """Monte Carlo standard error at one log10 k per wavelength (linear in log10 k)."""
        x = self.clip(log10_k)
        return np.array([np.interp(xi, self.log10_k, row) for xi, row in zip(x, self.stderr)])

    def on_grid(self, log10_k_grid: ArrayLike) -> np.ndarray:
        """ρ at every wavelength for each value of a common log10 k grid: shape (ng, nλ)."""
        return self._interpolant(np.clip(np.asarray(log10_k_grid, dtype=float), self.log10_k[0], self.log10_k[-1]))


def _check_grid(name: str, values: ArrayLike, allowed: str, low: float = -np.inf, high: float = np.inf) -> np.ndarray:
    try:
        grid = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(name, values, allowed) from None
    if (
        grid.ndim != 1
        or grid.size < 2
        or not np.all(np.isfinite(grid))
        or np.any(np.diff(grid) <= 0)
        or grid[0] < low
        or grid[-1] > high
    ):
        shown = np.array2string(grid, threshold=8, precision=4) if grid.ndim else values
        raise ParameterError(name, shown, allowed)
    return grid


def _cache_key(settings: dict) -> str:
    return hashlib.sha256(json.dumps(settings, sort_keys=True).encode()).hexdigest()[:16]


def _save(path: Path, settings_json: str, rho: np.ndarray, stderr: np.ndarray, done: np.ndarray) -> None:
    with atomic_path(path) as tmp, open(tmp, "wb") as f:
        np.savez(f, format=np.array(_FORMAT), settings=np.array(settings_json), rho=rho, stderr=stderr, done=done)


def _load(path: Path, settings_json: str, shape: tuple[int, int]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    try:
        with np.load(path, allow_pickle=False) as f:
            stored = {name: f[name] for name in ("format", "settings", "rho", "stderr", "done")}
    except (OSError, ValueError, KeyError) as exc:
        raise ModelFileError(f"{path}: unreadable calibration table cache ({exc}); delete it to recompute") from None
    if str(stored["format"]) != _FORMAT or str(stored["settings"]) != settings_json:
        raise ModelFileError(f"{path}: cache file does not hold this table (other settings); delete it to recompute")
    if stored["rho"].shape != shape or stored["stderr"].shape != shape or stored["done"].shape != shape[1:]:
        raise ModelFileError(f"{path}: cache arrays have the wrong shape; delete it to recompute")
    return stored["rho"].astype(float), stored["stderr"].astype(float), stored["done"].astype(bool)


def tabulate(
    member: EndMember,
    forward: ForwardModel,
    wavelengths_nm: ArrayLike,
    log10_k: ArrayLike,
    *,
    cache_dir: str | os.PathLike[str] | None = None,
    progress: Callable[[str, int, int], None] | None = None,
) -> ReflectanceTable:
    """Tabulates ρ(λᵢ, kⱼ) of one end-member with a forward model.

    Parameters
    ----------
    member : sandlight.calibration.EndMember
    forward : forward model
        See :mod:`sandlight.calibration.forward` (``settings`` and ``reflectance``).
    wavelengths_nm : array_like
        Strictly increasing vacuum wavelengths in [350, 2500] nm.
    log10_k : array_like
        Strictly increasing trial log10 k, at least 4 values, each in [-12, 1].
    cache_dir : str or os.PathLike or None
        Folder of the ``.npz`` cache. The file ``<id>-<key>.npz`` (key: a hash of the settings)
        is rewritten atomically after each k column, and a later call with the same settings
        computes only the columns it lacks. None: no cache.
    progress : callable or None
        Called as ``progress(member_id, columns_done, columns_total)`` after each column.

    Returns
    -------
    ReflectanceTable

    Raises
    ------
    sandlight.errors.ParameterError
        A grid that is not strictly increasing, finite or in its domain.
    sandlight.errors.ModelFileError
        A cache file that is unreadable or holds another table.
    """
    wl = _check_grid(
        "wavelengths_nm", wavelengths_nm, "strictly increasing wavelengths in [350, 2500] nm", 350.0, 2500.0
    )
    grid = _check_grid("log10_k", log10_k, "at least 4 strictly increasing values in [-12, 1]", -12.0, 1.0)
    if grid.size < 4:
        raise ParameterError("log10_k", log10_k, "at least 4 strictly increasing values in [-12, 1]")
    settings = {
        "member": dataclasses.asdict(member),
        "wavelengths_nm": wl.tolist(),
        "log10_k": grid.tolist(),
        "forward": forward.settings(member, wl),
    }
    settings_json = json.dumps(settings, sort_keys=True)
    shape = (wl.size, grid.size)
    path = None if cache_dir is None else Path(cache_dir) / f"{member.id}-{_cache_key(settings)}.npz"
    if path is not None and path.exists():
        rho, stderr, done = _load(path, settings_json, shape)
    else:
        rho, stderr, done = np.full(shape, np.nan), np.full(shape, np.nan), np.zeros(grid.size, bool)
    for j in np.flatnonzero(~done):
        values, errors = forward.reflectance(member, wl, float(10.0 ** grid[j]))
        rho[:, j], stderr[:, j] = values, errors
        done[j] = True
        if path is not None:
            _save(path, settings_json, rho, stderr, done)
        if progress is not None:
            progress(member.id, int(done.sum()), grid.size)
    return ReflectanceTable(member.id, wl, grid, rho, stderr, settings)
