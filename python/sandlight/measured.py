"""Measured reflectance spectra: USGS Spectral Library (splib07) ASCII files and two-column CSV.

Public objects
--------------
read_usgs
    A USGS splib07 ASCII spectrum with its wavelengths, as an :class:`xarray.DataArray`.
read_csv
    A two-column CSV spectrum (wavelength in nm, reflectance), as an :class:`xarray.DataArray`.
usgs_library
    Path of a splib07a spectrum by name, in the package copies or the project's shared data.

Both readers return reflectance as a fraction (0–1) on a ``wavelength`` coordinate in nm, with
NaN where the file marks a channel as deleted or leaves it blank. Malformed files raise
:class:`sandlight.errors.ModelFileError` naming the file and the line; missing files raise
:class:`FileNotFoundError`.

The package ships two validation spectra and the Beckman wavelength file in
``sandlight/data/measured/`` (public domain; see the README there); the rest of the library is
read from wherever the user keeps it.

References
----------
Kokaly, R. F., Clark, R. N., Swayze, G. A., Livo, K. E., Hoefen, T. M., Pearson, N. C.,
Wise, R. A., Benzel, W. M., Lowers, H. A., Driscoll, R. L., Klein, A. J. (2017). *USGS Spectral
Library Version 7*. U.S. Geological Survey Data Series 1035, https://doi.org/10.3133/ds1035.
"""

from __future__ import annotations

import glob
import math
import os
import re
from pathlib import Path

import numpy as np
import xarray as xr

from sandlight.errors import ModelFileError, ParameterError

__all__ = ["read_usgs", "read_csv", "usgs_library", "measured_spectrum"]

USGS_CITATION = (
    "Kokaly, R.F., et al., 2017, USGS Spectral Library Version 7: U.S. Geological "
    "Survey Data Series 1035, https://doi.org/10.3133/ds1035 (public domain)"
)
# splib07 marks deleted or bad channels with -1.23e34; anything below -1e34 is that marker.
_USGS_DELETED_BELOW = -1e34
# A CSV whose largest reflectance exceeds this is read as percent (see read_csv, Domain).
_FRACTION_MAX = 1.5
_PERCENT_MAX = 150.0

_PACKAGE_MEASURED = Path(__file__).resolve().parent / "data" / "measured"


def _read_lines(path: Path) -> list[str]:
    with open(path, encoding="utf-8", errors="strict") as f:
        try:
            return f.read().splitlines()
        except UnicodeDecodeError as exc:
            raise ModelFileError(f"{path}: not a text file ({exc.reason})") from None


def _read_usgs_column(path: Path) -> tuple[str, np.ndarray]:
    """Header and values of a splib07 ASCII file (header line, then one number per line).

    Deleted channels become NaN. Trailing blank lines are ignored; any other blank, non-numeric
    or non-finite line is an error naming the line.
    """
    lines = _read_lines(path)
    while lines and not lines[-1].strip():
        lines.pop()
    if not lines:
        raise ModelFileError(f"{path}: empty file, expected a splib07 header line and values")
    header = lines[0].strip()
    if _is_number(header) or not header:
        raise ModelFileError(
            f"{path}, line 1: expected the splib07 header line "
            f"(e.g. 'splib07a Record=...: <title>'), found {lines[0]!r}"
        )
    values = np.empty(len(lines) - 1)
    for i, line in enumerate(lines[1:]):
        try:
            value = float(line)
        except ValueError:
            raise ModelFileError(f"{path}, line {i + 2}: expected one number per line, found {line!r}") from None
        if not math.isfinite(value):
            raise ModelFileError(
                f"{path}, line {i + 2}: non-finite value {line.strip()!r} "
                f"(splib07 marks deleted channels with -1.23e34)"
            )
        values[i] = math.nan if value < _USGS_DELETED_BELOW else value
    if values.size == 0:
        raise ModelFileError(f"{path}: header line but no values")
    return header, values


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _find_wavelength_file(spectrum: Path, channels: int) -> Path:
    """The splib07 wavelength file next to `spectrum` whose channel count is `channels`."""
    matches = []
    for candidate in sorted(spectrum.parent.glob("*Wavelengths*")):
        if candidate.is_file():
            with open(candidate, encoding="utf-8", errors="replace") as f:
                count = sum(1 for line in f if line.strip()) - 1  # minus the header line
            if count == channels:
                matches.append(candidate)
    if len(matches) != 1:
        found = "none" if not matches else ", ".join(m.name for m in matches)
        raise ModelFileError(
            f"{spectrum}: cannot choose its wavelengths automatically: {channels} channels, "
            f"matching '*Wavelengths*' files in {spectrum.parent}: {found}. Pass "
            f"wavelengths=<path of the splib07 wavelength file> (e.g. "
            f"splib07a_Wavelengths_BECK_Beckman_0.2-3.0_microns.txt for 480 channels, "
            f"splib07a_Wavelengths_ASD_0.35-2.5_microns_2151_ch.txt for 2151)"
        )
    return matches[0]


