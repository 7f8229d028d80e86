"""Where a job's tasks run: in-process, a local process pool, or a Dask cluster.

All executors share one small protocol used by :class:`sandlight.jobs.Job`: ``submit`` a call,
``wait`` for any of a set of futures, read its ``result`` (which raises the task's exception),
and ``abort`` everything on Ctrl-C. Workers only compute; the job's parent process is the only
writer of the store, so a worker that dies can lose at most its own task, which is then
resubmitted.

=============  ====================================================================
executor       when to use
=============  ====================================================================
in-process     ``LocalExecutor(workers=1)``: debugging, or an engine that is itself
               multithreaded
local pool     ``LocalExecutor(workers=N)``: one machine (the default, N = CPU count)
dask           ``DaskExecutor(scheduler="tcp://HOST:PORT")`` for an existing cluster
               (e.g. one started by dask-jobqueue on SLURM), ``DaskExecutor(
               n_workers=N)`` for a LocalCluster, or ``DaskExecutor(client=...)``
=============  ====================================================================
"""

from __future__ import annotations

import concurrent.futures as cf
import logging
import multiprocessing
import os
import signal
from collections.abc import Callable, Collection
from concurrent.futures.process import BrokenProcessPool
from typing import TYPE_CHECKING, Any

from sandlight.errors import ParameterError

if TYPE_CHECKING:
    from distributed import Client


def _cpu_count() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1


def _init_worker() -> None:
    """Set up a pool worker: Ctrl-C is for the parent, and the worker dies with the parent."""
    # The terminal sends SIGINT to the whole process group; only the parent must react (it
    # stops the pool), otherwise every worker would print its own KeyboardInterrupt traceback.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:  # Linux: have the kernel kill this worker if the parent is killed (kill -9).
        import ctypes

        PR_SET_PDEATHSIG = 1
        ctypes.CDLL("libc.so.6", use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGKILL)
    except (OSError, AttributeError):  # other systems: orphans end when their queue closes
        pass


class Executor:
    """Protocol of a job executor (a context manager)."""

    #: Maximum number of tasks to keep submitted at once (None: submit them all).
    capacity: int | None = 1

    def __enter__(self) -> Executor:
        return self

    def __exit__(self, *exc: object) -> bool:
        self.close()
        return False

    def submit(self, fn: Callable[..., Any], *args: Any) -> Any:
        raise NotImplementedError

    def wait(self, futures: Collection[Any], timeout: float) -> Collection[Any]:
        """Futures of ``futures`` that are finished, waiting at most ``timeout`` seconds."""
        raise NotImplementedError

    def result(self, future: Any) -> Any:
        return future.result()

    def abort(self, futures: Collection[Any]) -> None:
        """Cancel ``futures`` and stop running tasks (Ctrl-C); they will be redone on resume."""

    def close(self) -> None:
        pass

    def describe(self) -> str:
        return type(self).__name__


class InProcessExecutor(Executor):
    """Run each task in the calling process when it is submitted (one at a time)."""

    capacity = 1

    def submit(self, fn: Callable[..., Any], *args: Any) -> cf.Future:
        future = cf.Future()
        try:
            future.set_result(fn(*args))
        except Exception as exc:  # noqa: BLE001 - the job decides whether to retry
            future.set_exception(exc)
        # KeyboardInterrupt (a BaseException) is not caught: it stops the job.
        return future

    def wait(self, futures: Collection[cf.Future], timeout: float) -> list[cf.Future]:
        return [f for f in futures if f.done()]

    def describe(self) -> str:
        return "in-process"


class LocalExecutor(Executor):
    """A pool of worker processes on this machine (``concurrent.futures.ProcessPoolExecutor``).

    Parameters
    ----------
    workers : int, optional
        Number of worker processes, >= 1. Default: the number of CPUs available to this process.
        (:func:`make_executor` gives an :class:`InProcessExecutor` for ``workers=1``; a pool of
        one process is still useful to survive a crashing task.)

    Notes
    -----
    Workers are started with the ``spawn`` method (a fresh interpreter): forking a parent that
    runs threads (progress bar, Dask, BLAS) can deadlock. The task function must therefore be
    importable (a module-level function or a ``functools.partial`` of one). If a worker dies
    (killed, out of memory) the pool breaks; it is restarted and every task that was in flight
    is resubmitted.
    """

    def __init__(self, workers: int | None = None):
        self.workers = _cpu_count() if workers is None else int(workers)
        if self.workers < 1:
            raise ParameterError("workers", workers, "an integer >= 1")
        self.capacity = 2 * self.workers  # keep every worker busy while results are written
        self._pool = None

    def _start(self) -> None:
        self._pool = cf.ProcessPoolExecutor(
            max_workers=self.workers, mp_context=multiprocessing.get_context("spawn"), initializer=_init_worker
        )

    def submit(self, fn: Callable[..., Any], *args: Any) -> cf.Future:
        if self._pool is None:
            self._start()
        try:
            return self._pool.submit(fn, *args)
        except BrokenProcessPool:
            # A worker died; its futures (and all others in flight) fail with
            # BrokenProcessPool and are resubmitted by the job. Start a fresh pool.
            self._pool.shutdown(wait=False, cancel_futures=True)
            self._start()
            return self._pool.submit(fn, *args)

    def wait(self, futures: Collection[cf.Future], timeout: float) -> set[cf.Future]:
        done, _ = cf.wait(futures, timeout=timeout, return_when=cf.FIRST_COMPLETED)
        return done

    def abort(self, futures: Collection[cf.Future]) -> None:
        for f in futures:
            f.cancel()
        self._terminate()

    def _terminate(self) -> None:
        if self._pool is None:
            return
        pool, self._pool = self._pool, None
        # Running tasks cannot be cancelled through the public API before Python 3.14
        # (terminate_workers); their results would be discarded anyway.
        processes = list(getattr(pool, "_processes", {}).values())
        pool.shutdown(wait=False, cancel_futures=True)
        for p in processes:
            p.terminate()
        for p in processes:
            p.join(timeout=5)

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)
            self._pool = None

    def describe(self) -> str:
        return f"local pool of {self.workers} processes"


