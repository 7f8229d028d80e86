"""Measuring the mesh nodes, fitting the spatial predictor and checking it on held-out points.

:func:`node_job` measures the BRDF of every node of a `Mesh` with the virtual goniophotometer
(`sandlight.gonio.measure.brdf`, uniform incidence, paper §3.2.1) as a restartable, distributable
job (:mod:`sandlight.jobs`): local process pool by default, Dask for scale-out. Each finished
node is stored at once; with a local executor each node's counts are also checkpointed about
every minute while it runs, so an interruption loses at most a minute of work per running
node. The consolidated dataset ``STORE/dataset.nc`` holds:

=========================  ==========================  =============================================
variable                   dims                        meaning
=========================  ==========================  =============================================
<parameter>                (node,)                     every SandSample parameter of the node
counts                     (node, incoming, outgoing)  raw goniophotometer counts n[i, j]
absorbed, launched, lost   (node, incoming)            raw per-incoming-patch counters
seed                       (node,)                     the node's engine seed
=========================  ==========================  =============================================

Global attributes: format ``sandlight-spatial-nodes``, wavelength_nm, rays, stacks, slices, mesh
(JSON), measure (the function used), ``memory`` when the engine ran with path memory
(docs/geometry.md; absent, the classic model) and the job settings.

:func:`train_spatial` runs the node job and a held-out job, fits a `SpatialModel`, scores it
(:func:`evaluate`) and saves both; ``sandlight train-spatial`` and
``scripts/data/train_default_spatial.py`` call it.
"""

from __future__ import annotations

import functools
import json
import os
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from sandlight.checks import check_wavelengths, check_whole_number
from sandlight.errors import ParameterError
from sandlight.gonio.brdf import MeasuredBRDF
from sandlight.gonio.hemisphere import CollectorHemisphere
from sandlight.gonio.reduction import REDUCTION_METHODS
from sandlight.gonio.symmetry import EquivalenceClasses
from sandlight.io import write_atomically
from sandlight.jobs import Job, JobStatus, derive_seed
from sandlight.jobs.executors import Executor, resolve_executor
from sandlight.spatial.mesh import Mesh
from sandlight.spatial.model import SpatialModel

if TYPE_CHECKING:
    import xarray as xr

    from sandlight.jobs.executors import Executor
    from sandlight.physics.medium import Traceable

#: ``measure(params, wavelength_nm, *, rays, seed, stacks, slices, threads, checkpoint)``
#: returning goniophotometer counts, standing in for the engine (tests).
Measure = Callable[..., Any]

__all__ = [
    "node_job",
    "measure_nodes",
    "node_brdfs",
    "evaluate",
    "cross_validate",
    "HoldoutReport",
    "train_spatial",
    "TrainingRun",
    "NODE_SET_FORMAT",
]

NODE_SET_FORMAT = "sandlight-spatial-nodes"
NODE_SET_FORMAT_VERSION = 1
#: Relative standard error below which a measured value enters the held-out score (issue 6).
HOLDOUT_MAX_RELATIVE_STDERR = 0.02


def engine_measure(
    params: Mapping | Traceable,
    wavelength_nm: float,
    *,
    rays: int,
    seed: int,
    stacks: int,
    slices: int,
    threads: int,
    checkpoint: str | os.PathLike[str] | None = None,
    memory: str | None = None,
) -> dict:
    """Goniophotometer counts of one sample with sandlight's engine (the default ``measure``).

    ``params`` is a node's SandSample parameters (a job's payload) or any Traceable medium
    (``sandlight.physics.medium.Traceable``; then ``memory`` must be 'none', the medium carries
    its own). Returns ``{"counts", "absorbed", "launched", "lost"}`` as integer arrays.
    """
    from sandlight.gonio.measure import brdf
    from sandlight.physics.medium import Traceable
    from sandlight.sample import SandSample

    b = brdf(
        params if isinstance(params, Traceable) else SandSample.from_dict(params),
        wavelength_nm,
        rays=rays,
        stacks=stacks,
        slices=slices,
        seed=seed,
        threads=threads,
        checkpoint=checkpoint,
        progress=False,
        memory=memory,
    )
    return {"counts": b.counts, "absorbed": b.absorbed, "launched": b.launched, "lost": b.lost}