def read_usgs(path: str | os.PathLike, wavelengths: str | os.PathLike | None = None) -> xr.DataArray:
    """Read a USGS Spectral Library Version 7 (splib07) ASCII spectrum.

    Parameters
    ----------
    path : str or os.PathLike
        The spectrum file: one header line (e.g. ``splib07a Record=9302: Quartz GDS74 Sand
        Ottawa BECKc AREF``), then one value per line, channel by channel; ``-1.23e34`` marks a
        deleted channel.
    wavelengths : str or os.PathLike, optional
        The splib07 wavelength file of the spectrometer (same layout, wavelengths in µm, one per
        channel). By default it is found next to `path` among files named ``*Wavelengths*`` by
        its channel count (480 for the Beckman BECK, 2151 for the ASD FieldSpec).

    Returns
    -------
    xarray.DataArray
        ``reflectance`` (dimensionless; for AREF files the absolute directional-hemispherical
        reflectance, 0–1) along dimension ``wavelength`` (vacuum wavelength in nm, converted
        from µm, increasing). Deleted channels are NaN. Attributes: ``title`` (the header line),
        ``source_file``, ``wavelength_file``, ``units``, ``deleted_channels``, ``citation``.

    Raises
    ------
    FileNotFoundError
        `path` or `wavelengths` does not exist.
    sandlight.errors.ModelFileError
        A file is empty, lacks its header line, has a non-numeric line (the message names file
        and line), the channel counts differ, the wavelengths are not strictly increasing or
        contain deleted values, or no unique wavelength file can be found automatically.

    Examples
    --------
    >>> spectrum = read_usgs(usgs_library("Quartz_GDS74_Sand_Ottawa_BECKc_AREF"))
    >>> spectrum.sizes["wavelength"]
    480
    >>> float(spectrum.sel(wavelength=550, method="nearest")) > 0.3
    True
    """
    path = Path(os.fspath(path))
    header, values = _read_usgs_column(path)
    wavelength_path = _find_wavelength_file(path, values.size) if wavelengths is None else Path(os.fspath(wavelengths))
    _, wavelength_um = _read_usgs_column(wavelength_path)
    if wavelength_um.size != values.size:
        raise ModelFileError(
            f"{path}: {values.size} channels, but the wavelength file {wavelength_path} has {wavelength_um.size}"
        )
    if np.any(np.isnan(wavelength_um)):
        line = int(np.flatnonzero(np.isnan(wavelength_um))[0]) + 2
        raise ModelFileError(f"{wavelength_path}, line {line}: deleted value in a wavelength file")
    steps = np.diff(wavelength_um)
    if np.any(steps <= 0):
        line = int(np.flatnonzero(steps <= 0)[0]) + 3
        raise ModelFileError(f"{wavelength_path}, line {line}: wavelengths are not strictly increasing")
    wavelength_nm = wavelength_um * 1000.0  # splib07 wavelength files are in micrometres
    return measured_spectrum(
        values,
        wavelength_nm,
        {
            "title": " ".join(header.split()),
            "source_file": str(path),
            "wavelength_file": str(wavelength_path),
            "units": "1",
            "long_name": "reflectance (fraction)",
            "deleted_channels": int(np.count_nonzero(np.isnan(values))),
            "citation": USGS_CITATION,
        },
    )


