"""Node measurement job (restartable), train_spatial, held-out evaluation; one tiny real-engine run."""

import json

import numpy as np
import pytest
import spatial_fakes
import xarray as xr

from sandlight.errors import ParameterError
from sandlight.gonio import MeasuredBRDF
from sandlight.jobs import InProcessExecutor, JobSettingsError
from sandlight.spatial import Mesh, SpatialModel, evaluate, measure_nodes, node_brdfs, train_spatial
from sandlight.spatial.training import NODE_SET_FORMAT, engine_measure

STACKS, SLICES = 5, 6


def run(path, mesh, rays=10**6, **kw):
    return measure_nodes(
        path,
        mesh,
        550.0,
        rays,
        7,
        InProcessExecutor(),
        stacks=STACKS,
        slices=SLICES,
        measure=spatial_fakes.fake_measure,
        progress=False,
        **kw,
    )


def test_node_dataset_layout(tmp_path):
    mesh = Mesh.beach(4)
    status = run(tmp_path / "nodes", mesh)
    assert status.complete
    with xr.open_dataset(status.dataset_path) as ds:
        assert ds.attrs["format"] == NODE_SET_FORMAT
        assert ds.attrs["wavelength_nm"] == 550.0 and ds.attrs["rays"] == 10**6
        r = 1 + (STACKS - 1) * SLICES
        assert ds["counts"].dims == ("node", "incoming", "outgoing") and ds["counts"].shape == (4, r, r)
        assert ds["counts"].dtype == np.uint32
        np.testing.assert_allclose(ds["saturation"].values, mesh.nodes[:, 0])
        assert (ds["launched"].sum(axis=1).values == 10**6).all()
    brdfs = node_brdfs(status.dataset_path)
    assert all(isinstance(b, MeasuredBRDF) for b in brdfs)
    assert brdfs[2].sample["saturation"] == pytest.approx(2 / 3)
    assert brdfs[2].sample["iron_oxide_form"] == "coating"


def test_interrupted_job_resumes_to_the_same_dataset(tmp_path):
    mesh = Mesh.beach(5)
    whole = run(tmp_path / "whole", mesh)
    first = run(tmp_path / "parts", mesh, max_tasks=2)
    assert not first.complete and first.n_done == 2
    resumed = run(tmp_path / "parts", mesh)
    assert resumed.complete
    with xr.open_dataset(whole.dataset_path) as a, xr.open_dataset(resumed.dataset_path) as b:
        for name in ("counts", "absorbed", "launched", "lost", "seed"):
            np.testing.assert_array_equal(a[name].values, b[name].values)
    with pytest.raises(JobSettingsError, match="rays"):
        run(tmp_path / "parts", mesh, rays=2 * 10**6)


def test_train_spatial_end_to_end(tmp_path):
    mesh = Mesh.beach(6)
    result = train_spatial(
        tmp_path,
        mesh,
        10**7,
        seed=1,
        holdout=[[0.5]],
        holdout_rays=10**8,
        stacks=STACKS,
        slices=SLICES,
        executor=InProcessExecutor(),
        measure=spatial_fakes.fake_measure,
        progress=False,
        model_params={"n_components": 2},
    )
    assert result.complete and result.model.n_components_ == 2
    report = result.reports[0]
    assert report.point == {"saturation": 0.5}
    assert report.n_pairs > 0 and 0 < report.fraction_pairs <= 1
    assert report.relative_rms < 0.05
    assert report.noise_rms < 0.02
    loaded = SpatialModel.load(result.model_path)
    assert loaded.holdout_scores_[0]["relative_rms"] == pytest.approx(report.relative_rms)
    assert loaded.training_set_["rays_per_node"] == 10**7
    saved = json.loads((tmp_path / "holdout-report.json").read_text())
    assert saved[0]["n_values"] == report.n_values
    # fit_only refits the stored measurements without measuring again.
    again = train_spatial(
        tmp_path,
        mesh,
        10**7,
        seed=1,
        holdout=[[0.5]],
        holdout_rays=10**8,
        stacks=STACKS,
        slices=SLICES,
        measure=spatial_fakes.fake_measure,
        fit_only=True,
        model_params={"n_components": 3},
    )
    assert again.model.n_components_ == 3
    np.testing.assert_array_equal(again.model.node_scores_[:, :2], result.model.node_scores_)


def test_held_out_points_outside_the_mesh_are_refused_before_measuring(tmp_path):
    with pytest.raises(ParameterError, match="saturation"):
        train_spatial(
            tmp_path,
            Mesh(("saturation",), [0.0, 0.5]),
            10**6,
            holdout=[[0.8]],
            stacks=STACKS,
            slices=SLICES,
            executor=InProcessExecutor(),
            measure=spatial_fakes.fake_measure,
            progress=False,
        )
    assert not (tmp_path / "holdout").exists()


