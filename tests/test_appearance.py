"""SandAppearance: the explicit spectral BRDF — energy, reciprocity, sampling, albedo, tables."""

import copy
import dataclasses
import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

sys.path.insert(0, str(Path(__file__).parent / "spatial"))
import spatial_fakes  # noqa: E402

from sandlight.appearance import DEFENSIVE_COSINE_SHARE, TABLE_FORMAT, SandAppearance  # noqa: E402
from sandlight.appearance.band_grid import hat_quadrature  # noqa: E402
from sandlight.errors import ParameterError  # noqa: E402
from sandlight.gonio.brdf import interpolate_band_grid  # noqa: E402
from sandlight.sample import SandSample  # noqa: E402
from sandlight.spatial import Mesh, SpatialApproximationWarning, SpatialModel  # noqa: E402
from sandlight.testing.chi2 import SIGNIFICANCE, hemisphere_chi2  # noqa: E402

STACKS, SLICES = 7, 8


@pytest.fixture(scope="module")
def spatial():
    mesh = Mesh.beach(6)
    return SpatialModel(n_components=3).fit(
        spatial_fakes.measured_nodes(mesh, 10**8, stacks=STACKS, slices=SLICES, seed=5), mesh
    )


@pytest.fixture(scope="module")
def spectral():
    return spatial_fakes.fitted_spectral_model()


@pytest.fixture(scope="module")
def app(spatial):
    # A bright spectrum (0.55–0.9) on the saturation-0.3 point: r(λ) is above r_0 at every λ.
    return SandAppearance(SandSample(saturation=0.3), spatial_fakes.fake_spectrum, spatial)


@pytest.fixture(scope="module")
def product(spatial):
    return SandAppearance(SandSample(saturation=0.3), spatial_fakes.fake_spectrum, spatial, combination="product")


def directions(n, seed, *, min_z=0.0):
    rng = np.random.default_rng(seed)
    d = rng.normal(size=(n, 3))
    d[:, 2] = np.abs(d[:, 2]) + min_z
    return d / np.linalg.norm(d, axis=1, keepdims=True)


def from_angles(theta_deg, phi_deg=0.0):
    t, p = np.radians(theta_deg), np.radians(phi_deg)
    return np.stack(np.broadcast_arrays(np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)), axis=-1)


def hemisphere_quadrature(n_mu=400, n_phi=200):
    """Midpoint rule over the hemisphere in (μ, φ): directions (M, 3) and weights dω (M,)."""
    mu = (np.arange(n_mu) + 0.5) / n_mu
    phi = (np.arange(n_phi) + 0.5) / n_phi * 2 * math.pi
    M, P = np.meshgrid(mu, phi, indexing="ij")
    s = np.sqrt(1 - M**2)
    d = np.stack([s * np.cos(P), s * np.sin(P), M], axis=-1).reshape(-1, 3)
    return d, np.full(d.shape[0], (1 / n_mu) * (2 * math.pi / n_phi))


# ---- energy -------------------------------------------------------------------------------------
@pytest.mark.parametrize("preset", SandSample.presets())
def test_albedo_at_most_one_at_every_incidence_for_every_preset(preset, spectral, spatial):
    app = SandAppearance(preset, spectral, spatial, fixed="ignore")
    wi = from_angles(np.linspace(0, 90, 181)[:, None] * np.ones((1, 1)))[:, 0]
    albedo = app.albedo(wi)
    assert (albedo >= 0).all() and (albedo <= 1 + 1e-12).all()
    # At normal incidence the albedo is the spectral prediction (paper §3.3).
    np.testing.assert_allclose(app.albedo([0, 0, 1])[0], app.normal_reflectance, atol=1e-12)