def measured_spectrum(values: np.ndarray, wavelength_nm: np.ndarray, attrs: dict) -> xr.DataArray:
    """A measured reflectance spectrum as the readers return it: ``values`` on the vacuum
    wavelengths ``wavelength_nm`` (nm), with the file's ``attrs``."""
    return xr.DataArray(
        values,
        dims="wavelength",
        coords={"wavelength": ("wavelength", wavelength_nm, {"units": "nm", "long_name": "vacuum wavelength"})},
        name="reflectance",
        attrs=attrs,
    )


def _split(line: str) -> list[str]:
    for delimiter in (",", ";", "\t"):
        if delimiter in line:
            return [field.strip() for field in line.split(delimiter)]
    return line.split()


def read_csv(path: str | os.PathLike) -> xr.DataArray:
    """Read a two-column reflectance spectrum: wavelength in nm, reflectance.

    Parameters
    ----------
    path : str or os.PathLike
        Text file with two columns separated by a comma (or semicolon, tab or spaces). Lines
        starting with ``#`` and blank lines are ignored. The first remaining line may be a
        header row (e.g. ``wavelength_nm,reflectance``); every other line holds two fields,
        the reflectance field may be empty (missing channel → NaN). Wavelengths must be strictly
        increasing. A first header field naming µm (``um``, ``µm``, ``micron``) means the
        wavelengths are in micrometres.

    Returns
    -------
    xarray.DataArray
        ``reflectance`` as a fraction along ``wavelength`` (nm). Attributes: ``source_file``,
        ``units``, ``reflectance_scale_in_file`` (``"fraction"`` or ``"percent"``).

    Raises
    ------
    FileNotFoundError
        `path` does not exist.
    sandlight.errors.ModelFileError
        Empty file, a line without exactly two fields, a non-numeric value, wavelengths not
        strictly increasing, wavelengths that look like µm without a header saying so, or
        reflectance beyond any plausible scale. The message names the file and the line.

    Notes
    -----
    **Domain** of the reflectance column (the scale is detected, never guessed per value):

    ============================  =====================
    values in file                read as
    ============================  =====================
    all ≤ 1.5                      fraction (0–1)
    any in (1.5, 150]              percent, divided by 100
    header names ``%``/percent     percent, divided by 100
    any > 150                      error
    ============================  =====================

    **Range** of the result: fraction; values are not clipped (noise may give small negative
    values, bright calibrated targets slightly more than 1).
    """
    path = Path(os.fspath(path))
    lines = _read_lines(path)
    rows: list[tuple[int, float, float]] = []
    header: list[str] | None = None
    for lineno, raw in enumerate(lines, start=1):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        fields = _split(line)
        if len(fields) != 2:
            raise ModelFileError(
                f"{path}, line {lineno}: expected 2 columns (wavelength_nm, "
                f"reflectance), found {len(fields)} in {raw!r}"
            )
        if not rows and header is None and not _is_number(fields[0]):
            header = fields
            continue
        try:
            wavelength = float(fields[0])
            reflectance = float(fields[1]) if fields[1] else math.nan
        except ValueError:
            raise ModelFileError(f"{path}, line {lineno}: expected two numbers, found {raw!r}") from None
        if not math.isfinite(wavelength):
            raise ModelFileError(f"{path}, line {lineno}: wavelength {fields[0]!r} is not finite")
        if rows and wavelength <= rows[-1][1]:
            raise ModelFileError(
                f"{path}, line {lineno}: wavelengths are not strictly increasing ({wavelength:g} after {rows[-1][1]:g})"
            )
        rows.append((lineno, wavelength, reflectance))
    if not rows:
        raise ModelFileError(f"{path}: no data rows (empty file or only comments/header)")
    wavelength = np.array([r[1] for r in rows])
    reflectance = np.array([r[2] for r in rows])

    first_name = header[0].lower() if header else ""
    if re.search(r"(\bum\b|_um\b|µm|micron)", first_name):
        wavelength = wavelength * 1000.0
    elif wavelength.max() < 100.0:
        raise ModelFileError(
            f"{path}: wavelengths end at {wavelength.max():g}, which looks like "
            f"micrometres; convert to nm or name the first column "
            f"'wavelength_um'"
        )

    finite = reflectance[np.isfinite(reflectance)]
    if finite.size == 0:
        raise ModelFileError(f"{path}: no reflectance values (every reflectance cell is empty)")
    says_percent = header is not None and re.search(r"%|percent", header[1].lower()) is not None
    peak = float(np.max(finite))
    if peak > _PERCENT_MAX:
        line = rows[int(np.nanargmax(reflectance))][0]
        raise ModelFileError(
            f"{path}, line {line}: reflectance {peak:g} exceeds {_PERCENT_MAX:g};"
            f" expected a fraction (0-1) or percent (0-100)"
        )
    scale = "percent" if (says_percent or peak > _FRACTION_MAX) else "fraction"
    if scale == "percent":
        reflectance = reflectance / 100.0
    return measured_spectrum(
        reflectance,
        wavelength,
        {
            "title": path.stem,
            "source_file": str(path),
            "units": "1",
            "long_name": "reflectance (fraction)",
            "reflectance_scale_in_file": scale,
        },
    )


