"""Monte Carlo reflectance of a sand sample (the transport engine's Python surface).

:func:`reflectance` traces rays through the sample with the native engine (docs/transport.md)
and returns the directional-hemispherical reflectance ρ(θᵢ, λ) = escaped / launched with its
standard error √(ρ(1 − ρ)/N) (docs/model.md §2.6). By default the wavelengths of a sand
medium share their paths (hero-wavelength sampling, docs/transport.md "Spectral path
sharing"): ρ is then the mean of per-ray weights, with standard errors and covariances from
their sums of squares and products. :func:`isotropic_halfspace` runs the same
transport and boundary code with the particles replaced by isotropic point scatterers, whose
exact answer (Chandrasekhar) checks the engine.
"""

from __future__ import annotations

import math
import operator
import os
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from sandlight import _native
from sandlight._runner import SHOW_AFTER_SECONDS, run_in_batches
from sandlight.checks import (
    check_count,
    check_incidence,
    check_real,
    check_seed,
    check_threads,
    check_wavelengths,
)
from sandlight.errors import ParameterError
from sandlight.physics.media import IsotropicScatterers, PackedSand, SandMedium, as_traceable, engine_settings
from sandlight.physics.medium import Traceable
from sandlight.physics.powder import Powder
from sandlight.physics.spectral_groups import DISPERSION_TOLERANCE, spectral_groups
from sandlight.progress import progress_bar

if TYPE_CHECKING:
    import xarray as xr

    from sandlight.sample import SandSample

__all__ = [
    "ReflectanceResult",
    "reflectance",
    "isotropic_halfspace",
    "shareable",
    "DEFAULT_MAX_EVENTS",
    "MAX_INTERNAL_REFLECTIONS",
    "DISPERSION_TOLERANCE",
]

DEFAULT_MAX_EVENTS = 10_000_000
MAX_INTERNAL_REFLECTIONS = 10_000
_COUNT_NAMES = ("launched", "escaped", "absorbed", "transmitted", "capped", "events")


def _add_exact(total: tuple, new: tuple) -> tuple:
    """Field by field sum of two shared-run totals: integers, and lists element by element."""
    return tuple(a + b if isinstance(a, int) else [x + y for x, y in zip(a, b)] for a, b in zip(total, new))


@dataclass(frozen=True)
class _CountLayout:
    """How the totals of a tracer's ``dhr`` batches are kept: their names, a batch's form
    (``convert``), the sum of two (``add``) and the totals as returned (``finish``)."""

    names: tuple[str, ...]
    convert: Callable[[tuple], Any]
    add: Callable[[Any, Any], Any]
    finish: Callable[[Any], Iterable]


#: A Medium's counts, summed as uint64, returned as Python integers.
_COUNTS = _CountLayout(_COUNT_NAMES, lambda c: np.array(c, dtype=np.uint64), operator.add, lambda t: map(int, t))
#: A SpectralGroup's totals: launched, capped, events, and the fixed-point 128-bit sums escaped,
#: transmitted (per wavelength) and products (i ≤ j, row by row), as exact Python integers.
_SHARED_SUMS = _CountLayout(
    ("launched", "capped", "events", "escaped", "transmitted", "products"), tuple, _add_exact, tuple
)


