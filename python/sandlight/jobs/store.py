"""On-disk store of a job: settings, result shards and the final consolidated dataset.

Layout of a store directory::

    STORE/job.json              format, version and the settings the job was made with
    STORE/shards/shard-NNNNNN.nc  results of the tasks finished so far (NetCDF, one file per flush)
    STORE/dataset.nc            the consolidated dataset, written once every task is done
    STORE/lock                  held by the run working on the store (:mod:`sandlight.jobs.lock`)

Every file is written to a temporary name in the same directory and moved into place with
``os.replace``, which is atomic on POSIX and Windows: a reader (or a resumed job) sees either the
whole file or nothing, whatever moment the writer was killed at. Results are keyed by task
index, so a task present in two shards (possible only if a job was killed between writing the
consolidated dataset and removing its shards) is read once.
"""

from __future__ import annotations

import json
import math
import os
import re
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from sandlight.io import remove_stale_temporaries, write_atomically
from sandlight.jobs.errors import JobError, JobSettingsError
from sandlight.jobs.lock import LOCK_FILE

if TYPE_CHECKING:
    import xarray as xr

STORE_FORMAT = "sandlight-job-store"
STORE_FORMAT_VERSION = 1
SETTINGS_FILE = "job.json"
DATASET_FILE = "dataset.nc"
SHARD_DIR = "shards"
_SHARD_RE = re.compile(r"^shard-(\d{6,})\.nc$")
_DAMAGED = "the store is damaged or not of this job: use another output directory"
_DATASET_ADVICE = "delete it and run the job again (every task is recomputed), or use another output directory"