def _counts_dtype(rays: int):
    # A cell cannot count more than `rays`; uint32 halves the store for up to 4·10⁹ trials.
    return np.uint32 if rays < 2**32 else np.uint64


def node_task(
    payload: dict,
    seed: int,
    *,
    wavelength_nm: float,
    rays: int,
    stacks: int,
    slices: int,
    threads: int,
    checkpoint_dir: str | None = None,
    measure: Measure | None = None,
    memory: str | None = None,
) -> dict:
    """Job task: goniophotometer counts of one node (runs on a worker)."""
    measure = functools.partial(engine_measure, memory=memory) if measure is None else measure
    params = {k: v for k, v in payload.items() if k != "node_index"}
    checkpoint = None
    if checkpoint_dir is not None:  # created here: the job store must exist (and be empty) before the job runs
        Path(checkpoint_dir).mkdir(parents=True, exist_ok=True)
        checkpoint = Path(checkpoint_dir) / f"node-{int(payload['node_index']):05d}.npz"
    out = measure(
        params,
        wavelength_nm,
        rays=rays,
        seed=seed,
        stacks=stacks,
        slices=slices,
        threads=threads,
        checkpoint=checkpoint,
    )
    r = CollectorHemisphere(stacks, slices).n_patches
    counts = np.asarray(out["counts"])
    if counts.shape != (r, r):
        raise ValueError(f"measure returned counts of shape {counts.shape}, expected ({r}, {r})")
    return {
        "counts": counts.astype(_counts_dtype(rays)),
        **{k: np.asarray(out[k]).astype(np.int64) for k in ("absorbed", "launched", "lost")},
    }


def _measure_name(measure: Measure | None) -> str:
    measure = engine_measure if measure is None else measure
    inner = measure.func if isinstance(measure, functools.partial) else measure
    return f"{getattr(inner, '__module__', '?')}.{getattr(inner, '__qualname__', repr(inner))}"


def node_job(
    path: str | os.PathLike[str],
    mesh_or_samples: Mesh | Sequence[Mapping],
    wavelength_nm: float,
    rays: int,
    seed: int,
    *,
    stacks: int = 31,
    slices: int = 30,
    threads: int = 1,
    checkpoint: bool = True,
    measure: Measure | None = None,
    kind: str = "nodes",
    memory: str | None = None,
) -> Job:
    """The job measuring the BRDF of every node of a mesh (or of a list of samples), not yet run.

    Parameters
    ----------
    path : str or Path
        Job store directory.
    mesh_or_samples : Mesh or sequence of dict
        The nodes (``Mesh.samples`` order) or explicit sample parameter dicts (held-out points).
    wavelength_nm : float
        Wavelength of the measurement, nm.
    rays : int
        Goniophotometer trials per node.
    seed : int
        Master seed; node i uses ``sandlight.jobs.task_seed(seed, i)``.
    stacks, slices : int
        Collector hemisphere (paper: 31 × 30).
    threads : int
        Engine threads per node (1 with a process pool: parallelism comes from nodes side by side).
    checkpoint : bool
        Checkpoint each running node's counts in ``path/checkpoints`` (needs a file system
        shared with the workers: use False for a remote Dask cluster).
    measure : callable, optional
        ``measure(params, wavelength_nm, *, rays, seed, stacks, slices, threads, checkpoint)``
        returning counts (default: the engine). Must be importable by workers.
    kind : str
        Label recorded in the settings ('nodes' or 'holdout').
    memory : {'none', 'channel', 'cut', 'packed'}, optional
        Path memory of sandlight's engine (docs/geometry.md; None: the engine's default,
        ``sandlight.physics.media.DEFAULT_MEMORY``). Recorded in the settings and attributes;
        resuming with another value is refused. Only with the default ``measure``.
    """
    from sandlight import __version__
    from sandlight.predictor.training import check_engine_memory, engine_memory_record

    CollectorHemisphere(stacks, slices)  # validates the geometry
    rays = check_whole_number("rays", rays, 1)
    threads = check_whole_number("threads", threads, 1)
    memory = check_engine_memory(memory, measure, "measure")
    with_memory = engine_memory_record(memory, measure)
    try:
        wl = float(wavelength_nm)
    except (TypeError, ValueError):
        raise ParameterError("wavelength_nm", wavelength_nm, "a wavelength in nm") from None
    if measure is None:
        check_wavelengths("wavelength_nm", wl)
    if isinstance(mesh_or_samples, Mesh):
        samples = [mesh_or_samples.sample_dict(x) for x in mesh_or_samples.nodes]
        mesh_dict = mesh_or_samples.to_dict()
    else:
        samples = [dict(s) for s in mesh_or_samples]
        mesh_dict = None
        if not samples:
            raise ParameterError("samples", samples, "at least one sample")
    payloads = [{"node_index": i, **s} for i, s in enumerate(samples)]
    path = Path(path)
    settings = {
        "kind": f"{NODE_SET_FORMAT}:{kind}",
        "wavelength_nm": wl,
        "rays": rays,
        "stacks": int(stacks),
        "slices": int(slices),
        "measure": _measure_name(measure),
        "sandlight_version": __version__,
        **with_memory,
    }
    fn = functools.partial(
        node_task,
        wavelength_nm=wl,
        rays=rays,
        stacks=int(stacks),
        slices=int(slices),
        threads=threads,
        checkpoint_dir=str(path / "checkpoints") if checkpoint else None,
        measure=measure,
        memory=memory,
    )
    attrs = {
        "format": NODE_SET_FORMAT,
        "format_version": NODE_SET_FORMAT_VERSION,
        "wavelength_nm": wl,
        "rays": rays,
        "stacks": int(stacks),
        "slices": int(slices),
        "seed": int(seed),
        "measure": settings["measure"],
        "sandlight_version": __version__,
        "mesh": mesh_dict,
        **with_memory,
    }
    var_attrs = {
        "counts": {"units": "1", "long_name": "trials with incidence in patch i escaping into patch j"},
        "absorbed": {"units": "1"},
        "launched": {"units": "1"},
        "lost": {"units": "1"},
        "wavelength_nm": {"units": "nm"},
    }
    return Job(
        path,
        fn,
        payloads,
        seed=seed,
        settings=settings,
        dims={
            "counts": ("incoming", "outgoing"),
            "absorbed": ("incoming",),
            "launched": ("incoming",),
            "lost": ("incoming",),
        },
        var_attrs=var_attrs,
        attrs=attrs,
        task_dim="node",
    )