def _trace(
    tracer: _native.Medium | _native.SpectralGroup,
    layout: _CountLayout,
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
    """Totals of ``tracer.dhr`` over ``rays`` (≥ 1) traced in batches, kept as ``layout`` says."""
    total = None

    def batch(first: int, n: int):
        nonlocal total
        new = layout.convert(
            tracer.dhr(incidence_deg, seed, stream, first, n, max_events, MAX_INTERNAL_REFLECTIONS, threads)
        )
        total = new if total is None else layout.add(total, new)

    run_in_batches(batch, rays, label=label, progress=progress)
    return dict(zip(layout.names, layout.finish(total)))


def _shared_moments(tot: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(ρ, transmitted fraction, covariance of ρ) of a shared run's totals, in exact integer
    arithmetic until the final division: Cov(ρ̂ᵢ, ρ̂ⱼ) = (N Σqᵢqⱼ − Σqᵢ Σqⱼ) / (N³ s²) with s the
    fixed-point scale (the plug-in estimate, which for one wavelength, weights 0 or 1, is the
    binomial ρ(1 − ρ)/N of independent runs)."""
    n, one = tot["launched"], _native.SpectralGroup.fixed_one
    esc = tot["escaped"]
    m = len(esc)
    cov = np.zeros((m, m))
    k = 0
    for i in range(m):
        for j in range(i, m):
            num = n * tot["products"][k] - esc[i] * esc[j]
            cov[i, j] = cov[j, i] = num / (n * n * n) / (one * one)
            k += 1
    rho = np.array([e / n / one for e in esc])
    transmitted = np.array([t / n / one for t in tot["transmitted"]])
    return rho, transmitted, cov


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
        With spectral sharing escaped, absorbed and transmitted are sums of per-ray weights
        (floats), and capped and events are those of the wavelength's group (shared paths).
    covariance : ndarray, shape (n, n)
        Covariance of the estimates ρ(λᵢ), ρ(λⱼ); its diagonal is ``stderr**2``. With sharing,
        from the per-ray weights' products within a group and 0 between groups (independent
        random streams); without, the off-diagonal is NaN (not estimated: the wavelengths use
        common random numbers, so their errors are correlated).
    shared : bool
        Whether the wavelengths shared paths (``groups`` lists them).
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
    covariance: np.ndarray | None = None
    shared: bool = False
    groups: tuple = ()
    dispersion_tolerance: float = DISPERSION_TOLERANCE

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
            v = np.asarray(v)
            data[f"count_{k}"] = (
                "wavelength",
                v if v.dtype.kind == "f" else v.astype(np.int64),
                {"units": "1", "long_name": f"rays {k}" if k != "events" else "particle events summed over rays"},
            )
        coords = {"wavelength": ("wavelength", self.wavelengths, WAVELENGTH_ATTRS)}
        if self.covariance is not None:
            coords["wavelength_b"] = ("wavelength_b", self.wavelengths, WAVELENGTH_ATTRS)
            data["covariance"] = (
                ("wavelength", "wavelength_b"),
                self.covariance,
                {"units": "1", "long_name": "covariance of the reflectance estimates (NaN: not estimated)"},
            )
        ds = xr.Dataset(
            data,
            coords=coords,
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
                "spectral_sharing": int(self.shared),
                "spectral_groups": json.dumps([[float(self.wavelengths[i]) for i in g] for g in self.groups]),
                "dispersion_tolerance": self.dispersion_tolerance,
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
    share: bool = True,
    dispersion_tolerance: float = DISPERSION_TOLERANCE,
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

    share : bool
        Spectral path sharing (docs/transport.md): the wavelengths of each group of nearly
        equal refractive indices are traced together, one path at a hero wavelength with a
        weight per wavelength. Applies to a sand medium, on the fly with any path memory or
        explicit, and to a ``Powder`` (:func:`shareable`); other media, and a single wavelength
        of an explicit one, are traced wavelength by wavelength. ``False`` traces every
        wavelength on its own (the reference of the sharing's tests).
    dispersion_tolerance : float
        Largest spread of any material's real index within a group (``share`` only), in
        [0, 1]; 0 groups only wavelengths of equal indices.

    ``geometry``, ``memory`` and ``packing`` apply to a sample (``sandlight.physics.media.as_traceable``);
    a Traceable carries its own.

    Returns
    -------
    ReflectanceResult
        ``sample`` holds the medium's description, ``geometry`` and ``memory`` the engine's.

    Notes
    -----
    Without sharing the same random streams are used at every wavelength (common random
    numbers), so the Monte Carlo noise is correlated across wavelengths and spectra come out
    smooth; each value's own standard error is unaffected. With sharing the wavelengths of a
    group share their paths (correlated errors, given in ``covariance``) and groups use
    independent streams (group g: stream g + 1).
    """
    wl = check_wavelengths("wavelengths_nm", wavelengths_nm)
    rays = check_count("rays", rays)
    incidence_deg = check_incidence("incidence_deg", incidence_deg)
    seed = check_seed("seed", seed)
    threads = check_threads("threads", threads)
    max_events = check_count("max_events", max_events)
    if not isinstance(share, bool):
        raise ParameterError("share", share, "True or False")
    dispersion_tolerance = check_real("dispersion_tolerance", dispersion_tolerance, 0.0, 1.0)
    start = time.perf_counter()
    traced = as_traceable(sample, geometry=geometry, memory=memory, packing=packing, seed=seed)
    run = dict(incidence_deg=incidence_deg, seed=seed, threads=threads, max_events=max_events, progress=progress)
    # A single wavelength of the explicit reference is traced on its own, as before sharing
    # (its paths unchanged; the on-the-fly media take a group of one).
    if share and shareable(traced) and (wl.size > 1 or not isinstance(traced, PackedSand)):
        values, stderr, counts, cov, groups = _shared_spectrum(traced, wl, rays, dispersion_tolerance, run)
    else:
        share = False
        # One bar over every wavelength (each wavelength's batches count into it).
        with progress_bar("tracing", wl.size * rays, unit="rays", enabled=progress, show_after_s=SHOW_AFTER_SECONDS):
            rows = [
                _trace(
                    traced.medium(float(lam)), _COUNTS, rays=rays, label=f"λ = {lam:g} nm ({i + 1}/{wl.size})", **run
                )
                for i, lam in enumerate(wl)
            ]
        counts = {k: np.array([r[k] for r in rows], dtype=np.int64) for k in _COUNT_NAMES}
        values = counts["escaped"] / counts["launched"]
        stderr = np.sqrt(values * (1 - values) / counts["launched"])
        cov = np.full((wl.size, wl.size), np.nan)
        np.fill_diagonal(cov, stderr**2)
        groups = tuple((i,) for i in range(wl.size))
    description, traced_geometry, traced_memory = engine_settings(traced.describe())
    return ReflectanceResult(
        wavelengths=wl,
        values=values,
        stderr=stderr,
        counts=counts,
        rays=rays,
        incidence_deg=incidence_deg,
        seed=seed,
        max_events=max_events,
        sample=description,
        elapsed_s=time.perf_counter() - start,
        geometry=traced_geometry,
        memory=traced_memory,
        covariance=cov,
        shared=share,
        groups=groups,
        dispersion_tolerance=dispersion_tolerance,
    )


def shareable(traced: Traceable) -> bool:
    """Whether spectral path sharing applies to ``traced``: a sand medium on the fly, with or
    without path memory, or through an explicit packing, or a powder (the reference media and
    user Traceables trace wavelength by wavelength, docs/transport.md)."""
    return isinstance(traced, (SandMedium, PackedSand, Powder))


def _shared_spectrum(
    traced: SandMedium | PackedSand | Powder, wl: np.ndarray, rays: int, tolerance: float, run: dict
) -> tuple[np.ndarray, np.ndarray, dict, np.ndarray, tuple]:
    """Values, standard errors, counts, covariance and groups of a shared run over ``wl``."""
    groups = spectral_groups(traced.composition, wl, tolerance, optical_constants=traced.optical_constants)
    m = wl.size
    values, transmitted, cov = np.zeros(m), np.zeros(m), np.zeros((m, m))
    counts = {k: np.zeros(m, dtype=np.int64) for k in ("launched", "capped", "events")}
    bar = progress_bar(
        "tracing", len(groups) * rays, unit="rays", enabled=run["progress"], show_after_s=SHOW_AFTER_SECONDS
    )
    with bar:  # one bar over every group
        for g, idx in enumerate(groups):
            group = _native.SpectralGroup([traced.medium(float(wl[i])) for i in idx])
            span = f"{wl[idx].min():g}–{wl[idx].max():g} nm" if idx.size > 1 else f"{wl[idx[0]]:g} nm"
            label = f"λ = {span} (group {g + 1}/{len(groups)})"
            tot = _trace(group, _SHARED_SUMS, rays=rays, label=label, stream=g + 1, **run)
            rho, trans, c = _shared_moments(tot)
            values[idx], transmitted[idx] = rho, trans
            cov[np.ix_(idx, idx)] = c
            for k in counts:
                counts[k][idx] = tot[k]
    launched = counts["launched"].astype(float)
    counts = {
        "launched": counts["launched"],
        "escaped": values * launched,
        "absorbed": launched * (1 - values - transmitted) - counts["capped"],
        "transmitted": transmitted * launched,
        "capped": counts["capped"],
        "events": counts["events"],
    }
    stderr = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    return values, stderr, counts, cov, tuple(tuple(int(i) for i in g) for g in groups)


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
        _COUNTS,
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