def to_json_value(value: Any) -> Any:
    """Convert settings to plain JSON types (numpy scalars and arrays, tuples, paths)."""
    if isinstance(value, dict):
        return {str(k): to_json_value(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [to_json_value(v) for v in value]
    if isinstance(value, np.ndarray):
        return [to_json_value(v) for v in value.tolist()]
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, Path):
        return str(value)
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    raise TypeError(f"setting value {value!r} of type {type(value).__name__} is not JSON-able")


def dumps(value: Any) -> str:
    """Canonical JSON (sorted keys; inf written as ``Infinity``, which Python reads back)."""
    return json.dumps(to_json_value(value), sort_keys=True, separators=(",", ":"))


def _first_difference(stored: Any, requested: Any, prefix: str = "") -> tuple[str, Any, Any] | None:
    """Dotted path and both values of the first difference between two JSON trees, or None."""
    if isinstance(stored, dict) and isinstance(requested, dict):
        for key in sorted(set(stored) | set(requested)):
            path = f"{prefix}.{key}" if prefix else key
            if key not in stored:
                return path, "<absent>", requested[key]
            if key not in requested:
                return path, stored[key], "<absent>"
            diff = _first_difference(stored[key], requested[key], path)
            if diff:
                return diff
        return None
    if isinstance(stored, list) and isinstance(requested, list) and len(stored) == len(requested):
        for i, (a, b) in enumerate(zip(stored, requested)):
            diff = _first_difference(a, b, f"{prefix}[{i}]")
            if diff:
                return diff
        return None
    same = stored == requested or (
        isinstance(stored, float) and isinstance(requested, float) and math.isnan(stored) and math.isnan(requested)
    )
    return None if same else (prefix or "value", stored, requested)


class ShardStore:
    """A job store directory (see the module docstring for the layout).

    Use :meth:`open` to create a store or to reopen one; it refuses a store made with other
    settings. Only the job's parent process writes to a store.
    """

    def __init__(self, path: Path, settings: dict):
        self.path = Path(path)
        self.settings = settings

    # ---- creation and validation -------------------------------------------------------------
    @classmethod
    def open(cls, path: str | os.PathLike[str], settings: dict) -> ShardStore:
        """Create the store at ``path`` or reopen it, checking that its settings equal ``settings``.

        Raises
        ------
        JobSettingsError
            The store exists and one of its settings differs (the error names it).
        JobError
            ``path`` exists but is not a job store, or its ``job.json`` is unreadable.
        """
        path = Path(path)
        requested = json.loads(dumps(settings))
        settings_file = path / SETTINGS_FILE
        if path.exists() and not path.is_dir():
            raise JobError(f"{path} is a file, not a job store directory; choose another output directory")
        if settings_file.exists():
            try:
                header = json.loads(settings_file.read_text(encoding="utf-8"))
            except (OSError, ValueError) as exc:
                raise JobError(f"{settings_file} is not a readable job settings file: {exc}") from exc
            if not isinstance(header, dict):
                raise JobError(
                    f"{settings_file} is not a sandlight job settings file (it holds a JSON "
                    f"{type(header).__name__}, not an object); choose another output directory"
                )
            if header.get("format") != STORE_FORMAT:
                raise JobError(f"{path} is not a sandlight job store (format {header.get('format')!r})")
            if header.get("format_version") != STORE_FORMAT_VERSION:
                raise JobSettingsError(path, "format_version", header.get("format_version"), STORE_FORMAT_VERSION)
            diff = _first_difference(header.get("settings"), requested)
            if diff:
                raise JobSettingsError(path, *diff)
        else:
            if path.exists() and any(p.name not in (SHARD_DIR, LOCK_FILE) for p in path.iterdir()):
                raise JobError(
                    f"{path} exists, is not empty and is not a sandlight job store; choose another output directory"
                )
            path.mkdir(parents=True, exist_ok=True)
            header = {"format": STORE_FORMAT, "format_version": STORE_FORMAT_VERSION, "settings": requested}
            text = json.dumps(header, indent=1, sort_keys=True) + "\n"
            write_atomically(settings_file, lambda tmp: tmp.write_text(text, encoding="utf-8"))
        store = cls(path, requested)
        if store.shard_dir.exists() and not store.shard_dir.is_dir():
            raise JobError(f"{store.shard_dir} is a file, not the shard directory of a job store; {_DAMAGED}")
        store.shard_dir.mkdir(exist_ok=True)
        store._remove_stale_temporaries()
        return store

    @property
    def shard_dir(self) -> Path:
        return self.path / SHARD_DIR

    @property
    def dataset_path(self) -> Path:
        return self.path / DATASET_FILE

    def _remove_stale_temporaries(self) -> None:
        # Temporaries left by a writer that was killed mid-write; never visible as results. A
        # live process's temporaries are being written right now (e.g. a job running while
        # another process asks for its status): leave them.
        for directory in (self.path, self.shard_dir):
            remove_stale_temporaries(directory)

    def _shards(self) -> list[Path]:
        return sorted(p for p in self.shard_dir.iterdir() if _SHARD_RE.match(p.name))

    # ---- reading ----------------------------------------------------------------------------
    @staticmethod
    def _read(path: Path, names: list[str] | None = None) -> dict:
        import xarray as xr

        try:
            with xr.open_dataset(path) as ds:
                keys = list(ds.data_vars) if names is None else names
                return {k: ds[k].values for k in keys}
        except Exception as exc:  # any reader failure means the file cannot be trusted
            raise JobError(
                f"cannot read job file {path} ({exc}); delete it and run the job again (its tasks will be recomputed)"
            ) from exc

    def done_indices(self) -> set[int]:
        """Indices of the tasks whose results are stored.

        Raises
        ------
        JobError
            The dataset or a shard is unreadable or not of this job: a dataset made with other
            settings, a shard with task indices outside the job, or shards of different results.
        """
        n_tasks = int(self.settings["n_tasks"])
        if self.dataset_path.exists():
            # Written only once every task was done; its shards are gone.
            self._check_dataset(n_tasks)
            return set(range(n_tasks))
        done: set[int] = set()
        first = None
        for shard in self._shards():
            index, schema = self._shard_summary(shard)
            if index.dtype.kind not in "iu" or (index.size and not (index.min() >= 0 and index.max() < n_tasks)):
                raise JobError(
                    f"the shard {shard} holds task indices {index[:5].tolist()}... outside 0..{n_tasks - 1}: it is "
                    f"not of this job. Delete it (its tasks are recomputed) and run the job again"
                )
            if first is not None and schema != first[1]:
                raise JobError(
                    f"the shards {first[0].name} and {shard.name} in {self.shard_dir} hold different results "
                    f"({first[1]} and {schema}); {_DAMAGED}"
                )
            first = first or (shard, schema)
            done.update(index.tolist())
        return done

    def _shard_summary(self, path: Path) -> tuple[np.ndarray, dict]:
        """The task indices of a shard and ``{name: (dtype kind, shape)}`` of its results."""
        import xarray as xr

        try:
            with xr.open_dataset(path) as ds:
                schema = {k: (v.dtype.kind, v.shape[1:]) for k, v in ds.data_vars.items() if k != "index"}
                return ds["index"].values, schema
        except Exception as exc:  # any reader failure means the file cannot be trusted
            raise JobError(
                f"cannot read job file {path} ({exc}); delete it and run the job again (its tasks will be recomputed)"
            ) from exc

    def _check_dataset(self, n_tasks: int) -> None:
        """Refuse a dataset that is unreadable or was not consolidated from this store's job."""
        import xarray as xr

        try:
            with xr.open_dataset(self.dataset_path) as ds:
                settings = ds.attrs.get("job_settings")
                sizes = set(ds.sizes.values())
        except Exception as exc:  # any reader failure means the file cannot be trusted
            raise JobError(f"{self.dataset_path} is not a readable dataset ({exc}); {_DATASET_ADVICE}") from exc
        if settings != dumps(self.settings) or n_tasks not in sizes:
            raise JobError(f"{self.dataset_path} is not the dataset of this job store's job; {_DATASET_ADVICE}")

    def result_schema(self) -> dict | None:
        """``{name: (dtype kind, shape)}`` of the stored per-task results, or None if none stored."""
        shards = self._shards()
        if not shards:
            return None
        data = self._read(shards[0])
        return {k: (v.dtype.kind, v.shape[1:]) for k, v in data.items() if k != "index"}

    def read_results(self) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        """All stored results, one row per task index, sorted by index (duplicates dropped)."""
        parts = [self._read(s) for s in self._shards()]
        if not parts:
            return np.empty(0, dtype=np.int64), {}
        index = np.concatenate([p["index"] for p in parts])
        # np.unique returns the first occurrence of each index, sorted: duplicates (same task,
        # same seed, hence same values) are dropped, and the order no longer depends on the
        # order tasks finished in.
        index, first = np.unique(index, return_index=True)
        names = [k for k in parts[0] if k != "index"]
        return index, {k: np.concatenate([p[k] for p in parts])[first] for k in names}

    # ---- writing ----------------------------------------------------------------------------
    def write_shard(self, indices: Sequence[int], results: dict[str, np.ndarray], dims: dict[str, tuple]) -> Path:
        """Write one shard holding the results of tasks ``indices`` (atomic)."""
        import xarray as xr

        existing = [int(_SHARD_RE.match(p.name).group(1)) for p in self._shards()]
        number = max(existing, default=-1) + 1
        data = {"index": ("task", np.asarray(indices, dtype=np.int64))}
        for name, values in results.items():
            data[name] = (("task",) + tuple(dims[name]), values)
        ds = xr.Dataset(data)
        path = self.shard_dir / f"shard-{number:06d}.nc"
        write_atomically(path, ds.to_netcdf)
        return path

    def write_dataset(self, ds: xr.Dataset) -> Path:
        """Write the consolidated dataset (atomic), then drop the shards it supersedes."""
        write_atomically(self.dataset_path, ds.to_netcdf)
        for shard in self._shards():
            shard.unlink(missing_ok=True)
        return self.dataset_path