def measure_nodes(
    path: str | os.PathLike[str],
    mesh: Mesh,
    wavelength_nm: float,
    rays: int,
    seed: int,
    executor: Executor | str | None = None,
    *,
    progress: bool = True,
    max_tasks: int | None = None,
    **job_options,
) -> JobStatus:
    """Measure every node of ``mesh`` (resumable: the same call continues an interrupted run).

    Parameters are those of `node_job`; ``executor`` is an `Executor` or 'local', 'in-process',
    'dask' (default: a local process pool). Returns the job status; ``.dataset_path`` is the
    dataset once complete.
    """
    job = node_job(path, mesh, wavelength_nm, rays, seed, **job_options)
    return job.run(
        resolve_executor(executor), max_tasks=max_tasks, progress=progress, description=Path(path).name, unit="node"
    )


def node_brdfs(dataset: str | os.PathLike[str] | xr.Dataset, method: str = "average") -> list[MeasuredBRDF]:
    """The `MeasuredBRDF` of every node of a node dataset (path, store directory or Dataset).

    Parameters
    ----------
    method : {'average', 'pooled'}
        Class estimator of the reduction (`sandlight.gonio.reduction.reduce_counts`).
    """
    import xarray as xr

    if method not in REDUCTION_METHODS:
        raise ParameterError("method", method, f"one of {REDUCTION_METHODS}")
    if not hasattr(dataset, "data_vars"):
        path = Path(dataset)
        path = path / "dataset.nc" if path.is_dir() else path
        if not path.is_file():
            raise ParameterError("dataset", str(path), "a complete node dataset (run the measurement to completion)")
        with xr.open_dataset(path) as ds:
            dataset = ds.load()
    ds = dataset
    if ds.attrs.get("format") != NODE_SET_FORMAT:
        raise ParameterError("dataset", ds.attrs.get("format"), f"a {NODE_SET_FORMAT!r} dataset")
    params = [k for k in ds.data_vars if ds[k].dims == ("node",) and k not in ("seed", "node_index")]
    out = []
    for i in range(ds.sizes["node"]):
        sample = {}
        for k in params:
            v = ds[k].values[i]
            sample[k] = str(v) if ds[k].dtype.kind in "US" else float(v)
        out.append(
            MeasuredBRDF.from_counts(
                ds["counts"].values[i].astype(np.int64),
                ds["absorbed"].values[i],
                ds["launched"].values[i],
                ds["lost"].values[i],
                stacks=int(ds.attrs["stacks"]),
                slices=int(ds.attrs["slices"]),
                sample=sample,
                wavelength_nm=float(ds.attrs["wavelength_nm"]),
                rays=int(ds.attrs["rays"]),
                seed=int(ds["seed"].values[i]),
                method=method,
            )
        )
    return out


