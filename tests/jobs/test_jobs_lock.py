"""The lock of a job store (issue 24 #11): a second run on a store is refused, naming the run
that holds it; the lock of a killed run is taken over."""

import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest
import xarray as xr
from test_jobs_runner import make_job

from sandlight.jobs import InProcessExecutor, JobError, JobStoreLockedError
from sandlight.jobs.lock import LOCK_FILE, store_lock

_SLOW_RUN = """
import functools, sys
import jobs_fakes
from test_jobs_runner import make_job
from sandlight.jobs import InProcessExecutor
make_job(sys.argv[1], fn=functools.partial(jobs_fakes.slow_square, 0.2)).run(InProcessExecutor(), progress=False)
"""


def _start_slow_run(store: Path) -> subprocess.Popen:
    """A run of the test job in another process, returned once it has stored some tasks."""
    root = Path(__file__).parents[2]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(root / "python"), str(Path(__file__).parent)])}
    proc = subprocess.Popen([sys.executable, "-c", _SLOW_RUN, str(store)], env=env)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and len(list(store.glob("shards/shard-*.nc"))) < 2:
        time.sleep(0.02)
    assert proc.poll() is None, "the first run ended before the test could start the second"
    return proc


def _dataset_bytes(status) -> bytes:
    return Path(status.dataset_path).read_bytes()


def test_a_second_run_is_refused_while_the_first_works(tmp_path):
    # Both used to compute every task, and one could consolidate while the other still wrote.
    store = tmp_path / "store"
    first = _start_slow_run(store)
    try:
        with pytest.raises(JobStoreLockedError) as info:
            make_job(store).run(InProcessExecutor(), progress=False)
        assert isinstance(info.value, JobError)
        assert info.value.holder["pid"] == first.pid and info.value.holder["host"] == socket.gethostname()
        assert f"in use by process {first.pid} on host {socket.gethostname()!r}, started " in str(info.value)
    finally:
        first.wait(timeout=120)
    assert first.returncode == 0
    # Once it is done the store is free again, and complete.
    status = make_job(store).run(InProcessExecutor(), progress=False)
    reference = make_job(tmp_path / "reference").run(InProcessExecutor(), progress=False)
    assert status.complete and _dataset_bytes(status) == _dataset_bytes(reference)


def test_the_lock_of_a_killed_run_is_taken_over(tmp_path):
    store = tmp_path / "store"
    killed = _start_slow_run(store)
    assert json.loads((store / LOCK_FILE).read_text())["pid"] == killed.pid
    os.kill(killed.pid, signal.SIGKILL)
    killed.wait()
    status = make_job(store).run(InProcessExecutor(), progress=False)  # not refused: the holder is dead
    assert status.complete
    assert (store / LOCK_FILE).read_text() == ""  # released, no holder named any more
    with xr.open_dataset(status.dataset_path) as ds:
        assert ds.sizes["sample"] == status.n_total


def test_the_command_line_refuses_a_store_in_use_with_exit_2(tmp_path):
    from typer.testing import CliRunner

    from sandlight.cli import app

    (tmp_path / "training").mkdir()
    with store_lock(tmp_path / "training"):
        res = CliRunner().invoke(
            app, ["train-spectral", "--out", str(tmp_path), "--samples", "20", "--rays", "100", "--no-progress"]
        )
    assert res.exit_code == 2, res.output
    assert f"is in use by process {os.getpid()}" in res.output and "Traceback" not in res.output
