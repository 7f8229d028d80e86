"""A restartable, distributable job: many independent tasks, results in one dataset.

A job is a list of task payloads (small dicts of scalars: e.g. the parameters of one sand
sample), a task function ``fn(payload, seed) -> {name: array}`` and a master seed. Task ``i``
gets the seed :func:`sandlight.jobs.task_seed` ``(master_seed, i)``, so its result depends on
nothing but its payload and the master seed: not on the executor, the order tasks finish in,
or how often the job was interrupted and resumed.

The job's parent process collects results as they arrive and writes them to the store (see
:mod:`sandlight.jobs.store`) at once, so killing the job (Ctrl-C, ``kill -9``, a node going
down) loses only the tasks in flight. Running the same job again skips the stored indices; once
every task is done the results are consolidated into ``STORE/dataset.nc``, sorted by task index
and therefore identical to the dataset of an uninterrupted run.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import signal
import threading
from collections import deque
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from types import FrameType
from typing import TYPE_CHECKING

import numpy as np

from sandlight.errors import Cancelled, ParameterError
from sandlight.jobs.errors import JobError
from sandlight.jobs.executors import Executor, make_executor
from sandlight.jobs.lock import store_lock
from sandlight.jobs.seeds import task_seed
from sandlight.jobs.store import ShardStore, dumps, to_json_value
from sandlight.progress import progress_bar

if TYPE_CHECKING:
    import xarray as xr

#: Settings the runner records itself; user settings may not use these names.
_RESERVED_SETTINGS = ("n_tasks", "master_seed", "payloads_sha256", "task_dim", "result_dims")


@dataclass(frozen=True)
class Task:
    """One unit of work: the task's index in the job, its payload and its seed."""

    index: int
    payload: Mapping
    seed: int


@dataclass(frozen=True)
class JobStatus:
    """How far a job got.

    Attributes
    ----------
    store : Path
        The job store directory.
    n_total, n_done : int
        Number of tasks in the job, and of those whose results are stored.
    dataset_path : Path or None
        The consolidated dataset, once every task is done.
    """

    store: Path
    n_total: int
    n_done: int
    dataset_path: Path | None

    @property
    def complete(self) -> bool:
        return self.n_done == self.n_total


def run_task(fn: Callable, task: Task) -> tuple[int, dict]:
    """Run one task in a worker and return ``(index, results)`` with results as numpy arrays."""
    results = fn(dict(task.payload), task.seed)
    if not isinstance(results, Mapping):
        raise TypeError(
            f"task function returned {type(results).__name__}, expected a mapping of result names to arrays"
        )
    return task.index, {str(k): np.asarray(v) for k, v in results.items()}