# ---- held-out check -------------------------------------------------------------------------------
@dataclass(frozen=True)
class HoldoutReport:
    """Predicted against directly measured normalised BRDF at a point not used in fitting.

    All relative errors are (predicted − measured)/measured of the unique values, restricted to
    the values whose own relative standard error is below ``max_relative_stderr``; "pairs"
    weights each value by the number of (incoming, outgoing) patch pairs it stands for, i.e. it
    is the RMS over the full r × r array.

    Attributes
    ----------
    point : dict
        Mesh coordinates of the held-out sample.
    rays : int
        Trials of the held-out measurement.
    max_relative_stderr : float
        Selection threshold (0.02).
    n_values, n_pairs : int
        Unique values, and patch pairs, passing the selection.
    fraction_pairs : float
        Share of all patch pairs selected.
    relative_rms : float
        RMS relative error over the selected patch pairs (the issue's figure).
    relative_rms_values : float
        The same, each unique value counted once.
    noise_rms : float
        RMS of the selected values' own relative standard errors (the part of relative_rms
        that is noise of the measurement).
    model_error : float
        √max(relative_rms² − noise_rms², 0): estimated error of the prediction itself.
    max_abs_relative : float
        Largest |relative error| over the selection.
    normalised_rms : float
        RMS over all values of (predicted − measured)/stderr: ≈ 1 if the prediction is within
        the measurement's noise everywhere.
    """

    point: dict
    rays: int
    max_relative_stderr: float
    n_values: int
    n_pairs: int
    fraction_pairs: float
    relative_rms: float
    relative_rms_values: float
    noise_rms: float
    model_error: float
    max_abs_relative: float
    normalised_rms: float

    def to_dict(self) -> dict:
        return dict(self.__dict__)

    def table(self) -> str:
        point = ", ".join(f"{k} = {v:g}" for k, v in self.point.items())
        return (
            f"held-out point {point} ({self.rays:,} trials): over the {self.n_pairs:,} patch pairs "
            f"({self.fraction_pairs:.1%}; {self.n_values} unique values) whose relative standard error < "
            f"{self.max_relative_stderr:.0%}: relative RMS {self.relative_rms:.2%} (per unique value "
            f"{self.relative_rms_values:.2%}), measurement noise {self.noise_rms:.2%}, estimated model error "
            f"{self.model_error:.2%}, max |error| {self.max_abs_relative:.2%}; all values: RMS of "
            f"error/stderr {self.normalised_rms:.2f}"
        )


