"""Background jobs of the explorer: Monte Carlo spectra and previews, off the event loop.

A job runs in a thread of a pool of ``max_running_jobs`` workers (the others wait in the queue),
so the server keeps answering the fast endpoints while it runs. Its progress comes from the
computation's own progress reports (`sandlight.progress.progress_to`), and the same hook stops
it: when the job is cancelled, the next report (at most one batch later, about 0.25 s) raises
`sandlight.errors.Cancelled` inside the computation. A client may have at most
``max_jobs_per_client`` unfinished jobs; finished ones are kept (the last ``max_kept_jobs``) so
their results can be read and exported.

The events of a job are server-sent events (``text/event-stream``): ``progress`` while it runs,
then one of ``done``, ``cancelled`` or ``failed``; a job that streams images also sends ``image``.
When the client that watches a job's events goes away (the tab is closed), the job is cancelled.
"""

from __future__ import annotations

import asyncio
import json
import logging
import secrets
import threading
import time
from collections import OrderedDict
from collections.abc import AsyncIterator, Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import Any

from sandlight.errors import Cancelled, ParameterError, SandlightError
from sandlight.progress import progress_to
from sandlight.web.errors import INTERNAL_MESSAGE, ApiError, parameter_body

__all__ = ["Job", "JobContext", "JobManager", "STATES"]

log = logging.getLogger("sandlight.web")

#: The states of a job; the last three are final.
STATES = ("queued", "running", "done", "cancelled", "failed")

#: Seconds between two looks at a job's state by its event stream.
EVENT_POLL_S = 0.05


@dataclass
class Job:
    """One background job (made by `JobManager.submit`).

    Attributes
    ----------
    id : str
        Unguessable identifier (URL-safe).
    kind : str
        What it computes ("reflectance", "preview").
    client : str
        Address of the client that started it.
    state : str
        One of `STATES`.
    progress : dict
        ``{"done", "total", "fraction", "text"}`` of the last report.
    result : object
        What the work returned (a dict for the answer; see `public_result`), once done.
    error : dict or None
        The JSON body of the refusal or failure, once failed.
    images : list of str
        The images streamed so far (data URLs), for jobs that send them.
    """

    id: str
    kind: str
    client: str
    state: str = "queued"
    progress: dict = field(default_factory=lambda: {"done": 0.0, "total": 0.0, "fraction": 0.0, "text": "queued"})
    result: Any = None
    error: dict | None = None
    images: list = field(default_factory=list)
    cancel_requested: threading.Event = field(default_factory=threading.Event)
    created: float = field(default_factory=time.time)

    @property
    def finished(self) -> bool:
        """Whether the job has stopped (done, cancelled or failed)."""
        return self.state in STATES[2:]

    def status(self) -> dict[str, Any]:
        """The body of ``GET /api/jobs/{id}``: state, progress, and the result or error when finished."""
        body: dict[str, Any] = {"id": self.id, "kind": self.kind, "state": self.state, "progress": self.progress}
        if self.state == "done":
            body["result"] = public_result(self.result)
        if self.error is not None:
            body["error"] = self.error
        return body


def public_result(result: Any) -> Any:
    """The JSON part of a result: a result may keep objects for exports under the key ``_keep``."""
    if isinstance(result, dict):
        return {k: v for k, v in result.items() if k != "_keep"}
    return result


class JobContext:
    """What a job's work sees: ``report`` its progress, ``image`` to stream a picture, and
    ``check`` to stop when cancelled. Progress reports of sandlight's own bars arrive by
    themselves (`sandlight.progress.progress_to`)."""

    def __init__(self, job: Job) -> None:
        self._job = job

    def check(self) -> None:
        """Raise `Cancelled` if the job was cancelled."""
        if self._job.cancel_requested.is_set():
            raise Cancelled(f"job {self._job.id} was cancelled")

    def report(self, done: float, total: float, text: str) -> None:
        """Record the progress, then stop if the job was cancelled."""
        self._job.progress = {
            "done": float(done),
            "total": float(total),
            "fraction": float(done) / float(total) if total else 0.0,
            "text": text,
        }
        self.check()

    def image(self, data_url: str) -> None:
        """Stream one more image (a ``data:image/png;base64,…`` URL)."""
        self._job.images.append(data_url)
        self.check()


