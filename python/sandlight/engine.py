"""Monte Carlo reflectance of a sand sample (the transport engine's Python surface).

:func:`reflectance` traces rays through the sample with the native engine (docs/transport.md)
and returns the directional-hemispherical reflectance ρ(θᵢ, λ) = escaped / launched with its
standard error √(ρ(1 − ρ)/N) (splits-model.md §2.6). :func:`isotropic_halfspace` runs the same
transport and boundary code with the particles replaced by isotropic point scatterers, whose
exact answer (Chandrasekhar) checks the engine.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field

import numpy as np

from sandlight import _native
from sandlight._runner import run_in_batches
from sandlight.errors import ParameterError
from sandlight.physics.composition import compose
from sandlight.physics.medium import native_medium

DEFAULT_MAX_EVENTS = 10_000_000
GEOMETRIES = ("on-the-fly", "explicit")
MEMORIES = ("none", "channel", "cut", "packed")
#: Path memory of the on-the-fly engine when none is asked for (docs/geometry.md).
DEFAULT_MEMORY = "none"
MAX_INTERNAL_REFLECTIONS = 10_000
_COUNT_NAMES = ("launched", "escaped", "absorbed", "transmitted", "capped", "events")


def _check_rays(rays) -> int:
    try:
        value = float(rays)
    except (TypeError, ValueError):
        raise ParameterError("rays", rays, "a whole number ≥ 1 (e.g. 1e6)") from None
    if not math.isfinite(value) or value < 1 or value != int(value) or isinstance(rays, bool):
        raise ParameterError("rays", rays, "a whole number ≥ 1 (e.g. 1e6)")
    return int(value)


def _check_incidence(incidence_deg) -> float:
    try:
        value = float(incidence_deg)
    except (TypeError, ValueError):
        raise ParameterError("incidence_deg", incidence_deg, "a number in [0, 90) degrees") from None
    if not (0.0 <= value < 90.0):
        raise ParameterError("incidence_deg", incidence_deg, "a number in [0, 90) degrees")
    return value


def _check_seed(seed) -> int:
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not (0 <= int(seed) < 2**64):
        raise ParameterError("seed", seed, "an integer in [0, 2**64)")
    return int(seed)


def _check_threads(threads):
    if threads is None:
        return None
    if isinstance(threads, bool) or not isinstance(threads, (int, np.integer)) or not (1 <= int(threads) <= 1024):
        raise ParameterError("threads", threads, "None (all cores) or an integer in [1, 1024]")
    return int(threads)


def _check_choice(name, value, allowed):
    if not isinstance(value, str) or value not in allowed:
        raise ParameterError(name, value, "one of " + ", ".join(repr(a) for a in allowed))
    return value


#: Why the surface-layer models are not for wet sand yet (docs/geometry.md, "Wet sand").
WET_TOP_LAYER = (
    "memory='cut' or 'packed' and geometry='explicit' put the flat water surface of a water-filled "
    "surface pore at the top of the surface layer, above the highest grain, so with water-filled pores "
    "(saturation above film_saturation) they lose more light in the water bands than the classic model; "
    "use memory='none' for wet sand (docs/geometry.md, 'Wet sand')"
)


def medium_factory(comp, *, geometry: str = "on-the-fly", memory: str | None = None, packing=None, seed: int = 0):
    """A function of the wavelength (nm) giving the native medium to trace, and the packing.

    For ``geometry="explicit"`` the packing (wavelength independent) is generated once, from
    ``seed``, unless one is given (``sandlight.physics.packing.generate_packing``).
    """
    from sandlight.physics.packing import generate_packing, reference_grain_mm

    geometry = _check_choice("geometry", geometry, GEOMETRIES)
    memory = _check_choice("memory", DEFAULT_MEMORY if memory is None else memory, MEMORIES)
    if comp.water_filled_probability > 0 and (memory in ("cut", "packed") or geometry == "explicit"):
        warnings.warn(WET_TOP_LAYER, UserWarning, stacklevel=3)
    if geometry == "on-the-fly":
        return (lambda lam: native_medium(comp, lam, memory=memory)), None
    if memory != "none":
        raise ParameterError("memory", memory, "'none' with geometry='explicit' (memory models the on-the-fly engine)")
    if packing is None:
        packing = generate_packing(native_medium(comp, 550.0), reference_mm=reference_grain_mm(comp), seed=seed)
    elif not isinstance(packing, _native.Packing):
        raise ParameterError("packing", packing, "None or a sandlight._native.Packing (generate_packing)")
    return (lambda lam: native_medium(comp, lam).explicit(packing, comp.depth_mm)), packing


def _check_wavelengths(wavelengths_nm) -> np.ndarray:
    wl = np.atleast_1d(np.asarray(wavelengths_nm, dtype=float))
    if wl.ndim != 1 or wl.size == 0:
        raise ParameterError("wavelengths_nm", wavelengths_nm, "a non-empty 1-D sequence of wavelengths in nm")
    bad = ~np.isfinite(wl) | (wl < 350.0) | (wl > 2500.0)
    if bad.any():
        raise ParameterError("wavelengths_nm", float(wl[bad][0]), "finite wavelengths in [350, 2500] nm")
    return wl


def _trace(medium, *, rays, incidence_deg, seed, threads, max_events, label, progress, stream=0) -> dict:
    counts = np.zeros(len(_COUNT_NAMES), dtype=np.uint64)

    def batch(first, n):
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

    def to_xarray(self):
        """An ``xarray.Dataset`` with units on every variable and the run's inputs as attributes."""
        import json

        import xarray as xr

        import sandlight

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
            coords={"wavelength": ("wavelength", self.wavelengths, {"units": "nm", "long_name": "vacuum wavelength"})},
            attrs={
                "title": "sandlight Monte Carlo reflectance",
                "sandlight_version": sandlight.__version__,
                "rays": self.rays,
                "incidence_deg": self.incidence_deg,
                "seed": str(self.seed),
                "max_events": self.max_events,
                "sample": json.dumps(self.sample),
                "elapsed_s": self.elapsed_s,
                "geometry": self.geometry,
                "memory": self.memory,
            },
        )
        return ds

    def to_netcdf(self, path) -> None:
        """Writes the result as NetCDF (h5netcdf), atomically."""
        from sandlight.io import atomic_path

        with atomic_path(path) as tmp:
            self.to_xarray().to_netcdf(tmp, engine="h5netcdf")

    def to_csv(self, path) -> None:
        """Writes ``wavelength_nm,reflectance,stderr,mean_events_per_ray,capped`` rows, atomically."""
        from sandlight.io import atomic_path

        table = np.column_stack([self.wavelengths, self.values, self.stderr, self.mean_events_per_ray, self.capped])
        with atomic_path(path) as tmp:
            np.savetxt(
                tmp,
                table,
                delimiter=",",
                fmt=["%.6g", "%.8f", "%.8f", "%.6g", "%d"],
                header="wavelength_nm,reflectance,stderr,mean_events_per_ray,capped",
                comments="",
            )

    def plot(self, path, *, title: str | None = None) -> None:
        """Plots the spectrum with ±2 standard-error band to a PNG."""
        from sandlight.plots import plot_spectrum

        plot_spectrum(self.wavelengths, self.values, self.stderr, path, title=title)


