"""The model file: how sandlight's fitted predictors are stored (plain arrays + JSON, never pickle).

A model file is the zip archive `numpy.savez` writes (members stored, or deflated when the format
says so):

==================  ===========================================================================
member              content
==================  ===========================================================================
``metadata.npy``    a 0-d unicode array holding a JSON object: ``format`` (the format's name,
                    e.g. ``"sandlight-spectral-model"``), ``format_version`` (int),
                    ``sandlight_version`` (that wrote it), then the model's own entries
``NAME.npy``        one plain numeric array per name the format declares (no object dtype)
==================  ===========================================================================

:meth:`ModelFileFormat.read` trusts nothing in the file. In this order it checks

1. that the file is a regular file and a zip archive; if not, the message says what the file is
   not, and what its first bytes say it is (NetCDF, HDF5, a single ``.npy``, a pickle);
2. the zip directory, before any member is read: only ``metadata.npy`` and the declared arrays,
   no duplicate names, each member's declared size within `MAX_METADATA_BYTES` or
   `MAX_ARRAY_BYTES` and their sum within `MAX_FILE_BYTES` (an unknown 3 GB member is refused
   without being read: issue 24 #8);
3. each member's ``.npy`` header: a plain dtype and a shape whose size in bytes is exactly what
   the member holds, so that nothing larger than the file is ever allocated;
4. the metadata: JSON text nested at most `MAX_JSON_DEPTH` levels (no ``RecursionError``), a JSON
   object of this format and a version in 1 .. ``version``.

Members are read in full with ``allow_pickle=False``, so zipfile checks every CRC-32. Checks of
the model's own content (shapes that fit together, finite values) are the model's.

Public objects
--------------
ModelFileFormat
    One format: name, newest version, the arrays; ``write`` (atomic) and ``read``.
ModelVersionWarning, warn_if_other_version
    A model file written by another sandlight version was loaded.
jsonable
    A JSON-able copy of metadata (numpy scalars and arrays become Python values).
sandlight_version
    The version written into every model file.
"""

from __future__ import annotations

import json
import re
import warnings
import zipfile
import zlib
from collections import Counter
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from sandlight.errors import ModelFileError
from sandlight.io import write_atomically

#: Largest ``metadata.npy`` member, bytes (shipped models: < 20 kB).
MAX_METADATA_BYTES = 16 * 2**20
#: Largest array member, bytes (shipped models: < 0.5 MB; a spatial model on a 60-stack
#: hemisphere would need ~20 MB).
MAX_ARRAY_BYTES = 256 * 2**20
#: Largest sum of the members' sizes, bytes.
MAX_FILE_BYTES = 1024 * 2**20
#: Deepest nesting of arrays and objects in the metadata JSON (shipped models: 5).
MAX_JSON_DEPTH = 32

METADATA = "metadata"

#: First bytes of formats a model file may be mistaken for, with what to call them.
_SIGNATURES = (
    (b"CDF\x01", "a NetCDF-3 file"),
    (b"CDF\x02", "a NetCDF-3 file"),
    (b"CDF\x05", "a NetCDF-3 file"),
    (b"\x89HDF\r\n\x1a\n", "an HDF5 or NetCDF-4 file"),
    (b"\x93NUMPY", "a single numpy array (.npy), not an .npz archive"),
    (b"\x80\x02", "a Python pickle"),
    (b"\x80\x03", "a Python pickle"),
    (b"\x80\x04", "a Python pickle"),
    (b"\x80\x05", "a Python pickle"),
)
_JSON_STRING = re.compile(r'"(?:[^"\\]|\\.)*"', re.DOTALL)


class ModelVersionWarning(UserWarning):
    """A model file written by another sandlight version was loaded (it may predict differently
    from a model trained with this version's engine)."""


def sandlight_version() -> str:
    """The version of the running sandlight."""
    import sandlight

    return sandlight.__version__


def jsonable(value: Any) -> Any:
    """JSON-able copy of metadata: numpy scalars and arrays become Python values, tuples lists,
    mapping keys strings."""
    if isinstance(value, Mapping):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return jsonable(value.tolist())
    if isinstance(value, np.generic):
        return value.item()
    return value


def warn_if_other_version(path: Path, metadata: Mapping, *, stacklevel: int = 2) -> None:
    """Warn `ModelVersionWarning` when ``metadata`` was written by another sandlight version."""
    written = metadata.get("sandlight_version")
    if written != sandlight_version():
        warnings.warn(
            f"{path} was written by sandlight {written}, this is sandlight {sandlight_version()}: "
            f"predictions follow the engine that trained the model",
            ModelVersionWarning,
            stacklevel=stacklevel + 1,
        )


