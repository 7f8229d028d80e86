"""SandAppearance: evaluation against the reference interpolant, reciprocity, arguments, model sources."""

import copy
import json

import numpy as np
import pytest
import spatial_fakes
import xarray as xr
from appearance_helpers import SLICES, STACKS, directions

from sandlight.appearance import SandAppearance
from sandlight.errors import ParameterError
from sandlight.gonio.brdf import interpolate_band_grid
from sandlight.sample import SandSample
from sandlight.spatial import Mesh, SpatialApproximationWarning, SpatialModel


@pytest.mark.parametrize("name", ["app", "product"])
def test_reciprocity_on_random_pairs(name, request):
    model = request.getfixturevalue(name)
    wi, wo = directions(5000, 3), directions(5000, 4)
    np.testing.assert_allclose(model.brdf(wi, wo), model.brdf(wo, wi), rtol=1e-12, atol=1e-15)


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
