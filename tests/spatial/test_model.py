"""SpatialModel: PCA of node BRDFs, barycentric interpolation of scores, reconstruction, files."""

import json
import warnings
import zipfile

import numpy as np
import pytest
import spatial_fakes
from spatial_fakes import RAYS, SLICES, STACKS

from sandlight.errors import ModelFileError, ParameterError, SandlightError
from sandlight.gonio import CollectorHemisphere, EquivalenceClasses
from sandlight.sample import SandSample
from sandlight.spatial import Mesh, SpatialApproximationWarning, SpatialModel
from sandlight.spatial import model as model_module


def test_scores_are_exact_at_the_nodes(beach_model, beach_mesh):
    np.testing.assert_array_equal(beach_model.scores(beach_mesh.nodes), beach_model.node_scores_)


@pytest.mark.parametrize("scaling", ["relative", "none", "noise"])
def test_prediction_at_a_node_is_its_rank_l_reconstruction(beach_nodes, beach_mesh, scaling):
    model = SpatialModel(n_components=2, scaling=scaling).fit(beach_nodes, beach_mesh)
    s = model.scale_
    V = model.components_ / s
    np.testing.assert_allclose(V @ V.T, np.eye(2), atol=1e-12)  # orthonormal in the scaled space
    if scaling == "none":
        np.testing.assert_array_equal(s, 1.0)
    elif scaling == "relative":
        np.testing.assert_allclose(s, np.abs(model.mean_))
    for node, measured in zip(beach_mesh.nodes, beach_nodes):
        g = (measured.unique_values - model.mean_) / s
        projection = model.mean_ + s * (g @ V.T @ V)
        np.testing.assert_allclose(model.predict([node])[0], projection, rtol=1e-12, atol=1e-14)


def test_interpolation_is_the_barycentric_combination(beach_model):
    # Half-way between nodes 0.4 and 0.6 of the 6-node mesh (eq. 7).
    mid = beach_model.predict([[0.5]])[0]
    ends = beach_model.predict([[0.4], [0.6]])
    np.testing.assert_allclose(mid, ends.mean(axis=0), rtol=1e-12)


def test_reconstructions_stay_normalised(beach_model):
    h = CollectorHemisphere(STACKS, SLICES)
    classes = EquivalenceClasses(h)
    cap_row = classes.class_of[h.cap]
    for x in np.linspace(0, 1, 13):
        unique = beach_model.predict([[x]])[0]
        assert np.dot(h.projected_solid_angles, unique[cap_row]) == pytest.approx(1.0, abs=1e-12)


def test_held_out_prediction_matches_the_truth(beach_model):
    # Noise-free truth at a point between nodes: the prediction is within 2 % RMS.
    params = SandSample(saturation=0.5).to_dict()
    truth = spatial_fakes.expected_unique(params, STACKS, SLICES)
    predicted = beach_model.predict(SandSample(saturation=0.5))[0]
    assert np.sqrt(np.mean(((predicted - truth) / truth) ** 2)) < 0.02


def test_number_of_components(beach_nodes, beach_mesh):
    model = SpatialModel(variance_threshold=0.9999999).fit(beach_nodes, beach_mesh)
    assert model.n_components_ >= 2
    ratio = model.signal_variance_ratio_
    assert ratio.sum() == pytest.approx(1.0) and (ratio >= 0).all()
    # Noise is subtracted: the components beyond the signal carry none of it.
    assert model.signal_variance_ratio_[-1] < model.explained_variance_ratio_[-1]
    assert SpatialModel(n_components=3).fit(beach_nodes, beach_mesh).n_components_ == 3
    with pytest.raises(ParameterError, match="n_nodes"):
        SpatialModel(n_components=6).fit(beach_nodes, beach_mesh)
    with pytest.raises(ParameterError):
        SpatialModel(variance_threshold=1.5).fit(beach_nodes, beach_mesh)
    with pytest.raises(ParameterError, match="scaling"):
        SpatialModel(scaling="log").fit(beach_nodes, beach_mesh)


def test_more_components_reconstruct_better(beach_nodes, beach_mesh):
    errors = [SpatialModel(n_components=k).fit(beach_nodes, beach_mesh).reconstruction_rms_ for k in (1, 2, 5)]
    assert errors[0] > errors[1] > errors[2]
    assert errors[2] < 1e-12  # n − 1 components reproduce the centred data exactly


def test_fit_refuses_inconsistent_measurements(beach_nodes, beach_mesh):
    with pytest.raises(ParameterError, match="one MeasuredBRDF per mesh node"):
        SpatialModel().fit(beach_nodes[:-1], beach_mesh)
    other = spatial_fakes.measured_nodes(Mesh.beach(6), 10**6, stacks=5, slices=4)
    with pytest.raises(ParameterError, match="collector hemisphere"):
        SpatialModel().fit(beach_nodes[:-1] + other[-1:], beach_mesh)
    with pytest.raises(SandlightError, match="not fitted"):
        SpatialModel().predict([[0.5]])


