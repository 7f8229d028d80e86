"""File writing shared by every writer in sandlight: nothing is ever left half-written.

Each writer produces its file under a temporary name beside the target and renames it into
place with ``os.replace``, atomic on one file system: a reader sees the old file or the complete
new one, never a partial write; a failed or interrupted write leaves no debris. The temporary
name is unique per call and created by the writer itself, so the final file gets the usual
permissions (umask), not the private mode of ``mkstemp``.
"""

from __future__ import annotations

import contextlib
import os
import uuid
from collections.abc import Callable, Iterator
from pathlib import Path

#: Temporary files end with this suffix (stores clean up leftovers of killed writers by it).
TEMPORARY_SUFFIX = ".part"

#: Bytes of the target's name kept in a temporary name. With the process id, the token and the
#: suffix a temporary name stays far below the 255-byte limit of a file name, whatever the
#: target's length (the whole name was kept, so a legal 230-byte name could not be written).
_NAME_BYTES = 64


def _name_prefix(name: str) -> str:
    # Cut in bytes, as the file system counts; a character cut in two decodes to surrogate
    # escapes, which os.fsencode turns back into the same bytes.
    return os.fsdecode(os.fsencode(name)[:_NAME_BYTES])


def temporary_sibling(path: str | os.PathLike[str]) -> Path:
    """A fresh, unique temporary name in the directory of ``path``: the first 64 bytes of its
    name, the process id and a random token (at most about 100 bytes in all)."""
    path = Path(path)
    return path.with_name(f".{_name_prefix(path.name)}.{os.getpid()}.{uuid.uuid4().hex[:12]}{TEMPORARY_SUFFIX}")


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike[str], *, make_dirs: bool = True) -> Iterator[Path]:
    """Yields a temporary path beside ``path``; on success it is renamed over ``path``.

    Parameters
    ----------
    path : str or os.PathLike
        The final file.
    make_dirs : bool
        Create missing parent directories; if False a missing directory raises
        ``FileNotFoundError`` naming it.
    """
    path = Path(path)
    parent = path.parent if str(path.parent) else Path(".")
    if make_dirs:
        parent.mkdir(parents=True, exist_ok=True)
    elif not parent.is_dir():
        raise FileNotFoundError(f"Output directory {str(parent)!r} does not exist (writing {str(path)!r}).")
    tmp = temporary_sibling(path)
    try:
        yield tmp
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def write_atomically(path: str | os.PathLike[str], write: Callable[[Path], object], *, make_dirs: bool = True) -> Path:
    """Calls ``write(tmp)`` on a temporary path beside ``path``, then renames it onto ``path``."""
    with atomic_path(path, make_dirs=make_dirs) as tmp:
        write(tmp)
    return Path(path)


def write_model_npz(path: str | os.PathLike[str], metadata: dict, arrays: dict, *, compressed: bool = False) -> Path:
    """Writes a trained model as plain arrays plus a JSON ``metadata`` entry (never pickle),
    atomically; :func:`read_model_npz` reads it back."""
    import json

    import numpy as np

    meta = np.array(json.dumps(metadata, sort_keys=True))
    save = np.savez_compressed if compressed else np.savez

    def write(tmp: Path) -> None:
        with open(tmp, "wb") as fh:
            save(fh, metadata=meta, **arrays)

    return write_atomically(path, write)


def read_model_npz(path: str | os.PathLike[str], *, kind: str, format_name: str, max_version: int) -> tuple[dict, dict]:
    """Reads a trained model stored as plain arrays plus a JSON ``metadata`` entry (never pickle).

    Every member is read in full, so zipfile checks its CRC-32 and a flipped bit anywhere is
    caught. ``kind`` (e.g. "spectral model") names the file in messages.

    Returns
    -------
    (metadata, arrays) : tuple of dict

    Raises
    ------
    sandlight.errors.ModelFileError
        The file is missing, truncated, corrupt, not a sandlight ``kind`` (format name) or of a
        format version outside 1 .. ``max_version``.
    """
    import json
    import zipfile

    import numpy as np

    from sandlight.errors import ModelFileError

    path = Path(path)
    if not path.is_file():
        raise ModelFileError(f"{kind} file {path} does not exist")
    try:
        with np.load(path, allow_pickle=False) as npz:
            if "metadata" not in npz.files:
                raise ModelFileError(f"{path} is not a sandlight {kind} (an .npz file without a metadata entry)")
            data = {name: npz[name] for name in npz.files}
    except ModelFileError:
        raise
    except (OSError, ValueError, EOFError, KeyError, zipfile.BadZipFile) as exc:
        raise ModelFileError(
            f"{path} is not a readable sandlight {kind} file (truncated, corrupt or another format): {exc}"
        ) from exc
    try:
        meta = json.loads(str(data["metadata"][()]))
    except (ValueError, TypeError) as exc:
        raise ModelFileError(f"{path}: the metadata entry is not valid JSON ({exc})") from exc
    if not isinstance(meta, dict) or meta.get("format") != format_name:
        raise ModelFileError(
            f"{path} is not a sandlight {kind} (format {meta.get('format') if isinstance(meta, dict) else None!r})"
        )
    version = meta.get("format_version")
    if not isinstance(version, int) or not 1 <= version <= max_version:
        raise ModelFileError(
            f"{path} has {kind} format version {version!r}; this sandlight reads versions "
            f"1..{max_version} (upgrade sandlight)"
        )
    return meta, data
