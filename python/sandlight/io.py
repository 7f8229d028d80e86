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
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import xarray as xr

#: Temporary files end with this suffix (stores clean up leftovers of killed writers by it).
TEMPORARY_SUFFIX = ".part"


def temporary_sibling(path: str | os.PathLike) -> Path:
    """A fresh, unique temporary name in the directory of ``path``."""
    path = Path(path)
    return path.with_name(f".{path.name}.{os.getpid()}.{uuid.uuid4().hex[:12]}{TEMPORARY_SUFFIX}")


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike, *, make_dirs: bool = True) -> Iterator[Path]:
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


def write_atomically(path: str | os.PathLike, write: Callable[[Path], object], *, make_dirs: bool = True) -> Path:
    """Calls ``write(tmp)`` on a temporary path beside ``path``, then renames it onto ``path``."""
    with atomic_path(path, make_dirs=make_dirs) as tmp:
        write(tmp)
    return Path(path)


def read_netcdf_file(path: str | os.PathLike, *, kind: str, format_name: str, max_version: int) -> xr.Dataset:
    """Reads a sandlight NetCDF-4 file whose global attributes ``format`` and ``format_version``
    name its format, refusing anything else.

    ``kind`` (e.g. "BRDF") names the file in messages. Checks only the container and the two
    attributes; each format's reader checks its variables.

    Returns
    -------
    xarray.Dataset
        Loaded into memory (the file is closed).

    Raises
    ------
    FileNotFoundError
        ``path`` does not exist.
    sandlight.errors.ModelFileError
        The file is not readable NetCDF-4/HDF5 (truncated, corrupt), its ``format`` is not
        ``format_name`` (a foreign file), or its ``format_version`` is not an integer in
        1 .. ``max_version`` (e.g. written by a newer sandlight).
    """
    import numpy as np
    import xarray as xr

    from sandlight.errors import ModelFileError

    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"{path}: no such {kind} file")
    try:
        with xr.open_dataset(path, engine="h5netcdf") as ds:
            ds = ds.load()
    except Exception as exc:  # h5py/h5netcdf raise OSError, ValueError, KeyError… on damaged files
        raise ModelFileError(f"{path}: not a readable NetCDF-4 file (truncated or corrupt?): {exc}") from exc
    fmt = ds.attrs.get("format")
    if fmt != format_name:
        raise ModelFileError(
            f"{path}: not a sandlight {kind} file (global attribute format = {fmt!r}, expected {format_name!r})"
        )
    version = ds.attrs.get("format_version")
    version = version.item() if isinstance(version, np.generic) else version
    if not (isinstance(version, int) and not isinstance(version, bool) and 1 <= version <= max_version):
        readable = "version 1" if max_version == 1 else f"versions 1 to {max_version}"
        newer = isinstance(version, int) and version > max_version
        raise ModelFileError(
            f"{path}: {format_name} format version {version!r} is not supported (this sandlight reads "
            f"{readable}{'; the file was written by a newer sandlight: upgrade to read it' if newer else ''})"
        )
    return ds
