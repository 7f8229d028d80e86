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
from collections.abc import Callable
from pathlib import Path

#: Temporary files end with this suffix (stores clean up leftovers of killed writers by it).
TEMPORARY_SUFFIX = ".part"


def temporary_sibling(path) -> Path:
    """A fresh, unique temporary name in the directory of ``path``."""
    path = Path(path)
    return path.with_name(f".{path.name}.{os.getpid()}.{uuid.uuid4().hex[:12]}{TEMPORARY_SUFFIX}")


@contextlib.contextmanager
def atomic_path(path, *, make_dirs: bool = True):
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


def write_atomically(path, write: Callable[[Path], object], *, make_dirs: bool = True) -> Path:
    """Calls ``write(tmp)`` on a temporary path beside ``path``, then renames it onto ``path``."""
    with atomic_path(path, make_dirs=make_dirs) as tmp:
        write(tmp)
    return Path(path)
