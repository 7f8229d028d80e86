import json
import os

import numpy as np
import pytest
import xarray as xr

from sandlight.errors import ModelFileError
from sandlight.gonio import CollectorHemisphere, MeasuredBRDF, read_netcdf, to_netcdf
from sandlight.gonio.io import FORMAT_NAME, FORMAT_VERSION
from sandlight.testing import synthetic_brdf


@pytest.fixture(scope="module")
def small_brdf():
    h = CollectorHemisphere(7, 6)
    c = synthetic_brdf.sample_counts(
        h, synthetic_brdf.chandrasekhar_probabilities(h, 0.8), 10**6, seed=3, lost_probability=0.01
    )
    return MeasuredBRDF.from_counts(
        **c,
        stacks=7,
        slices=6,
        sample={"name": "test", "grain_size_um": [150, 300]},
        wavelength_nm=632.8,
        seed=3,
        method="pooled",
    )


def test_round_trip_gives_the_same_object(tmp_path, chandrasekhar_brdf):
    path = to_netcdf(chandrasekhar_brdf, tmp_path / "brdf.nc")
    back = read_netcdf(path)
    assert back == chandrasekhar_brdf
    np.testing.assert_array_equal(back.values, chandrasekhar_brdf.values)
    assert os.listdir(tmp_path) == ["brdf.nc"]  # no temporary file left behind


def test_round_trip_small_with_pooled_and_without_optional_metadata(tmp_path, small_brdf):
    assert read_netcdf(to_netcdf(small_brdf, tmp_path / "a.nc")) == small_brdf
    bare = MeasuredBRDF.from_counts(
        small_brdf.counts, small_brdf.absorbed, small_brdf.launched, small_brdf.lost, stacks=7, slices=6
    )
    back = read_netcdf(to_netcdf(bare, tmp_path / "b.nc"))
    assert back == bare and back.wavelength_nm is None and back.seed is None and back.sample == {}


def test_round_trip_of_a_shared_run_keeps_its_weight_sums(tmp_path):
    from sandlight.gonio.measure import brdf

    shared = brdf("red-dune", [500.0, 600.0], rays=3_000, stacks=5, slices=4, seed=1, progress=False)[1]
    path = to_netcdf(shared, tmp_path / "shared.nc")
    assert read_netcdf(path) == shared
    ds = xr.open_dataset(path, engine="h5netcdf")
    assert ds["counts"].dtype == np.float64 and ds["squares"].dims == ("incoming", "outgoing")
    ds.close()


def test_file_contents_units_and_attributes(tmp_path, small_brdf):
    path = to_netcdf(small_brdf, tmp_path / "brdf.nc")
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        assert ds.attrs["format"] == FORMAT_NAME and ds.attrs["format_version"] == FORMAT_VERSION
        assert json.loads(ds.attrs["sample"]) == small_brdf.sample
        assert ds.attrs["wavelength_nm"] == 632.8 and ds.attrs["seed"] == 3 and ds.attrs["rays"] == 10**6
        assert (ds.attrs["stacks"], ds.attrs["slices"]) == (7, 6)
        assert ds.attrs["reduction_method"] == "pooled"
        assert "sandlight_version" in ds.attrs
        for name, var in ds.data_vars.items():
            assert "units" in var.attrs, name
        assert ds["brdf"].attrs["units"] == "sr-1" and ds["solid_angle"].attrs["units"] == "sr"
        assert ds["counts"].shape == (37, 37) and ds["unique_brdf"].shape == (small_brdf.unique_values.size,)
        np.testing.assert_array_equal(ds["counts"].values, small_brdf.counts)
        np.testing.assert_allclose(ds["projected_solid_angle"].values.sum(), np.pi, rtol=1e-13)


def test_overwrite_replaces_atomically(tmp_path, small_brdf, chandrasekhar_brdf):
    path = tmp_path / "brdf.nc"
    to_netcdf(chandrasekhar_brdf, path)
    to_netcdf(small_brdf, path)
    assert read_netcdf(path) == small_brdf
    assert sorted(os.listdir(tmp_path)) == ["brdf.nc"]


def test_truncated_file_is_refused(tmp_path, small_brdf):
    path = to_netcdf(small_brdf, tmp_path / "brdf.nc")
    data = path.read_bytes()
    cut = tmp_path / "cut.nc"
    cut.write_bytes(data[: len(data) // 2])
    with pytest.raises(ModelFileError, match="cut.nc"):
        read_netcdf(cut)


def test_foreign_netcdf_is_refused(tmp_path):
    path = tmp_path / "other.nc"
    xr.Dataset({"t": ("x", np.arange(3.0))}, attrs={"title": "someone else's"}).to_netcdf(path, engine="h5netcdf")
    with pytest.raises(ModelFileError, match="not a sandlight BRDF file"):
        read_netcdf(path)


def test_not_netcdf_at_all(tmp_path):
    path = tmp_path / "notes.nc"
    path.write_text("these are not the bytes you are looking for\n")
    with pytest.raises(ModelFileError, match="not a readable NetCDF"):
        read_netcdf(path)


def written(brdf, tmp_path):
    """The dataset of a file written by to_netcdf, in memory, to alter and write back."""
    with xr.open_dataset(to_netcdf(brdf, tmp_path / "written.nc"), engine="h5netcdf") as ds:
        return ds.load()


def test_other_format_version_is_refused(tmp_path, small_brdf):
    ds = written(small_brdf, tmp_path)
    ds.attrs["format_version"] = FORMAT_VERSION + 1
    path = tmp_path / "future.nc"
    ds.to_netcdf(path, engine="h5netcdf")
    with pytest.raises(ModelFileError, match="version 2 is not supported"):
        read_netcdf(path)
    ds.attrs["format_version"] = "one"
    ds.to_netcdf(path, engine="h5netcdf")
    with pytest.raises(ModelFileError, match="version 'one' is not supported"):
        read_netcdf(path)


def test_missing_or_inconsistent_variables_are_refused(tmp_path, small_brdf):
    ds = written(small_brdf, tmp_path)
    ds.drop_vars("unique_brdf_stderr").to_netcdf(tmp_path / "missing.nc", engine="h5netcdf")
    with pytest.raises(ModelFileError, match="inconsistent"):
        read_netcdf(tmp_path / "missing.nc")
    broken = ds.copy()
    broken["launched"] = broken["launched"] + 1
    broken.to_netcdf(tmp_path / "unbalanced.nc", engine="h5netcdf")
    with pytest.raises(ModelFileError, match="launched"):
        read_netcdf(tmp_path / "unbalanced.nc")


def test_missing_file(tmp_path):
    with pytest.raises(FileNotFoundError):
        read_netcdf(tmp_path / "nope.nc")