def test_bright_spectrum_stays_energy_conserving(app, product):
    grazing = from_angles(89.9)
    assert app.albedo(grazing).max() <= 1 + 1e-12
    # The paper's product would reflect more than arrives at grazing incidence for this spectrum.
    assert product.albedo(grazing).max() > 1.2
    # Both reproduce r(λ) at normal incidence, and agree where r ≤ r_0.
    np.testing.assert_allclose(app.albedo([0, 0, 1])[0], product.albedo([0, 0, 1])[0], atol=1e-12)


def test_energy_combination_equals_the_product_for_darker_spectra(spatial):
    dark = lambda s: (np.arange(400.0, 701.0, 20.0), np.full(16, 0.05))  # noqa: E731
    a = SandAppearance(SandSample(saturation=0.3), dark, spatial)
    b = SandAppearance(SandSample(saturation=0.3), dark, spatial, combination="product")
    assert a.reference_reflectance > 0.05
    wi, wo = directions(500, 1), directions(500, 2)
    np.testing.assert_array_equal(a.brdf(wi, wo), b.brdf(wi, wo))


@pytest.mark.parametrize("theta", [0.0, 30.0, 60.0, 80.0, 89.0])
def test_albedo_equals_the_integral_of_the_brdf(app, theta):
    d, w = hemisphere_quadrature()
    wi = from_angles(theta, 20.0)
    f = app.brdf(wi, d)
    integral = (f * d[:, 2:3] * w[:, None]).sum(axis=0)
    np.testing.assert_allclose(integral, app.albedo(wi)[0], rtol=2e-3)


def test_continuous_brdf_is_normalised_at_normal_incidence(product):
    d, w = hemisphere_quadrature()
    f = product.brdf([0, 0, 1], d, [550.0])[:, 0] / product.reflectance_at([550.0])[0]
    assert (f * d[:, 2] * w).sum() == pytest.approx(1.0, rel=2e-3)


# ---- reciprocity, symmetry, reference implementation ----------------------------------------------
@pytest.mark.parametrize("name", ["app", "product"])
def test_reciprocity_on_random_pairs(name, request):
    model = request.getfixturevalue(name)
    wi, wo = directions(5000, 3), directions(5000, 4)
    np.testing.assert_allclose(model.brdf(wi, wo), model.brdf(wo, wi), rtol=1e-12, atol=1e-15)


def test_isotropy_and_mirror_symmetry(app):
    wi, wo = directions(1000, 5), directions(1000, 6)
    a = app.brdf(wi, wo)
    angle = 1.234
    rot = np.array([[math.cos(angle), -math.sin(angle), 0], [math.sin(angle), math.cos(angle), 0], [0, 0, 1]])
    np.testing.assert_allclose(app.brdf(wi @ rot.T, wo @ rot.T), a, rtol=1e-10)
    mirror = np.diag([1.0, -1.0, 1.0])
    np.testing.assert_allclose(app.brdf(wi @ mirror, wo @ mirror), a, rtol=1e-10)