def test_outside_the_mesh(beach_model):
    with pytest.raises(ParameterError, match="saturation"):
        beach_model.predict([[1.2]])
    narrow = SpatialModel().fit(
        spatial_fakes.measured_nodes(Mesh(("saturation",), [0.2, 0.4, 0.6]), RAYS, stacks=STACKS, slices=SLICES),
        Mesh(("saturation",), [0.2, 0.4, 0.6]),
    )
    with pytest.raises(ParameterError, match=r"saturation = 0\.1"):
        narrow.brdf(SandSample(saturation=0.1))


def test_parameters_the_mesh_does_not_vary(beach_model):
    other = SandSample(saturation=0.5, porosity=0.3)
    with pytest.warns(SpatialApproximationWarning, match="porosity"):
        beach_model.predict(other)
    with pytest.raises(ParameterError, match="porosity"):
        beach_model.predict(other, fixed="error")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        a = beach_model.predict(other, fixed="ignore")
        b = beach_model.predict(SandSample(saturation=0.5))  # on the base: no warning
    np.testing.assert_array_equal(a, b)


def test_predicted_brdf_object(beach_model):
    b = beach_model.brdf(SandSample(saturation=0.3))
    assert b.values.shape == (b.hemisphere.n_patches,) * 2
    np.testing.assert_allclose(b.weights.sum(), 1.0)
    # The continuous BRDF is the goniophotometer's interpolant: exact at patch centroids.
    c = b.hemisphere.centroids
    i, j = np.meshgrid(np.arange(len(c)), np.arange(len(c)), indexing="ij")
    np.testing.assert_allclose(b.f(c[i.ravel()], c[j.ravel()]), b.values.ravel(), rtol=1e-10)


# ---- files -------------------------------------------------------------------------------------
def test_save_load_round_trip(beach_model, tmp_path):
    path = beach_model.save(tmp_path / "m.npz")
    again = SpatialModel.load(path)
    for name in (
        "mean_",
        "components_",
        "scale_",
        "node_scores_",
        "node_normal_reflectance_",
        "explained_variance_ratio_",
        "signal_variance_ratio_",
    ):
        np.testing.assert_array_equal(getattr(again, name), getattr(beach_model, name))
    assert again.mesh_ == beach_model.mesh_
    assert (again.stacks_, again.slices_, again.wavelength_nm_) == (STACKS, SLICES, 550.0)
    assert again.training_set_ == {"synthetic": True}
    x = np.linspace(0, 1, 7)[:, None]
    np.testing.assert_array_equal(again.predict(x), beach_model.predict(x))
    with np.load(path, allow_pickle=False) as z:  # plain arrays, JSON metadata: no pickle needed
        assert json.loads(str(z["metadata"][()]))["format"] == model_module.MODEL_FORMAT


def _rewrite(path, out, change):
    with np.load(path, allow_pickle=False) as z:
        data = {k: z[k] for k in z.files}
    change(data)
    with open(out, "wb") as fh:
        np.savez(fh, **data)
    return out


def _meta(change):
    def edit(data):
        meta = json.loads(str(data["metadata"][()]))
        change(meta)
        data["metadata"] = np.array(json.dumps(meta))

    return edit


