"""File writing shared by every writer in sandlight: nothing is ever left half-written.

Each writer produces its file under a temporary name beside the target and renames it into
place with ``os.replace``, atomic on one file system: a reader sees the old file or the complete
new one, never a partial write; a failed or interrupted write leaves no debris. The temporary
name is unique per call and created by the writer itself, so the final file gets the usual
permissions (umask), not the private mode of ``mkstemp``.

A writer killed outright (``kill -9``, power loss) cannot remove its temporary file. The name
holds the writer's process id, so the next write of the same target removes temporaries whose
writer is gone (:func:`remove_stale_temporaries`; job stores do the same for their directories).
"""

from __future__ import annotations

import contextlib
import os
import re
import stat
import uuid
import warnings
from collections.abc import Callable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import PIL.Image
    import xarray as xr

from sandlight.errors import ParameterError

#: Temporary files end with this suffix (stores clean up leftovers of killed writers by it).
TEMPORARY_SUFFIX = ".part"

#: Bytes of the target's name kept in a temporary name. With the process id, the token and the
#: suffix a temporary name stays far below the 255-byte limit of a file name, whatever the
#: target's length (the whole name was kept, so a legal 230-byte name could not be written).
_NAME_BYTES = 64

#: ".<name prefix>.<pid>.<12 hex digits>.part", as made by `temporary_sibling`.
_TEMPORARY_RE = re.compile(r"^\.(?P<prefix>.*)\.(?P<pid>\d+)\.[0-9a-f]{12}" + re.escape(TEMPORARY_SUFFIX) + "$", re.S)

#: Slack of the comparison between a file's modification time and a process's start time (the
#: start time is derived from the boot time, which the kernel gives to the second).
_CLOCK_SLACK_S = 2.0


def _name_prefix(name: str) -> str:
    # Cut in bytes, as the file system counts; a character cut in two decodes to surrogate
    # escapes, which os.fsencode turns back into the same bytes.
    return os.fsdecode(os.fsencode(name)[:_NAME_BYTES])


def temporary_sibling(path: str | os.PathLike[str]) -> Path:
    """A fresh, unique temporary name in the directory of ``path``: the first 64 bytes of its
    name, the process id and a random token (at most about 100 bytes in all)."""
    path = Path(path)
    return path.with_name(f".{_name_prefix(path.name)}.{os.getpid()}.{uuid.uuid4().hex[:12]}{TEMPORARY_SUFFIX}")


def is_stale_temporary(path: str | os.PathLike[str]) -> bool:
    """True if ``path`` is a temporary file of `temporary_sibling` whose writer is gone: no
    process has its id, or the process that has it started after the file was last written
    (process ids are reused). A temporary of a live writer is being written: False."""
    import psutil

    path = Path(path)
    match = _TEMPORARY_RE.match(path.name)
    if match is None:
        return False
    try:
        started = psutil.Process(int(match["pid"])).create_time()
        modified = path.stat().st_mtime
    except psutil.NoSuchProcess:
        return True
    except (psutil.Error, OSError):  # not ours to judge (another user's process) or already gone
        return False
    return modified < started - _CLOCK_SLACK_S


def remove_stale_temporaries(directory: str | os.PathLike[str], target: str | None = None) -> int:
    """Remove the stale temporaries (see `is_stale_temporary`) in ``directory``: those of the
    file named ``target``, or all of them if ``target`` is None. Returns how many were removed."""
    prefix = None if target is None else _name_prefix(target)
    removed = 0
    with contextlib.suppress(OSError), os.scandir(directory) as entries:
        for entry in entries:
            match = _TEMPORARY_RE.match(entry.name)
            if match and prefix in (None, match["prefix"]) and is_stale_temporary(entry.path):
                with contextlib.suppress(FileNotFoundError):
                    os.unlink(entry.path)
                    removed += 1
    return removed


