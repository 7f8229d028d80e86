"""Monte Carlo reflectance of a sand sample (the transport engine's Python surface).

:func:`reflectance` traces rays through the sample with the native engine (docs/transport.md)
and returns the directional-hemispherical reflectance ρ(θᵢ, λ) = escaped / launched with its
standard error √(ρ(1 − ρ)/N) (docs/model.md §2.6). :func:`isotropic_halfspace` runs the same
transport and boundary code with the particles replaced by isotropic point scatterers, whose
exact answer (Chandrasekhar) checks the engine.
"""

from __future__ import annotations

import math
import os
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from sandlight import _native
from sandlight._runner import SHOW_AFTER_SECONDS, run_in_batches
from sandlight.checks import check_count, check_incidence, check_seed, check_threads, check_wavelengths
from sandlight.physics.media import IsotropicScatterers, as_traceable, engine_settings
from sandlight.physics.medium import Traceable
from sandlight.progress import progress_bar

if TYPE_CHECKING:
    import xarray as xr

    from sandlight.sample import SandSample

__all__ = ["ReflectanceResult", "reflectance", "isotropic_halfspace", "DEFAULT_MAX_EVENTS", "MAX_INTERNAL_REFLECTIONS"]

DEFAULT_MAX_EVENTS = 10_000_000
MAX_INTERNAL_REFLECTIONS = 10_000
_COUNT_NAMES = ("launched", "escaped", "absorbed", "transmitted", "capped", "events")


def _trace(
    medium: _native.Medium,
    *,
    rays: int,
    incidence_deg: float,
    seed: int,
    threads: int | None,
    max_events: int,
    label: str,
    progress: bool,
    stream: int = 0,
) -> dict:
    counts = np.zeros(len(_COUNT_NAMES), dtype=np.uint64)

    def batch(first: int, n: int):
        counts[:] += np.array(
            medium.dhr(incidence_deg, seed, stream, first, n, max_events, MAX_INTERNAL_REFLECTIONS, threads),
            dtype=np.uint64,
        )

    run_in_batches(batch, rays, label=label, progress=progress)
    return dict(zip(_COUNT_NAMES, (int(c) for c in counts)))


