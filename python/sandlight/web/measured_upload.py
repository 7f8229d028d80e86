"""An uploaded measured spectrum, read with sandlight's own readers, and its RMS against the model.

The upload's bytes are written to a fresh temporary directory under a fixed name chosen by the
server (never a name or path from the request) and read there with `sandlight.measured.read_csv`
or `read_usgs`; messages name the upload as the client named it, not the temporary file. A
splib07 ASCII file is read with the shipped Beckman wavelength file (480 channels).

The RMS compares the model's spectrum with the measurement brought to the model's wavelengths
(`sandlight.validation.scoring.measured_on_grid`: the mean of the channels within ±5 nm, else
the interpolation across a gap of at most 50 nm), over the wavelengths where both exist.
"""

from __future__ import annotations

import math
import tempfile
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from sandlight.checks import check_choice
from sandlight.errors import ModelFileError
from sandlight.measured import read_csv, read_usgs
from sandlight.validation.scoring import measured_on_grid
from sandlight.web.spectra import Prediction

__all__ = ["FORMATS", "read_upload", "overlay_answer"]

#: The formats of an upload; "auto" picks splib07 when the first line starts with "splib07".
FORMATS = ("auto", "csv", "usgs")

_BECKMAN = "splib07a_Wavelengths_BECK_Beckman_0.2-3.0_microns.txt"


def _display_name(name: str) -> str:
    """The client's file name as text for messages only (last component, printable, short)."""
    base = name.replace("\\", "/").rsplit("/", 1)[-1]
    base = "".join(c for c in base if c.isprintable())[:80]
    return base or "the upload"


def read_upload(data: bytes, filename: str, form: str = "auto") -> xr.DataArray:
    """The spectrum in an uploaded file's ``data`` (reflectance on ``wavelength`` in nm).

    Raises
    ------
    ParameterError
        ``form`` is not one of `FORMATS`.
    ModelFileError
        The data is not a spectrum of that format (the message names the upload and the line).
    """
    form = check_choice("format", form, FORMATS)
    if form == "auto":
        form = "usgs" if data.lstrip()[:7].lower() == b"splib07" else "csv"
    shown = _display_name(filename)
    with tempfile.TemporaryDirectory(prefix="sandlight-upload-") as folder:
        path = Path(folder) / ("upload.txt" if form == "usgs" else "upload.csv")
        path.write_bytes(data)
        try:
            if form == "csv":
                spectrum = read_csv(path)
            else:
                with resources.as_file(resources.files("sandlight") / "data" / "measured" / _BECKMAN) as wl:
                    spectrum = read_usgs(path, wavelengths=wl)
        except (ModelFileError, FileNotFoundError) as exc:
            raise ModelFileError(str(exc).replace(str(path), shown)) from None
        spectrum.load()
    spectrum.attrs = {k: v for k, v in spectrum.attrs.items() if k not in ("source_file", "wavelength_file")}
    spectrum.attrs["upload"] = shown
    spectrum.attrs["format"] = form
    return spectrum


def _json_numbers(values: np.ndarray) -> list[float | None]:
    return [float(v) if math.isfinite(v) else None for v in values]


def overlay_answer(spectrum: xr.DataArray, prediction: Prediction) -> dict[str, Any]:
    """The body of ``POST /api/measured``: the measured spectrum and, when a model covers the
    sample, its RMS difference from the model over their common wavelengths."""
    answer: dict[str, Any] = {
        "name": spectrum.attrs["upload"],
        "format": spectrum.attrs["format"],
        "title": str(spectrum.attrs.get("title", "")),
        "wavelengths_nm": _json_numbers(spectrum["wavelength"].values),
        "reflectance": _json_numbers(spectrum.values),
        "model": prediction.model,
        "rms": None,
        "compared_nm": [],
    }
    if prediction.covered:
        measured = measured_on_grid(spectrum, prediction.wavelengths_nm)
        both = np.isfinite(measured)
        if both.any():
            diff = prediction.reflectance[both] - measured[both]
            answer["rms"] = float(np.sqrt(np.mean(diff**2)))
            answer["compared_nm"] = prediction.wavelengths_nm[both].tolist()
    return answer