def read_regular_file(path: str | os.PathLike[str], what: str, *, max_bytes: int) -> bytes:
    """The bytes of the regular file at ``path`` (a symlink is followed), at most ``max_bytes``.

    Anything else is refused without being read: a directory, a device (a symlink to
    ``/dev/zero`` was read until memory ran out), a FIFO (reading one waits for a writer for
    ever), a socket. The file is opened without blocking and checked on the open descriptor,
    so it cannot be swapped for something else between the check and the read.

    Parameters
    ----------
    what : str
        What the file is, for messages (e.g. ``"sample file"``).

    Raises
    ------
    FileNotFoundError
        Nothing at ``path``.
    ParameterError
        Not a regular file, or larger than ``max_bytes``.
    """
    path = Path(path)
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            raise ParameterError(what, str(path), "a regular file (not a directory, device, pipe or socket)")
        data = bytearray()
        while len(data) <= max_bytes:  # one byte more than allowed tells a file that is too large
            chunk = os.read(fd, max_bytes + 1 - len(data))
            if not chunk:
                break
            data += chunk
    finally:
        os.close(fd)
    if len(data) > max_bytes:
        raise ParameterError(what, str(path), f"a file of at most {max_bytes:,} bytes")
    return bytes(data)


@contextlib.contextmanager
def open_image(path: str | os.PathLike[str], what: str, *, bytes_per_pixel: float) -> Iterator[PIL.Image.Image]:
    """The image file at ``path`` opened by pillow, its pixels not yet decoded, once its size is
    known to fit: ``bytes_per_pixel`` (what the caller's work needs per pixel, estimated) times
    the pixel count must be within `sandlight.checks.MAX_ALLOCATION_BYTES`.

    Pillow's own guard against decompression bombs (an error beyond about 179 million pixels, a
    warning from half that) is turned into the same kind of message: a 30000² heightfield raised
    an uncaught ``DecompressionBombError``, a 12000² photo to colourise needed 7.3 GB.

    Raises
    ------
    FileNotFoundError
        Nothing at ``path``.
    ParameterError
        ``what`` = the path: too many pixels, with the memory needed and the limit.
    PIL.UnidentifiedImageError, OSError
        Not an image pillow reads (the callers say what they expected).
    """
    from PIL import Image

    from sandlight.checks import MAX_ALLOCATION_BYTES, check_allocation

    path = Path(path)
    with warnings.catch_warnings():
        # The check below says more than pillow's warning (the memory and the limit).
        warnings.simplefilter("ignore", Image.DecompressionBombWarning)
        try:
            image = Image.open(path)
        except Image.DecompressionBombError as exc:
            most = int(MAX_ALLOCATION_BYTES / bytes_per_pixel)
            raise ParameterError(what, str(path), f"an image of at most {most:,} pixels (pillow: {exc})") from None
    with image:
        width, height = image.size
        check_allocation(what, f"{path} ({width}×{height} pixels)", width * height * bytes_per_pixel)
        yield image


def _existing_ancestor(path: Path) -> Path:
    """``path`` or its nearest ancestor that exists (``.`` for a relative path)."""
    for candidate in (path, *path.parents):
        if candidate.exists():
            return candidate
    return Path(".")


def _check_writable_directory(directory: Path, name: str, target: Path) -> None:
    if not directory.is_dir():
        raise ParameterError(name, str(target), f"a path in a directory, but {str(directory)!r} is a file")
    if not os.access(directory, os.W_OK | os.X_OK):
        raise ParameterError(name, str(target), f"a path in a directory you can write to ({str(directory)!r} is not)")


