"""The BRDF table: SandAppearance.table's values and the 'sandlight-brdf-table' file (layout, writer, reader)."""

import dataclasses
import math

import numpy as np
import pytest
import spatial_fakes
import xarray as xr
from appearance_helpers import from_angles, hemisphere_quadrature

from sandlight.appearance import TABLE_FORMAT, SandAppearance, table_file
from sandlight.appearance.band_grid import hat_quadrature
from sandlight.errors import ModelFileError, ParameterError
from sandlight.sample import SandSample


def test_table_layout_and_values(app, tmp_path):
    path = app.to_table(tmp_path / "brdf.nc", n_mu=9, n_dphi=7)
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        assert ds.attrs["format"] == TABLE_FORMAT and ds.attrs["format_version"] == 1
        assert ds["f"].dims == ("wavelength", "mu_i", "mu_o", "dphi")
        assert ds["f"].attrs["units"] == "sr-1" and ds["wavelength"].attrs["units"] == "nm"
        assert ds["dphi"].attrs["units"] == "rad"
        mu, dphi, wl = ds["mu_i"].values, ds["dphi"].values, ds["wavelength"].values
        np.testing.assert_array_equal(mu, np.linspace(0, 1, 9))
        np.testing.assert_array_equal(ds["mu_o"].values, mu)
        np.testing.assert_allclose(dphi, np.linspace(0, math.pi, 7))
        np.testing.assert_array_equal(wl, app.wavelengths_nm)
        f = ds["f"].values
        np.testing.assert_array_equal(f, f.transpose(0, 2, 1, 3))  # reciprocity, exactly
        assert (f >= 0).all()
        # Away from the horizon the (smooth) synthetic BRDF and its table agree closely.
        i, j, k = np.meshgrid(np.arange(3, 9), np.arange(3, 9), np.arange(7), indexing="ij")
        wi = from_angles(np.degrees(np.arccos(mu[i.ravel()])))
        wo = from_angles(np.degrees(np.arccos(mu[j.ravel()])), np.degrees(dphi[k.ravel()]))
        np.testing.assert_allclose(f[:, 3:, 3:, :].reshape(len(wl), -1).T, app.brdf(wi, wo), rtol=0.03)
        albedo = ds["albedo"].values
        assert (albedo <= 1 + 1e-12).all() and albedo.shape == (len(wl), 9)
        np.testing.assert_allclose(ds["normal_reflectance"].values, app.normal_reflectance)


def test_table_conserves_the_albedo(app):
    # Multilinear interpolation of the table, integrated over the outgoing hemisphere, gives the
    # albedo variable: exactly in μ_o (cos-weighted hat averages), to the Δφ sampling otherwise.
    ds = app.table(n_mu=17, n_dphi=33)
    f, mu, dphi = ds["f"].values, ds["mu_o"].values, ds["dphi"].values
    h = mu[1] - mu[0]
    hat_mu = np.full(mu.size, h * 0.0)
    for q in range(mu.size):  # ∫ hat_q(μ) μ dμ
        if q > 0:
            hat_mu[q] += h * (mu[q - 1] + 2 * mu[q]) / 6
        if q < mu.size - 1:
            hat_mu[q] += h * (2 * mu[q] + mu[q + 1]) / 6
    over_phi = 2 * np.trapezoid(f, dphi, axis=3)  # Δφ over [0, 2π) by evenness
    integral = over_phi @ hat_mu
    np.testing.assert_allclose(integral, ds["albedo"].values, rtol=2e-3)
    # The albedo of the table is the model's albedo averaged over each node's hat: close to it.
    np.testing.assert_allclose(ds["albedo"].values[:, -1], app.normal_reflectance, rtol=0.02)