def reflectance(
    sample,
    wavelengths_nm,
    *,
    rays,
    incidence_deg: float = 0.0,
    seed: int = 0,
    threads: int | None = None,
    max_events: int = DEFAULT_MAX_EVENTS,
    progress: bool = True,
    geometry: str = "on-the-fly",
    memory: str | None = None,
    packing=None,
) -> ReflectanceResult:
    """Monte Carlo directional-hemispherical reflectance of a sand sample.

    Parameters
    ----------
    sample : SandSample or str
        The sample, or the name of a preset (``SandSample.preset``).
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
        Path memory of the on-the-fly engine (default ``DEFAULT_MEMORY``); must be 'none' for
        explicit geometry. 'packed' (the cut surface, the pore's walls and the packing's pair
        correlation) is the closest to the explicit reference (docs/geometry.md).
    packing : sandlight._native.Packing, optional
        A packing to trace (explicit geometry); generated from ``seed`` when None.

    Returns
    -------
    ReflectanceResult

    Notes
    -----
    The same random streams are used at every wavelength (common random numbers), so the Monte
    Carlo noise is correlated across wavelengths and spectra come out smooth; each value's own
    standard error is unaffected.
    """
    from sandlight.sample import SandSample

    if isinstance(sample, str):
        sample = SandSample.preset(sample)
    if not isinstance(sample, SandSample):
        raise ParameterError("sample", sample, "a SandSample or the name of a preset")
    wl = _check_wavelengths(wavelengths_nm)
    rays = _check_rays(rays)
    incidence_deg = _check_incidence(incidence_deg)
    seed = _check_seed(seed)
    threads = _check_threads(threads)
    max_events = _check_rays(max_events)
    comp = compose(sample)
    start = time.perf_counter()
    make_medium, _ = medium_factory(comp, geometry=geometry, memory=memory, packing=packing, seed=seed)
    rows = []
    for i, lam in enumerate(wl):
        rows.append(
            _trace(
                make_medium(float(lam)),
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
    return ReflectanceResult(
        wavelengths=wl,
        values=rho,
        stderr=np.sqrt(rho * (1 - rho) / counts["launched"]),
        counts=counts,
        rays=rays,
        incidence_deg=incidence_deg,
        seed=seed,
        max_events=max_events,
        sample=sample.to_dict(),
        elapsed_s=time.perf_counter() - start,
        geometry=geometry,
        memory=DEFAULT_MEMORY if memory is None else memory,
    )


def isotropic_halfspace(
    albedo: float,
    *,
    rays,
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
    reflectance is 1 − H(μ₀)√(1 − ω) (splits-model.md §2.7).

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
    rays = _check_rays(rays)
    medium = _native.Medium.isotropic(float(albedo), float(depth))
    c = _trace(
        medium,
        rays=rays,
        incidence_deg=_check_incidence(incidence_deg),
        seed=_check_seed(seed),
        threads=_check_threads(threads),
        max_events=_check_rays(max_events),
        label="isotropic half-space",
        progress=False,
    )
    rho = c["escaped"] / c["launched"]
    return rho, math.sqrt(rho * (1 - rho) / c["launched"])


__all__ = ["ReflectanceResult", "reflectance", "isotropic_halfspace"]
