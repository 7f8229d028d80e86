"""The explorer's downloads: the sample as TOML, the spectrum as CSV or NetCDF, the BRDF table
as NetCDF. Each is written by the package's own writer (so a download reads back like any other
sandlight file) into a fresh temporary directory under a name the server chooses, then sent.

A predicted spectrum is written as a ``reflectance`` variable on ``wavelength`` (nm) with the
model's name and hold-out error as attributes; a Monte Carlo job's spectrum is its
`sandlight.engine.ReflectanceResult` (``to_csv``, ``to_netcdf``: values, standard errors, counts).
"""

from __future__ import annotations

import json
import tempfile
from collections.abc import Callable
from pathlib import Path

import xarray as xr

from sandlight.appearance.table_file import write_table
from sandlight.engine import ReflectanceResult
from sandlight.io import WAVELENGTH_ATTRS, atomic_path, cf_attributes, write_csv
from sandlight.sample import SandSample
from sandlight.web.brdf_maps import appearance_of
from sandlight.web.spectra import Prediction

__all__ = ["EXPORTS", "sample_toml", "prediction_file", "reflectance_file", "brdf_table_file"]

#: What each export's file name ends with, and its media type.
EXPORTS = {
    "sample.toml": "application/toml",
    "spectrum.csv": "text/csv",
    "spectrum.nc": "application/x-netcdf",
    "brdf.nc": "application/x-netcdf",
}


def _written(suffix: str, write: Callable[[Path], object]) -> bytes:
    with tempfile.TemporaryDirectory(prefix="sandlight-export-") as folder:
        path = Path(folder) / f"export{suffix}"
        write(path)
        return path.read_bytes()


def sample_toml(sample: SandSample) -> bytes:
    """The sample as TOML (`SandSample.to_toml`), which `SandSample.from_file` reads back."""
    return sample.to_toml().encode("utf-8")


def _prediction_dataset(sample: SandSample, p: Prediction) -> xr.Dataset:
    return xr.Dataset(
        {"reflectance": ("wavelength", p.reflectance, {"units": "1", "long_name": "predicted reflectance"})},
        coords={"wavelength": ("wavelength", p.wavelengths_nm, WAVELENGTH_ATTRS)},
        attrs={
            **cf_attributes("Predicted directional-hemispherical reflectance of a sand", "sandlight serve"),
            "model": p.model,
            "model_description": p.description,
            "holdout_rms_error": p.holdout_rms,
            "sample": json.dumps(sample.to_dict(), sort_keys=True),
        },
    )


def prediction_file(sample: SandSample, p: Prediction, suffix: str) -> bytes:
    """A predicted spectrum as CSV (``suffix`` ".csv") or NetCDF (".nc")."""
    ds = _prediction_dataset(sample, p)
    if suffix == ".csv":
        rows = zip(p.wavelengths_nm, p.reflectance)
        return _written(
            suffix,
            lambda path: write_csv(path, ("wavelength_nm", "reflectance"), rows, ("%g", "%.6f"), ds.attrs),
        )

    def netcdf(path: Path) -> None:
        with atomic_path(path) as tmp:
            ds.to_netcdf(tmp, engine="h5netcdf")

    return _written(suffix, netcdf)


def reflectance_file(result: ReflectanceResult, suffix: str) -> bytes:
    """A Monte Carlo spectrum as CSV or NetCDF (`ReflectanceResult.to_csv` / ``to_netcdf``)."""
    return _written(suffix, result.to_csv if suffix == ".csv" else result.to_netcdf)


def brdf_table_file(sample: SandSample, n_mu: int, n_dphi: int) -> bytes:
    """The BRDF table of a sample (`SandAppearance.table`, format 'sandlight-brdf-table') as NetCDF."""
    app, _ = appearance_of(sample)
    return _written(".nc", lambda path: write_table(app.table(n_mu, n_dphi), path))