def evaluate(
    model: SpatialModel,
    measured: MeasuredBRDF,
    *,
    max_relative_stderr: float = HOLDOUT_MAX_RELATIVE_STDERR,
    attach: bool = False,
) -> HoldoutReport:
    """Compare the model's prediction with a direct goniophotometer measurement.

    Parameters
    ----------
    model : SpatialModel
    measured : MeasuredBRDF
        Measurement of a sample inside the mesh (its ``sample`` dict gives the coordinates), on
        the model's hemisphere.
    max_relative_stderr : float
        Only values measured to better than this relative standard error are scored.
    attach : bool
        Append the report to ``model.holdout_scores_`` (saved with the model).
    """
    if (measured.stacks, measured.slices) != (model.stacks_, model.slices_):
        raise ParameterError(
            "measured",
            (measured.stacks, measured.slices),
            f"a measurement on the model's hemisphere {(model.stacks_, model.slices_)}",
        )
    if not 0 < max_relative_stderr < 1:
        raise ParameterError("max_relative_stderr", max_relative_stderr, "a fraction in (0, 1)")
    predicted = model.predict(measured.sample, fixed="warn")[0]
    value, stderr = measured.unique_values, measured.unique_stderr
    sizes = EquivalenceClasses(CollectorHemisphere(model.stacks_, model.slices_)).sizes
    with np.errstate(invalid="ignore", divide="ignore"):
        rel_se = stderr / value
        keep = np.isfinite(rel_se) & (value > 0) & (rel_se < max_relative_stderr)
        rel = (predicted - value) / value
        finite = np.isfinite(stderr) & (stderr > 0)
        normalised = (predicted - value)[finite] / stderr[finite]
    if not keep.any():
        raise ParameterError(
            "measured",
            f"{measured.rays:,} trials",
            f"a held-out measurement with some values to better than {max_relative_stderr:.0%} "
            f"relative standard error (measure with more trials)",
        )
    w = sizes[keep].astype(float)
    rms = float(np.sqrt(np.sum(w * rel[keep] ** 2) / w.sum()))
    noise = float(np.sqrt(np.sum(w * rel_se[keep] ** 2) / w.sum()))
    point = dict(zip(model.mesh_.parameters, model.mesh_.coordinates(measured.sample)[0].tolist()))
    report = HoldoutReport(
        point=point,
        rays=int(measured.rays),
        max_relative_stderr=float(max_relative_stderr),
        n_values=int(keep.sum()),
        n_pairs=int(w.sum()),
        fraction_pairs=float(w.sum() / sizes.sum()),
        relative_rms=rms,
        relative_rms_values=float(np.sqrt(np.mean(rel[keep] ** 2))),
        noise_rms=noise,
        model_error=float(np.sqrt(max(rms**2 - noise**2, 0.0))),
        max_abs_relative=float(np.abs(rel[keep]).max()),
        normalised_rms=float(np.sqrt(np.mean(normalised**2))),
    )
    if attach:
        model.holdout_scores_ = list(model.holdout_scores_ or []) + [report.to_dict()]
    return report


def cross_validate(
    brdfs: Sequence[MeasuredBRDF],
    mesh: Mesh,
    model_params: Mapping | None = None,
    *,
    max_relative_stderr: float = HOLDOUT_MAX_RELATIVE_STDERR,
) -> list:
    """Leave-one-out check: each node inside the others' mesh is predicted by a model fitted
    without it and scored against its own measurement (`evaluate`).

    Nodes on the mesh's hull (whose removal would leave them outside), and nodes with no value
    measured to better than ``max_relative_stderr`` (nothing to score), are skipped. The gap
    around a removed node is twice the mesh spacing, so this is a pessimistic estimate of the
    error between nodes.

    Returns
    -------
    list of (node index, HoldoutReport)
    """
    out = []
    n = mesh.n_nodes
    for k in range(n):
        others = [i for i in range(n) if i != k]
        try:
            sub = Mesh(mesh.parameters, mesh.nodes[others], mesh.base)
            sub.locate(mesh.nodes[k : k + 1])
        except ParameterError:  # degenerate without node k, or node k on the hull
            continue
        model = SpatialModel(**dict(model_params or {})).fit([brdfs[i] for i in others], sub)
        try:
            out.append((k, evaluate(model, brdfs[k], max_relative_stderr=max_relative_stderr)))
        except ParameterError:  # node k has no value measured well enough to score
            continue
    return out


# ---- the whole pipeline ---------------------------------------------------------------------------
@dataclass
class TrainingRun:
    """What :func:`train_spatial` produced (model and reports are None until the jobs complete)."""

    model: SpatialModel | None
    reports: list
    model_path: Path | None
    nodes: JobStatus
    holdout: JobStatus | None
    measurement_s: float
    fit_s: float

    @property
    def complete(self) -> bool:
        return self.model is not None