def test_native_evaluator_matches_the_reference_interpolant(app):
    # f = a(λ) F + b(λ) P(μ_i) P(μ_o), with F the goniophotometer's interpolant (numpy reference).
    wi, wo = directions(3000, 7), directions(3000, 8)
    dphi = np.arctan2(wo[:, 1], wo[:, 0]) - np.arctan2(wi[:, 1], wi[:, 0])
    F = interpolate_band_grid(app.band_grid.grid, app.band_grid.nodes, wi[:, 2], wo[:, 2], dphi)
    nodes_asc = app.band_grid.nodes[::-1]
    profile = lambda mu: np.interp(mu, nodes_asc, app._combination.profile[::-1])  # noqa: E731
    a, b = app._combination.weights(app.normal_reflectance)
    expected = F[:, None] * a + (profile(wi[:, 2]) * profile(wo[:, 2]))[:, None] * b
    np.testing.assert_allclose(app.brdf(wi, wo), expected, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(app.brdf(wi, wo, threads=2), expected, rtol=1e-12, atol=1e-15)


def test_below_the_horizon_and_bad_input(app):
    f = app.brdf([[0, 0, 1], [0, 0, 1]], [[1, 0, -0.1], [1, 0, 0]])
    assert (f == 0).all()
    assert (app.albedo([0.5, 0, -0.5]) == 0).all()
    with pytest.raises(ParameterError, match="wo"):
        app.brdf([[0, 0, 1]], [[0, 0, 0]])
    with pytest.raises(ParameterError, match=r"\(N, 3\)"):
        app.brdf([[0, 0, 1, 0]], [[0, 0, 1, 0]])
    with pytest.raises(ParameterError, match="400"):
        app.brdf([0, 0, 1], [0, 0, 1], [380.0])
    with pytest.raises(ParameterError, match="u1"):
        app.sample([[0, 0, 1]], [1.0], [0.5])
    with pytest.raises(ParameterError, match="method"):
        app.pdf([[0, 0, 1]], [[0, 0, 1]], method="phong")
    with pytest.raises(ParameterError, match="combination"):
        SandAppearance(SandSample(), spatial_fakes.fake_spectrum, None, combination="sum")


def test_wavelengths_between_the_model_grid(app):
    r = app.reflectance_at([410.0, 700.0])
    np.testing.assert_allclose(r, [np.mean(app.normal_reflectance[:2]), app.normal_reflectance[-1]])
    wi, wo = directions(10, 9), directions(10, 10)
    f = app.brdf(wi, wo, [410.0])
    both = app.brdf(wi, wo, [400.0, 420.0])
    # Linear in r below r_0 or above it: the interpolated spectrum's BRDF is the mean of the neighbours'.
    np.testing.assert_allclose(f[:, 0], both.mean(axis=1), rtol=1e-12)


def test_samples_away_from_the_mesh_base(spatial, spectral):
    with pytest.warns(SpatialApproximationWarning, match="iron_oxide"):
        SandAppearance("red-dune", spectral, spatial)
    with pytest.raises(ParameterError, match="base sample"):
        SandAppearance("red-dune", spectral, spatial, fixed="error")
    with pytest.raises(ParameterError, match="saturation"):
        SandAppearance(
            SandSample(saturation=0.3),
            spectral,
            SpatialModel(n_components=1).fit(
                spatial_fakes.measured_nodes(
                    Mesh(("saturation",), [0.5, 0.7, 0.9]), 10**6, stacks=STACKS, slices=SLICES
                ),
                Mesh(("saturation",), [0.5, 0.7, 0.9]),
            ),
        )


# ---- sampling -----------------------------------------------------------------------------------
def cell_edges(app, split=2):
    """Bin edges aligned with the sampler's cells for an incident azimuth of 0."""
    h = app.spatial.hemisphere
    first = np.concatenate([[0], 1 + SLICES * np.arange(STACKS - 1)])
    z = np.unique(np.concatenate([h.bounds[first, 0], [1.0]]))
    mu = np.unique(np.concatenate([np.linspace(a, b, split + 1) for a, b in zip(z[:-1], z[1:])]))
    step = 2 * math.pi / SLICES
    b = np.concatenate([[0.0], step * (np.arange(SLICES) + 0.5), [2 * math.pi]])
    phi = np.unique(np.concatenate([np.linspace(a, c, split + 1) for a, c in zip(b[:-1], b[1:])]))
    return mu, phi


@pytest.mark.parametrize("theta", [0.0, 37.0, 75.0, 88.0])
@pytest.mark.parametrize("method", ["brdf", "cosine"])
def test_sampler_follows_its_pdf_chi_square(app, theta, method):
    n = 200_000
    rng = np.random.default_rng(int(theta * 10) + (method == "brdf"))
    wi = np.broadcast_to(from_angles(theta), (n, 3))
    wo, weight, pdf = app.sample(wi, rng.random(n), rng.random(n), 550.0, method=method)
    mu_edges, phi_edges = cell_edges(app)
    result = hemisphere_chi2(
        wo, lambda d: app.pdf(np.broadcast_to(wi[0], d.shape), d, method=method), mu_edges=mu_edges, phi_edges=phi_edges
    )
    assert result.pdf_integral == pytest.approx(1.0, abs=1e-3)
    assert result.passed(SIGNIFICANCE), result


def test_chi_square_detects_a_wrong_pdf(app):
    n = 200_000
    rng = np.random.default_rng(11)
    wi = np.broadcast_to(from_angles(75.0), (n, 3))
    wo, _, _ = app.sample(wi, rng.random(n), rng.random(n), method="cosine")
    mu_edges, phi_edges = cell_edges(app)
    result = hemisphere_chi2(
        wo, lambda d: app.pdf(np.broadcast_to(wi[0], d.shape), d, method="brdf"), mu_edges=mu_edges, phi_edges=phi_edges
    )
    assert result.p_value < 1e-6


@pytest.mark.parametrize("method", ["brdf", "cosine"])
def test_weight_is_f_cos_over_pdf(app, method):
    n = 2000
    rng = np.random.default_rng(12)
    wi = directions(n, 13)
    wo, weight, pdf = app.sample(wi, rng.random(n), rng.random(n), [450.0, 650.0], method=method)
    assert weight.shape == (n, 2) and (wo[:, 2] > 0).all()
    np.testing.assert_allclose(np.linalg.norm(wo, axis=1), 1.0, rtol=1e-12)
    np.testing.assert_allclose(pdf, app.pdf(wi, wo, method=method), rtol=1e-12)
    expected = app.brdf(wi, wo, [450.0, 650.0]) * wo[:, 2:3] / pdf[:, None]
    np.testing.assert_allclose(weight, expected, rtol=1e-12)
    _, scalar, _ = app.sample(wi, rng.random(n), rng.random(n), 550.0, method=method)
    assert scalar.shape == (n,)


@pytest.mark.parametrize("theta", [20.0, 85.0])
def test_sampled_weights_estimate_the_albedo(app, theta):
    n = 400_000
    rng = np.random.default_rng(14)
    wi = np.broadcast_to(from_angles(theta, 50.0), (n, 3))
    exact = app.albedo(wi[0], [550.0])[0, 0]
    spread = {}
    for method in ("brdf", "cosine"):
        _, w, _ = app.sample(wi, rng.random(n), rng.random(n), 550.0, method=method)
        se = w.std() / math.sqrt(n)
        assert abs(w.mean() - exact) < 4 * se
        spread[method] = w.std()
    if theta > 80:  # at grazing incidence the tabulated sampler beats cosine sampling
        assert spread["brdf"] < spread["cosine"]


@pytest.mark.parametrize("method", ["brdf", "cosine"])
def test_pdf_is_normalised(app, method):
    d, w = hemisphere_quadrature(600, 320)
    for theta in (0.0, 45.0, 89.0):
        wi = np.broadcast_to(from_angles(theta, 10.0), d.shape)
        assert (app.pdf(wi, d, method=method) * w).sum() == pytest.approx(1.0, abs=2e-3)


def test_defensive_share_bounds_the_weight(app):
    n = 20000
    rng = np.random.default_rng(15)
    wi = directions(n, 16)
    wo, weight, _ = app.sample(wi, rng.random(n), rng.random(n), 700.0)
    f = app.brdf(wi, wo, [700.0])[:, 0]
    assert (weight <= math.pi * f / DEFENSIVE_COSINE_SHARE * (1 + 1e-12)).all()


def test_sampling_commutes_with_rotation_about_the_normal(app):
    n = 1000
    rng = np.random.default_rng(17)
    u1, u2 = rng.random(n), rng.random(n)
    wi = directions(n, 18)
    angle = 0.7
    rot = np.array([[math.cos(angle), -math.sin(angle), 0], [math.sin(angle), math.cos(angle), 0], [0, 0, 1]])
    wo, w, p = app.sample(wi, u1, u2, 550.0)
    wo_r, w_r, p_r = app.sample(wi @ rot.T, u1, u2, 550.0)
    np.testing.assert_allclose(wo_r, wo @ rot.T, atol=1e-10)
    np.testing.assert_allclose(p_r, p, rtol=1e-9)


# ---- table export -------------------------------------------------------------------------------
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


def test_models_of_different_engine_memories_are_flagged(spatial, spectral, tmp_path):
    # A callable's memory is unknown: no warning, recorded as such.
    table = SandAppearance(SandSample(saturation=0.3), spatial_fakes.fake_spectrum, spatial).to_table(
        tmp_path / "a.nc", n_mu=3, n_dphi=3
    )
    with xr.open_dataset(table, engine="h5netcdf") as ds:
        assert json.loads(ds.attrs["engine_memory"]) == {"spectral": "unknown", "spatial": "none"}
    same = SandAppearance(SandSample(saturation=0.3), spectral, spatial)
    assert same.spectral_memory == "none"
    packed = copy.deepcopy(spectral)
    packed.training_set_ = {**packed.training_set_, "engine": {"memory": "packed"}}
    with pytest.warns(UserWarning, match="engine memory 'packed'.*'none'"):
        mixed = SandAppearance(SandSample(saturation=0.3), packed, spatial)
    with xr.open_dataset(mixed.to_table(tmp_path / "b.nc", n_mu=3, n_dphi=3), engine="h5netcdf") as ds:
        assert json.loads(ds.attrs["engine_memory"]) == {"spectral": "packed", "spatial": "none"}


def test_table_arguments(app):
    with pytest.raises(ParameterError, match="n_mu"):
        app.table(n_mu=1)
    ds = app.table(n_mu=3, n_dphi=2, wavelengths_nm=[550.0])
    assert ds["f"].shape == (1, 3, 3, 2)


# ---- the shipped spatial model ----------------------------------------------------------------
from sandlight.spatial.model import default_model_path  # noqa: E402

shipped = pytest.mark.skipif(not default_model_path().is_file(), reason="shipped spatial model not trained yet")


@shipped
@pytest.mark.parametrize("preset", SandSample.presets())
def test_shipped_spatial_model_conserves_energy_for_every_preset(preset, spectral):
    app = SandAppearance(preset, spectral, None, fixed="ignore")
    wi = from_angles(np.linspace(0, 90, 181))
    albedo = app.albedo(wi)
    assert (albedo >= 0).all() and (albedo <= 1 + 1e-12).all()
    np.testing.assert_allclose(app.albedo([0, 0, 1])[0], app.normal_reflectance, atol=1e-12)


@shipped
@pytest.mark.parametrize("saturation", [0.0, 0.5, 1.0])
def test_normal_incidence_peak_does_not_rescale_the_brdf(saturation):
    # Saturated sand has a narrow mirror peak back towards normal incidence (flat water). The
    # continuous BRDF keeps the measured values elsewhere: at normal incidence, its values at the
    # outgoing band centroids equal the spatial prediction's patch values (Δφ-independent there).
    flat = lambda s: (np.arange(400.0, 701.0, 20.0), np.full(16, 0.5))  # noqa: E731
    app = SandAppearance(SandSample(saturation=saturation), flat, None, combination="product")
    h = app.spatial.hemisphere
    bands = 1 + h.slices * np.arange(h.n_bands)  # first patch of every band
    f = app.brdf([0, 0, 1], h.centroids[bands], [550.0])[:, 0] / 0.5
    np.testing.assert_allclose(f, app.spatial.values[h.cap, bands], rtol=0.05)
    # and the albedo at normal incidence is exactly the spectral value.
    assert app.albedo([0, 0, 1], [550.0])[0, 0] == pytest.approx(0.5, abs=1e-12)
