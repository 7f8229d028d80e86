"""NetCDF storage of a `MeasuredBRDF` (format 'sandlight-brdf', version 1).

Public objects
--------------
to_netcdf
    Write a measured BRDF atomically (temporary file + ``os.replace``).
read_netcdf
    Read it back; refuses truncated, foreign or newer-format files with `ModelFileError`.
FORMAT_NAME, FORMAT_VERSION
    The ``format`` and ``format_version`` global attributes written and required.

Layout (NetCDF-4/HDF5 via xarray + h5netcdf; r patches, m unique values)
-------------------------------------------------------------------------
Dimensions ``incoming`` (r), ``outgoing`` (r), ``patch`` (r), ``unique`` (m), ``xyz`` (3).

==============================  ====================  =====  ==========================================
variable                        dimensions            units  meaning
==============================  ====================  =====  ==========================================
counts                          incoming, outgoing    1      raw n[i, j] (shared run: Σ F, float)
squares                         incoming, outgoing    1      shared run only: Σ F² per cell
absorbed, launched, lost        incoming              1      raw counters per incoming patch
brdf                            incoming, outgoing    sr-1   reduced f̂ (normalised), full array
unique_brdf                     unique                sr-1   the m unique values of f̂
unique_brdf_stderr              unique                sr-1   their standard errors
unique_brdf_absolute            unique                sr-1   f̄ before normalisation
unique_brdf_absolute_stderr     unique                sr-1   its standard errors
unique_members                  unique                1      entries averaged into each value
unique_band_in/out, delta       unique                1      canonical (band_in, band_out, Δslice)
normal_reflectance(_stderr)     (scalar)              1      R and its standard error
centroid                        patch, xyz            1      unit centroid vectors
cos_theta_min/max               patch                 1      patch bounds in cos θ
phi_min/max                     patch                 rad    patch bounds in azimuth
solid_angle                     patch                 sr     2π/r each
projected_solid_angle           patch                 sr     ω_p, summing to π
==============================  ====================  =====  ==========================================

A run with spectral path sharing (``sandlight.brdf`` over several wavelengths, docs/transport.md)
stores weight sums: ``counts``, ``absorbed`` and ``lost`` are float64 sums of the trials'
weights F, and the variable ``squares`` (absent otherwise) holds Σ F² per cell, which the
standard errors need (`sandlight.gonio.reduction`). ``launched`` always counts trials.

Global attributes: ``format``, ``format_version``, ``sandlight_version``, ``stacks``, ``slices``,
``rays``, ``seed`` (absent if None), ``wavelength_nm`` (absent if None), ``sample`` (JSON),
``reduction_method``.
"""

from __future__ import annotations

import json
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from sandlight.errors import ModelFileError, ParameterError
from sandlight.gonio.brdf import MeasuredBRDF
from sandlight.gonio.hemisphere import CollectorHemisphere
from sandlight.gonio.reduction import ReducedBRDF, check_sums
from sandlight.gonio.symmetry import EquivalenceClasses
from sandlight.io import read_netcdf_file, write_atomically

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["to_netcdf", "read_netcdf", "FORMAT_NAME", "FORMAT_VERSION"]

FORMAT_NAME = "sandlight-brdf"
FORMAT_VERSION = 1

_COMPRESSED = {"zlib": True, "complevel": 4}


def _dataset(brdf: MeasuredBRDF) -> xr.Dataset:
    import xarray as xr

    from sandlight.io import cf_attributes

    h = brdf.hemisphere
    classes = brdf.classes
    red = brdf.reduced
    pair = ("incoming", "outgoing")

    def var(dims: str | tuple[str, ...], data: ArrayLike, units: str, long_name: str) -> xr.Variable:
        return xr.Variable(dims, data, {"units": units, "long_name": long_name})

    data = {
        "counts": var(pair, brdf.counts, "1", "trials with incidence in patch i escaping into patch j"),
        "absorbed": var("incoming", brdf.absorbed, "1", "trials absorbed, per incoming patch"),
        "launched": var("incoming", brdf.launched, "1", "all trials (escaped + absorbed + lost), per incoming patch"),
        "lost": var("incoming", brdf.lost, "1", "trials stopped by the event cap or transmitted, per incoming patch"),
        "brdf": var(pair, brdf.values, "sr-1", "reduced BRDF normalised to unit reflectance at normal incidence"),
        "unique_brdf": var("unique", red.unique_values, "sr-1", "unique values of the normalised BRDF"),
        "unique_brdf_stderr": var("unique", red.unique_stderr, "sr-1", "standard error of unique_brdf"),
        "unique_brdf_absolute": var(
            "unique", red.unique_absolute, "sr-1", "unique values of the BRDF before normalisation"
        ),
        "unique_brdf_absolute_stderr": var(
            "unique", red.unique_absolute_stderr, "sr-1", "standard error of unique_brdf_absolute"
        ),
        "unique_members": var("unique", red.members, "1", "entries averaged into each unique value"),
        "unique_band_in": var("unique", classes.band_in, "1", "incoming band of the class (0 = cap)"),
        "unique_band_out": var("unique", classes.band_out, "1", "outgoing band of the class (0 = cap)"),
        "unique_delta": var("unique", classes.delta, "1", "slice difference (outgoing - incoming) mod slices"),
        "normal_reflectance": var(
            (), red.normal_reflectance, "1", "directional-hemispherical reflectance at normal incidence"
        ),
        "normal_reflectance_stderr": var(
            (), red.normal_reflectance_stderr, "1", "standard error of normal_reflectance"
        ),
        "centroid": var(("patch", "xyz"), h.centroids, "1", "unit vector of the patch centroid"),
        "cos_theta_min": var("patch", h.bounds[:, 0], "1", "lower patch bound in cos(zenith)"),
        "cos_theta_max": var("patch", h.bounds[:, 1], "1", "upper patch bound in cos(zenith)"),
        "phi_min": var("patch", h.bounds[:, 2], "rad", "start azimuth of the patch"),
        "phi_max": var("patch", h.bounds[:, 3], "rad", "end azimuth of the patch"),
        "solid_angle": var("patch", h.solid_angles, "sr", "solid angle of the patch"),
        "projected_solid_angle": var("patch", h.projected_solid_angles, "sr", "projected solid angle of the patch"),
    }
    if brdf.squares is not None:
        data["squares"] = var(pair, brdf.squares, "1", "sum of squared trial weights, per (incoming, outgoing) patch")
    attrs = {
        **cf_attributes("BRDF measured by the sandlight virtual goniophotometer", "sandlight.gonio.brdf"),
        "format": FORMAT_NAME,
        "format_version": FORMAT_VERSION,
        "sandlight_version": brdf.sandlight_version,
        "stacks": brdf.stacks,
        "slices": brdf.slices,
        "rays": brdf.rays,
        "reduction_method": brdf.reduction_method,
        "sample": json.dumps(brdf.sample, sort_keys=True),
    }
    if brdf.seed is not None:
        attrs["seed"] = np.uint64(brdf.seed)  # an integer of the full range [0, 2**64)
    if brdf.wavelength_nm is not None:
        attrs["wavelength_nm"] = brdf.wavelength_nm
    return xr.Dataset(data, attrs=attrs)


