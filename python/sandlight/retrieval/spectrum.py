"""The measured spectrum a fit starts from: a pair, a DataArray or a file, checked and in nm.

Public objects
--------------
as_spectrum
    Any accepted input as an :class:`xarray.DataArray` of reflectance (fraction) on a strictly
    increasing ``wavelength`` coordinate in nm, finite everywhere.
read_envi_library
    One spectrum of an ENVI spectral library (``.hdr`` + ``.sli``), read with the `spectral`
    package (Spectral Python).

Files are read by their format: ``.hdr``/``.sli`` as ENVI spectral libraries, text files whose
first line starts with ``splib07`` as USGS splib07 ASCII (:func:`sandlight.measured.read_usgs`),
any other text file as a two-column CSV (:func:`sandlight.measured.read_csv`). A file's deleted
channels (NaN) are dropped; in a pair or a DataArray given in memory, NaN is an error.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from sandlight.errors import ModelFileError, ParameterError
from sandlight.measured import measured_spectrum, read_csv, read_usgs

__all__ = ["as_spectrum", "read_envi_library", "MICROMETRE_LIMIT_NM"]

#: A wavelength grid ending below this many nm is taken for micrometres and refused: reflectance
#: spectra of sand start in the near ultraviolet (>= 300 nm), and 100 µm is beyond any of them.
MICROMETRE_LIMIT_NM = 100.0

#: ENVI header values of ``wavelength units`` meaning micrometres (lower case).
_ENVI_MICROMETRES = ("micrometers", "micrometer", "microns", "micron", "um", "µm")


def as_spectrum(measured: Any, *, name: str | None = None) -> xr.DataArray:
    """The measured spectrum as a checked DataArray on a ``wavelength`` coordinate in nm.

    Parameters
    ----------
    measured : (wavelengths_nm, reflectance) pair, xarray.DataArray, str or os.PathLike
        Two 1-D arrays of the same length; a 1-D DataArray with a ``wavelength`` dimension in
        nm (a ``units`` attribute, if present, must say nm); or a file (CSV, USGS splib07
        ASCII, ENVI spectral library ``.hdr``/``.sli``).
    name : str, optional
        The spectrum to take from an ENVI library holding several.

    Returns
    -------
    xarray.DataArray
        Reflectance (fraction), finite, on strictly increasing wavelengths in nm.

    Raises
    ------
    sandlight.errors.ParameterError
        Arrays of different lengths or shapes, fewer than two points, NaN or infinite values,
        wavelengths not strictly increasing, or a grid that looks like micrometres (ending
        below `MICROMETRE_LIMIT_NM`), or a reflectance outside [-0.5, 1.5] (percent?).
    sandlight.errors.ModelFileError, FileNotFoundError
        A malformed or missing file (the readers' messages name the file and the line).
    """
    if isinstance(measured, (str, os.PathLike)):
        spectrum = _read_file(Path(os.fspath(measured)), name)
        keep = np.isfinite(spectrum.values)
        if not keep.any():
            raise ModelFileError(f"{measured}: no finite reflectance value")
        return _checked(spectrum[keep], f"spectrum in {measured}")
    if isinstance(measured, xr.DataArray):
        if measured.ndim != 1 or "wavelength" not in measured.dims:
            raise ParameterError(
                "measured", f"a DataArray with dims {measured.dims}", "a 1-D DataArray along a 'wavelength' dimension"
            )
        units = measured["wavelength"].attrs.get("units", "nm") if "wavelength" in measured.coords else "nm"
        if str(units).strip().lower() != "nm":
            raise ParameterError("measured.wavelength units", units, "nm (convert the coordinate first)")
        wavelengths = measured["wavelength"].values if "wavelength" in measured.coords else None
        if wavelengths is None:
            raise ParameterError("measured", "a DataArray without a wavelength coordinate", "wavelengths in nm")
        return _checked(
            measured_spectrum(np.asarray(measured.values, float), np.asarray(wavelengths, float), dict(measured.attrs)),
            "measured",
        )
    if isinstance(measured, (tuple, list)) and len(measured) == 2:
        wl, r = (np.asarray(a, dtype=float) for a in measured)
        if wl.ndim != 1 or wl.shape != r.shape:
            raise ParameterError(
                "measured", f"arrays of shapes {wl.shape} and {r.shape}", "two 1-D arrays of the same length"
            )
        return _checked(measured_spectrum(r, wl, {"title": "measured"}), "measured")
    raise ParameterError(
        "measured",
        type(measured).__name__,
        "a (wavelengths_nm, reflectance) pair, an xarray.DataArray with a 'wavelength' coordinate "
        "in nm, or a file path",
    )


def _checked(spectrum: xr.DataArray, what: str) -> xr.DataArray:
    wl = spectrum["wavelength"].values
    r = spectrum.values
    if wl.size < 2:
        raise ParameterError(f"{what}: number of wavelengths", int(wl.size), "at least 2")
    for label, values in (("wavelength", wl), ("reflectance", r)):
        bad = ~np.isfinite(values)
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            where = f" at {wl[i]:g} nm" if label == "reflectance" else f" (point {i})"
            raise ParameterError(
                f"{what}: {label}{where}", float(values[i]), "a finite number (drop the point or mask its band)"
            )
    steps = np.diff(wl)
    if np.any(steps <= 0):
        i = int(np.flatnonzero(steps <= 0)[0])
        raise ParameterError(
            f"{what}: wavelengths", f"{wl[i]:g} then {wl[i + 1]:g}", "strictly increasing wavelengths in nm"
        )
    if wl[-1] < MICROMETRE_LIMIT_NM:
        raise ParameterError(
            f"{what}: wavelengths", f"{wl[0]:g}–{wl[-1]:g}", "nm (these look like micrometres: multiply by 1000)"
        )
    if r.min() < -0.5 or r.max() > 1.5:
        raise ParameterError(
            f"{what}: reflectance", f"{r.min():g}–{r.max():g}", "a fraction, about 0–1 (percent? divide by 100)"
        )
    return spectrum


def _read_file(path: Path, name: str | None) -> xr.DataArray:
    if not path.exists():
        raise FileNotFoundError(f"no such spectrum file: {path}")
    if path.suffix.lower() in (".hdr", ".sli"):
        return read_envi_library(path, name)
    with open(path, "rb") as f:
        head = f.read(64)
    if head.lstrip().lower().startswith(b"splib07"):
        return read_usgs(path)
    return read_csv(path)


def read_envi_library(path: str | os.PathLike, name: str | None = None) -> xr.DataArray:
    """One spectrum of an ENVI spectral library, read with `spectral` (``spectral.envi``).

    Parameters
    ----------
    path : str or os.PathLike
        The header (``.hdr``) or the data file (``.sli``); the other is found next to it.
    name : str, optional
        The spectrum's name in the header's ``spectra names``; required when there are several.

    Raises
    ------
    sandlight.errors.ModelFileError
        The header or data file is missing or malformed, it is not a spectral library, it has
        no wavelengths, or ``name`` is not one of its spectra (the message lists them).
    """
    import spectral.io.envi as envi

    path = Path(os.fspath(path))
    header = path.with_suffix(".hdr")
    data = path.with_suffix(".sli")
    for p in (header, data):
        if not p.is_file():
            raise ModelFileError(f"{path}: an ENVI spectral library needs {p.name} next to it")
    try:
        library = envi.open(str(header), str(data))
    except (envi.EnviException, ValueError, OSError, KeyError) as exc:
        raise ModelFileError(f"{header}: not a readable ENVI spectral library: {exc}") from exc
    if not hasattr(library, "spectra"):
        raise ModelFileError(f"{header}: an ENVI image, not a spectral library (file type 'ENVI Spectral Library')")
    centers = library.bands.centers
    if not centers:
        raise ModelFileError(f"{header}: no 'wavelength' list in the header")
    wl = np.asarray(centers, dtype=float)
    units = str(library.bands.band_unit or library.metadata.get("wavelength units", "")).strip().lower()
    if units in _ENVI_MICROMETRES:
        wl = wl * 1000.0
    elif units not in ("nanometers", "nanometer", "nm"):
        raise ModelFileError(f"{header}: wavelength units {units!r}; expected Micrometers or Nanometers")
    names = list(library.names or [])
    spectra = np.asarray(library.spectra, dtype=float)
    if name is None:
        if spectra.shape[0] != 1:
            raise ModelFileError(f"{header}: {spectra.shape[0]} spectra; choose one by name: {names}")
        row = 0
    elif name in names:
        row = names.index(name)
    else:
        raise ModelFileError(f"{header}: no spectrum named {name!r}; its spectra: {names}")
    scale = float(library.metadata.get("reflectance scale factor", 1.0) or 1.0)
    title = names[row] if names else header.stem
    return measured_spectrum(spectra[row] / scale, wl, {"title": title, "source_file": str(header), "units": "1"})
