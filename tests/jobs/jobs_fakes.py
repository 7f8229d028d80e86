"""Deterministic task functions for the job tests (module-level: workers must import them)."""

import os
import time
from pathlib import Path

import numpy as np


def noisy_square(payload, seed):
    """x² plus seeded noise on a 3-point axis: depends only on the payload and the seed."""
    rng = np.random.default_rng(seed)
    x = payload["x"]
    return {"value": x**2 + 0.01 * rng.standard_normal(3), "label_length": len(payload["label"])}


def _first_attempt(marker_dir, index) -> bool:
    """True the first time it is called for ``index`` (across processes: a marker file)."""
    marker = Path(marker_dir) / f"attempted-{index}"
    try:
        fd = os.open(marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
    except FileExistsError:
        return False
    os.close(fd)
    return True


def fail_once(marker_dir, fail_index, mode, payload, seed):
    """Like noisy_square, but the first attempt at task ``fail_index`` fails.

    mode "raise": raises RuntimeError; mode "exit": the worker process dies (os._exit), as if
    killed or out of memory.
    """
    if payload["i"] == fail_index and _first_attempt(marker_dir, fail_index):
        if mode == "exit":
            os._exit(3)
        raise RuntimeError(f"simulated failure of task {fail_index}")
    return noisy_square(payload, seed)


def always_fails_at(fail_index, payload, seed):
    if payload["i"] == fail_index:
        raise ValueError(f"task {fail_index} cannot be computed")
    return noisy_square(payload, seed)


def interrupt_after(marker_dir, k, payload, seed):
    """Acts like Ctrl-C (KeyboardInterrupt) at the (k+1)-th call in this process."""
    calls = Path(marker_dir) / "calls"
    n = int(calls.read_text()) if calls.exists() else 0
    calls.write_text(str(n + 1))
    if n == k:
        raise KeyboardInterrupt
    return noisy_square(payload, seed)


def slow_square(delay_s, payload, seed):
    time.sleep(delay_s)
    return noisy_square(payload, seed)


def shape_depends_on_x(payload, seed):
    return {"value": np.zeros(1 + int(payload["x"] > 0.15))}


def payloads(n):
    return [{"i": i, "x": 0.1 * i, "label": "s" * (i % 4 + 1)} for i in range(n)]


def signal_at(target_pid, signum, trigger_index, delay_s, payload, seed):
    """Like ``slow_square``, but task ``trigger_index`` sends ``signum`` to ``target_pid`` (the
    process running the job), so the interruption comes at a known point of the run."""
    if payload["i"] == trigger_index:
        os.kill(target_pid, signum)
    return slow_square(delay_s, payload, seed)
