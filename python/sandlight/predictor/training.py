"""Training sets for the spectral predictor, and the whole train-and-evaluate pipeline.

:func:`generate_training_set` draws samples over a :class:`~sandlight.predictor.domain.Domain`,
runs the Monte Carlo engine on each at normal incidence (a restartable job, see
:mod:`sandlight.jobs`) and stores one dataset:

===============  =====================  ====================================================
variable         dims                   meaning
===============  =====================  ====================================================
<parameter>      (sample,)              one variable per SandSample parameter (incl. sand,
                                        depth_mm and iron_oxide_form)
reflectance      (sample, wavelength)   directional-hemispherical reflectance, fraction
stderr           (sample, wavelength)   its Monte Carlo standard error
seed             (sample,)              engine seed of the sample
wavelength       (wavelength,)          nm
===============  =====================  ====================================================

Global attributes: format, n_samples, seed, rays, design, domain (JSON), engine settings (JSON:
incidence, threads, rays, ``memory`` when the engine ran with path memory, docs/geometry.md,
absent for the classic model; ``films`` when the film water is not a uniform film,
docs/model.md §2.5), simulator, sandlight_version and the job settings.

:func:`train_spectral` runs the training and hold-out jobs, fits a :class:`SpectralModel`,
evaluates it on the hold-out set and saves it; the ``sandlight train-spectral`` command and
``scripts/data/train_default_spectral.py`` call it.
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from sandlight.checks import check_choice, check_seed, check_wavelengths, check_whole_number, parse_range
from sandlight.errors import ParameterError
from sandlight.io import write_atomically
from sandlight.jobs import Job, JobStatus, derive_seed
from sandlight.jobs.executors import Executor, resolve_executor
from sandlight.optics import MAX_WAVELENGTHS
from sandlight.predictor.domain import CLEAN_SAND, FORM_PARAMETER, Domain
from sandlight.predictor.spectral import IRON_FREE_FORMS, HoldoutReport, SpectralModel, evaluate

if TYPE_CHECKING:
    import os

    import xarray as xr

    from sandlight.engine import ReflectanceResult
    from sandlight.jobs.executors import Executor
    from sandlight.physics.medium import Traceable

TRAINING_SET_FORMAT = "sandlight-spectral-training-set"
TRAINING_SET_FORMAT_VERSION = 1
#: Engine settings of every training sample: normal incidence (paper §3.1), one thread per task
#: (parallelism comes from running tasks side by side).
ENGINE_SETTINGS = {"incidence_deg": 0.0, "threads": 1}


def wavelength_grid(spec: str | npt.ArrayLike) -> np.ndarray:
    """Wavelengths in nm from ``"start:stop:step"`` (stop included) or ``"w1,w2,..."``.

    Examples
    --------
    >>> wavelength_grid("400:700:20").tolist()[:3], len(wavelength_grid("400:700:20"))
    ([400.0, 420.0, 440.0], 16)
    """
    if not isinstance(spec, str):
        grid = np.asarray(spec, dtype=float)
    else:
        grid = parse_range("wavelengths", spec)  # the bounded parser of every command
        if ":" in spec:
            # The values np.arange gives, as training sets have always recorded them (start + i·step
            # differs in the last bits for fractional steps, and a store's grid must match exactly);
            # the count is the parser's, so the grid never passes stop (400:411:3 ended at 412).
            start, stop, step = (float(x) for x in spec.split(":"))
            grid = np.arange(start, stop + step / 2, step)[: grid.size]
    if grid.size > MAX_WAVELENGTHS:
        raise ParameterError("wavelengths", spec, f"at most {MAX_WAVELENGTHS:,} wavelengths")
    if grid.ndim != 1 or grid.size == 0 or not np.all(np.isfinite(grid)) or np.any(np.diff(grid) <= 0) or grid[0] <= 0:
        raise ParameterError("wavelengths", spec, "increasing positive wavelengths in nm")
    return grid


def engine_simulate(
    params: Mapping | Traceable, wavelengths_nm: np.ndarray, *, rays: int, seed: int, memory: str | None = None
) -> ReflectanceResult:
    """Run sandlight's Monte Carlo engine on one sample at normal incidence.

    Parameters
    ----------
    params : dict or Traceable
        SandSample keyword arguments (a job's payload), or any Traceable medium
        (``sandlight.physics.medium.Traceable``), which carries its own memory (then
        ``memory`` must be 'none').
    wavelengths_nm : ndarray
    rays : int
        Rays per wavelength.
    seed : int
    memory : {'none', 'channel', 'cut', 'packed'}, optional
        Path memory of the engine (``sandlight.reflectance``; None: its default), for a sample.

    Returns
    -------
    ReflectanceResult
        with ``.values`` and ``.stderr`` (n_wl,)
    """
    from sandlight.engine import reflectance
    from sandlight.physics.medium import Traceable
    from sandlight.sample import SandSample

    sample = params if isinstance(params, Traceable) else SandSample(**params)
    return reflectance(sample, wavelengths_nm, rays=rays, seed=seed, memory=memory, **ENGINE_SETTINGS)


def reflectance_task(
    payload: dict,
    seed: int,
    *,
    wavelengths_nm: npt.ArrayLike,
    rays: int,
    simulate: Callable | None = None,
    memory: str | None = None,
) -> dict[str, np.ndarray]:
    """Job task: reflectance and standard error of one sample (runs on a worker)."""
    wavelengths = np.asarray(wavelengths_nm, dtype=float)
    if simulate is None:
        result = engine_simulate(payload, wavelengths, rays=rays, seed=seed, memory=memory)
    else:
        result = simulate(payload, wavelengths, rays=rays, seed=seed)
    values, stderr = (result.values, result.stderr) if hasattr(result, "values") else result
    values, stderr = np.asarray(values, dtype=float), np.asarray(stderr, dtype=float)
    if values.shape != wavelengths.shape or stderr.shape != wavelengths.shape:
        raise ValueError(f"simulate returned shapes {values.shape}, {stderr.shape} for {wavelengths.size} wavelengths")
    return {"reflectance": values, "stderr": stderr}


def _simulator_name(simulate: Callable | None) -> str:
    simulate = engine_simulate if simulate is None else simulate
    inner = simulate.func if isinstance(simulate, functools.partial) else simulate
    return f"{getattr(inner, '__module__', '?')}.{getattr(inner, '__qualname__', repr(inner))}"


def _check_domain_against_sample(domain: Domain) -> None:
    """Check the domain against SandSample's parameter table, when that module is present."""
    try:
        from sandlight.sample import PARAMETERS
    except ImportError:  # a checkout without the sample module: nothing to check against
        return
    domain.check_covers(PARAMETERS)


def check_engine_memory(memory: str | None, custom: Callable | None = None, custom_name: str = "simulate") -> str:
    """``memory`` checked as the path memory of sandlight's engine, None its default
    (``sandlight.physics.media.DEFAULT_MEMORY``); only 'none' (or None) goes with a ``custom``
    function (named ``custom_name``) standing in for the engine."""
    if custom is not None:
        if memory not in (None, "none"):
            raise ParameterError(
                "memory",
                memory,
                f"'none' with a {custom_name} function (path "
                f"memory is a setting of sandlight's engine: give it to your "
                f"{custom_name})",
            )
        return "none"
    from sandlight.physics.media import DEFAULT_MEMORY, MEMORIES

    return check_choice("memory", DEFAULT_MEMORY if memory is None else memory, MEMORIES)


def engine_memory_record(memory: str, custom: Callable | None = None) -> dict:
    """The engine's path memory and film model as recorded in datasets, job settings and models.

    Each by omission for the model before it existed (memory 'none', films 'uniform'), as in
    everything written before, so that those stores still resume and read as what they are.
    The film model is the engine's default (samples are traced as ``compose`` makes them); with a
    ``custom`` function standing in for the engine nothing but the memory is known.
    """
    from sandlight.physics.composition import DEFAULT_FILMS

    record = {"memory": memory} if memory != "none" else {}
    if custom is None and DEFAULT_FILMS != "uniform":
        record["films"] = DEFAULT_FILMS
    return record


def training_job(
    path: str | os.PathLike,
    n_samples: int,
    wavelengths_nm: str | npt.ArrayLike,
    rays: int,
    seed: int,
    *,
    domain: Domain | None = None,
    design: str = "lhs",
    simulate: Callable | None = None,
    memory: str | None = None,
) -> Job:
    """The job behind :func:`generate_training_set` (same arguments), without running it."""
    from sandlight import __version__

    domain = Domain.default() if domain is None else domain
    wavelengths = wavelength_grid(wavelengths_nm)
    if simulate is None:
        check_wavelengths("wavelengths", wavelengths)  # inside the tasks it failed every task after every retry
    check_whole_number("n_samples", n_samples, 1)
    check_whole_number("rays", rays, 1)
    check_seed("seed", seed)
    memory = check_engine_memory(memory, simulate)
    if simulate is None:
        _check_domain_against_sample(domain)
    payloads = domain.draw(n_samples, seed, design)
    engine = {**ENGINE_SETTINGS, "rays": int(rays), **engine_memory_record(memory, simulate)}
    settings = {
        "kind": TRAINING_SET_FORMAT,
        "wavelengths_nm": wavelengths,
        "rays": int(rays),
        "design": design,
        "domain": domain.to_dict(),
        "engine": engine,
        "simulator": _simulator_name(simulate),
        "sandlight_version": __version__,
    }
    fn = functools.partial(
        reflectance_task, wavelengths_nm=tuple(wavelengths.tolist()), rays=int(rays), simulate=simulate, memory=memory
    )
    units = {d.name: {"units": d.unit} for d in domain.dimensions}
    units.update(
        {"sand": {"units": "1"}, "depth_mm": {"units": "mm"}, FORM_PARAMETER: {"description": "form of the iron oxide"}}
    )
    var_attrs = {
        **units,
        "reflectance": {"units": "1", "long_name": "directional-hemispherical reflectance at normal incidence"},
        "stderr": {"units": "1", "long_name": "Monte Carlo standard error of reflectance"},
        "wavelength": {"units": "nm"},
    }
    attrs = {
        "format": TRAINING_SET_FORMAT,
        "format_version": TRAINING_SET_FORMAT_VERSION,
        "n_samples": int(n_samples),
        "seed": int(seed),
        "rays": int(rays),
        "design": design,
        "domain": domain.to_dict(),
        "engine": engine,
        "simulator": settings["simulator"],
        "sandlight_version": __version__,
    }
    return Job(
        path,
        fn,
        payloads,
        seed=seed,
        settings=settings,
        dims={"reflectance": ("wavelength",), "stderr": ("wavelength",)},
        coords={"wavelength": wavelengths},
        var_attrs=var_attrs,
        attrs=attrs,
        task_dim="sample",
    )


def generate_training_set(
    path: str | os.PathLike,
    n_samples: int,
    wavelengths_nm: str | npt.ArrayLike,
    rays: int,
    seed: int,
    executor: Executor | str | None = None,
    *,
    domain: Domain | None = None,
    design: str = "lhs",
    simulate: Callable | None = None,
    progress: bool = True,
    max_tasks: int | None = None,
    max_retries: int = 2,
    memory: str | None = None,
) -> JobStatus:
    """Draw samples, run the engine on each, store the training set (resumable).

    Parameters
    ----------
    path : str or Path
        Job store directory; the dataset is ``path/dataset.nc`` once complete. Running the same
        call again resumes an interrupted run; other settings are refused.
    n_samples : int
        Number of samples (paper: 3000).
    wavelengths_nm : str or array_like
        Wavelengths in nm, e.g. ``"400:700:20"`` (paper: 16 wavelengths, 400–700 nm).
    rays : int
        Rays per sample and wavelength (Monte Carlo noise ≈ √(r(1 − r)/rays)).
    seed : int
        Master seed: the draws and every sample's engine seed derive from it.
    executor : Executor or {"local", "in-process", "dask"}, optional
        Where samples run (default: local process pool, one worker per CPU).
    domain : Domain, optional
        Default ``Domain.default()``.
    design : {"lhs", "random"}
    simulate : callable, optional
        ``simulate(params: dict, wavelengths_nm, *, rays, seed)`` returning ``.values`` and
        ``.stderr`` (or a pair); default: sandlight's engine. Must be importable by workers.
    progress : bool
        Progress bar.
    max_tasks : int, optional
        Stop after this many samples (resumable).
    max_retries : int
        Retries of a failed sample.
    memory : {'none', 'channel', 'cut', 'packed'}, optional
        Path memory of sandlight's engine (docs/geometry.md); None: the engine's default
        (``sandlight.physics.media.DEFAULT_MEMORY``, 'packed', the closest to a packing and the
        memory of the shipped models); 'none' the classic model, about 1.4x as fast. Recorded in
        the dataset's engine settings (and so in the model); resuming with another value is
        refused. Only with the default ``simulate``.

    Returns
    -------
    JobStatus
        ``.dataset_path`` is the dataset once every sample is done.
    """
    job = training_job(
        path, n_samples, wavelengths_nm, rays, seed, domain=domain, design=design, simulate=simulate, memory=memory
    )
    return job.run(
        resolve_executor(executor),
        max_tasks=max_tasks,
        max_retries=max_retries,
        progress=progress,
        description=f"{Path(path).name}",
        unit="sample",
    )


def file_sha256(path: str | os.PathLike) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _samples_inside(ds: xr.Dataset, domain: Domain):
    """The samples of a training-set dataset that lie inside ``domain``."""
    columns = {n: ds[n].values for n in (*domain.names, *domain.fixed)}
    keep = np.flatnonzero(domain.contains(columns, ds[FORM_PARAMETER].values.astype(str)))
    if keep.size == 0:
        raise ParameterError("fit_domain", domain.to_dict(), "a domain holding some of the dataset's samples")
    return ds.isel(sample=keep)


def fit_training_set(
    path: str | os.PathLike,
    holdout: str | os.PathLike | None = None,
    *,
    name: str = "spectral",
    description: str = "",
    fit_domain: Domain | None = None,
    enrichment: str | os.PathLike | None = None,
    **model_params: Any,
) -> tuple[SpectralModel, HoldoutReport | None]:
    """Fit a SpectralModel on a training-set dataset and score it on a hold-out dataset.

    Parameters
    ----------
    path : str or Path
        Training dataset (``.nc``) or its job store directory.
    holdout : str or Path, optional
        Hold-out dataset or job store; its scores are attached to the model.
    name, description : str
        The model's ``name_`` and ``description_``.
    fit_domain : Domain, optional
        Fit (and score) only the samples inside this domain, which becomes the model's domain:
        e.g. a range that leaves out a point where the engine is discontinuous. Default: the
        dataset's domain.
    enrichment : str or Path, optional
        A second training dataset (or job store) fitted together with the first: samples drawn
        from a sub-domain where the first has few (see :func:`train_spectral`). Its wavelengths,
        rays and engine must be the first's; it is recorded beside it in ``training_set_``.
    **model_params
        SpectralModel hyper-parameters.
    """
    import xarray as xr

    path = _dataset_file(path)
    with xr.open_dataset(path) as ds:
        ds = ds.load()
    reference = {"path": str(path), "sha256": file_sha256(path)}
    if enrichment is not None:
        enrichment = _dataset_file(enrichment)
        with xr.open_dataset(enrichment) as extra:
            extra = extra.load()
        ds = _with_enrichment(ds, extra, enrichment)
        reference["enrichment"] = {
            "path": str(enrichment),
            "sha256": file_sha256(enrichment),
            "n_samples": int(extra.sizes["sample"]),
            "domain": json.loads(extra.attrs["domain"]),
        }
    if fit_domain is not None:
        ds = _samples_inside(ds, fit_domain)
        reference["n_used"] = int(ds.sizes["sample"])
    model = SpectralModel(**model_params).fit(
        ds, domain=fit_domain, training_set=reference, name=name, description=description
    )
    report = None
    if holdout is not None:
        holdout = _dataset_file(holdout)
        scored = holdout
        if fit_domain is not None:
            with xr.open_dataset(holdout) as ho:
                scored = _samples_inside(ho.load(), fit_domain)
        report = evaluate(model, scored, attach=True)
        model.holdout_scores_["path"] = str(holdout)
        model.holdout_scores_["sha256"] = file_sha256(holdout)
    return model, report


def clean_corner(domain: Domain) -> Domain:
    """The clean-sand corner of ``domain`` (``CLEAN_SAND`` fixed; the iron-oxide forms continuous
    at zero iron oxide, the only ones asked there): where a model's enrichment samples go."""
    return domain.restrict(forms=IRON_FREE_FORMS, **CLEAN_SAND)


def _check_enrichment(enrichment: Any, domain: Domain) -> None:
    """Refuse an enrichment that is not (n ≥ 1, a Domain inside ``domain``) before generating."""
    if not (isinstance(enrichment, tuple) and len(enrichment) == 2 and isinstance(enrichment[1], Domain)):
        raise ParameterError("enrichment", enrichment, "a pair (number of samples, Domain)")
    n, sub = enrichment
    check_whole_number("enrichment samples", n, 1)
    values, codes = sub.draw_arrays(min(int(n), 256), seed=0, design="random")
    columns = sub.columns(values, codes)
    inside = domain.contains(columns, columns[FORM_PARAMETER])
    if not inside.all():
        raise ParameterError("enrichment", sub.to_dict(), "a sub-domain of the training domain")


def _with_enrichment(ds: xr.Dataset, extra: xr.Dataset, path: Path) -> xr.Dataset:
    """``ds`` followed by the samples of ``extra`` (same variables, wavelengths, rays and engine),
    keeping ``ds``'s attributes (its domain) with the total number of samples."""
    import xarray as xr

    for key in ("rays", "engine", "simulator"):
        if str(extra.attrs.get(key)) != str(ds.attrs.get(key)):
            raise ParameterError(
                "enrichment", str(path), f"a training set with the first's {key} ({ds.attrs.get(key)})"
            )
    if set(extra.data_vars) != set(ds.data_vars) or not np.array_equal(extra["wavelength"], ds["wavelength"]):
        raise ParameterError("enrichment", str(path), "a training set with the first's variables and wavelengths")
    extra = extra.assign_coords(sample=extra["sample"].values + ds.sizes["sample"])
    both = xr.concat([ds, extra], dim="sample", data_vars="all", combine_attrs="override")
    both.attrs["n_samples"] = int(both.sizes["sample"])
    return both


def _dataset_file(path: str | os.PathLike) -> Path:
    path = Path(path)
    if path.is_dir():
        path = path / "dataset.nc"
    if not path.is_file():
        raise ParameterError(
            "training set", str(path), "a complete training-set dataset (run the generation to completion first)"
        )
    return path


@dataclass
class TrainingRun:
    """What :func:`train_spectral` produced."""

    model: SpectralModel | None
    report: HoldoutReport | None
    model_path: Path | None
    training: JobStatus
    holdout: JobStatus | None
    generation_s: float
    fit_s: float

    @property
    def complete(self) -> bool:
        return self.model is not None


def train_spectral(
    out_dir: str | os.PathLike,
    n_samples: int,
    rays: int,
    wavelengths_nm: str | npt.ArrayLike = "400:700:20",
    seed: int = 0,
    *,
    n_holdout: int | None = None,
    executor: Executor | str | None = None,
    domain: Domain | None = None,
    fit_only: bool = False,
    simulate: Callable | None = None,
    progress: bool = True,
    max_tasks: int | None = None,
    model_params: dict | None = None,
    holdout_rays: int | None = None,
    name: str = "spectral",
    description: str = "",
    fit_domain: Domain | None = None,
    memory: str | None = None,
    enrichment: tuple[int, Domain] | None = None,
) -> TrainingRun:
    """Generate the training and hold-out sets, fit, evaluate and save a spectral model.

    Layout of ``out_dir``: ``training/`` and ``holdout/`` (job stores, each with its
    ``dataset.nc``), ``enrichment/`` when asked for, and ``spectral-model.npz``. Resumable: the
    same call again continues the jobs; with ``fit_only`` the existing complete datasets are only
    refitted.

    Parameters
    ----------
    n_holdout : int, optional
        Hold-out samples (random design, independent seed ``derive_seed(seed, "holdout")``);
        default max(20, n_samples // 10).
    holdout_rays : int, optional
        Rays per hold-out sample and wavelength (default ``rays``). More rays make the
        reference less noisy, so that the hold-out error measures the model, not the noise.
    name, description : str
        The model's ``name_`` and ``description_`` (kept in the model file).
    fit_domain : Domain, optional
        Fit and score only the samples inside this sub-domain (see :func:`fit_training_set`).
    max_tasks : int, optional
        Stop each job after this many samples (for testing resumption).
    model_params : dict, optional
        SpectralModel hyper-parameters.
    enrichment : (int, Domain), optional
        Extra training samples (Latin hypercube, seed ``derive_seed(seed, "enrichment")``, the
        training set's rays) from a sub-domain of ``domain`` that its random draws hardly reach,
        e.g. a corner where several parameters are exactly 0; fitted together with the training
        set (:func:`fit_training_set`). The hold-out set stays drawn from ``domain`` alone.

    Other parameters are those of :func:`generate_training_set`.
    """
    out = Path(out_dir)
    SpectralModel(**(model_params or {})).validate_params()  # before hours of generation, not after
    if enrichment is not None:
        _check_enrichment(enrichment, Domain.default() if domain is None else domain)
    if n_holdout is not None and not (isinstance(n_holdout, (int, np.integer)) and n_holdout >= 0):
        # -1 silently meant no hold-out set
        raise ParameterError("n_holdout", n_holdout, "an integer >= 0 (0: no hold-out set), or None for the default")
    n_holdout = max(20, int(n_samples) // 10) if n_holdout is None else int(n_holdout)
    jobs = [
        training_job(
            out / "training",
            n_samples,
            wavelengths_nm,
            rays,
            seed,
            domain=domain,
            design="lhs",
            simulate=simulate,
            memory=memory,
        )
    ]
    if enrichment is not None:
        jobs.append(
            training_job(
                out / "enrichment",
                enrichment[0],
                wavelengths_nm,
                rays,
                derive_seed(seed, "enrichment"),
                domain=enrichment[1],
                design="lhs",
                simulate=simulate,
                memory=memory,
            )
        )
    if n_holdout > 0:
        jobs.append(
            training_job(
                out / "holdout",
                n_holdout,
                wavelengths_nm,
                rays if holdout_rays is None else holdout_rays,
                derive_seed(seed, "holdout"),
                domain=domain,
                design="random",
                simulate=simulate,
                memory=memory,
            )
        )
    start = time.perf_counter()
    executor = resolve_executor(executor) if not fit_only else None
    statuses = [
        job.status()
        if fit_only
        else job.run(executor, max_tasks=max_tasks, progress=progress, description=job.path.name, unit="sample")
        for job in jobs
    ]
    generation_s = time.perf_counter() - start
    enrichment_status = statuses[1] if enrichment is not None else None
    holdout_status = statuses[-1] if n_holdout > 0 else None
    if not all(s.complete for s in statuses):
        if fit_only:
            incomplete = [f"{s.store} ({s.n_done}/{s.n_total})" for s in statuses if not s.complete]
            raise ParameterError(
                "fit_only",
                True,
                f"complete datasets; incomplete: {', '.join(incomplete)} (run without --fit-only to finish)",
            )
        return TrainingRun(None, None, None, statuses[0], holdout_status, generation_s, 0.0)
    start = time.perf_counter()
    model, report = fit_training_set(
        statuses[0].dataset_path,
        holdout_status.dataset_path if holdout_status else None,
        name=name,
        description=description,
        fit_domain=fit_domain,
        enrichment=enrichment_status.dataset_path if enrichment_status else None,
        **(model_params or {}),
    )
    fit_s = time.perf_counter() - start
    model_path = model.save(out / "spectral-model.npz")
    text = json.dumps(report.to_dict() if report else None, indent=1) + "\n"
    write_atomically(out / "holdout-report.json", lambda tmp: tmp.write_text(text, encoding="utf-8"))
    return TrainingRun(model, report, model_path, statuses[0], holdout_status, generation_s, fit_s)