class DaskExecutor(Executor):
    """Run tasks on a Dask distributed cluster.

    Parameters
    ----------
    scheduler : str, optional
        Address of a running scheduler, e.g. ``"tcp://10.0.0.5:8786"``.
    n_workers : int, optional
        Start a ``LocalCluster`` with this many workers (used when ``scheduler`` and ``client``
        are not given).
    threads_per_worker : int
        Threads per worker of the LocalCluster (default 1: one task per core).
    processes : bool
        LocalCluster workers are processes (True, default) or threads of this process.
    client : distributed.Client, optional
        An existing client (e.g. on a dask-jobqueue cluster); it is not closed by this executor.

    Notes
    -----
    Tasks are submitted with ``pure=False`` so that a resubmitted task is a new computation, not
    the cached failure. When a worker dies, the scheduler reruns its tasks elsewhere; a task
    that keeps killing workers ends in ``KilledWorker``, which the job counts as a failed
    attempt. Workers must be able to import sandlight (and the task function).
    """

    capacity = None  # let the scheduler queue everything: adaptive clusters grow with the queue

    def __init__(
        self,
        scheduler: str | None = None,
        n_workers: int | None = None,
        threads_per_worker: int = 1,
        processes: bool = True,
        client: Client | None = None,
    ):
        given = [x is not None for x in (scheduler, n_workers, client)]
        if sum(given) > 1:
            raise ValueError("give at most one of scheduler, n_workers and client")
        self.scheduler = scheduler
        self.n_workers = n_workers
        self.threads_per_worker = threads_per_worker
        self.processes = processes
        self._client = client
        self._owns_client = client is None
        self._cluster = None

    @property
    def client(self) -> Client:
        if self._client is None:
            from distributed import Client, LocalCluster

            if self.scheduler is not None:
                self._client = Client(self.scheduler)
            else:
                self._cluster = LocalCluster(
                    n_workers=self.n_workers or _cpu_count(),
                    threads_per_worker=self.threads_per_worker,
                    processes=self.processes,
                    dashboard_address=":0",
                    silence_logs=logging.ERROR,
                )
                self._client = Client(self._cluster)
        return self._client

    def __enter__(self) -> DaskExecutor:
        self.client  # noqa: B018 - connect now, so that a bad address fails before any work
        return self

    def submit(self, fn: Callable[..., Any], *args: Any) -> Any:
        return self.client.submit(fn, *args, pure=False)

    def wait(self, futures: Collection[Any], timeout: float) -> Collection[Any]:
        from distributed import wait

        try:
            done, _ = wait(futures, timeout=timeout, return_when="FIRST_COMPLETED")
        except TimeoutError:
            return []
        return done

    def abort(self, futures: Collection[Any]) -> None:
        if self._client is not None and futures:
            self._client.cancel(list(futures))

    def close(self) -> None:
        if self._owns_client and self._client is not None:
            self._client.close()
            self._client = None
        if self._cluster is not None:
            self._cluster.close()
            self._cluster = None

    def describe(self) -> str:
        if self.scheduler:
            return f"dask cluster at {self.scheduler}"
        if self._owns_client:
            return f"dask LocalCluster of {self.n_workers or _cpu_count()} workers"
        return "dask cluster"


def make_executor(workers: int | None = None, dask_local: int | None = None, scheduler: str | None = None) -> Executor:
    """Executor from command-line style options (at most one of them may be given).

    Parameters
    ----------
    workers : int, optional
        Local process pool of this size (1: in-process). The default when nothing is given,
        with one worker per CPU.
    dask_local : int, optional
        Start a Dask LocalCluster with this many worker processes.
    scheduler : str, optional
        Connect to the Dask scheduler at this address (``tcp://HOST:PORT``).
    """
    options = {"workers": workers, "dask_local": dask_local, "scheduler": scheduler}
    chosen = {k: v for k, v in options.items() if v is not None}
    if len(chosen) > 1:
        raise ParameterError(" and ".join(chosen), tuple(chosen.values()), "choose one executor option")
    if scheduler is not None:
        return DaskExecutor(scheduler=scheduler)
    if dask_local is not None:
        if int(dask_local) < 1:
            raise ParameterError("dask_local", dask_local, "an integer >= 1")
        return DaskExecutor(n_workers=int(dask_local))
    if workers is not None and int(workers) == 1:
        return InProcessExecutor()
    return LocalExecutor(workers)


def resolve_executor(executor: Executor | str | None) -> Executor:
    """An Executor as given, or one named ``"local"`` (default, also for None), ``"in-process"``
    or ``"dask"``."""
    if isinstance(executor, Executor):
        return executor
    choices = {"local": LocalExecutor, "in-process": InProcessExecutor, "dask": DaskExecutor}
    if executor is None:
        return LocalExecutor()
    if executor not in choices:
        raise ParameterError("executor", executor, f"an Executor or one of {sorted(choices)}")
    return choices[executor]()
