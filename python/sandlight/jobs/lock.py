"""The lock of a job store: one run at a time works on a store.

Two runs on one store both computed every task, and one could consolidate the dataset and
remove the shards while the other was still reading them ("cannot consolidate …: tasks [2] are
missing"). A run therefore holds an exclusive ``flock`` on ``STORE/lock`` while it works; a
second run is refused at once, with the holder (process id, host, start time) that the first
wrote into the file.

The kernel releases the lock when its holder ends, however it ends (``kill -9``, a crash): a
lock left by a dead process is never in the way, and the next run takes it over and writes
itself in. Nothing has to judge whether a holder is still alive. ``flock`` is POSIX (Linux,
macOS); it also works on NFS v4 and on Linux's NFS v3 client (which maps it to ``fcntl`` locks).
"""

from __future__ import annotations

import contextlib
import fcntl
import json
import os
import socket
from collections.abc import Iterator
from datetime import UTC, datetime
from pathlib import Path

from sandlight.jobs.errors import JobError

#: Name of the lock file inside a store directory.
LOCK_FILE = "lock"

#: Longest holder description read back (it is one short JSON line).
_MAX_HOLDER_BYTES = 4096


class JobStoreLockedError(JobError):
    """Another run holds the job store.

    Attributes
    ----------
    holder : dict
        What the holder wrote: ``pid``, ``host`` and ``started`` (ISO 8601, UTC), or ``{}`` if
        it could not be read (the holder was still writing it).
    """

    def __init__(self, store: Path, holder: dict) -> None:
        self.holder = holder
        who = (
            f"process {holder.get('pid')} on host {holder.get('host')!r}, started {holder.get('started')}"
            if holder
            else "another process"
        )
        super().__init__(
            f"the job store {store} is in use by {who}: two runs on one store would both compute "
            f"every task. Wait for that run to finish (or stop it), then run this command again"
        )


def _holder(fd: int) -> dict:
    try:
        holder = json.loads(os.pread(fd, _MAX_HOLDER_BYTES, 0).decode("utf-8"))
    except (OSError, ValueError):
        return {}
    return holder if isinstance(holder, dict) else {}


@contextlib.contextmanager
def store_lock(store: str | os.PathLike[str]) -> Iterator[None]:
    """Hold the lock of the job store directory ``store`` (which must exist) while the block runs.

    Raises
    ------
    JobStoreLockedError
        Another process holds it; the message names that process.
    """
    store = Path(store)
    fd = os.open(store / LOCK_FILE, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise JobStoreLockedError(store, _holder(fd)) from None
        started = datetime.now(UTC).isoformat(timespec="seconds")
        holder = {"pid": os.getpid(), "host": socket.gethostname(), "started": started}
        os.ftruncate(fd, 0)
        os.pwrite(fd, json.dumps(holder).encode("utf-8"), 0)
        try:
            yield
        finally:
            os.ftruncate(fd, 0)  # no holder any more; the file stays (removing it would race)
            fcntl.flock(fd, fcntl.LOCK_UN)
    finally:
        os.close(fd)