@dataclass(frozen=True)
class ModelFileFormat:
    """One model-file format.

    Parameters
    ----------
    name : str
        Value of the metadata's ``format`` (e.g. ``"sandlight-spectral-model"``).
    version : int
        Format version written; versions 1 .. ``version`` are read.
    kind : str
        What the file holds, in messages (e.g. ``"spectral model"``).
    arrays : tuple of str
        Arrays every file has.
    optional : tuple of str
        Arrays a file may have.
    compressed : bool
        Deflate the members when writing.
    """

    name: str
    version: int
    kind: str
    arrays: tuple[str, ...]
    optional: tuple[str, ...] = ()
    compressed: bool = False

    # ---- writing ---------------------------------------------------------------------------
    def write(self, path: str | Path, metadata: Mapping, arrays: Mapping[str, np.ndarray]) -> Path:
        """Write ``arrays`` and the JSON ``metadata`` (the format's header added) atomically.

        Returns the path.
        """
        unknown = sorted(set(arrays) - set(self.arrays) - set(self.optional))
        missing = sorted(set(self.arrays) - set(arrays))
        if unknown or missing:  # a programming error, not bad input
            raise ValueError(f"{self.name}: arrays {unknown} are not declared, {missing} are missing")
        header = {"format": self.name, "format_version": self.version, "sandlight_version": sandlight_version()}
        text = np.array(json.dumps(jsonable({**metadata, **header}), sort_keys=True))
        save = np.savez_compressed if self.compressed else np.savez

        def write(tmp: Path) -> None:
            with open(tmp, "wb") as fh:
                save(fh, allow_pickle=False, **{METADATA: text}, **arrays)

        return write_atomically(path, write)

    # ---- reading ---------------------------------------------------------------------------
    def read(self, path: str | Path) -> tuple[dict, dict[str, np.ndarray]]:
        """Read a file of this format after the checks of the module docstring.

        Returns
        -------
        (metadata, arrays) : tuple of dict
            The metadata (a dict) and the arrays by name (the optional ones when present).

        Raises
        ------
        sandlight.errors.ModelFileError
            The file is missing, not a regular file, not a zip archive, truncated or corrupt,
            holds members other than this format's or too large ones, an object array, metadata
            that is not JSON or nested too deep, another format, or a newer format version; or
            a required array is missing.
        """
        path = Path(path)
        if not path.exists():
            raise ModelFileError(f"{self.kind} file {path} does not exist")
        if not path.is_file():
            raise ModelFileError(f"{path} is not a {self.kind} file: not a regular file")
        try:
            with zipfile.ZipFile(path) as archive:
                members = self._check_directory(path, archive)
                meta = self._read_metadata(path, archive, members.pop(f"{METADATA}.npy"))
                data = {name[: -len(".npy")]: self._read_array(path, archive, info) for name, info in members.items()}
        except ModelFileError:
            raise
        except zipfile.BadZipFile as exc:
            raise ModelFileError(
                f"{path} is not a readable sandlight {self.kind} file: not a zip (.npz) archive, or a "
                f"truncated or corrupt one{_what_it_is(path)} ({exc})"
            ) from exc
        except (OSError, ValueError, EOFError, zlib.error) as exc:
            raise ModelFileError(
                f"{path} is not a readable sandlight {self.kind} file (truncated or corrupt): {exc}"
            ) from exc
        missing = [a for a in self.arrays if a not in data]
        if missing:
            raise ModelFileError(f"{path} is an incomplete {self.kind} file: missing arrays {missing}")
        return meta, data

    def _check_directory(self, path: Path, archive: zipfile.ZipFile) -> dict[str, zipfile.ZipInfo]:
        """The members by name, after the checks of the zip directory (nothing is read yet)."""
        infos = archive.infolist()
        names = [info.filename for info in infos]
        if f"{METADATA}.npy" not in names:
            raise ModelFileError(f"{path} is not a sandlight {self.kind} (an .npz file without a metadata entry)")
        repeated = sorted(n for n, count in Counter(names).items() if count > 1)
        if repeated:
            raise ModelFileError(f"{path} is not a sandlight {self.kind} file: members {repeated} appear twice")
        known = {f"{a}.npy" for a in (METADATA, *self.arrays, *self.optional)}
        unknown = [n for n in names if n not in known]
        if unknown:
            raise ModelFileError(
                f"{path} is not a sandlight {self.kind} file: it has members {_short(unknown)} that a "
                f"{self.kind} file does not have (it has metadata and {', '.join(self.arrays + self.optional)})"
            )
        for info in infos:
            limit = MAX_METADATA_BYTES if info.filename == f"{METADATA}.npy" else MAX_ARRAY_BYTES
            if info.file_size > limit:
                raise ModelFileError(
                    f"{path} is not a usable {self.kind} file: member {info.filename} declares "
                    f"{info.file_size} bytes, more than the {limit} bytes allowed"
                )
        total = sum(info.file_size for info in infos)
        if total > MAX_FILE_BYTES:
            raise ModelFileError(
                f"{path} is not a usable {self.kind} file: its members declare {total} bytes, "
                f"more than the {MAX_FILE_BYTES} bytes allowed"
            )
        return dict(zip(names, infos))

    def _read_array(self, path: Path, archive: zipfile.ZipFile, info: zipfile.ZipInfo) -> np.ndarray:
        """A member's array, after checking that its header describes what the member holds."""
        with archive.open(info) as fh:
            version = np.lib.format.read_magic(fh)
            if version == (1, 0):
                shape, _, dtype = np.lib.format.read_array_header_1_0(fh)
            elif version == (2, 0):
                shape, _, dtype = np.lib.format.read_array_header_2_0(fh)
            else:
                raise ModelFileError(f"{path}: member {info.filename} is an .npy of unsupported version {version}")
            if dtype.hasobject:
                raise ModelFileError(
                    f"{path} is not a sandlight {self.kind} file: member {info.filename} holds Python "
                    f"objects (a pickle), which sandlight never loads"
                )
            expected = int(np.prod(shape, dtype=np.int64)) * dtype.itemsize
            if fh.tell() + expected != info.file_size:
                raise ModelFileError(
                    f"{path}: member {info.filename} declares an array of {shape} {dtype} "
                    f"({expected} bytes) but holds {info.file_size - fh.tell()} bytes"
                )
        with archive.open(info) as fh:
            array = np.lib.format.read_array(fh, allow_pickle=False)
            fh.read(1)  # at the end of the member: zipfile has checked its CRC-32
        return array

    def _read_metadata(self, path: Path, archive: zipfile.ZipFile, info: zipfile.ZipInfo) -> dict:
        """The metadata, checked for format and version."""
        entry = self._read_array(path, archive, info)
        if entry.shape != () or entry.dtype.kind != "U":
            raise ModelFileError(f"{path}: the metadata entry is not JSON text (a {entry.dtype} array {entry.shape})")
        text = str(entry[()])
        depth = json_depth(text)
        if depth > MAX_JSON_DEPTH:
            raise ModelFileError(
                f"{path}: the metadata JSON is nested {depth} levels deep; a {self.kind} has at most {MAX_JSON_DEPTH}"
            )
        try:
            meta = json.loads(text)
        except ValueError as exc:
            raise ModelFileError(f"{path}: the metadata entry is not valid JSON ({exc})") from exc
        if not isinstance(meta, dict) or meta.get("format") != self.name:
            found = meta.get("format") if isinstance(meta, dict) else None
            raise ModelFileError(f"{path} is not a sandlight {self.kind} (format {found!r})")
        version = meta.get("format_version")
        if isinstance(version, bool) or not isinstance(version, int) or not 1 <= version <= self.version:
            raise ModelFileError(
                f"{path} has {self.kind} format version {version!r}; this sandlight reads versions "
                f"1..{self.version} (upgrade sandlight)"
            )
        return meta


def json_depth(text: str) -> int:
    """Deepest nesting of arrays and objects in JSON text (brackets inside strings not counted)."""
    codes = np.frombuffer(_JSON_STRING.sub('""', text).encode("utf-8"), dtype=np.uint8)
    steps = np.isin(codes, (ord("["), ord("{"))).astype(np.int64) - np.isin(codes, (ord("]"), ord("}")))
    return int(np.cumsum(steps).max(initial=0))


def _what_it_is(path: Path) -> str:
    """ ", it looks like <a known format>" from the first bytes of ``path``, or ""."""
    try:
        with open(path, "rb") as fh:
            head = fh.read(8)
    except OSError:
        return ""
    for signature, what in _SIGNATURES:
        if head.startswith(signature):
            return f"; it looks like {what}"
    return ""


def _short(names: list[str]) -> str:
    """At most five names, for messages."""
    return str(names) if len(names) <= 5 else f"{names[:5]} and {len(names) - 5} more"