def train_spatial(
    out_dir: str | os.PathLike[str],
    mesh: Mesh,
    rays: int,
    wavelength_nm: float = 550.0,
    seed: int = 0,
    *,
    holdout: Sequence | None = None,
    holdout_rays: int | None = None,
    stacks: int = 31,
    slices: int = 30,
    method: str = "average",
    executor: Executor | str | None = None,
    threads: int = 1,
    checkpoint: bool = True,
    fit_only: bool = False,
    measure: Measure | None = None,
    progress: bool = True,
    max_tasks: int | None = None,
    model_params: Mapping | None = None,
    memory: str | None = None,
) -> TrainingRun:
    """Measure the nodes and held-out points, fit, score and save a spatial model (resumable).

    Layout of ``out_dir``: ``nodes/`` and ``holdout/`` (job stores with their ``dataset.nc``),
    ``spatial-model.npz`` and ``holdout-report.json``.

    Parameters
    ----------
    mesh : Mesh
    rays : int
        Trials per node.
    holdout : sequence, optional
        Held-out points: mesh coordinates (d,) or samples; each is measured separately (seed
        ``derive_seed(seed, "holdout")``) and compared with the prediction.
    holdout_rays : int, optional
        Trials per held-out point (default ``rays``).
    method : {'average', 'pooled'}
        Reduction of the counts (the paper: average).
    fit_only : bool
        Only refit from complete datasets.
    model_params : mapping, optional
        `SpatialModel` hyper-parameters.

    Other parameters are those of `node_job` and `measure_nodes`.
    """
    from sandlight.sample import SandSample

    if method not in REDUCTION_METHODS:
        raise ParameterError("method", method, f"one of {REDUCTION_METHODS}")
    from sandlight.predictor.training import check_engine_memory, engine_memory_record, file_sha256

    SpatialModel(**dict(model_params or {})).validate_params()  # before the measurements, not after
    memory = check_engine_memory(memory, measure, "measure")
    out = Path(out_dir)
    options = {
        "stacks": stacks,
        "slices": slices,
        "threads": threads,
        "checkpoint": checkpoint,
        "measure": measure,
        "memory": memory,
    }
    jobs = [node_job(out / "nodes", mesh, wavelength_nm, rays, seed, kind="nodes", **options)]
    if holdout:
        points = []
        for h in holdout:
            if isinstance(h, (SandSample, Mapping)):
                points.append(h.to_dict() if isinstance(h, SandSample) else SandSample.from_dict(h).to_dict())
            else:
                points.append(mesh.sample_dict(mesh.coordinates(h)[0]))
        mesh.checked_coordinates(points)  # refuse held-out points outside the mesh before measuring
        jobs.append(
            node_job(
                out / "holdout",
                points,
                wavelength_nm,
                holdout_rays or rays,
                derive_seed(seed, "holdout"),
                kind="holdout",
                **options,
            )
        )
    start = time.perf_counter()
    if fit_only:
        statuses = [job.status() for job in jobs]
    else:
        ex = resolve_executor(executor)
        statuses = [
            job.run(ex, max_tasks=max_tasks, progress=progress, description=job.path.name, unit="node") for job in jobs
        ]
    measurement_s = time.perf_counter() - start
    holdout_status = statuses[1] if len(statuses) > 1 else None
    if not all(s.complete for s in statuses):
        if fit_only:
            incomplete = ", ".join(f"{s.store} ({s.n_done}/{s.n_total})" for s in statuses if not s.complete)
            raise ParameterError("fit_only", True, f"complete datasets; incomplete: {incomplete}")
        return TrainingRun(None, [], None, statuses[0], holdout_status, measurement_s, 0.0)

    start = time.perf_counter()
    nodes_path = statuses[0].dataset_path
    info = {
        "path": str(nodes_path),
        "sha256": file_sha256(nodes_path),
        "rays_per_node": int(rays),
        "seed": int(seed),
        "wavelength_nm": float(wavelength_nm),
        "stacks": int(stacks),
        "slices": int(slices),
        "reduction_method": method,
        "measure": _measure_name(measure),
        **engine_memory_record(memory, measure),
    }
    model = SpatialModel(**dict(model_params or {})).fit(node_brdfs(nodes_path, method), mesh, training_set=info)
    reports = []
    if holdout_status is not None:
        for measured in node_brdfs(holdout_status.dataset_path, method):
            reports.append(evaluate(model, measured, attach=True))
    fit_s = time.perf_counter() - start
    model_path = model.save(out / "spatial-model.npz")
    text = json.dumps([r.to_dict() for r in reports], indent=1) + "\n"
    write_atomically(out / "holdout-report.json", lambda tmp: tmp.write_text(text, encoding="utf-8"))
    return TrainingRun(model, reports, model_path, statuses[0], holdout_status, measurement_s, fit_s)