def test_evaluate_scores_the_prediction_against_the_noise():
    mesh = Mesh.beach(6)
    model = SpatialModel(n_components=2).fit(
        spatial_fakes.measured_nodes(mesh, 10**8, stacks=STACKS, slices=SLICES), mesh
    )
    params = mesh.sample_dict([0.5])
    counts = spatial_fakes.fake_measure(params, 550.0, rays=10**8, seed=99, stacks=STACKS, slices=SLICES, threads=1)
    measured = MeasuredBRDF.from_counts(**counts, stacks=STACKS, slices=SLICES, sample=params, rays=10**8)
    report = evaluate(model, measured)
    assert report.relative_rms >= report.noise_rms * 0.5
    assert report.model_error <= report.relative_rms
    # A wrong model is caught: scoring the measurement against the prediction at the other end.
    far = MeasuredBRDF.from_counts(
        **spatial_fakes.fake_measure(
            mesh.sample_dict([1.0]), 550.0, rays=10**8, seed=98, stacks=STACKS, slices=SLICES, threads=1
        ),
        stacks=STACKS,
        slices=SLICES,
        sample=params,
        rays=10**8,
    )
    assert evaluate(model, far).relative_rms > 5 * report.relative_rms
    few = MeasuredBRDF.from_counts(
        **spatial_fakes.fake_measure(params, 550.0, rays=1000, seed=1, stacks=STACKS, slices=SLICES, threads=1),
        stacks=STACKS,
        slices=SLICES,
        sample=params,
    )
    with pytest.raises(ParameterError, match="more trials"):
        evaluate(model, few)


def test_tiny_run_with_the_real_engine(tmp_path):
    # The whole chain with sandlight's transport engine: 3 nodes × 20 000 trials on 4 × 4 patches.
    mesh = Mesh.beach(3)
    status = measure_nodes(
        tmp_path / "nodes", mesh, 550.0, 20_000, 3, InProcessExecutor(), stacks=4, slices=4, progress=False
    )
    brdfs = node_brdfs(status.dataset_path)
    reference = engine_measure(
        mesh.sample_dict(mesh.nodes[1]),
        550.0,
        rays=20_000,
        seed=int(xr.open_dataset(status.dataset_path)["seed"].values[1]),
        stacks=4,
        slices=4,
        threads=1,
    )
    np.testing.assert_array_equal(brdfs[1].counts, reference["counts"])  # the job is the engine, bit for bit
    # Saturated sand is darker than dry sand at 550 nm.
    assert brdfs[2].normal_reflectance < brdfs[0].normal_reflectance
    model = SpatialModel().fit(brdfs, mesh)
    assert model.predict([[0.25]]).shape == (1, brdfs[0].unique_values.size)


def test_path_memory_is_the_engines_and_is_recorded(tmp_path):
    # Dry sand, two iron-oxide contents: the job's counts are the engine's with memory="cut", bit
    # for bit, and differ from the classic model's; the memory is recorded and kept on resume.
    mesh = Mesh.grid("red-dune", iron_oxide=[0.01, 0.03])
    kw = dict(stacks=4, slices=4, progress=False)
    status = measure_nodes(tmp_path / "nodes", mesh, 450.0, 20_000, 3, InProcessExecutor(), memory="cut", **kw)
    with xr.open_dataset(status.dataset_path) as ds:
        assert ds.attrs["memory"] == "cut"
        seed = int(ds["seed"].values[1])
    measured = node_brdfs(status.dataset_path)[1].counts
    node = dict(
        params=mesh.sample_dict(mesh.nodes[1]),
        wavelength_nm=450.0,
        rays=20_000,
        seed=seed,
        stacks=4,
        slices=4,
        threads=1,
    )
    np.testing.assert_array_equal(measured, engine_measure(**node, memory="cut")["counts"])
    assert not np.array_equal(measured, engine_measure(**node, memory="none")["counts"])
    with pytest.raises(JobSettingsError, match="memory"):
        measure_nodes(tmp_path / "nodes", mesh, 450.0, 20_000, 3, InProcessExecutor(), **kw)
    model = SpatialModel().fit(node_brdfs(status.dataset_path), mesh, training_set={"memory": "cut"})
    assert SpatialModel.load(model.save(tmp_path / "m.npz")).memory_ == "cut"
    assert SpatialModel().fit(node_brdfs(status.dataset_path), mesh).memory_ == "none"
    with pytest.raises(ParameterError, match="memory.*measure"):
        run(tmp_path / "fake", mesh, memory="cut")


def test_leave_one_out_cross_validation():
    from sandlight.spatial import cross_validate

    mesh = Mesh.beach(6)
    brdfs = spatial_fakes.measured_nodes(mesh, 10**8, stacks=STACKS, slices=SLICES)
    results = cross_validate(brdfs, mesh, {"n_components": 2})
    assert [k for k, _ in results] == [1, 2, 3, 4]  # the end nodes are on the hull
    assert all(r.relative_rms < 0.1 for _, r in results)
    assert results[0][1].point == {"saturation": pytest.approx(0.2)}


def test_the_engine_measure_traces_any_traceable():
    from sandlight.gonio.measure import brdf
    from sandlight.physics.media import LambertianSurface

    wall = LambertianSurface(0.5)
    kw = dict(rays=5000, seed=2, stacks=4, slices=4, threads=1)
    counts = engine_measure(wall, 550.0, **kw)
    np.testing.assert_array_equal(counts["counts"], brdf(wall, 550.0, progress=False, **kw).counts)
    # A Lambertian surface absorbs the rest of its albedo and loses nothing.
    assert counts["absorbed"].sum() > 0 and counts["lost"].sum() == 0
