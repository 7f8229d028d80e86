"""The BRDF table file (format 'sandlight-brdf-table', version 1): layout, writer and reader.

Public objects
--------------
FORMAT_NAME, FORMAT_VERSION
    The ``format`` and ``format_version`` global attributes written and required.
table_dataset
    An ``xarray.Dataset`` in the layout below from arrays (the one place that names variables,
    dimensions, units and the format attributes).
write_table
    Write such a dataset atomically (temporary file + ``os.replace``).
read_table
    Read a table back; refuses missing, truncated, foreign, newer-format or incomplete files.

Writers: `sandlight.SandAppearance.to_table` (hat-averaged values on a uniform grid, with
``albedo`` and ``normal_reflectance``) and `sandlight.render.BrdfTable.to_netcdf` (a stack of
tables, point values on any grid). Reader: `sandlight.render.BrdfTable.from_netcdf`. The full
description, with the meaning of the values, is in docs/spatial-predictor.md.

Layout (NetCDF-4/HDF5 via xarray + h5netcdf)
--------------------------------------------
==========================  ==================================  =====  ==========================================
variable                    dimensions                          units  meaning
==========================  ==================================  =====  ==========================================
``f``                       ([level,] wavelength, mu_i, mu_o,   sr-1   BRDF, ≥ 0, reciprocal, even in Δφ
                            dphi)
``wavelength``              wavelength                          nm     ascending
``mu_i``, ``mu_o``          mu_i, mu_o                          1      cos θ, ascending, first 0 and last 1
``dphi``                    dphi                                rad    |φ_o − φ_i|, ascending, first 0, last π
level (any name, optional)  level                               —      parameter value of each level, ascending
``albedo`` (optional)       wavelength, mu_i                    1      directional-hemispherical reflectance
``normal_reflectance``      wavelength                          1      r(λ) at normal incidence
(optional)
==========================  ==================================  =====  ==========================================

Global attributes: ``format``, ``format_version``, ``sandlight_version``, ``title``,
``conventions``, ``interpolation`` (how the values were made and are to be interpolated), and the
writer's own (provenance: sample, models, source).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from sandlight.errors import ModelFileError, ParameterError
from sandlight.io import read_netcdf_file, write_atomically

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["FORMAT_NAME", "FORMAT_VERSION", "AXES", "table_dataset", "write_table", "read_table"]

FORMAT_NAME = "sandlight-brdf-table"
FORMAT_VERSION = 1
#: The last four dimensions of ``f``, in order.
AXES = ("wavelength", "mu_i", "mu_o", "dphi")
#: What the files call the directions and the BRDF.
CONVENTIONS = (
    "local frame: z = surface normal; mu = cos(zenith angle); dphi = |phi_o - phi_i| in [0, pi]; "
    "wi points towards the light, wo towards the viewer; f in sr-1 with "
    "L_o = integral of f L_i cos(theta_i) d(omega_i)"
)


def table_dataset(
    f: ArrayLike,
    wavelength_nm: ArrayLike,
    mu_i: ArrayLike,
    mu_o: ArrayLike,
    dphi: ArrayLike,
    *,
    interpolation: str,
    title: str = "Spectral BRDF table (sandlight)",
    attrs: dict | None = None,
    albedo: ArrayLike | None = None,
    normal_reflectance: ArrayLike | None = None,
    level_name: str | None = None,
    level_values: ArrayLike | None = None,
) -> xr.Dataset:
    """A BRDF table in the file layout (module docstring).

    Parameters
    ----------
    f : numpy.ndarray, shape ([levels,] wavelength, mu_i, mu_o, dphi)
        BRDF values, sr⁻¹ (a leading level axis requires ``level_name`` and ``level_values``).
    wavelength_nm, mu_i, mu_o, dphi : numpy.ndarray
        The axes: nm, cosines, cosines, radians.
    interpolation : str
        How the values were made and how to interpolate them (global attribute).
    title : str
        Global attribute ``title``.
    attrs : dict, optional
        The writer's further global attributes (provenance).
    albedo : numpy.ndarray, shape (wavelength, mu_i), optional
        Directional-hemispherical reflectance of the tabulated model, dimensionless.
    normal_reflectance : numpy.ndarray, shape (wavelength,), optional
        r(λ) at normal incidence, dimensionless.
    level_name : str, optional
        Name of the level dimension (e.g. ``"saturation"``).
    level_values : numpy.ndarray, shape (levels,), optional
        Parameter value of each level.

    Returns
    -------
    xarray.Dataset
    """
    import xarray as xr

    import sandlight
    from sandlight.io import WAVELENGTH_ATTRS, cf_attributes

    if (level_name is None) != (level_values is None) or np.ndim(f) != (4 if level_name is None else 5):
        raise ParameterError(
            "f",
            f"an array of shape {np.shape(f)} with level_name {level_name!r}",
            "f (wavelength, mu_i, mu_o, dphi), or f (level, ...) with level_name and level_values",
        )
    dims = AXES if level_name is None else (level_name, *AXES)
    data = {"f": (dims, f, {"units": "sr-1", "long_name": "bidirectional reflectance distribution function"})}
    if albedo is not None:
        data["albedo"] = (
            ("wavelength", "mu_i"),
            albedo,
            {"units": "1", "long_name": "directional-hemispherical reflectance of the continuous model"},
        )
    if normal_reflectance is not None:
        data["normal_reflectance"] = (
            ("wavelength",),
            normal_reflectance,
            {
                "units": "1",
                "long_name": "directional-hemispherical reflectance at normal incidence (spectral predictor)",
            },
        )
    coords = {
        "wavelength": ("wavelength", wavelength_nm, WAVELENGTH_ATTRS),
        "mu_i": ("mu_i", mu_i, {"units": "1", "long_name": "cosine of the incident zenith angle"}),
        "mu_o": ("mu_o", mu_o, {"units": "1", "long_name": "cosine of the outgoing zenith angle"}),
        "dphi": ("dphi", dphi, {"units": "rad", "long_name": "azimuth difference |phi_o - phi_i|"}),
    }
    if level_name is not None:
        level_attrs = {"units": "1", "long_name": f"{level_name} of each level"}
        coords = {level_name: (level_name, level_values, level_attrs), **coords}
    global_attrs = {
        **cf_attributes(title, "sandlight.appearance"),
        "format": FORMAT_NAME,
        "format_version": FORMAT_VERSION,
        "sandlight_version": sandlight.__version__,
        **(attrs or {}),
        "conventions": CONVENTIONS,
        "interpolation": interpolation,
    }
    return xr.Dataset(data, coords=coords, attrs=global_attrs)


def write_table(dataset: xr.Dataset, path: str | os.PathLike) -> Path:
    """Write a `table_dataset` to NetCDF-4 (h5netcdf, ``f`` compressed) atomically.

    The file is written under a temporary name beside ``path`` and moved into place, so a reader
    never sees a half-written table and an existing file survives a failed write.

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    ParameterError
        ``dataset`` does not carry this format's attributes (not made by `table_dataset`).
    """
    fmt = (dataset.attrs.get("format"), dataset.attrs.get("format_version"))
    if fmt != (FORMAT_NAME, FORMAT_VERSION):
        raise ParameterError("dataset", f"a dataset of format {fmt}", f"a {FORMAT_NAME} dataset (table_dataset)")
    encoding = {"f": {"zlib": True, "complevel": 4}}
    return write_atomically(path, lambda tmp: dataset.to_netcdf(tmp, engine="h5netcdf", encoding=encoding))


def read_table(path: str | os.PathLike) -> xr.Dataset:
    """Read a BRDF table file and check its format, version and layout.

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    xarray.Dataset
        In memory, with ``f`` and its four (or five) coordinates present as the layout requires.
        The values themselves (ascending axes, finite non-negative f) are checked by the reader
        that uses them (`sandlight.render.BrdfTable`).

    Raises
    ------
    FileNotFoundError
        No such file.
    sandlight.errors.ModelFileError
        Not readable NetCDF-4 (truncated, corrupt), not a 'sandlight-brdf-table' file (foreign),
        a format version this sandlight does not read (newer), or variables or coordinates
        missing or of the wrong dimensions.
    """
    path = Path(path)
    ds = read_netcdf_file(path, kind="BRDF table", format_name=FORMAT_NAME, max_version=FORMAT_VERSION)
    incomplete = f"{path}: incomplete {FORMAT_NAME} file"
    if "f" not in ds.data_vars:
        raise ModelFileError(f"{incomplete}: no variable 'f' (expected f(wavelength, mu_i, mu_o, dphi) in sr-1)")
    f = ds["f"]
    if f.ndim not in (4, 5) or tuple(f.dims[-4:]) != AXES:
        raise ModelFileError(
            f"{incomplete}: variable f has dimensions {f.dims}; expected (wavelength, mu_i, mu_o, dphi), "
            f"optionally after one level dimension"
        )
    for name in f.dims:
        if name not in ds.coords:
            raise ModelFileError(f"{incomplete}: no coordinate {name!r} (the axis values of f's dimension {name})")
    for name, dims in (("albedo", ("wavelength", "mu_i")), ("normal_reflectance", ("wavelength",))):
        if name in ds.data_vars and ds[name].dims != dims:
            raise ModelFileError(f"{incomplete}: variable {name} has dimensions {ds[name].dims}; expected {dims}")
    return ds