@contextlib.contextmanager
def _stop_requests():
    """While a job runs, Ctrl-C (SIGINT) and ``kill PID`` (SIGTERM) only set a flag that the task
    loop checks between waits (at most half a second apart). Raising from the signal handler
    instead could interrupt the executor inside its own locks and hang its shutdown."""
    stop = threading.Event()
    if threading.current_thread() is not threading.main_thread():
        yield stop
        return

    def handler(signum: int, frame: FrameType | None) -> None:
        stop.set()

    previous = {s: signal.signal(s, handler) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield stop
    finally:
        for s, h in previous.items():
            signal.signal(s, h)


def _value_array(name: str, values: list):
    """Column of payload values as a numpy array of one consistent type."""
    kinds = {type(v) for v in values}
    if kinds <= {bool, np.bool_}:
        return np.asarray(values, dtype=bool)
    if kinds <= {int, np.int64, np.int32}:
        return np.asarray(values, dtype=np.int64)
    if kinds <= {int, float, np.float64, np.float32, np.int64, np.int32}:
        return np.asarray(values, dtype=np.float64)
    if kinds <= {str, np.str_}:
        return np.asarray(values, dtype=str)
    raise JobError(
        f"payload entry {name!r} mixes or uses unsupported types "
        f"{sorted(k.__name__ for k in kinds)}; use float, int, bool or str"
    )


class Job:
    """A restartable set of independent tasks whose results are stored in one dataset.

    Parameters
    ----------
    path : str or Path
        Job store directory (created if missing; see :mod:`sandlight.jobs.store`).
    fn : callable
        ``fn(payload: dict, seed: int) -> Mapping[str, array_like]``. Must be deterministic for a
        given payload and seed, and importable by the workers (a module-level function or a
        ``functools.partial`` of one). Every task must return the same names and shapes.
    payloads : sequence of mapping
        One payload per task: a dict of scalars (float, int, bool or str) with the same keys
        for every task. Stored as one variable per key in the dataset.
    seed : int
        Master seed (>= 0). Task ``i`` receives ``task_seed(seed, i)``.
    settings : mapping, optional
        JSON-able settings that define the job (e.g. rays, wavelengths, versions). A store made
        with other settings is refused, naming the first setting that differs.
    dims : mapping, optional
        Dimension names of each result's non-task axes, e.g. ``{"reflectance": ("wavelength",)}``.
        Results not listed get ``("<name>_dim0", ...)``.
    coords : mapping, optional
        Coordinates of those dimensions, e.g. ``{"wavelength": wavelengths_nm}``.
    var_attrs : mapping, optional
        Attributes per variable of the final dataset (e.g. ``{"reflectance": {"units": "1"}}``).
    attrs : mapping, optional
        Global attributes of the final dataset (non-scalar values are stored as JSON strings).
    task_dim : str
        Name of the task dimension in the final dataset (e.g. ``"sample"``).

    Examples
    --------
    >>> job = Job("out/store", fn, [{"x": 0.1}, {"x": 0.2}], seed=1)   # doctest: +SKIP
    >>> job.run(make_executor(workers=4)).complete                      # doctest: +SKIP
    True
    """

    def __init__(
        self,
        path: str | os.PathLike[str],
        fn: Callable,
        payloads: Sequence[Mapping],
        *,
        seed: int,
        settings: Mapping | None = None,
        dims: Mapping | None = None,
        coords: Mapping | None = None,
        var_attrs: Mapping | None = None,
        attrs: Mapping | None = None,
        task_dim: str = "task",
    ):
        self.path = Path(path)
        self.fn = fn
        self.payloads = list(payloads)
        self.seed = int(seed)
        self.user_settings = dict(settings or {})
        self.dims = {k: tuple(v) for k, v in (dims or {}).items()}
        self.coords = dict(coords or {})
        self.var_attrs = dict(var_attrs or {})
        self.attrs = dict(attrs or {})
        self.task_dim = task_dim

    # ---- definition --------------------------------------------------------------------------
    @property
    def n_tasks(self) -> int:
        return len(self.payloads)

    def task(self, index: int) -> Task:
        return Task(index, self.payloads[index], task_seed(self.seed, index))

    def settings(self) -> dict:
        """Everything that defines the job's results (what a resumed run must agree with)."""
        clash = sorted(set(self.user_settings) & set(_RESERVED_SETTINGS))
        if clash:
            raise ParameterError("settings", clash, f"names other than {_RESERVED_SETTINGS}")
        if self.seed < 0:
            raise ParameterError("seed", self.seed, "an integer >= 0")
        # Payloads are hashed rather than stored: they can be long, and any change must be seen.
        digest = hashlib.sha256(dumps(self.payloads).encode("utf-8")).hexdigest()
        return {
            **to_json_value(self.user_settings),
            "n_tasks": self.n_tasks,
            "master_seed": self.seed,
            "payloads_sha256": digest,
            "task_dim": self.task_dim,
            "result_dims": {k: list(v) for k, v in sorted(self.dims.items())},
        }

    def _result_dims(self, name: str, ndim: int) -> tuple:
        dims = self.dims.get(name, tuple(f"{name}_dim{i}" for i in range(ndim)))
        if len(dims) != ndim:
            raise JobError(f"result {name!r} has {ndim} non-task axes but dims gives {dims}")
        return dims

    # ---- state -------------------------------------------------------------------------------
    def open_store(self) -> ShardStore:
        """Create or reopen the store, refusing one made with other settings."""
        return ShardStore.open(self.path, self.settings())

    def status(self) -> JobStatus:
        """Count the stored tasks (creates the store if it does not exist yet)."""
        store = self.open_store()
        done = store.done_indices()
        dataset = store.dataset_path if store.dataset_path.exists() else None
        return JobStatus(self.path, self.n_tasks, len(done), dataset)

    def dataset(self) -> xr.Dataset:
        """The consolidated dataset (``xarray.Dataset``, loaded in memory)."""
        import xarray as xr

        status = self.status()
        if status.dataset_path is None:
            raise JobError(
                f"job {self.path} is not complete ({status.n_done} of "
                f"{status.n_total} tasks done); run it again to finish it"
            )
        with xr.open_dataset(status.dataset_path) as ds:  # checked readable by status()
            return ds.load()

    # ---- running -----------------------------------------------------------------------------
    def run(
        self,
        executor: Executor | None = None,
        *,
        max_tasks: int | None = None,
        max_retries: int = 2,
        progress: bool = True,
        description: str = "tasks",
        unit: str = "task",
    ) -> JobStatus:
        """Run the tasks not yet stored, then consolidate the dataset if all are done.

        Parameters
        ----------
        executor : Executor, optional
            Where tasks run (default: :func:`make_executor` ``()``, a local process pool).
        max_tasks : int, optional
            Run at most this many of the missing tasks, then stop (the job stays resumable).
        max_retries : int
            How often a failed task (exception, dead worker) is resubmitted before the job
            gives up on it (>= 0).
        progress : bool
            Show a progress bar with count, rate and ETA.
        description, unit : str
            Labels of the progress bar.

        Returns
        -------
        JobStatus

        Raises
        ------
        Cancelled
            Ctrl-C or SIGTERM: the tasks in flight are dropped, every finished one is stored.
        JobError
            Some tasks still failed after ``max_retries`` retries (the others are stored).
        JobSettingsError
            The store was made with other settings.
        JobStoreLockedError
            Another run is working on the store (the message names it).
        """
        if max_retries < 0:
            raise ParameterError("max_retries", max_retries, "an integer >= 0")
        if max_tasks is not None and max_tasks < 0:
            raise ParameterError("max_tasks", max_tasks, "an integer >= 0 or None")
        columns = self._payload_columns()  # validate payloads before any work
        # Opened once to create it or refuse a foreign directory, then again under the lock: a
        # run that got there first may have created it with other settings.
        with store_lock(self.open_store().path):
            store = self.open_store()
            done = store.done_indices()
            todo = [i for i in range(self.n_tasks) if i not in done]
            if max_tasks is not None:
                todo = todo[:max_tasks]
            if todo:
                executor = make_executor() if executor is None else executor
                with (
                    _stop_requests() as stop,
                    executor,
                    progress_bar(
                        description, self.n_tasks, unit=f"{unit}s", completed=len(done), enabled=progress
                    ) as bar,
                ):
                    self._run_tasks(store, executor, todo, done, max_retries, bar.advance, stop)
            if len(done) == self.n_tasks and not store.dataset_path.exists():
                self._consolidate(store, columns)
            dataset = store.dataset_path if store.dataset_path.exists() else None
        return JobStatus(self.path, self.n_tasks, len(done), dataset)

    def _run_tasks(
        self,
        store: ShardStore,
        executor: Executor,
        todo: list[int],
        done: set[int],
        max_retries: int,
        advance: Callable[[int], None],
        stop: threading.Event,
    ) -> None:
        schema = store.result_schema()
        stored = schema is not None  # the shape of the stored results: a mismatch is the store's
        queue = deque(todo)
        in_flight: dict = {}  # future -> task index
        attempts: dict[int, int] = {}
        failures: dict[int, BaseException] = {}
        try:
            while queue or in_flight:
                while queue and (executor.capacity is None or len(in_flight) < executor.capacity):
                    index = queue.popleft()
                    in_flight[executor.submit(run_task, self.fn, self.task(index))] = index
                finished = executor.wait(list(in_flight), timeout=0.5)
                batch: dict[int, dict] = {}
                for future in finished:
                    index = in_flight.pop(future)
                    try:
                        _, result = executor.result(future)
                    except Exception as exc:  # noqa: BLE001 - task error or lost worker: retry
                        attempts[index] = attempts.get(index, 0) + 1
                        if attempts[index] <= max_retries:
                            queue.appendleft(index)
                        else:
                            failures[index] = exc
                        continue
                    if index in done or index in batch:
                        continue  # a duplicate (e.g. a task rerun by the scheduler): same values
                    schema = self._check_schema(index, result, schema, store if stored else None)
                    stored = False
                    batch[index] = result
                if batch:
                    self._write(store, batch)
                    done.update(batch)
                    advance(len(batch))
                if stop.is_set():
                    raise KeyboardInterrupt
        except KeyboardInterrupt:
            executor.abort(list(in_flight))
            raise Cancelled(
                f"stopped after {len(done)} of {self.n_tasks} tasks; the job store {self.path} "
                f"is consistent: run the same command again to resume"
            ) from None
        if failures:
            index, exc = min(failures.items())
            raise JobError(
                f"{len(failures)} task(s) failed after {max_retries + 1} attempts (indices "
                f"{sorted(failures)[:10]}{' ...' if len(failures) > 10 else ''}); task {index}: "
                f"{type(exc).__name__}: {exc}. The {len(done)} finished tasks are stored; run "
                f"the job again to retry the others"
            ) from exc

    @staticmethod
    def _check_schema(
        index: int, result: dict[str, np.ndarray], schema: dict | None, store: ShardStore | None = None
    ) -> dict:
        """The schema of the results so far; ``store`` when ``schema`` is that of its shards."""
        got = {k: (v.dtype.kind, v.shape) for k, v in result.items()}
        for name, (kind, _) in got.items():
            if kind not in "biuf":
                raise JobError(f"task {index} returned {name!r} of dtype kind {kind!r}; results must be numeric arrays")
        if schema is not None and {k: s for k, (_, s) in got.items()} != {k: s for k, (_, s) in schema.items()}:
            if store is not None:
                raise JobError(
                    f"the shards in {store.shard_dir} hold results {schema}, but this job's tasks return {got}: "
                    f"they are not of this job; use another output directory"
                )
            raise JobError(
                f"task {index} returned results {got}, but earlier tasks returned "
                f"{schema}; a task function must return the same names and shapes"
            )
        return got if schema is None else schema

    def _write(self, store: ShardStore, batch: dict[int, dict]) -> None:
        indices = sorted(batch)
        names = sorted(batch[indices[0]])
        results = {n: np.stack([batch[i][n] for i in indices]) for n in names}
        dims = {n: self._result_dims(n, results[n].ndim - 1) for n in names}
        store.write_shard(indices, results, dims)

    def _payload_columns(self) -> dict[str, np.ndarray]:
        if not self.payloads:
            return {}
        keys = list(self.payloads[0])
        for i, p in enumerate(self.payloads):
            if list(p) != keys:
                raise JobError(
                    f"payload {i} has keys {sorted(p)}, payload 0 has {sorted(keys)}; "
                    f"every task must have the same payload keys"
                )
        return {k: _value_array(k, [p[k] for p in self.payloads]) for k in keys}

    def _consolidate(self, store: ShardStore, columns: dict[str, np.ndarray]):
        import xarray as xr

        index, results = store.read_results()
        if not np.array_equal(index, np.arange(self.n_tasks)):
            missing = sorted(set(range(self.n_tasks)) - set(index.tolist()))[:10]
            raise JobError(f"cannot consolidate {self.path}: tasks {missing} are missing")
        data = {k: (self.task_dim, v) for k, v in columns.items()}
        data["seed"] = (self.task_dim, np.array([task_seed(self.seed, i) for i in range(self.n_tasks)], dtype=np.int64))
        for name, values in results.items():
            data[name] = ((self.task_dim,) + self._result_dims(name, values.ndim - 1), values)
        coords = {self.task_dim: np.arange(self.n_tasks, dtype=np.int64), **self.coords}
        attrs = {}
        for key, value in {**self.attrs, "job_settings": self.settings()}.items():
            value = to_json_value(value)
            attrs[key] = dumps(value) if isinstance(value, (dict, list, bool)) or value is None else value
        ds = xr.Dataset(data, coords=coords, attrs=attrs)
        ds["seed"].attrs["description"] = "seed of the task (derived from the job's master seed)"
        for name, var_attrs in self.var_attrs.items():
            if name in ds.variables:
                ds[name].attrs.update(var_attrs)
        store.write_dataset(ds)