@pytest.mark.parametrize(
    "damage",
    [
        "truncated",
        "flipped",
        "text",
        "no-metadata",
        "foreign-format",
        "newer-version",
        "missing-array",
        "nan",
        "wrong-shape",
        "bad-json",
    ],
)
def test_corrupt_files_are_refused(beach_model, tmp_path, damage):
    good = beach_model.save(tmp_path / "good.npz")
    bad = tmp_path / "bad.npz"
    raw = good.read_bytes()
    if damage == "truncated":
        bad.write_bytes(raw[: len(raw) // 2])
    elif damage == "flipped":
        # Flip a byte inside the compressed payload of the largest member: the CRC check fails.
        with zipfile.ZipFile(good) as z:
            info = max(z.infolist(), key=lambda i: i.compress_size)
        offset = info.header_offset + 30 + len(info.filename) + len(info.extra) + info.compress_size // 2
        data = bytearray(raw)
        data[offset] ^= 0xFF
        bad.write_bytes(bytes(data))
    elif damage == "text":
        bad.write_text("not a model")
    elif damage == "no-metadata":
        _rewrite(good, bad, lambda d: d.pop("metadata"))
    elif damage == "foreign-format":
        _rewrite(good, bad, _meta(lambda m: m.update(format="sandlight-spectral-model")))
    elif damage == "newer-version":
        _rewrite(good, bad, _meta(lambda m: m.update(format_version=99)))
    elif damage == "missing-array":
        _rewrite(good, bad, lambda d: d.pop("components"))
    elif damage == "nan":
        _rewrite(good, bad, lambda d: d.__setitem__("mean", np.full_like(d["mean"], np.nan)))
    elif damage == "wrong-shape":
        _rewrite(
            good,
            bad,
            lambda d: d.__setitem__(
                "node_scores",
                d["node_scores"][:, :1].copy() if d["node_scores"].shape[1] > 1 else d["node_scores"][:-1],
            ),
        )
    elif damage == "bad-json":
        _rewrite(good, bad, lambda d: d.__setitem__("metadata", np.array("{not json")))
    with pytest.raises(ModelFileError):
        SpatialModel.load(bad)


def test_missing_file(tmp_path):
    with pytest.raises(ModelFileError, match="does not exist"):
        SpatialModel.load(tmp_path / "nothing.npz")


def test_default_model_missing_is_a_model_file_error(monkeypatch, tmp_path):
    monkeypatch.setattr(model_module, "default_model_path", lambda: tmp_path / "absent.npz")
    model_module.default_model.cache_clear()
    try:
        with pytest.raises(ModelFileError, match="train_default_spatial"):
            model_module.default_model()
    finally:
        model_module.default_model.cache_clear()


@pytest.mark.skipif(not model_module.default_model_path().is_file(), reason="default spatial model not trained yet")
def test_shipped_default_model():
    model = model_module.default_model()
    assert model.mesh_.parameters == ("saturation",) and model.mesh_.n_nodes == 16
    np.testing.assert_allclose(model.mesh_.nodes[:, 0], np.linspace(0, 1, 16))
    assert model.mesh_.base == SandSample().to_dict()
    assert model.wavelength_nm_ == 550.0 and (model.stacks_, model.slices_) == (31, 30)
    assert model.holdout_scores_ and model.holdout_scores_[0]["point"] == {"saturation": 0.5}


def test_unknown_member_is_refused(beach_model, tmp_path):
    # Issue 24 #8: a member the format does not declare (here a large one) is refused unread.
    good = beach_model.save(tmp_path / "good.npz")
    bad = tmp_path / "bad.npz"
    with zipfile.ZipFile(good) as z, zipfile.ZipFile(bad, "w", zipfile.ZIP_DEFLATED) as out:
        for info in z.infolist():
            out.writestr(info.filename, z.read(info))
        out.writestr("extra.npy", bytes(10**7))
    with pytest.raises(ModelFileError, match=r"members \['extra.npy'\] that a spatial model file does not have"):
        SpatialModel.load(bad)


# ---- interpolation in the log normal reflectance (absorbers) ---------------------------------
@pytest.fixture(scope="module")
def albedo_mesh():
    """Iron oxide × saturation: in the fakes the shape depends on the albedo alone."""
    return Mesh.grid(iron_oxide=[0.0, 0.05, 0.1], saturation=[0.0, 0.5, 1.0])


@pytest.fixture(scope="module")
def albedo_nodes(albedo_mesh):
    return spatial_fakes.measured_nodes(albedo_mesh, RAYS, stacks=STACKS, slices=SLICES, seed=11)


def test_absorbers_interpolate_in_log_normal_reflectance(albedo_mesh, albedo_nodes):
    model = SpatialModel(n_components=3, absorbers=("iron_oxide",)).fit(albedo_nodes, albedo_mesh)
    r = model.node_normal_reflectance_
    # the interpolation coordinates: log r0, then the other mesh parameters
    np.testing.assert_allclose(model.interpolation_.nodes[:, 0], np.log(r))
    np.testing.assert_allclose(model.interpolation_.nodes[:, 1], albedo_mesh.nodes[:, 1])
    # at a node with its own r0 the prediction is that node's (exact, as eq. 7 is at nodes)
    for k in (0, 4, 8):
        node = albedo_mesh.sample_dict(albedo_mesh.nodes[k])
        np.testing.assert_allclose(
            model.scores(node, normal_reflectance=r[k]), model.node_scores_[k : k + 1], rtol=1e-12, atol=1e-12
        )
    # the iron oxide acts only through r0: two samples with one r0 and saturation share their shape
    a = model.predict({**albedo_mesh.base, "iron_oxide": 0.02, "saturation": 0.3}, normal_reflectance=0.4)
    b = model.predict({**albedo_mesh.base, "iron_oxide": 0.07, "saturation": 0.3}, normal_reflectance=0.4)
    np.testing.assert_array_equal(a, b)


def test_an_r0_beyond_the_nodes_takes_the_shape_at_the_hull(albedo_mesh, albedo_nodes):
    model = SpatialModel(n_components=3, absorbers=("iron_oxide",)).fit(albedo_nodes, albedo_mesh)
    sample = {**albedo_mesh.base, "iron_oxide": 0.05, "saturation": 0.5}
    far, further = (model.predict(sample, normal_reflectance=r) for r in (0.999, 1.0))
    np.testing.assert_allclose(far, further, rtol=1e-9)  # both moved onto the hull, at one point
    assert np.isfinite(far).all()
    with pytest.raises(ParameterError, match="normal_reflectance"):
        model.predict(sample, normal_reflectance=0.0)


def test_r0_defaults_to_the_spectral_predictor(albedo_mesh, albedo_nodes):
    from sandlight.predictor.prediction import predict

    model = SpatialModel(n_components=3, absorbers=("iron_oxide",)).fit(albedo_nodes, albedo_mesh)
    sample = SandSample(iron_oxide=0.03, saturation=0.4)
    r0 = float(predict([sample], [550.0])["reflectance"].values.ravel()[0])
    np.testing.assert_array_equal(model.predict(sample), model.predict(sample, normal_reflectance=r0))


def test_interpolation_coordinates_survive_a_file(albedo_mesh, albedo_nodes, tmp_path):
    model = SpatialModel(n_components=3, absorbers=["iron_oxide"], log_parameters=[]).fit(albedo_nodes, albedo_mesh)
    back = SpatialModel.load(model.save(tmp_path / "albedo.npz"))
    assert back.absorbers == ("iron_oxide",) and back.log_parameters == ()
    sample = {**albedo_mesh.base, "iron_oxide": 0.02, "saturation": 0.3}
    np.testing.assert_array_equal(
        back.predict(sample, normal_reflectance=0.3), model.predict(sample, normal_reflectance=0.3)
    )


def test_bad_interpolation_coordinates_are_named(albedo_mesh, albedo_nodes):
    with pytest.raises(ParameterError, match="absorbers.*grain_size"):
        SpatialModel(absorbers=("grain_size",)).fit(albedo_nodes, albedo_mesh)
    with pytest.raises(ParameterError, match="log_parameters.*iron_oxide"):
        SpatialModel(absorbers=("iron_oxide",), log_parameters=("iron_oxide",)).fit(albedo_nodes, albedo_mesh)
    with pytest.raises(ParameterError, match="log_parameters.*saturation"):  # saturation 0 at a node
        SpatialModel(log_parameters=("saturation",)).fit(albedo_nodes, albedo_mesh)
    with pytest.raises(ParameterError, match="absorbers"):
        SpatialModel(absorbers=("colour",)).fit(albedo_nodes, albedo_mesh)


def test_reflectance_anchors_bracket_a_prediction_linear_in_log_r0(albedo_mesh, albedo_nodes, beach_model):
    model = SpatialModel(n_components=3, absorbers=("iron_oxide",)).fit(albedo_nodes, albedo_mesh)
    sample = {**albedo_mesh.base, "iron_oxide": 0.03, "saturation": 0.3}
    nodes = model.node_normal_reflectance_
    anchors = model.reflectance_anchors(sample, 1e-4, 1.0)
    # the range is clipped to the nodes' r0, the anchors ascend and include both ends
    np.testing.assert_allclose(anchors[[0, -1]], [nodes.min(), nodes.max()], rtol=1e-12)
    assert (np.diff(anchors) > 0).all()
    # at the ANCHOR_POINTS reflectances of the range, linear interpolation in log r0 between the
    # bracketing anchors stays within the tolerance
    x = np.log(anchors)
    grid = np.linspace(x[0], x[-1], model_module.ANCHOR_POINTS)
    scores = model.scores([sample] * grid.size, fixed="ignore", normal_reflectance=np.exp(grid))
    at = model.scores([sample] * x.size, fixed="ignore", normal_reflectance=anchors)
    j = np.clip(np.searchsorted(x, grid, side="right") - 1, 0, x.size - 2)
    t = (grid - x[j]) / (x[j + 1] - x[j])
    between = at[j] + t[:, None] * (at[j + 1] - at[j])
    error = np.linalg.norm(between - scores, axis=1) / np.sqrt(model.n_classes_)
    assert error.max() <= model_module.ANCHOR_TOLERANCE * (1 + 1e-9)
    assert anchors.size > 2 and error.max() > 0  # the prediction bends: anchors were needed
    # a looser tolerance needs no more anchors; a point range gives one
    assert model.reflectance_anchors(sample, 1e-4, 1.0, tolerance=0.05).size <= anchors.size
    np.testing.assert_allclose(model.reflectance_anchors(sample, 0.3, 0.3), [0.3])
    with pytest.raises(ParameterError, match="low, high"):
        model.reflectance_anchors(sample, 0.5, 0.2)
    with pytest.raises(ParameterError, match="absorbers"):
        beach_model.reflectance_anchors(sample, 0.1, 0.5)
