"""The mesh of the spatial predictor: node validation and barycentric location (paper eq. 6)."""

import numpy as np
import pytest

from sandlight.errors import ParameterError
from sandlight.sample import SandSample
from sandlight.spatial import Mesh


def check_weights(mesh, points):
    idx, w = mesh.locate(points)
    assert idx.shape == w.shape == (len(points), mesh.dimension + 1)
    assert (w >= 0).all()
    np.testing.assert_allclose(w.sum(axis=1), 1.0, rtol=0, atol=1e-14)
    # Affine combination of the simplex's vertices reproduces the point (eq. 6).
    np.testing.assert_allclose(np.einsum("kv,kvd->kd", w, mesh.nodes[idx]), points, rtol=0, atol=1e-12)
    return idx, w


def test_beach_mesh_is_the_paper_saturation_mesh():
    mesh = Mesh.beach()
    assert mesh.n_nodes == 16 and mesh.parameters == ("saturation",)
    np.testing.assert_allclose(mesh.nodes[:, 0], np.linspace(0, 1, 16))
    assert mesh.base == SandSample().to_dict()
    samples = mesh.samples()
    assert [s.saturation for s in samples] == pytest.approx(np.linspace(0, 1, 16).tolist())
    assert all(s.iron_oxide == SandSample().iron_oxide for s in samples)


def test_one_dimensional_weights_are_linear_interpolation():
    mesh = Mesh.beach()
    x = np.random.default_rng(1).random((200, 1))
    idx, w = check_weights(mesh, x)
    # The simplex is the segment of neighbouring nodes holding x.
    lo, hi = mesh.nodes[idx[:, 0], 0], mesh.nodes[idx[:, 1], 0]
    assert (lo <= x[:, 0] + 1e-15).all() and (x[:, 0] <= hi + 1e-15).all()
    np.testing.assert_allclose(hi - lo, 1 / 15, rtol=1e-12)


def test_unsorted_one_dimensional_nodes():
    mesh = Mesh(("saturation",), [0.6, 0.0, 1.0, 0.3])
    idx, w = check_weights(mesh, np.array([[0.45]]))
    assert set(mesh.nodes[idx[0], 0]) == {0.3, 0.6}
    np.testing.assert_allclose(sorted(w[0]), [0.5, 0.5])


@pytest.mark.parametrize(
    "mesh",
    [
        Mesh.beach(),
        Mesh.grid(saturation=[0, 0.5, 1], hematite_ratio=[0, 1]),
        Mesh.grid(saturation=[0, 0.5, 1], iron_oxide=[0, 0.01, 0.03], hematite_ratio=[0, 0.5, 1]),
        Mesh(
            ("saturation", "iron_oxide"),
            np.vstack([[[0, 0], [1, 0], [0, 0.05], [1, 0.05]], np.random.default_rng(5).random((12, 2)) * [1, 0.05]]),
        ),
    ],
    ids=["1d", "2d-grid", "3d-grid", "2d-scattered"],
)
def test_exact_at_nodes(mesh):
    idx, w = mesh.locate(mesh.nodes)
    for i in range(mesh.n_nodes):
        assert w[i].max() == 1.0 and np.count_nonzero(w[i]) == 1  # one-hot, not merely close
        assert idx[i, np.argmax(w[i])] == i


@pytest.mark.parametrize(
    "axes",
    [
        {"saturation": [0, 0.5, 1], "hematite_ratio": [0, 1]},
        {"saturation": [0, 0.5, 1], "iron_oxide": [0, 0.01, 0.03], "hematite_ratio": [0, 0.5, 1]},
    ],
)
def test_grid_weights_inside(axes):
    mesh = Mesh.grid(**axes)
    rng = np.random.default_rng(2)
    points = mesh.lower + rng.random((300, mesh.dimension)) * (mesh.upper - mesh.lower)
    check_weights(mesh, points)
    # Points on the boundary (faces, edges, corners) are inside.
    check_weights(
        mesh, np.vstack([mesh.lower, mesh.upper, np.where(np.arange(mesh.dimension) == 0, mesh.lower, points[0])])
    )


def test_scattered_weights_inside_hull():
    rng = np.random.default_rng(3)
    nodes = rng.random((25, 2)) * [1.0, 0.05]
    mesh = Mesh(("saturation", "iron_oxide"), nodes)
    # Convex combinations of nodes lie in the hull.
    coeffs = rng.dirichlet(np.ones(4), size=200)
    picks = rng.integers(0, 25, size=(200, 4))
    points = np.einsum("kv,kvd->kd", coeffs, nodes[picks])
    check_weights(mesh, points)


def test_outside_the_mesh_is_a_clear_error():
    mesh = Mesh(("saturation",), [0.2, 0.5, 0.8])
    with pytest.raises(ParameterError) as e:
        mesh.locate([[0.9]])
    message = str(e.value)
    assert "saturation" in message and "0.9" in message and "[0.2, 0.8]" in message
    mesh2 = Mesh(("saturation", "iron_oxide"), [[0, 0], [1, 0], [0, 0.05]])  # a triangle
    with pytest.raises(ParameterError, match="convex hull"):
        mesh2.locate([[0.9, 0.04]])  # inside the bounding box, outside the triangle
    with pytest.raises(ParameterError):
        mesh.locate([[np.nan]])


def test_samples_give_their_mesh_coordinates():
    mesh = Mesh.grid(saturation=[0, 1], iron_oxide=[0, 0.02])
    sample = SandSample(saturation=0.25, iron_oxide=0.01)
    np.testing.assert_allclose(mesh.coordinates(sample), [[0.25, 0.01]])
    idx, w = mesh.locate(sample)
    np.testing.assert_allclose(w[0] @ mesh.nodes[idx[0]], [0.25, 0.01], atol=1e-15)
    assert mesh.differing_parameters(sample) == {}
    assert set(mesh.differing_parameters(SandSample(saturation=0.3, porosity=0.3))) == {"porosity"}


def test_invalid_meshes_are_refused():
    with pytest.raises(ParameterError, match="float parameters"):
        Mesh(("colour",), [0, 1])
    with pytest.raises(ParameterError, match="float parameters"):
        Mesh(("iron_oxide_form",), [0, 1])
    with pytest.raises(ParameterError, match="distinct"):
        Mesh(("saturation",), [0, 0.5, 0.5])
    with pytest.raises(ParameterError, match="domain"):
        Mesh(("saturation",), [0, 1.5])
    with pytest.raises(ParameterError, match="at least"):
        Mesh(("saturation", "iron_oxide"), [[0, 0], [1, 0]])
    with pytest.raises(ParameterError, match="hyperplane"):
        Mesh(("saturation", "iron_oxide"), [[0, 0], [0.5, 0.01], [1, 0.02]])  # collinear
    with pytest.raises(ParameterError):
        Mesh.grid(saturation=[0.5])


def test_texture_meshes_keep_the_separates_consistent():
    mesh = Mesh.grid(silt=[0.0, 0.1], clay=[0.0, 0.02])
    for s in mesh.samples():
        assert s.sand + s.silt + s.clay == pytest.approx(1.0)


def test_round_trip_through_a_dict():
    mesh = Mesh.grid(SandSample.preset("red-dune"), saturation=[0, 0.5, 1], hematite_ratio=[0.2, 0.9])
    again = Mesh.from_dict(mesh.to_dict())
    assert again == mesh
    idx, w = mesh.locate([[0.3, 0.5]])
    idx2, w2 = again.locate([[0.3, 0.5]])
    np.testing.assert_array_equal(idx, idx2)
    np.testing.assert_array_equal(w, w2)