def test_table_keeps_a_normal_incidence_peak_energy(spatial):
    # A narrow peak at the cap (as flat water gives) must not be smeared into extra energy.
    peaked = SandAppearance(SandSample(saturation=0.3), spatial_fakes.fake_spectrum, spatial, combination="product")
    grid = peaked.band_grid.grid.copy()
    grid[:2, :2, :] *= 50.0  # the cap → cap value (nodes μ = 1 and the cap's edge)
    from sandlight import _native

    peaked.band_grid = dataclasses.replace(peaked.band_grid, grid=grid)
    peaked._evaluator = _native.BandGridBrdf(grid, peaked.band_grid.nodes, peaked._combination.profile)
    d, w = hemisphere_quadrature(4000, 8)
    exact = (peaked.brdf([0, 0, 1], d, [550.0])[:, 0] * d[:, 2] * w).sum()
    ds = peaked.table(n_mu=32, n_dphi=9, wavelengths_nm=[550.0])
    f, mu, dphi = ds["f"].values[0], ds["mu_o"].values, ds["dphi"].values
    h = mu[1] - mu[0]
    hat_mu = np.array(
        [
            (h * (mu[q - 1] + 2 * mu[q]) / 6 if q > 0 else 0)
            + (h * (2 * mu[q] + mu[q + 1]) / 6 if q < mu.size - 1 else 0)
            for q in range(mu.size)
        ]
    )
    from_table = (2 * np.trapezoid(f[-1], dphi, axis=1)) @ hat_mu
    # The table's μ_i = 1 row averages over its hat in μ_i too, diluting the cap: compare with the
    # model averaged the same way.
    x, W = hat_quadrature(peaked.band_grid.nodes, mu)
    row = W[-1] @ np.array(
        [
            (peaked.brdf(from_angles(np.degrees(np.arccos(min(xi, 1.0)))), d, [550.0])[:, 0] * d[:, 2] * w).sum()
            for xi in x
        ]
    )
    assert from_table == pytest.approx(row, rel=5e-3)
    assert exact > from_table  # the peak at exactly μ_i = 1 is brighter than its hat average


def test_table_arguments(app):
    with pytest.raises(ParameterError, match="n_mu"):
        app.table(n_mu=1)
    ds = app.table(n_mu=3, n_dphi=2, wavelengths_nm=[550.0])
    assert ds["f"].shape == (1, 3, 3, 2)


# ---- the file: written by SandAppearance and BrdfTable, read and checked by one reader ----------
def readers():
    """Both ways of reading a table file: the format's reader and the renderer's."""
    from sandlight.render import BrdfTable

    return [pytest.param(table_file.read_table, id="read_table"), pytest.param(BrdfTable.from_netcdf, id="BrdfTable")]


@pytest.fixture(scope="module")
def small_table(app):
    return app.table(n_mu=5, n_dphi=4, wavelengths_nm=[450.0, 650.0])


def test_appearance_table_reads_back_in_the_renderer(app, small_table, tmp_path):
    from sandlight.render import BrdfTable

    path = app.to_table(tmp_path / "brdf.nc", n_mu=5, n_dphi=4, wavelengths_nm=[450.0, 650.0])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["brdf.nc"]  # no temporary file left behind
    back = BrdfTable.from_netcdf(path)
    np.testing.assert_array_equal(back.f[0], small_table["f"].values)
    np.testing.assert_array_equal(back.mu_o, small_table["mu_o"].values)
    ds = table_file.read_table(path)
    assert ds.attrs["format"] == table_file.FORMAT_NAME and ds.attrs["format_version"] == table_file.FORMAT_VERSION
    assert ds.attrs["reference_reflectance"] == app.reference_reflectance


def test_renderer_stacks_are_written_in_the_format(tmp_path):
    from sandlight.render import BrdfTable

    wl = [450.0, 650.0]
    stack = BrdfTable.stack([BrdfTable.oren_nayar(a, 20.0, wl) for a in (0.2, 0.5)], [0.0, 1.0], "saturation")
    ds = table_file.read_table(stack.to_netcdf(tmp_path / "stack.nc"))
    assert ds.attrs["format"] == TABLE_FORMAT and ds["f"].dims == ("saturation", *table_file.AXES)
    assert ds["f"].attrs["units"] == "sr-1" and ds["dphi"].attrs["units"] == "rad"
    np.testing.assert_array_equal(ds["saturation"].values, [0.0, 1.0])


