"""Exports: each file reads back with sandlight's own readers and holds what the page shows."""

import io

import numpy as np
import pytest
import xarray as xr

from sandlight.appearance.table_file import read_table
from sandlight.sample import SandSample


def _export(client, name, **body):
    res = client.post(f"/api/export/{name}", json=body)
    assert res.status_code == 200, res.text
    assert res.headers["content-disposition"] == f'attachment; filename="sandlight-{name}"'
    return res.content


def test_the_sample_toml_reads_back_as_the_same_sample(client, tmp_path):
    sample = SandSample.preset("wet-beach").replace(saturation=0.3, depth_mm=12.5)
    path = tmp_path / "s.toml"
    path.write_bytes(_export(client, "sample.toml", sample=sample.to_dict()))
    assert SandSample.from_file(path) == sample


def test_the_spectrum_csv_and_netcdf_hold_the_predicted_spectrum(client, tmp_path):
    predicted = client.post("/api/spectrum", json={"sample": "red-dune"}).json()
    text = _export(client, "spectrum.csv", sample="red-dune").decode()
    assert f"# model: {predicted['model']}" in text
    table = np.loadtxt(io.StringIO(text), delimiter=",", comments="#", skiprows=text.count("#") + 1)
    np.testing.assert_allclose(table[:, 0], predicted["wavelengths_nm"])
    np.testing.assert_allclose(table[:, 1], predicted["reflectance"], atol=5e-7)
    path = tmp_path / "s.nc"
    path.write_bytes(_export(client, "spectrum.nc", sample="red-dune"))
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        np.testing.assert_allclose(ds["reflectance"].values, predicted["reflectance"])
        assert ds.attrs["model"] == predicted["model"] and ds["wavelength"].attrs["units"] == "nm"


def test_the_brdf_table_is_a_sandlight_brdf_table(client, tmp_path):
    path = tmp_path / "b.nc"
    path.write_bytes(_export(client, "brdf.nc", sample="wet-beach", n_mu=6, n_dphi=5))
    table = read_table(path)
    assert table["f"].shape[1:] == (6, 6, 5)
    assert float(table["f"].min()) >= 0


def test_exports_of_what_cannot_be_exported_are_refused(client):
    res = client.post("/api/export/spectrum.xlsx", json={"sample": "red-dune"})
    assert res.status_code == 400 and res.json()["parameter"] == "export"
    res = client.post("/api/export/spectrum.csv", json={"sample": {"depth_mm": 5}})
    assert res.status_code == 400 and "depth_mm" in res.json()["message"]
    res = client.post("/api/export/spectrum.csv", json={"sample": "red-dune", "job": "nope"})
    assert res.status_code == 404 and res.json()["error"] == "not-found"
    res = client.post("/api/export/brdf.nc", json={"sample": "red-dune", "n_mu": 1000})
    assert res.status_code == 400 and res.json()["parameter"] == "n_mu"


@pytest.mark.parametrize("name", ["../../etc/passwd", "sample.toml/../x"])
def test_no_export_name_reaches_the_file_system(client, name):
    res = client.post(f"/api/export/{name}", json={})
    assert res.status_code in (400, 404) and "root:" not in res.text