@dataclass(frozen=True)
class ReflectanceResult:
    """Directional-hemispherical reflectance of a sample from a Monte Carlo run.

    Attributes
    ----------
    wavelengths : ndarray, shape (n,)
        Vacuum wavelength λ (nm).
    values : ndarray, shape (n,)
        ρ(θᵢ, λ) = escaped / launched, in [0, 1].
    stderr : ndarray, shape (n,)
        Standard error √(ρ(1 − ρ)/N).
    counts : dict[str, ndarray]
        Per wavelength: launched, escaped, absorbed, transmitted (through the bottom of a finite
        sample), capped (stopped by the event cap), events (particle events, summed over rays).
    """

    wavelengths: np.ndarray
    values: np.ndarray
    stderr: np.ndarray
    counts: dict
    rays: int
    incidence_deg: float
    seed: int
    max_events: int
    sample: dict = field(default_factory=dict)
    elapsed_s: float = 0.0
    geometry: str = "on-the-fly"
    memory: str = "none"

    @property
    def mean_events_per_ray(self) -> np.ndarray:
        """Mean particle events per ray, per wavelength."""
        return self.counts["events"] / self.counts["launched"]

    @property
    def capped(self) -> np.ndarray:
        """Rays stopped by the event cap, per wavelength (reported, never silently dropped)."""
        return self.counts["capped"]

    def to_xarray(self) -> xr.Dataset:
        """An ``xarray.Dataset`` with units on every variable and the run's inputs as attributes."""
        import json

        import xarray as xr

        import sandlight
        from sandlight.io import WAVELENGTH_ATTRS, cf_attributes

        data = {
            "reflectance": (
                "wavelength",
                self.values,
                {"units": "1", "long_name": "directional-hemispherical reflectance"},
            ),
            "stderr": (
                "wavelength",
                self.stderr,
                {"units": "1", "long_name": "Monte Carlo standard error of reflectance"},
            ),
        }
        for k, v in self.counts.items():
            data[f"count_{k}"] = (
                "wavelength",
                np.asarray(v, dtype=np.int64),
                {"units": "1", "long_name": f"rays {k}" if k != "events" else "particle events summed over rays"},
            )
        ds = xr.Dataset(
            data,
            coords={"wavelength": ("wavelength", self.wavelengths, WAVELENGTH_ATTRS)},
            attrs={
                **cf_attributes("sandlight Monte Carlo reflectance", "sandlight.reflectance"),
                "sandlight_version": sandlight.__version__,
                "rays": self.rays,
                "incidence_deg": self.incidence_deg,
                "seed": np.uint64(self.seed),  # an integer of the full range [0, 2**64)
                "max_events": self.max_events,
                "sample": json.dumps(self.sample),
                "elapsed_s": self.elapsed_s,
                "geometry": self.geometry,
                "memory": self.memory,
            },
        )
        return ds

    def to_netcdf(self, path: str | os.PathLike) -> None:
        """Writes the result as NetCDF (h5netcdf), atomically."""
        from sandlight.io import atomic_path

        with atomic_path(path) as tmp:
            self.to_xarray().to_netcdf(tmp, engine="h5netcdf")

    def to_csv(self, path: str | os.PathLike) -> None:
        """Writes ``wavelength_nm,reflectance,stderr,mean_events_per_ray,capped`` rows, atomically,
        after ``# key: value`` comment lines holding the NetCDF output's attributes and the units."""
        from sandlight.io import write_csv

        table = np.column_stack([self.wavelengths, self.values, self.stderr, self.mean_events_per_ray, self.capped])
        units = "wavelength_nm nm; reflectance 1; stderr 1; mean_events_per_ray 1; capped rays"
        write_csv(
            path,
            ("wavelength_nm", "reflectance", "stderr", "mean_events_per_ray", "capped"),
            table,
            ("%.6g", "%.8f", "%.8f", "%.6g", "%d"),
            {**self.to_xarray().attrs, "units": units},
        )

    def plot(self, path: str | os.PathLike, *, title: str | None = None) -> None:
        """Plots the spectrum with ±2 standard-error band to a PNG."""
        from sandlight.plots import plot_spectrum

        plot_spectrum(self.wavelengths, self.values, self.stderr, path, title=title)


