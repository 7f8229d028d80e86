"""Timing shared by the benchmark scripts (imported from their own folder, which Python puts first
on ``sys.path`` when a script in it runs)."""

from __future__ import annotations

import time
from collections.abc import Callable


def best_of(fn: Callable[[], object], repeat: int = 3) -> tuple[float, float]:
    """The best wall-clock and the best CPU time (s) of ``repeat`` calls of ``fn``."""
    best_wall, best_cpu = float("inf"), float("inf")
    for _ in range(repeat):
        w, c = time.perf_counter(), time.process_time()
        fn()
        best_wall = min(best_wall, time.perf_counter() - w)
        best_cpu = min(best_cpu, time.process_time() - c)
    return best_wall, best_cpu
