"""Deterministic seeds: one master seed gives every task its own independent stream.

A task's seed depends only on the master seed and the task's index (never on the order in which
tasks run, on the executor or on restarts), which is what makes a resumed or distributed job
give the same numbers as an uninterrupted local one.
"""

from __future__ import annotations

import zlib

import numpy as np

#: Seeds are kept below 2**63 so that they fit every signed 64-bit consumer (NetCDF int64, Rust
#: i64/u64, numpy) unchanged.
_SEED_MASK = (1 << 63) - 1


def _key(part: int | str) -> int:
    """Map one key part (non-negative int or str) to a non-negative int, stably across runs."""
    if isinstance(part, str):
        # crc32 rather than hash(): Python's str hash is salted per process.
        return zlib.crc32(part.encode("utf-8"))
    part = int(part)
    if part < 0:
        raise ValueError(f"seed key parts must be non-negative, got {part}")
    return part


def derive_seed(master_seed: int, *keys: int | str) -> int:
    """Derive an independent seed from a master seed and a path of keys.

    Uses numpy's ``SeedSequence`` with the keys as its spawn key, so different key paths give
    statistically independent streams (the same guarantee as ``SeedSequence.spawn``).

    Parameters
    ----------
    master_seed : int
        Master seed, non-negative.
    *keys : int or str
        Path of keys, e.g. ``(index,)`` for a task or ``("holdout",)`` for a sub-job.

    Returns
    -------
    int
        Seed in [0, 2**63).

    Examples
    --------
    >>> derive_seed(42, 0) == derive_seed(42, 0)
    True
    >>> derive_seed(42, 0) != derive_seed(42, 1)
    True
    """
    master_seed = int(master_seed)
    if master_seed < 0:
        raise ValueError(f"master_seed must be non-negative, got {master_seed}")
    sequence = np.random.SeedSequence(master_seed, spawn_key=tuple(_key(k) for k in keys))
    return int(sequence.generate_state(1, dtype=np.uint64)[0]) & _SEED_MASK


def task_seed(master_seed: int, index: int) -> int:
    """Seed of task ``index`` of a job with master seed ``master_seed``."""
    return derive_seed(master_seed, index)