def reflectance(
    sample: SandSample | str | Traceable,
    wavelengths_nm: npt.ArrayLike,
    *,
    rays: int,
    incidence_deg: float = 0.0,
    seed: int = 0,
    threads: int | None = None,
    max_events: int = DEFAULT_MAX_EVENTS,
    progress: bool = True,
    geometry: str = "on-the-fly",
    memory: str | None = None,
    packing: _native.Packing | None = None,
) -> ReflectanceResult:
    """Monte Carlo directional-hemispherical reflectance of a sand sample.

    Parameters
    ----------
    sample : SandSample, str or Traceable
        The sample, the name of a preset (``SandSample.preset``), or any Traceable medium
        (``sandlight.physics.medium.Traceable``: a ``Powder``, a reference medium, a
        ``SandMedium`` or ``PackedSand`` built beforehand), traced as it is.
    wavelengths_nm : array_like
        Vacuum wavelengths λ in nm, each in [350, 2500].
    rays : int
        Rays per wavelength N ≥ 1 (floats such as ``1e6`` are accepted when integral).
    incidence_deg : float
        Zenith angle θᵢ of the incident light, in [0, 90) degrees.
    seed : int
        Master seed in [0, 2**64). The same seed gives bit-identical results for any ``threads``.
    threads : int, optional
        Worker threads (default: all cores).
    max_events : int
        Cap on particle events per ray; rays reaching it are counted in ``capped``.
    progress : bool
        Show a progress bar for runs longer than a second.
    geometry : {'on-the-fly', 'explicit'}
        'on-the-fly' (the fast model: each next particle drawn at random) or 'explicit' (the
        slow reference: rays traced through a stored random dense packing of the sample's own
        grains with the same per-particle physics; docs/geometry.md). With 'explicit',
        ``counts["transmitted"]`` counts rays that went below a finite sample.
    memory : {'none', 'channel', 'cut', 'packed'}, optional
        Path memory of the on-the-fly engine (default ``sandlight.physics.media.DEFAULT_MEMORY``); 'none' for
        explicit geometry. 'packed' (the cut surface, the pore's walls and the packing's pair
        correlation) is the closest to the explicit reference (docs/geometry.md).
    packing : sandlight._native.Packing, optional
        A packing to trace (explicit geometry); generated from ``seed`` when None.

    ``geometry``, ``memory`` and ``packing`` apply to a sample (``sandlight.physics.media.as_traceable``);
    a Traceable carries its own.

    Returns
    -------
    ReflectanceResult
        ``sample`` holds the medium's description, ``geometry`` and ``memory`` the engine's.

    Notes
    -----
    The same random streams are used at every wavelength (common random numbers), so the Monte
    Carlo noise is correlated across wavelengths and spectra come out smooth; each value's own
    standard error is unaffected.
    """
    wl = check_wavelengths("wavelengths_nm", wavelengths_nm)
    rays = check_count("rays", rays)
    incidence_deg = check_incidence("incidence_deg", incidence_deg)
    seed = check_seed("seed", seed)
    threads = check_threads("threads", threads)
    max_events = check_count("max_events", max_events)
    start = time.perf_counter()
    traced = as_traceable(sample, geometry=geometry, memory=memory, packing=packing, seed=seed)
    rows = []
    # One bar over every wavelength (each wavelength's batches count into it).
    with progress_bar("tracing", wl.size * rays, unit="rays", enabled=progress, show_after_s=SHOW_AFTER_SECONDS):
        for i, lam in enumerate(wl):
            rows.append(
                _trace(
                    traced.medium(float(lam)),
                    rays=rays,
                    incidence_deg=incidence_deg,
                    seed=seed,
                    threads=threads,
                    max_events=max_events,
                    progress=progress,
                    label=f"λ = {lam:g} nm ({i + 1}/{wl.size})",
                )
            )
    counts = {k: np.array([r[k] for r in rows], dtype=np.int64) for k in _COUNT_NAMES}
    rho = counts["escaped"] / counts["launched"]
    description, traced_geometry, traced_memory = engine_settings(traced.describe())
    return ReflectanceResult(
        wavelengths=wl,
        values=rho,
        stderr=np.sqrt(rho * (1 - rho) / counts["launched"]),
        counts=counts,
        rays=rays,
        incidence_deg=incidence_deg,
        seed=seed,
        max_events=max_events,
        sample=description,
        elapsed_s=time.perf_counter() - start,
        geometry=traced_geometry,
        memory=traced_memory,
    )


def isotropic_halfspace(
    albedo: float,
    *,
    rays: int,
    incidence_deg: float = 0.0,
    seed: int = 0,
    threads: int | None = None,
    max_events: int = DEFAULT_MAX_EVENTS,
    depth: float = math.inf,
) -> tuple[float, float]:
    """Reflectance of a half-space of isotropic point scatterers (Chandrasekhar's problem).

    Same free-path, boundary and tally code as :func:`reflectance`, with each particle replaced
    by a point that scatters isotropically with probability ω (``albedo``) and absorbs
    otherwise; free paths are exponential with unit mean. The exact directional-hemispherical
    reflectance is 1 − H(μ₀)√(1 − ω) (docs/model.md §2.7).

    Parameters
    ----------
    albedo : float
        Single-scattering albedo ω in [0, 1].
    depth : float
        Optical thickness of the slab (mean free paths); ``inf`` for a half-space.

    Returns
    -------
    (reflectance, stderr) : tuple of float
    """
    c = _trace(
        IsotropicScatterers(albedo, depth).medium(0.0),
        rays=check_count("rays", rays),
        incidence_deg=check_incidence("incidence_deg", incidence_deg),
        seed=check_seed("seed", seed),
        threads=check_threads("threads", threads),
        max_events=check_count("max_events", max_events),
        label="isotropic half-space",
        progress=False,
    )
    rho = c["escaped"] / c["launched"]
    return rho, math.sqrt(rho * (1 - rho) / c["launched"])
