"""Restartable, distributable jobs of independent tasks (training sets, BRDF measurements).

Public objects
--------------
Job, Task, JobStatus
    A job, one of its tasks, and how far it got (:mod:`sandlight.jobs.runner`).
LocalExecutor, InProcessExecutor, DaskExecutor, make_executor
    Where the tasks run (:mod:`sandlight.jobs.executors`).
derive_seed, task_seed
    Deterministic per-task seeds (:mod:`sandlight.jobs.seeds`).
JobError, JobSettingsError
    Failures, and a store made with other settings (:mod:`sandlight.jobs.errors`).
JobStoreLockedError
    Another run is working on the store (:mod:`sandlight.jobs.lock`).
"""

from sandlight.jobs.errors import JobError, JobSettingsError
from sandlight.jobs.executors import DaskExecutor, Executor, InProcessExecutor, LocalExecutor, make_executor
from sandlight.jobs.lock import JobStoreLockedError
from sandlight.jobs.runner import Job, JobStatus, Task
from sandlight.jobs.seeds import derive_seed, task_seed

__all__ = [
    "Job",
    "Task",
    "JobStatus",
    "Executor",
    "LocalExecutor",
    "InProcessExecutor",
    "DaskExecutor",
    "make_executor",
    "derive_seed",
    "task_seed",
    "JobError",
    "JobSettingsError",
    "JobStoreLockedError",
]