def _shared_usgs_folder() -> Path | None:
    """The project's shared ``data/measured/usgs_splib07a/ascii`` folder: from the environment
    variable ``SANDLIGHT_SHARED`` (the ``shared`` folder), else the first ``shared/`` above this
    file (a source tree) or above the working directory (an installed package run from a
    checkout)."""
    sub = Path("data") / "measured" / "usgs_splib07a" / "ascii"
    if os.environ.get("SANDLIGHT_SHARED"):
        candidate = Path(os.environ["SANDLIGHT_SHARED"]) / sub
        return candidate if candidate.is_dir() else None
    for start in (Path(__file__).resolve(), Path.cwd().resolve() / "."):
        for parent in start.parents:
            candidate = parent / "shared" / sub
            if candidate.is_dir():
                return candidate
    return None


def usgs_library(stem: str, root: str | os.PathLike | None = None) -> Path:
    """Path of a splib07a ASCII spectrum, found by its name.

    Parameters
    ----------
    stem : str
        The spectrum's name as in the library file names without the ``splib07a_`` prefix and
        ``.txt`` suffix, e.g. ``"Quartz_GDS74_Sand_Ottawa_BECKc_AREF"``; a unique prefix such
        as ``"Quartz_GDS74"`` is enough.
    root : str or os.PathLike, optional
        Folder holding splib07a ASCII files, or a ``usgs_splib07a`` folder with an ``ascii/``
        subfolder. By default the spectra shipped with sandlight are searched first, then the
        project's shared folder ``shared/data/measured/usgs_splib07a/ascii`` found above the
        installed package (as in the source tree next to the repository).

    Returns
    -------
    pathlib.Path
        The spectrum file; pass it to :func:`read_usgs`.

    Raises
    ------
    FileNotFoundError
        No spectrum matches `stem` in the folders searched (the message lists them).
    sandlight.errors.ParameterError
        `stem` is empty or matches several spectra (the message lists them).
    """
    if not isinstance(stem, str) or not stem.strip():
        raise ParameterError("stem", stem, "a splib07a spectrum name such as 'Quartz_GDS74_Sand_Ottawa_BECKc_AREF'")
    stem = stem.strip()
    if stem.startswith("splib07a_"):
        stem = stem[len("splib07a_") :]
    if stem.endswith(".txt"):
        stem = stem[: -len(".txt")]
    if root is not None:
        root = Path(os.fspath(root))
        folders = [root, root / "ascii"]
    else:
        folders = [_PACKAGE_MEASURED]
        shared = _shared_usgs_folder()
        if shared is not None:
            folders.append(shared)
    for folder in folders:
        if not folder.is_dir():
            continue
        exact = folder / f"splib07a_{stem}.txt"
        if exact.is_file():
            return exact
        matches = [
            p
            for p in sorted(folder.glob(f"splib07a_{glob.escape(stem)}*.txt"))
            if "Wavelengths" not in p.name and "Bandpass" not in p.name
        ]
        if len(matches) == 1:
            return matches[0]
        if len(matches) > 1:
            raise ParameterError(
                "stem",
                stem,
                f"a name matching one spectrum; in {folder} it matches " + ", ".join(p.name for p in matches),
            )
    raise FileNotFoundError(f"no splib07a spectrum named {stem!r} in " + ", ".join(str(f) for f in folders))