def to_netcdf(brdf: MeasuredBRDF, path: str | PathLike) -> Path:
    """Write ``brdf`` to ``path`` (NetCDF-4, h5netcdf) atomically.

    The file is written to a temporary file in the same directory and moved into place with
    ``os.replace``, so a reader never sees a half-written file and an existing file survives a
    failed write.

    Parameters
    ----------
    brdf : MeasuredBRDF
    path : str or os.PathLike
        Destination, conventionally ``*.nc``.

    Returns
    -------
    pathlib.Path
        The path written.
    """
    if not isinstance(brdf, MeasuredBRDF):
        raise ParameterError("brdf", type(brdf).__name__, "must be a MeasuredBRDF")
    path = Path(path)
    ds = _dataset(brdf)
    encoding = {name: dict(_COMPRESSED) for name in ("counts", "brdf", "squares") if name in ds}
    return write_atomically(path, lambda tmp: ds.to_netcdf(tmp, engine="h5netcdf", encoding=encoding), make_dirs=False)


def read_netcdf(path: str | PathLike) -> MeasuredBRDF:
    """Read a BRDF written by `to_netcdf`.

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    MeasuredBRDF
        Equal (``==``) to the object written.

    Raises
    ------
    FileNotFoundError
        If ``path`` does not exist.
    sandlight.errors.ModelFileError
        If the file is not readable NetCDF/HDF5 (e.g. truncated), is not a 'sandlight-brdf'
        file, has another format version, or its variables are missing or inconsistent.
    """
    path = Path(path)
    ds = read_netcdf_file(path, kind="BRDF", format_name=FORMAT_NAME, max_version=FORMAT_VERSION)
    try:
        return _from_dataset(ds)
    except (KeyError, ValueError, TypeError) as exc:  # ParameterError is a ValueError
        raise ModelFileError(f"{path}: inconsistent {FORMAT_NAME} file: {exc}") from exc


def _from_dataset(ds: xr.Dataset) -> MeasuredBRDF:
    attrs = ds.attrs
    h = CollectorHemisphere(int(attrs["stacks"]), int(attrs["slices"]))
    squares = ds["squares"].values if "squares" in ds else None
    counts, absorbed, launched, lost, squares = check_sums(
        h, ds["counts"].values, ds["absorbed"].values, ds["launched"].values, ds["lost"].values, squares
    )
    m = EquivalenceClasses(h).n_classes

    def unique(name: str) -> np.ndarray:
        a = ds[name].values
        if a.shape != (m,):
            raise ValueError(f"variable {name} has shape {a.shape}, expected ({m},)")
        return a

    if not np.allclose(ds["centroid"].values, h.centroids, rtol=0, atol=1e-12):
        raise ValueError("patch centroids differ from this sandlight's collector hemisphere")
    reduced = ReducedBRDF(
        unique_values=unique("unique_brdf"),
        unique_stderr=unique("unique_brdf_stderr"),
        unique_absolute=unique("unique_brdf_absolute"),
        unique_absolute_stderr=unique("unique_brdf_absolute_stderr"),
        members=unique("unique_members").astype(np.int64),
        normal_reflectance=float(ds["normal_reflectance"].values),
        normal_reflectance_stderr=float(ds["normal_reflectance_stderr"].values),
    )
    for a in (counts, absorbed, launched, lost, squares):
        if a is not None:
            a.setflags(write=False)
    return MeasuredBRDF(
        stacks=h.stacks,
        slices=h.slices,
        counts=counts,
        absorbed=absorbed,
        launched=launched,
        lost=lost,
        reduced=reduced,
        sample=json.loads(attrs["sample"]),
        wavelength_nm=float(attrs["wavelength_nm"]) if "wavelength_nm" in attrs else None,
        rays=int(attrs["rays"]),
        seed=int(attrs["seed"]) if "seed" in attrs else None,
        sandlight_version=str(attrs["sandlight_version"]),
        reduction_method=str(attrs["reduction_method"]),
        squares=squares,
    )
