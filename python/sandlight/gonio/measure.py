"""Measuring a BRDF with the virtual goniophotometer (paper §3.2.1) by tracing trials through a
sand sample, or through any Traceable medium (``sandlight.physics.medium.Traceable``), such as a
reference medium with a known answer. Samples are resolved as by the engine
(``sandlight.physics.media.as_traceable``).

Uniform incidence (the paper's variant): every trial draws its incident direction uniformly over
the hemisphere, and counters n[i, j] are kept for incoming patch i and outgoing patch j, with
absorbed and lost trials counted per incoming patch. Fixed incidence: the classic instrument.
Long runs can checkpoint their counts and resume: trial k always uses random stream k, so a
resumed run gives exactly the counts of an uninterrupted one.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import warnings
import zipfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from sandlight import _native
from sandlight._runner import SHOW_AFTER_SECONDS, run_in_batches
from sandlight.checks import check_count, check_incidence, check_real, check_seed, check_threads, check_wavelengths
from sandlight.engine import DEFAULT_MAX_EVENTS, MAX_INTERNAL_REFLECTIONS, shareable
from sandlight.errors import ModelFileError, ParameterError
from sandlight.gonio.brdf import MeasuredBRDF
from sandlight.gonio.hemisphere import CollectorHemisphere
from sandlight.gonio.reduction import reduce_fixed_incidence
from sandlight.io import atomic_path
from sandlight.physics.media import IsotropicScatterers, LambertianSurface, as_traceable
from sandlight.physics.medium import Traceable
from sandlight.physics.spectral_groups import DISPERSION_TOLERANCE, spectral_groups
from sandlight.progress import progress_bar

if TYPE_CHECKING:
    from sandlight.sample import SandSample

# The reference media live with the other media in sandlight.physics.media; they are named here
# too because the goniophotometer is where they are used.
__all__ = ["brdf", "fixed_incidence", "FixedIncidenceBRDF", "IsotropicScatterers", "LambertianSurface"]


def _checkpoint_key(meta: dict) -> str:
    return hashlib.sha256(json.dumps(meta, sort_keys=True).encode()).hexdigest()


#: Bytes a checkpoint member may hold beyond its array's data: the .npy header, or a small
#: scalar (``key`` is a 64-character string, ``done`` one integer).
_NPY_HEADER_ROOM = 4096


def _checkpoint_error(path: Path, problem: str) -> ModelFileError:
    return ModelFileError(f"{path}: {problem}; delete it to start afresh")


def _load_checkpoint(path: Path, key: str, arrays: dict[str, np.ndarray], rays: int) -> int:
    """Fills ``arrays`` from the checkpoint at ``path`` and returns the trials already done (0
    when there is no checkpoint). Everything is checked before it is used: a zip npz holding
    exactly ``key``, ``done`` and the count arrays, no pickled data, ``key`` the string ``key``
    of this run, ``done`` an integer in [0, rays], each count array of the expected shape and an
    unsigned integer dtype. Anything else raises ModelFileError naming the file and the fault."""
    if not path.exists():
        return 0
    expected = {f"{name}.npy" for name in ("key", "done", *arrays)}
    try:
        if not zipfile.is_zipfile(path):
            raise _checkpoint_error(path, "not a checkpoint (not a zip npz file; truncated or empty?)")
        with zipfile.ZipFile(path) as zf:
            sizes = {info.filename: info.file_size for info in zf.infolist()}
        if set(sizes) != expected:
            raise _checkpoint_error(
                path, f"not a brdf checkpoint (members {sorted(sizes)}, expected {sorted(expected)})"
            )
        # Sizes are checked before anything is read: a member far larger than its array cannot be right.
        for name, size in sizes.items():
            target = arrays.get(name.removesuffix(".npy"))
            limit = (0 if target is None else target.nbytes) + _NPY_HEADER_ROOM
            if size > limit:
                raise _checkpoint_error(path, f"member {name!r} holds {size:,} bytes, at most {limit:,} expected")
        with np.load(path, allow_pickle=False) as z:
            stored_key = z["key"]
            if stored_key.shape != () or stored_key.dtype.kind != "U":
                raise _checkpoint_error(path, "'key' is not a string")
            if str(stored_key) != key:
                raise ModelFileError(
                    f"{path}: checkpoint of a different run (other sample, wavelength, seed, rays or geometry); "
                    "delete it to start afresh or choose another output"
                )
            done = z["done"]
            if done.shape != () or done.dtype.kind not in "iu" or not 0 <= int(done) <= rays:
                raise _checkpoint_error(
                    path, f"'done' = {done.item()!r} is not an integer in [0, {rays}] (the trials of this run)"
                )
            for name, target in arrays.items():
                stored = z[name]
                if stored.shape != target.shape or stored.dtype.kind != "u":
                    raise _checkpoint_error(
                        path,
                        f"{name!r} has shape {stored.shape} and dtype {stored.dtype}, "
                        f"expected shape {target.shape} and an unsigned integer dtype",
                    )
                target[...] = stored
            return int(done)
    except ModelFileError:
        raise
    except (OSError, KeyError, ValueError, EOFError, zipfile.BadZipFile) as e:
        raise _checkpoint_error(path, f"unreadable checkpoint ({e})") from None


def rays_for_every_patch(n_patches: int) -> int:
    """Trials N after which an incoming patch is left without any trial in about one run in 100.

    Uniform incidence over r equal-solid-angle patches leaves r (1 − 1/r)^N ≈ r e^(−N/r) patches
    empty on average; that is 0.01 at N = r ln(100 r): 10 280 for the paper's 901 patches.
    """
    return math.ceil(n_patches * math.log(100 * n_patches))


def _warn_if_undefined(result: MeasuredBRDF, launched: np.ndarray) -> None:
    """Warns, with their number, when some BRDF values are NaN because too few trials were run."""
    n_nan = int(np.isnan(result.unique_values).sum())
    if n_nan == 0:
        return
    r = launched.size
    warnings.warn(
        f"{n_nan} of {result.unique_values.size} BRDF values are NaN: {int((launched == 0).sum())} of {r} "
        f"incoming patches received no trial with rays = {result.rays}; use at least about "
        f"{rays_for_every_patch(r)} rays for {r} patches",
        UserWarning,
        stacklevel=3,
    )


def _save_checkpoint(path: Path, key: str, done: int, arrays: dict[str, np.ndarray]) -> None:
    with atomic_path(path) as tmp, open(tmp, "wb") as f:
        np.savez(f, key=np.array(key), done=np.array(done), **arrays)


#: Most wavelengths measured together (spectral path sharing): a group's sums take 24 bytes per
#: (incoming patch, outgoing patch, wavelength), 19.5 MB per wavelength at 901 patches, so a
#: group of 16 holds 312 MB (docs/performance.md). Larger dispersion groups are split.
MAX_GONIO_GROUP = 16


@dataclass(frozen=True)
class _Settings:
    """The parameters every unit of a :func:`brdf` run (a wavelength, or a group sharing paths)
    is traced and reduced with."""

    hemisphere: CollectorHemisphere
    rays: int
    seed: int
    threads: int | None
    max_events: int
    method: str
    sample: dict
    checkpoint_seconds: float
    progress: bool


def _run_unit(
    settings: _Settings,
    key_fields: dict,
    arrays: dict[str, np.ndarray],
    batch: Callable[[int, int], None],
    label: str,
    checkpoint: Path | None,
) -> None:
    """Traces the rays of one unit into ``arrays`` (unsigned integers, filled in place by
    ``batch(first, n)``), resuming from and saving to ``checkpoint`` (which :func:`brdf`
    removes once every unit is done, so an interrupted run keeps its finished units)."""
    h = settings.hemisphere
    key = _checkpoint_key(
        {
            "sample": settings.sample,
            **key_fields,
            "rays": settings.rays,
            "seed": settings.seed,
            "stacks": h.stacks,
            "slices": h.slices,
            "max_events": settings.max_events,
        }
    )
    done = _load_checkpoint(checkpoint, key, arrays, settings.rays) if checkpoint is not None else 0
    save = (lambda d: _save_checkpoint(checkpoint, key, d, arrays)) if checkpoint is not None else None
    run_in_batches(
        batch,
        settings.rays,
        label=label,
        progress=settings.progress,
        start_at=done,
        on_checkpoint=save,
        checkpoint_seconds=settings.checkpoint_seconds,
    )


def _measure_one(settings: _Settings, medium: _native.Medium, wl: float, checkpoint: Path | None) -> MeasuredBRDF:
    """The BRDF at ``wl`` (nm) from trials of its own (random stream 0)."""
    h = settings.hemisphere
    r = h.n_patches
    arrays = {
        "counts": np.zeros((r, r), np.uint64),
        "absorbed": np.zeros(r, np.uint64),
        "launched": np.zeros(r, np.uint64),
        "lost": np.zeros(r, np.uint64),
    }

    def batch(first: int, n: int) -> None:
        parts = medium.brdf_counts(
            h.stacks,
            h.slices,
            settings.seed,
            0,
            first,
            n,
            settings.max_events,
            MAX_INTERNAL_REFLECTIONS,
            settings.threads,
        )
        for name, part in zip(arrays, parts):
            arrays[name] += part

    _run_unit(settings, {"wavelength_nm": wl}, arrays, batch, f"BRDF at {wl:g} nm", checkpoint)
    return MeasuredBRDF.from_counts(*arrays.values(), **_metadata(settings), wavelength_nm=wl, method=settings.method)


def _zero_sums(n_incoming: int, n_patches: int, n_wavelengths: int) -> dict[str, np.ndarray]:
    """The fixed-point sums ``SpectralGroup.brdf_sums`` fills (``sandlight_core::gonio::
    spectral_sums``), zeroed: per (incoming patch, outgoing patch, wavelength) Σ q with
    q = round(F·2³²) (``escaped``) and Σ q² exactly, a u128 as its high and low uint64 words
    (``squares``, one more axis of 2); per incoming patch and wavelength
    Σ round(F·2³²) over transmitted trials; per incoming patch the trials and the event-capped
    trials. Uniform incidence has ``n_patches`` incoming patches, a fixed direction one."""
    n, r, w = n_incoming, n_patches, n_wavelengths
    return {
        "escaped": np.zeros((n, r, w), np.uint64),
        "squares": np.zeros((n, r, w, 2), np.uint64),
        "transmitted": np.zeros((n, w), np.uint64),
        "launched": np.zeros(n, np.uint64),
        "capped": np.zeros(n, np.uint64),
    }


def _shared_batch(
    group: _native.SpectralGroup,
    hemisphere: CollectorHemisphere,
    sums: dict[str, np.ndarray],
    settings: tuple[int, int, int, int | None],
    incidence_deg: tuple[float, float] | None = None,
) -> Callable[[int, int], None]:
    """``batch(first, n)`` adding trials ``first .. first + n`` of ``group`` to ``sums``, with
    ``settings`` = (seed, random stream, max_events, threads): uniform incidence, or every trial
    from ``incidence_deg`` = (zenith, azimuth) in degrees."""
    seed, stream, max_events, threads = settings

    def batch(first: int, n: int) -> None:
        group.brdf_sums(
            hemisphere.stacks,
            hemisphere.slices,
            seed,
            stream,
            first,
            n,
            max_events,
            MAX_INTERNAL_REFLECTIONS,
            *sums.values(),
            threads,
            incidence_deg,
        )

    return batch


def _weight_sums(sums: dict[str, np.ndarray], k: int) -> tuple[np.ndarray, ...]:
    """Wavelength ``k``'s (counts, absorbed, launched, lost, squares) per incoming patch from
    the fixed-point ``sums``: counts = Σ F per cell, lost = Σ F over transmitted trials + the
    event-capped trials, absorbed = launched − escaped − lost, squares = Σ F² per cell."""
    one, square_one = _native.SpectralGroup.fixed_one, _native.SpectralGroup.square_one
    launched = sums["launched"].astype(np.int64)
    counts = sums["escaped"][:, :, k] / one
    lost = sums["transmitted"][:, k] / one + sums["capped"]
    high, low = sums["squares"][:, :, k, 0], sums["squares"][:, :, k, 1]
    squares = high * (2.0**64 / square_one) + low / square_one  # the u128 (high·2⁶⁴ + low) over its scale
    return counts, launched - counts.sum(axis=1) - lost, launched, lost, squares


def _measure_shared(
    settings: _Settings, group: _native.SpectralGroup, wl: np.ndarray, stream: int, label: str, checkpoint: Path | None
) -> list[MeasuredBRDF]:
    """The BRDFs at the wavelengths ``wl`` of ``group`` from shared trials (random stream
    ``stream``): the fixed-point sums of the native group (``SpectralGroup.brdf_sums``) as
    weight sums Σ F and Σ F² per cell (:func:`_weight_sums`)."""
    h = settings.hemisphere
    arrays = _zero_sums(h.n_patches, h.n_patches, wl.size)
    batch = _shared_batch(group, h, arrays, (settings.seed, stream, settings.max_events, settings.threads))
    # The squares' scale in the key: a checkpoint summed at another scale is refused.
    key_fields = {"wavelengths_nm": wl.tolist(), "shared_stream": stream, "square_one": group.square_one}
    _run_unit(settings, key_fields, arrays, batch, label, checkpoint)
    results = []
    for k, lam in enumerate(wl):
        counts, absorbed, launched, lost, squares = _weight_sums(arrays, k)
        results.append(
            MeasuredBRDF.from_counts(
                counts,
                absorbed,
                launched,
                lost,
                squares=squares,
                **_metadata(settings),
                wavelength_nm=float(lam),
                method=settings.method,
            )
        )
    return results


def _metadata(settings: _Settings) -> dict:
    """The keywords of `MeasuredBRDF.from_counts` that every unit shares."""
    h = settings.hemisphere
    return {
        "stacks": h.stacks,
        "slices": h.slices,
        "sample": settings.sample,
        "rays": settings.rays,
        "seed": settings.seed,
    }


def _shared_groups(traced: Traceable, wl: np.ndarray, share: bool, tolerance: float) -> list[np.ndarray] | None:
    """The groups of wavelengths ``wl`` measured with shared trials, as indices into ``wl``:
    the dispersion groups of ``traced`` (``spectral_groups``) split at :data:`MAX_GONIO_GROUP`.
    None when nothing is shared: not ``share``, a single wavelength, or a medium that does not
    share (``shareable``)."""
    if not (share and wl.size > 1 and shareable(traced)):
        return None
    groups = spectral_groups(traced.composition, wl, tolerance, optical_constants=traced.optical_constants)
    return [part for g in groups for part in np.array_split(g, math.ceil(g.size / MAX_GONIO_GROUP))]


def _native_group(traced: Traceable, wl: np.ndarray, idx: np.ndarray) -> tuple[_native.SpectralGroup, str]:
    """The native group of the wavelengths ``wl[idx]`` of ``traced``, and their span for labels."""
    group = _native.SpectralGroup([traced.medium(float(wl[i])) for i in idx])
    return group, f"{wl[idx].min():g}–{wl[idx].max():g} nm" if idx.size > 1 else f"{wl[idx[0]]:g} nm"


def _unit_checkpoint(checkpoint: Path | None, unit: int, units: int) -> Path | None:
    """The checkpoint file of unit ``unit`` of ``units``: ``checkpoint`` itself for one unit,
    else ``checkpoint`` with ``.{unit}`` appended to its name."""
    if checkpoint is None or units == 1:
        return checkpoint
    return checkpoint.with_name(f"{checkpoint.name}.{unit}")


def brdf(
    sample: SandSample | str | Traceable,
    wavelength_nm: float | npt.ArrayLike = 550.0,
    *,
    rays: int,
    stacks: int = 31,
    slices: int = 30,
    seed: int = 0,
    threads: int | None = None,
    method: str = "average",
    max_events: int = DEFAULT_MAX_EVENTS,
    checkpoint: str | os.PathLike | None = None,
    checkpoint_seconds: float = 60.0,
    progress: bool = True,
    geometry: str = "on-the-fly",
    memory: str | None = None,
    packing: _native.Packing | None = None,
    share: bool = True,
    dispersion_tolerance: float = DISPERSION_TOLERANCE,
) -> MeasuredBRDF | list[MeasuredBRDF]:
    """Measures the BRDF of a sample with uniform incidence (paper §3.2.1).

    Parameters
    ----------
    sample : SandSample, str or Traceable
        The sand sample (or preset name), or any Traceable medium, e.g. a reference medium
        (``IsotropicScatterers``, ``LambertianSurface``) or a ``Powder``.
    wavelength_nm : float or array_like
        Vacuum wavelength λ (nm), in [350, 2500], or a sequence of them (one BRDF each).
    rays : int
        Trials N per wavelength (the paper uses about 10⁸).
    stacks, slices : int
        Collector hemisphere: r = 1 + (stacks − 1)·slices equal-solid-angle patches (31 × 30 → 901).
    seed : int
        Master seed; results are identical for any ``threads`` and across resumed runs.
    method : {'average', 'pooled'}
        How values equal by isotropy and reciprocity are combined (``MeasuredBRDF.from_counts``).
    checkpoint : path, optional
        File where the counts are saved about every minute; an existing checkpoint of the same
        run is resumed. Removed when the run completes. A run of several wavelengths keeps one
        file per wavelength or shared group, named with ``.0``, ``.1``, … appended.
    checkpoint_seconds : float
        Wall time between two saves of the checkpoint, s, ≥ 0 (default 60; 0: after every batch
        of rays).
    geometry, memory, packing
        As in :func:`sandlight.reflectance`: 'explicit' traces a stored packing of the sample's
        grains (the slow reference, docs/geometry.md). A packing generated here uses ``seed``.
    share : bool
        Spectral path sharing (docs/transport.md), as in :func:`sandlight.reflectance`: with
        several wavelengths, those of each group of nearly equal refractive indices (at most
        :data:`MAX_GONIO_GROUP`) are measured with the same trials, each trial traced once at a
        hero wavelength with a weight per wavelength; group g uses random stream g + 1. Applies
        to the media :func:`sandlight.engine.shareable` names; a single wavelength, other media
        and ``False`` measure every wavelength with trials of its own (stream 0, the same at
        every wavelength), as a single-wavelength call does.
    dispersion_tolerance : float
        Largest spread of any material's real index within a group (``share`` only), in [0, 1].

    Returns
    -------
    MeasuredBRDF or list of MeasuredBRDF
        One for a scalar ``wavelength_nm``, else one per wavelength in the order given: raw
        counts (weight sums and ``squares`` when shared), reduced and normalised values with
        standard errors, metadata.

    Warns
    -----
    UserWarning
        When some values are NaN, with their number: a value is undefined when no trial came
        in through any patch of its class, and every normalised value is when one of the
        normal-incidence row's classes saw no trial. Too few rays are not refused (a short run
        is a legitimate smoke test) but warned about, naming :func:`rays_for_every_patch`
        (N = r ln(100 r), 10 280 for 901 patches), after which an empty patch is rare.
    """
    wl = check_wavelengths("wavelength_nm", wavelength_nm)
    rays = check_count("rays", rays)
    seed = check_seed("seed", seed)
    threads = check_threads("threads", threads)
    checkpoint_seconds = check_real("checkpoint_seconds", checkpoint_seconds, 0.0)
    if not isinstance(share, bool):
        raise ParameterError("share", share, "True or False")
    dispersion_tolerance = check_real("dispersion_tolerance", dispersion_tolerance, 0.0, 1.0)
    hemi = CollectorHemisphere(stacks, slices)  # validates stacks and slices
    traced = as_traceable(sample, geometry=geometry, memory=memory, packing=packing, seed=seed)
    settings = _Settings(
        hemi, rays, seed, threads, int(max_events), method, traced.describe(), checkpoint_seconds, progress
    )
    checkpoint = Path(checkpoint) if checkpoint is not None else None
    results: list[MeasuredBRDF | None] = [None] * wl.size
    groups = _shared_groups(traced, wl, share, dispersion_tolerance)
    sharing = groups is not None
    if sharing:
        with progress_bar(
            "tracing", len(groups) * rays, unit="rays", enabled=progress, show_after_s=SHOW_AFTER_SECONDS
        ):
            for g, idx in enumerate(groups):
                group, span = _native_group(traced, wl, idx)
                label = f"BRDF at λ = {span} (group {g + 1}/{len(groups)})"
                unit = _unit_checkpoint(checkpoint, g, len(groups))
                for i, b in zip(idx, _measure_shared(settings, group, wl[idx], g + 1, label, unit)):
                    results[i] = b
    else:
        with progress_bar("tracing", wl.size * rays, unit="rays", enabled=progress, show_after_s=SHOW_AFTER_SECONDS):
            for i, lam in enumerate(wl):
                unit = _unit_checkpoint(checkpoint, i, wl.size)
                results[i] = _measure_one(settings, traced.medium(float(lam)), float(lam), unit)
    units = len(groups) if sharing else wl.size
    for unit in range(units) if checkpoint is not None else ():
        _unit_checkpoint(checkpoint, unit, units).unlink(missing_ok=True)
    for result in results:
        _warn_if_undefined(result, result.launched)
    return results[0] if np.ndim(wavelength_nm) == 0 else results


@dataclass(frozen=True)
class FixedIncidenceBRDF:
    """BRDF per outgoing patch for one incident direction (the classic goniophotometer).

    ``counts`` (n_j per outgoing patch), ``absorbed`` and ``lost`` are trial counts, or weight
    sums Σ F (floats) when the wavelength was measured with shared paths; ``squares`` then holds
    Σ F² per outgoing patch (None for independent trials); ``launched`` is N, the trials;
    ``values`` and ``stderr`` are f_j and its standard error (``reduce_fixed_incidence``);
    ``wavelength_nm`` the vacuum wavelength.
    """

    hemisphere: CollectorHemisphere
    incidence_deg: float
    azimuth_deg: float
    counts: np.ndarray
    absorbed: int | float
    launched: int
    lost: int | float
    values: np.ndarray
    stderr: np.ndarray
    squares: np.ndarray | None = None
    wavelength_nm: float | None = None

    @property
    def reflectance(self) -> float:
        """Directional-hemispherical reflectance, escaped / launched."""
        return float(self.counts.sum()) / self.launched


def fixed_incidence(
    sample: SandSample | str | Traceable,
    wavelength_nm: float | npt.ArrayLike = 550.0,
    *,
    incidence_deg: float,
    azimuth_deg: float = 0.0,
    rays: int,
    stacks: int = 31,
    slices: int = 30,
    seed: int = 0,
    threads: int | None = None,
    max_events: int = DEFAULT_MAX_EVENTS,
    progress: bool = True,
    geometry: str = "on-the-fly",
    memory: str | None = None,
    packing: _native.Packing | None = None,
    share: bool = True,
    dispersion_tolerance: float = DISPERSION_TOLERANCE,
) -> FixedIncidenceBRDF | list[FixedIncidenceBRDF]:
    """The classic goniophotometer: f_j = n_j / (ω_p(j) N) for light from (θᵢ, φᵢ).

    ``sample``, ``geometry``, ``memory`` and ``packing`` as in :func:`brdf`; ``azimuth_deg`` is the
    azimuth φᵢ of the incident light (degrees, finite). ``wavelength_nm`` is a wavelength or a
    sequence of them (one result each, in the order given); ``share`` and
    ``dispersion_tolerance`` as in :func:`brdf`: the wavelengths of a group are measured with
    the same trials (random stream g + 1 for group g), their n_j replaced by weight sums Σ F and
    their standard errors computed from Σ F² (``squares``); a single wavelength, a medium that
    does not share and ``share=False`` trace every wavelength with trials of its own (stream 0),
    as a single-wavelength call does.
    """
    wl = check_wavelengths("wavelength_nm", wavelength_nm)
    rays, seed, threads = check_count("rays", rays), check_seed("seed", seed), check_threads("threads", threads)
    theta = check_incidence("incidence_deg", incidence_deg)
    azimuth_deg = float(check_real("azimuth_deg", azimuth_deg))
    if not isinstance(share, bool):
        raise ParameterError("share", share, "True or False")
    dispersion_tolerance = check_real("dispersion_tolerance", dispersion_tolerance, 0.0, 1.0)
    run = _FixedRun(
        CollectorHemisphere(stacks, slices), theta, azimuth_deg, rays, seed, threads, int(max_events), progress
    )
    traced = as_traceable(sample, geometry=geometry, memory=memory, packing=packing, seed=seed)
    results: list[FixedIncidenceBRDF | None] = [None] * wl.size
    groups = _shared_groups(traced, wl, share, dispersion_tolerance)
    units = wl.size if groups is None else len(groups)
    with progress_bar("tracing", units * rays, unit="rays", enabled=progress, show_after_s=SHOW_AFTER_SECONDS):
        for g, idx in enumerate(groups or ()):
            group, span = _native_group(traced, wl, idx)
            label = f"fixed incidence {theta:g}° at λ = {span} (group {g + 1}/{len(groups)})"
            for i, b in zip(idx, run.shared(group, wl[idx], g + 1, label)):
                results[i] = b
        for i in range(wl.size) if groups is None else ():
            results[i] = run.one(traced.medium(float(wl[i])), float(wl[i]))
    return results[0] if np.ndim(wavelength_nm) == 0 else results


@dataclass(frozen=True)
class _FixedRun:
    """The parameters every wavelength of a :func:`fixed_incidence` run is traced with."""

    hemisphere: CollectorHemisphere
    incidence_deg: float
    azimuth_deg: float
    rays: int
    seed: int
    threads: int | None
    max_events: int
    progress: bool

    def _result(
        self,
        counts: np.ndarray,
        absorbed: float,
        launched: int,
        lost: float,
        squares: np.ndarray | None,
        wavelength_nm: float,
    ) -> FixedIncidenceBRDF:
        f, se = reduce_fixed_incidence(self.hemisphere, counts, absorbed, launched, lost, squares=squares)
        return FixedIncidenceBRDF(
            self.hemisphere,
            self.incidence_deg,
            self.azimuth_deg,
            counts,
            absorbed,
            launched,
            lost,
            f,
            se,
            squares,
            wavelength_nm,
        )

    def one(self, medium: _native.Medium, wavelength_nm: float) -> FixedIncidenceBRDF:
        """The result at ``wavelength_nm`` from trials of its own (random stream 0)."""
        h = self.hemisphere
        counts = np.zeros(h.n_patches, np.uint64)
        totals = np.zeros(3, np.uint64)

        def batch(first: int, n: int) -> None:
            c, a, l_, lost = medium.fixed_counts(
                h.stacks,
                h.slices,
                self.incidence_deg,
                self.azimuth_deg,
                self.seed,
                0,
                first,
                n,
                self.max_events,
                MAX_INTERNAL_REFLECTIONS,
                self.threads,
            )
            counts[:] += c
            totals[:] += np.array([a, l_, lost], np.uint64)

        run_in_batches(batch, self.rays, label=f"fixed incidence {self.incidence_deg:g}°", progress=self.progress)
        absorbed, launched, lost = (int(t) for t in totals)
        return self._result(counts, absorbed, launched, lost, None, wavelength_nm)

    def shared(self, group: _native.SpectralGroup, wl: np.ndarray, stream: int, label: str) -> list[FixedIncidenceBRDF]:
        """The results at the wavelengths ``wl`` of ``group`` from shared trials (random stream
        ``stream``): the sums of one incoming patch (:func:`_zero_sums`, :func:`_weight_sums`)."""
        sums = _zero_sums(1, self.hemisphere.n_patches, wl.size)
        settings = (self.seed, stream, self.max_events, self.threads)
        batch = _shared_batch(group, self.hemisphere, sums, settings, (self.incidence_deg, self.azimuth_deg))
        run_in_batches(batch, self.rays, label=label, progress=self.progress)
        results = []
        for k, lam in enumerate(wl):
            counts, absorbed, launched, lost, squares = _weight_sums(sums, k)
            results.append(self._result(counts[0], absorbed[0], int(launched[0]), lost[0], squares[0], float(lam)))
        return results
