"""Running a native computation in batches: progress bar, Ctrl-C, and determinism.

Each native call traces a contiguous range of rays with the GIL released; between calls Python
handles signals, so Ctrl-C stops a run within one batch (about a quarter of a second) and raises
``KeyboardInterrupt`` with nothing half-written. Results do not depend on the batch boundaries
because every ray has its own counter-based random stream.
"""

from __future__ import annotations

import time
from collections.abc import Callable

from sandlight.progress import progress_bar

TARGET_BATCH_SECONDS = 0.25
FIRST_BATCH = 2048
SHOW_AFTER_SECONDS = 1.0


def run_in_batches(
    run_batch: Callable[[int, int], None],
    total: int,
    *,
    label: str,
    progress: bool = True,
    start_at: int = 0,
    on_checkpoint: Callable[[int], None] | None = None,
    checkpoint_seconds: float = 60.0,
) -> None:
    """Calls ``run_batch(first, count)`` over ``start_at .. total`` in adaptively sized batches.

    A progress bar (`sandlight.progress`) appears once the run has taken more than a second;
    inside a bar of rays already showing (the wavelengths of one `sandlight.reflectance`), the
    rays count into that one. ``on_checkpoint(done)``
    is called every ``checkpoint_seconds`` and at the end, so a long run can be resumed.
    """
    done, batch = start_at, min(FIRST_BATCH, total - start_at)
    last_checkpoint = time.perf_counter()
    with progress_bar(
        label, total, unit="rays", completed=start_at, enabled=progress, show_after_s=SHOW_AFTER_SECONDS
    ) as bar:
        while done < total:
            n = min(batch, total - done)
            t0 = time.perf_counter()
            run_batch(done, n)
            dt = time.perf_counter() - t0
            done += n
            # Aim for a fixed wall time per batch, growing at most 4× at a time.
            batch = int(max(256, min(4 * n, n * TARGET_BATCH_SECONDS / max(dt, 1e-6))))
            bar.advance(n, description=label)
            if on_checkpoint is not None and time.perf_counter() - last_checkpoint > checkpoint_seconds:
                on_checkpoint(done)
                last_checkpoint = time.perf_counter()