def check_output_file(
    path: str | os.PathLike[str], name: str, suffixes: Sequence[str] | None = None, *, make_dirs: bool = False
) -> Path:
    """Refuse, before any work is done, an output file that cannot be written.

    Parameters
    ----------
    path : str or os.PathLike
        The file a command will write (and overwrite if it exists).
    name : str
        The option or parameter naming it in messages, e.g. ``"--output"``.
    suffixes : sequence of str, optional
        The allowed suffixes, lower case with the dot (e.g. ``(".nc", ".csv")``): the format
        written is the one the suffix says.
    make_dirs : bool
        The writer creates missing directories (`atomic_path`): then the nearest existing one
        must be writable; otherwise the file's directory must exist and be writable.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    ParameterError
        Wrong suffix, a directory where the file should be, a missing, non-directory or
        unwritable directory.
    """
    path = Path(path)
    if path.is_dir():
        raise ParameterError(name, str(path), "a file, but this is a directory")
    if suffixes is not None and path.suffix.lower() not in suffixes:
        raise ParameterError(name, str(path), "a file name ending in " + " or ".join(suffixes))
    parent = path.parent
    if not make_dirs and not parent.exists():
        raise ParameterError(name, str(path), f"a path in an existing directory ({str(parent)!r} does not exist)")
    _check_writable_directory(_existing_ancestor(parent), name, path)
    return path


def check_output_directory(path: str | os.PathLike[str], name: str) -> Path:
    """Refuse, before any work is done, an output directory that cannot be written: an
    existing file, or a path whose nearest existing directory is not writable (missing
    directories are created by the writers).

    Raises
    ------
    ParameterError
        The message names ``name`` (e.g. ``"--out"``), the path and what is wrong.
    """
    path = Path(path)
    existing = _existing_ancestor(path)
    if existing == path and not path.is_dir():
        raise ParameterError(name, str(path), "a directory, but this is a file")
    _check_writable_directory(existing, name, path)
    return path


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
    remove_stale_temporaries(parent, path.name)
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


#: The version of the CF metadata conventions the NetCDF outputs follow: global ``Conventions``,
#: ``title``, ``source``, ``history`` and ``references``; ``units`` and ``long_name`` on every
#: variable and coordinate.
CF_CONVENTIONS = "CF-1.10"

#: The CF attributes of a wavelength coordinate.
WAVELENGTH_ATTRS = {"units": "nm", "long_name": "vacuum wavelength", "standard_name": "radiation_wavelength"}


def cf_attributes(title: str, made_by: str) -> dict[str, str]:
    """The CF global attributes of a NetCDF output: ``Conventions``, ``title``, ``source`` (this
    sandlight's version), ``history`` (what wrote the file, ``made_by``, e.g. "sandlight.reflectance")
    and ``references``.

    ``history`` has no time stamp, so that the same inputs give the same file, byte for byte.
    """
    import sandlight

    version = sandlight.__version__
    return {
        "Conventions": CF_CONVENTIONS,
        "title": title,
        "source": f"sandlight {version} (Monte Carlo light transport in sand)",
        "history": f"written by {made_by} (sandlight {version})",
        "references": "Sandlight documentation, docs/ in the source distribution",
    }


def write_csv(
    path: str | os.PathLike[str],
    columns: Sequence[str],
    rows: Sequence[Sequence[object]] | object,
    formats: Sequence[str],
    metadata: Mapping[str, object],
) -> Path:
    """Write a CSV file atomically: its metadata as ``# key: value`` comment lines (what a NetCDF
    output keeps in its attributes: what made it, units, settings), then the header of
    ``columns`` and one line per row, each value formatted with its ``formats`` entry ("%.6g").

    Read it back with ``pandas.read_csv(path, comment="#")``.
    """
    # "Conventions" names the NetCDF conventions: not said of a CSV file.
    comment = "".join(
        f"# {key}: {' '.join(str(value).splitlines())}\n" for key, value in metadata.items() if key != "Conventions"
    )
    body = "".join(",".join(f % v for f, v in zip(formats, row)) + "\n" for row in rows)
    text = comment + ",".join(columns) + "\n" + body
    return write_atomically(path, lambda tmp: tmp.write_text(text, encoding="utf-8"))


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
