"""Running a native computation in batches: progress bar, Ctrl-C, and determinism.

Each native call traces a contiguous range of rays with the GIL released; between calls Python
handles signals, so Ctrl-C stops a run within one batch (about a quarter of a second) and raises
``KeyboardInterrupt`` with nothing half-written. Results do not depend on the batch boundaries
because every ray has its own counter-based random stream.
"""

from __future__ import annotations

import time
from typing import Callable

from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn

TARGET_BATCH_SECONDS = 0.25
FIRST_BATCH = 2048
SHOW_AFTER_SECONDS = 1.0


def run_in_batches(run_batch: Callable[[int, int], None], total: int, *, label: str, progress: bool = True) -> None:
    """Calls ``run_batch(first, count)`` over ``0 .. total`` in adaptively sized batches.

    A progress bar appears once the run has taken more than a second.
    """
    done, batch = 0, min(FIRST_BATCH, total)
    start = time.perf_counter()
    bar = task = None
    try:
        while done < total:
            n = min(batch, total - done)
            t0 = time.perf_counter()
            run_batch(done, n)
            dt = time.perf_counter() - t0
            done += n
            # Aim for a fixed wall time per batch, growing at most 4× at a time.
            batch = int(max(256, min(4 * n, n * TARGET_BATCH_SECONDS / max(dt, 1e-6))))
            if progress and bar is None and time.perf_counter() - start > SHOW_AFTER_SECONDS and done < total:
                bar = Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                               TextColumn("{task.fields[rate]}"), TimeElapsedColumn(), TimeRemainingColumn(), transient=True)
                bar.start()
                task = bar.add_task(label, total=total, completed=done, rate="")
            if bar is not None:
                rate = done / (time.perf_counter() - start)
                bar.update(task, completed=done, rate=f"{rate:,.0f} rays/s")
    finally:
        if bar is not None:
            bar.stop()