@pytest.mark.parametrize("read", readers())
def test_foreign_netcdf_is_refused(read, small_table, tmp_path):
    # A BRDF in the same layout but not written by sandlight: no format attribute.
    foreign = small_table.copy()
    foreign.attrs = {"title": "someone else's BRDF"}
    foreign.to_netcdf(tmp_path / "other.nc", engine="h5netcdf")
    with pytest.raises(ModelFileError, match=r"other\.nc: not a sandlight BRDF table file .*format = None"):
        read(tmp_path / "other.nc")
    xr.Dataset({"t": ("x", np.arange(3.0))}, attrs={"format": "sandlight-brdf"}).to_netcdf(
        tmp_path / "gonio.nc", engine="h5netcdf"
    )
    with pytest.raises(ModelFileError, match="format = 'sandlight-brdf', expected 'sandlight-brdf-table'"):
        read(tmp_path / "gonio.nc")


@pytest.mark.parametrize("read", readers())
def test_newer_or_unknown_format_version_is_refused(read, small_table, tmp_path):
    newer = small_table.copy()
    newer.attrs["format_version"] = table_file.FORMAT_VERSION + 1
    newer.to_netcdf(tmp_path / "future.nc", engine="h5netcdf")
    with pytest.raises(ModelFileError, match=r"future\.nc: sandlight-brdf-table format version 2 .*newer sandlight"):
        read(tmp_path / "future.nc")
    newer.attrs["format_version"] = "one"
    newer.to_netcdf(tmp_path / "odd.nc", engine="h5netcdf")
    with pytest.raises(ModelFileError, match="version 'one' is not supported"):
        read(tmp_path / "odd.nc")


@pytest.mark.parametrize("read", readers())
def test_missing_variables_are_refused(read, small_table, tmp_path):
    small_table.drop_vars("f").to_netcdf(tmp_path / "no_f.nc", engine="h5netcdf")
    with pytest.raises(ModelFileError, match=r"no_f\.nc: incomplete sandlight-brdf-table file: no variable 'f'"):
        read(tmp_path / "no_f.nc")
    small_table.drop_vars("mu_o").to_netcdf(tmp_path / "no_mu_o.nc", engine="h5netcdf")
    with pytest.raises(ModelFileError, match="no coordinate 'mu_o'"):
        read(tmp_path / "no_mu_o.nc")
    small_table.transpose("mu_i", "wavelength", "mu_o", "dphi").to_netcdf(tmp_path / "order.nc", engine="h5netcdf")
    with pytest.raises(ModelFileError, match=r"variable f has dimensions \('mu_i', 'wavelength'"):
        read(tmp_path / "order.nc")


@pytest.mark.parametrize("read", readers())
def test_truncated_or_corrupt_file_is_refused(read, app, tmp_path):
    data = app.to_table(tmp_path / "brdf.nc", n_mu=5, n_dphi=4).read_bytes()
    (tmp_path / "cut.nc").write_bytes(data[: len(data) // 2])
    with pytest.raises(ModelFileError, match=r"cut\.nc: not a readable NetCDF-4 file \(truncated or corrupt\?\)"):
        read(tmp_path / "cut.nc")
    (tmp_path / "notes.nc").write_text("not a table\n")
    with pytest.raises(ModelFileError, match=r"notes\.nc: not a readable NetCDF-4 file"):
        read(tmp_path / "notes.nc")
    with pytest.raises(FileNotFoundError, match="absent.nc"):
        read(tmp_path / "absent.nc")


def test_renderer_refuses_invalid_values_naming_the_file(small_table, tmp_path):
    from sandlight.render import BrdfTable

    bad = small_table.copy()
    bad["f"] = -bad["f"]
    bad.to_netcdf(tmp_path / "negative.nc", engine="h5netcdf")
    with pytest.raises(ModelFileError, match=r"negative\.nc: .*BRDF values ≥ 0"):
        BrdfTable.from_netcdf(tmp_path / "negative.nc")


def test_writer_takes_only_datasets_in_the_format(small_table, tmp_path):
    with pytest.raises(ParameterError, match="dataset"):
        table_file.write_table(xr.Dataset({"f": ("x", np.ones(2))}), tmp_path / "x.nc")
    assert not (tmp_path / "x.nc").exists()
    with pytest.raises(ParameterError, match="level_name"):
        table_file.table_dataset(np.ones((1, 1, 2, 2, 2)), [500.0], [0, 1], [0, 1], [0, np.pi], interpolation="")