class JobManager:
    """Jobs with bounded concurrency, per-client limits, progress events and cancel.

    Parameters
    ----------
    max_running : int
        Worker threads (jobs running at once).
    max_per_client : int
        Unfinished jobs one client may have.
    max_kept : int
        Finished jobs kept for reading.
    """

    def __init__(self, max_running: int, max_per_client: int, max_kept: int) -> None:
        self._pool = ThreadPoolExecutor(max_workers=max_running, thread_name_prefix="sandlight-job")
        self._jobs: OrderedDict[str, Job] = OrderedDict()
        self._lock = threading.Lock()
        self.max_per_client, self.max_kept = max_per_client, max_kept

    def submit(self, kind: str, client: str, work: Callable[[JobContext], Any]) -> Job:
        """Queue ``work(context)`` as a new job of ``client``.

        Raises
        ------
        ApiError
            429 when the client already has ``max_per_client`` unfinished jobs.
        """
        with self._lock:
            unfinished = sum(1 for j in self._jobs.values() if j.client == client and not j.finished)
            if unfinished >= self.max_per_client:
                raise ApiError(
                    429,
                    "limit",
                    f"at most {self.max_per_client} unfinished jobs per client; cancel one or wait for it to finish",
                )
            job = Job(secrets.token_urlsafe(12), kind, client)
            self._jobs[job.id] = job
            self._forget_old()
        self._pool.submit(self._run, job, work)
        return job

    def _forget_old(self) -> None:
        finished = [j.id for j in self._jobs.values() if j.finished]
        for job_id in finished[: max(0, len(finished) - self.max_kept)]:
            del self._jobs[job_id]

    def _run(self, job: Job, work: Callable[[JobContext], Any]) -> None:
        context = JobContext(job)
        try:
            context.check()
            job.state = "running"
            with progress_to(context.report):
                result = work(context)
        except Cancelled:
            job.state = "cancelled"
        except ParameterError as exc:  # a value only the computation could check
            job.error, job.state = parameter_body(exc), "failed"
        except SandlightError as exc:
            job.error, job.state = {"error": "refused", "message": str(exc)}, "failed"
        except Exception:  # a bug: logged, and the client told no more than that
            log.exception("job %s (%s) failed", job.id, job.kind)
            job.error, job.state = {"error": "internal", "message": INTERNAL_MESSAGE}, "failed"
        else:
            job.result, job.state = result, "done"

    def get(self, job_id: str) -> Job:
        """The job called ``job_id``; 404 when there is none (never was, or forgotten)."""
        job = self._jobs.get(job_id)
        if job is None:
            raise ApiError(404, "not-found", f"no job {job_id!r} (finished jobs are kept {self.max_kept} at most)")
        return job

    def cancel(self, job_id: str) -> Job:
        """Ask the job to stop (a queued job never starts; a running one stops within a batch)."""
        job = self.get(job_id)
        job.cancel_requested.set()
        return job

    async def events(self, job: Job) -> AsyncIterator[str]:
        """The job's server-sent events until it finishes; cancels the job if the stream is
        closed first (the client went away)."""
        sent_progress, sent_images = None, 0
        try:
            while True:
                while sent_images < len(job.images):
                    yield _event("image", {"index": sent_images, "url": job.images[sent_images]})
                    sent_images += 1
                if job.progress != sent_progress:
                    sent_progress = job.progress
                    yield _event("progress", {"state": job.state, **sent_progress})
                if job.finished and sent_images == len(job.images):
                    yield _event(job.state, job.status())
                    return
                await asyncio.sleep(EVENT_POLL_S)
        finally:
            if not job.finished:
                job.cancel_requested.set()

    def shutdown(self) -> None:
        """Cancel every job and stop the workers."""
        for job in list(self._jobs.values()):
            job.cancel_requested.set()
        self._pool.shutdown(wait=True, cancel_futures=True)


def _event(name: str, data: Any) -> str:
    return f"event: {name}\ndata: {json.dumps(data)}\n\n"
