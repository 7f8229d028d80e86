"""Training sets (a restartable job over the engine) and the fit/evaluate pipeline, with a fake
deterministic engine (predictor_fakes)."""

import functools
import json

import numpy as np
import predictor_fakes
import pytest
import xarray as xr
from test_predictor_spectral import SMALL

from sandlight.errors import ParameterError
from sandlight.jobs import DaskExecutor, InProcessExecutor, JobSettingsError, LocalExecutor
from sandlight.predictor import (
    Domain,
    SpectralModel,
    evaluate,
    fit_training_set,
    generate_training_set,
    train_spectral,
    wavelength_grid,
)
from sandlight.predictor.training import training_job

WL = "400:700:20"
RAYS = 20_000
N = 240


def generate(path, executor=None, **kw):
    args = dict(
        n_samples=N,
        wavelengths_nm=WL,
        rays=RAYS,
        seed=11,
        domain=SMALL,
        simulate=predictor_fakes.fake_reflectance,
        progress=False,
    )
    args.update(kw)
    return generate_training_set(path, executor=executor or InProcessExecutor(), **args)


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    status = generate(tmp_path_factory.mktemp("ref") / "training")
    assert status.complete
    with xr.open_dataset(status.dataset_path) as ds:
        return ds.load(), status.dataset_path.read_bytes()


def assert_same(status, reference):
    with xr.open_dataset(status.dataset_path) as ds:
        xr.testing.assert_identical(ds.load(), reference[0])
    assert status.dataset_path.read_bytes() == reference[1]


def test_wavelength_grid():
    assert wavelength_grid("400:700:20").tolist() == list(np.arange(400.0, 701.0, 20.0))
    assert wavelength_grid("350:2500:10")[-1] == 2500.0
    assert wavelength_grid("450,550,650").tolist() == [450.0, 550.0, 650.0]
    for bad in ("700:400:20", "400:700:0", "a,b", "500,400", "400:700"):
        with pytest.raises(ParameterError, match="wavelengths"):
            wavelength_grid(bad)


@pytest.mark.parametrize("spec", ["400:inf:20", "400:700:1e-9", "nan:700:20", ",".join(["500"] * 10_001)])
def test_wavelength_grid_is_bounded_before_it_is_allocated(spec):
    # "400:inf:20" raised OverflowError, "400:700:1e-9" MemoryError (a 2 TiB grid).
    from sandlight.optics import MAX_WAVELENGTHS

    with pytest.raises(ParameterError, match="wavelengths"):
        wavelength_grid(spec)
    assert wavelength_grid(f"400:{400 + MAX_WAVELENGTHS - 1}:1").size == MAX_WAVELENGTHS


class TestDataset:
    def test_contents(self, reference):
        ds, _ = reference
        assert ds.sizes == {"sample": N, "wavelength": 16}
        for name in SMALL.names + ("sand", "depth_mm", "iron_oxide_form", "seed"):
            assert ds[name].dims == ("sample",), name
        for name in SMALL.fixed:
            assert (ds[name] == SMALL.fixed[name]).all(), name
        assert ds["reflectance"].dims == ("sample", "wavelength")
        assert ds["grain_size"].attrs["units"] == "mm" and ds["wavelength"].attrs["units"] == "nm"
        assert ds.attrs["format"] == "sandlight-spectral-training-set"
        assert (ds.attrs["rays"], ds.attrs["seed"], ds.attrs["design"]) == (RAYS, 11, "lhs")
        assert json.loads(ds.attrs["domain"])["forms"] == list(SMALL.forms)
        assert json.loads(ds.attrs["engine"]) == {"incidence_deg": 0.0, "threads": 1, "rays": RAYS}
        assert ds.attrs["simulator"].endswith("predictor_fakes.fake_reflectance")
        assert "sandlight_version" in ds.attrs

    def test_values_are_the_simulators_at_the_sample_seed(self, reference):
        ds, _ = reference
        for i in (0, 17, N - 1):
            params = {k: ds[k].values[i].item() for k in ds.data_vars if ds[k].dims == ("sample",) and k != "seed"}
            expected = predictor_fakes.fake_reflectance(
                params, ds["wavelength"].values, rays=RAYS, seed=int(ds["seed"][i])
            )
            np.testing.assert_array_equal(ds["reflectance"][i], expected.values)
            np.testing.assert_array_equal(ds["stderr"][i], expected.stderr)


class TestRestartAndScaleOut:
    def test_interrupted_then_resumed_equals_uninterrupted(self, tmp_path, reference):
        status = generate(tmp_path / "training", max_tasks=70)
        assert (status.n_done, status.complete) == (70, False)
        assert_same(generate(tmp_path / "training"), reference)

    def test_process_pool_equals_in_process(self, tmp_path, reference):
        assert_same(generate(tmp_path / "training", LocalExecutor(workers=2)), reference)

    def test_dask_local_cluster_with_a_failing_task_equals_local(self, tmp_path, reference):
        # The sample with index 5 fails on its first attempt (as on a dying worker); it is
        # resubmitted, and no sample is lost or stored twice.
        seed_5 = int(reference[0]["seed"][5])
        simulate = functools.partial(predictor_fakes.fail_once, str(tmp_path), seed_5)
        status = generate(
            tmp_path / "training", DaskExecutor(n_workers=2, processes=False), simulate=simulate, max_tasks=None
        )
        assert (tmp_path / "failed-once").exists()
        with xr.open_dataset(status.dataset_path) as ds:
            # same numbers; only the recorded simulator name differs
            xr.testing.assert_equal(ds.load(), reference[0])

    def test_other_settings_are_refused(self, tmp_path):
        generate(tmp_path / "training", max_tasks=5)
        with pytest.raises(JobSettingsError, match="rays"):
            generate(tmp_path / "training", rays=RAYS + 1)
        with pytest.raises(JobSettingsError, match="domain.dimensions"):
            generate(tmp_path / "training", domain=SMALL.restrict(saturation=(0.0, 0.5)))
        with pytest.raises(JobSettingsError, match="simulator"):
            generate(tmp_path / "training", simulate=functools.partial(predictor_fakes.fail_once, str(tmp_path), -1))


@pytest.fixture(scope="module")
def fitted(reference, tmp_path_factory):
    holdout = generate(tmp_path_factory.mktemp("holdout") / "holdout", n_samples=80, seed=12, design="random")
    train_path = tmp_path_factory.mktemp("train") / "training.nc"
    train_path.write_bytes(reference[1])
    model, report = fit_training_set(train_path, holdout.dataset_path)
    with xr.open_dataset(holdout.dataset_path) as ds:
        return model, report, ds.load()


class TestFitAndEvaluate:
    def test_model_records_its_training_set(self, fitted):
        model, _, _ = fitted
        assert model.training_set_["rays"] == RAYS and model.training_set_["n_samples"] == N
        assert len(model.training_set_["sha256"]) == 64
        assert model.domain_ == SMALL
        np.testing.assert_array_equal(model.wavelengths_, wavelength_grid(WL))
        # k is chosen on the noise-free variance: Monte Carlo noise, spread over all 16
        # directions, would otherwise push k up (the raw ratios do not reach 99.9 % by then).
        k = model.n_components_
        assert 1 <= k <= 6
        assert model.signal_variance_ratio_[:k].sum() >= 0.999
        assert model.explained_variance_ratio_[:k].sum() < 0.999

    def test_prediction_beats_the_noise_of_one_monte_carlo_run(self, fitted):
        # The regression averages the Monte Carlo noise of 240 samples: against the noise-free
        # truth it must be closer than a single Monte Carlo estimate is.
        model, _, holdout = fitted
        params = [
            {k: holdout[k].values[i].item() for k in holdout.data_vars if holdout[k].dims == ("sample",)}
            for i in range(holdout.sizes["sample"])
        ]
        truth = np.array([predictor_fakes.true_reflectance(p, model.wavelengths_) for p in params])
        error = np.sqrt(np.mean((model.predict(holdout) - truth) ** 2))
        mc_noise = np.sqrt(np.mean(holdout["stderr"].values ** 2))
        assert error < mc_noise

    def test_report_separates_model_error_from_reference_noise(self, fitted):
        model, report, holdout = fitted
        assert report.n_samples == 80 and report.rms_error.shape == (16,)
        error = model.predict(holdout) - holdout["reflectance"].values
        np.testing.assert_allclose(report.rms_error, np.sqrt((error**2).mean(0)))
        np.testing.assert_allclose(report.max_error, np.abs(error).max(0))
        np.testing.assert_allclose(report.mc_noise_rms, np.sqrt((holdout["stderr"].values ** 2).mean(0)))
        # errors against MC are mostly its noise: RMS error ≈ MC noise (±40 % for 80 samples)
        assert np.all(report.rms_error < 1.4 * report.mc_noise_rms + report.model_error_estimate)
        assert "RMS error" in report.table() and len(report.table().splitlines()) == 18
        assert model.holdout_scores_["rms_error_overall"] == report.rms_error_overall
        assert len(model.holdout_scores_["sha256"]) == 64

    def test_evaluate_refuses_other_wavelengths(self, fitted):
        model, _, holdout = fitted
        with pytest.raises(ParameterError, match="wavelengths"):
            evaluate(model, holdout.isel(wavelength=slice(0, 8)))


def pipeline_arguments(**changes):
    """The arguments of train_spectral shared by the pipeline tests (the fake engine, in process)."""
    args = dict(
        n_samples=N,
        rays=RAYS,
        wavelengths_nm=WL,
        seed=3,
        executor=InProcessExecutor(),
        domain=SMALL,
        simulate=predictor_fakes.fake_reflectance,
        progress=False,
    )
    args.update(changes)
    return args


class TestPipeline:
    def test_train_spectral_end_to_end_and_rerun(self, tmp_path):
        kw = pipeline_arguments(n_holdout=40)
        partial = train_spectral(tmp_path, max_tasks=50, **kw)
        assert not partial.complete and partial.training.n_done == 50
        with pytest.raises(ParameterError, match="incomplete"):
            train_spectral(tmp_path, fit_only=True, **kw)
        run = train_spectral(tmp_path, **kw)
        assert run.complete and run.model_path == tmp_path / "spectral-model.npz"
        assert (tmp_path / "training" / "dataset.nc").exists()
        assert (tmp_path / "holdout" / "dataset.nc").exists()
        report = json.loads((tmp_path / "holdout-report.json").read_text())
        assert report["n_samples"] == 40
        first = run.model_path.read_bytes()
        # again: nothing to compute, the same model
        again = train_spectral(tmp_path, **{**kw, "simulate": predictor_fakes.fake_reflectance})
        assert again.model_path.read_bytes() == first
        refit = train_spectral(tmp_path, fit_only=True, **{**kw, "executor": None})
        loaded = SpectralModel.load(refit.model_path)
        assert loaded.holdout_scores_["n_samples"] == 40

    def test_holdout_rays_and_model_name(self, tmp_path):
        kw = pipeline_arguments(n_holdout=20)
        run = train_spectral(tmp_path, holdout_rays=RAYS * 16, name="small", description="a small domain", **kw)
        with (
            xr.open_dataset(tmp_path / "holdout" / "dataset.nc") as ho,
            xr.open_dataset(tmp_path / "training" / "dataset.nc") as tr,
        ):
            assert (ho.attrs["rays"], tr.attrs["rays"]) == (RAYS * 16, RAYS)
            # the fake engine's noise falls as 1/√rays: 4× less in the hold-out
            ratio = np.sqrt((tr["stderr"] ** 2).mean() / (ho["stderr"] ** 2).mean())
            assert float(ratio) == pytest.approx(4.0, rel=0.1)
        loaded = SpectralModel.load(run.model_path)
        assert (loaded.name_, loaded.description_) == ("small", "a small domain")

    def test_enrichment_adds_samples_from_a_corner(self, tmp_path):
        kw = pipeline_arguments(n_holdout=40)
        corner = SMALL.restrict(forms=["particles"], iron_oxide=0.0, silt=0.0, clay=0.0)
        run = train_spectral(tmp_path, enrichment=(30, corner), **kw)
        with xr.open_dataset(tmp_path / "enrichment" / "dataset.nc") as extra:
            assert extra.sizes["sample"] == 30 and extra.attrs["rays"] == RAYS
            assert (extra["iron_oxide"].values == 0).all() and (extra["silt"].values == 0).all()
            assert set(extra["iron_oxide_form"].values.astype(str)) == {"particles"}
        ts = run.model.training_set_
        assert ts["n_samples"] == N + 30 and ts["enrichment"]["n_samples"] == 30
        assert Domain.from_dict(ts["enrichment"]["domain"]) == corner and len(ts["enrichment"]["sha256"]) == 64
        assert run.model.domain_ == SMALL and run.report.n_samples == 40  # the hold-out: the domain's draws only
        # The fit saw the corner: its samples are predicted within the fake engine's noise.
        with xr.open_dataset(tmp_path / "enrichment" / "dataset.nc") as extra:
            error = run.model.predict(extra) - extra["reflectance"].values
            assert np.sqrt(np.mean(error**2)) < 4 * float(extra["stderr"].mean())
        again = SpectralModel.load(train_spectral(tmp_path, fit_only=True, enrichment=(30, corner), **kw).model_path)
        assert again.training_set_["enrichment"]["sha256"] == ts["enrichment"]["sha256"]

    def test_enrichment_outside_the_domain_or_malformed_is_refused(self, tmp_path):
        kw = pipeline_arguments()
        wider = Domain.default().restrict(forms=["particles"], iron_oxide=0.0)
        with pytest.raises(ParameterError, match="enrichment.*sub-domain"):
            train_spectral(tmp_path, enrichment=(30, wider), **kw)
        with pytest.raises(ParameterError, match="enrichment"):
            train_spectral(tmp_path, enrichment=30, **kw)
        with pytest.raises(ParameterError, match="enrichment samples"):
            train_spectral(tmp_path, enrichment=(0, SMALL), **kw)
        assert not (tmp_path / "training").exists()  # refused before any generation

    def test_fit_training_set_refuses_an_enrichment_of_other_rays(self, tmp_path):
        first = generate(tmp_path / "a", n_samples=60)
        other = generate(tmp_path / "b", n_samples=20, rays=RAYS // 4, seed=12)
        with pytest.raises(ParameterError, match="enrichment.*rays"):
            fit_training_set(first.dataset_path, enrichment=other.dataset_path)

    def test_fit_domain_keeps_the_samples_inside_it(self, tmp_path):
        kw = pipeline_arguments(n_holdout=40)
        low, high = SMALL.dimension("grain_size").low, SMALL.dimension("grain_size").high
        middle = float(np.sqrt(low * high))
        sub = SMALL.restrict(grain_size=(middle, high))
        run = train_spectral(tmp_path, fit_domain=sub, **kw)
        with (
            xr.open_dataset(tmp_path / "training" / "dataset.nc") as tr,
            xr.open_dataset(tmp_path / "holdout" / "dataset.nc") as ho,
        ):
            n_train = int((tr["grain_size"].values >= middle).sum())
            n_hold = int((ho["grain_size"].values >= middle).sum())
        assert 0 < n_train < N and 0 < n_hold < 40
        assert run.model.domain_ == sub and run.model.training_set_["n_used"] == n_train
        assert run.report.n_samples == n_hold
        with pytest.raises(ParameterError, match="grain_size"):
            run.model.predict(SMALL.restrict(grain_size=(low, middle * 0.9)).draw(1, seed=1))


class TestPathMemory:
    """Training with path memory (docs/geometry.md): the engine's setting, recorded and kept."""

    @pytest.fixture
    def fake_engine(self, monkeypatch):
        import sandlight.predictor.training as training

        monkeypatch.setattr(training, "engine_simulate", predictor_fakes.fake_reflectance)

    def test_the_engine_runs_with_the_memory_asked_for(self, tmp_path):
        from sandlight import reflectance
        from sandlight.sample import SandSample

        # Two dry samples of the real engine, 450 nm, few rays: the stored values are those of
        # sandlight.reflectance with memory="cut" at each sample's seed, bit for bit.
        dry = SMALL.restrict(saturation=0.0)
        status = generate_training_set(
            tmp_path / "cut", 2, "450", 2000, 5, InProcessExecutor(), domain=dry, progress=False, memory="cut"
        )
        with xr.open_dataset(status.dataset_path) as ds:
            ds = ds.load()
        assert json.loads(ds.attrs["engine"])["memory"] == "cut"
        for i in range(2):
            params = {k: ds[k].values[i].item() for k in ds.data_vars if ds[k].dims == ("sample",) and k != "seed"}
            run = functools.partial(
                reflectance,
                SandSample(**params),
                [450.0],
                rays=2000,
                seed=int(ds["seed"][i]),
                incidence_deg=0.0,
                threads=1,
            )
            np.testing.assert_array_equal(ds["reflectance"][i], run(memory="cut").values)
            assert ds["reflectance"][i].item() != run(memory="none").values[0]

    def test_recorded_in_the_model_and_refused_on_resume(self, tmp_path, fake_engine):
        kw = pipeline_arguments(n_holdout=20, simulate=None)
        train_spectral(tmp_path, max_tasks=5, memory="packed", **kw)
        with pytest.raises(JobSettingsError, match="engine"):
            train_spectral(tmp_path, memory="none", **kw)
        run = train_spectral(tmp_path, **kw)  # the default memory is 'packed': it resumes
        assert run.model.memory_ == "packed"
        loaded = SpectralModel.load(run.model_path)
        assert loaded.memory_ == "packed" and loaded.training_set_["engine"]["rays"] == RAYS
        # the fake engine is 10 % darker with memory, and so is the model trained on it
        sample = SMALL.draw(1, seed=2)[0]
        truth = predictor_fakes.true_reflectance(sample, loaded.wavelengths_)
        assert np.abs(loaded.predict(sample)[0] / truth - predictor_fakes.MEMORY_FACTOR).max() < 0.02
        from sandlight.predictor import ModelBank

        assert "engine memory 'packed'" in ModelBank([loaded]).describe(0)

    def test_the_default_engine_by_default_and_classic_in_older_files(self, tmp_path, fake_engine):
        from sandlight.physics.media import DEFAULT_MEMORY
        from sandlight.predictor import default_model

        status = generate_training_set(
            tmp_path / "t", 3, "450", 100, 1, InProcessExecutor(), domain=SMALL, progress=False
        )
        with xr.open_dataset(status.dataset_path) as ds:
            engine = json.loads(ds.attrs["engine"])
        assert engine["memory"] == DEFAULT_MEMORY == "packed" and engine["films"] == "pendular"
        # files written before path memory and the pendular rings record neither: the classic
        # model with uniform films, as a training set with memory 'none' and a custom simulate
        status = generate_training_set(
            tmp_path / "c",
            3,
            "450",
            100,
            1,
            InProcessExecutor(),
            domain=SMALL,
            progress=False,
            simulate=predictor_fakes.fake_reflectance,
        )
        with xr.open_dataset(status.dataset_path) as ds:
            assert "memory" not in json.loads(ds.attrs["engine"]) and "films" not in json.loads(ds.attrs["engine"])
        # the shipped bank is trained with the default engine
        bank = default_model()
        assert {m.memory_ for m in bank.models} == {DEFAULT_MEMORY}
        assert {m.training_set_["engine"].get("films") for m in bank.models} == {"pendular"}
        assert f"engine memory {DEFAULT_MEMORY!r}" in bank.describe(0)

    def test_bad_memory(self, tmp_path):
        with pytest.raises(ParameterError, match="memory.*'none', 'channel', 'cut', 'packed'"):
            training_job(tmp_path, 3, "450", 100, 1, domain=SMALL, memory="full")
        with pytest.raises(ParameterError, match="memory.*simulate"):
            training_job(
                tmp_path, 3, "450", 100, 1, domain=SMALL, memory="cut", simulate=predictor_fakes.fake_reflectance
            )


class TestCommandLine:
    @pytest.fixture
    def fake_engine(self, monkeypatch):
        import sandlight.predictor.training as training

        monkeypatch.setattr(training, "engine_simulate", predictor_fakes.fake_reflectance)

    def invoke(self, *args):
        from typer.testing import CliRunner

        from sandlight.cli import app

        return CliRunner().invoke(app, [str(a) for a in args])

    def test_train_spectral_then_resume(self, tmp_path, fake_engine):
        args = [
            "train-spectral",
            "--samples",
            60,
            "--holdout",
            20,
            "--rays",
            1000,
            "--wavelengths",
            "400:700:100",
            "--seed",
            4,
            "--out",
            tmp_path,
            "--workers",
            1,
            "--ridge",
            1e-3,
            "--no-progress",
        ]
        result = self.invoke(*args)
        assert result.exit_code == 0, result.output
        assert "principal components: k =" in result.output and "hold-out: 20 samples" in result.output
        model = SpectralModel.load(tmp_path / "spectral-model.npz")
        assert model.wavelengths_.tolist() == [400.0, 500.0, 600.0, 700.0]
        assert model.get_params()["ridge"] == 1e-3
        again = self.invoke(*args)
        assert again.exit_code == 0
        changed = self.invoke(*[a if a != 1000 else 2000 for a in args])
        assert changed.exit_code == 2 and "rays" in changed.output
        assert "engine memory 'packed'" in result.output and model.memory_ == "packed"  # the default
        other = self.invoke(*args, "--memory", "none")
        assert other.exit_code == 2 and "engine" in other.output
        result = self.invoke(*[tmp_path / "classic" if a == tmp_path else a for a in args], "--memory", "none")
        assert result.exit_code == 0, result.output
        assert "engine memory 'none'" in result.output
        assert SpectralModel.load(tmp_path / "classic" / "spectral-model.npz").memory_ == "none"
        bad = self.invoke(*[tmp_path / "bad" if a == tmp_path else a for a in args], "--memory", "full")
        assert bad.exit_code == 2 and "memory" in bad.output

    def test_bad_options(self, tmp_path):
        result = self.invoke("train-spectral", "--out", tmp_path, "--workers", 2, "--dask-local", 2)
        assert result.exit_code == 2 and "choose one executor" in result.output
        result = self.invoke("train-spectral", "--out", tmp_path, "--wavelengths", "700:400:1")
        assert result.exit_code == 2 and "wavelengths" in result.output

    def test_predict_refuses_a_damaged_model(self, tmp_path):
        bad = tmp_path / "model.npz"
        bad.write_bytes(b"PK\x03\x04 truncated")
        result = self.invoke("predict", "--preset", "red-dune", "--model", bad)
        assert result.exit_code == 2 and "not a readable sandlight spectral model" in result.output

    def test_predict_with_a_model(self, tmp_path):
        pytest.importorskip("sandlight.sample")
        train = Domain.default().draw(3000, seed=1)
        R = np.array([predictor_fakes.true_reflectance(s, wavelength_grid(WL)) for s in train])
        model = SpectralModel(ridge=1e-6).fit(train, R, wavelengths_nm=wavelength_grid(WL))
        path = model.save(tmp_path / "m.npz")
        out = tmp_path / "r.csv"
        result = self.invoke(
            "predict", "--preset", "red-dune", "--model", path, "-o", out, "--plot", tmp_path / "r.png", "--extrapolate"
        )
        assert result.exit_code == 0, result.output
        rows = [row for row in out.read_text().splitlines() if not row.startswith("# ")]  # metadata comments
        assert rows[0] == "wavelength_nm,reflectance" and len(rows) == 17
        assert (tmp_path / "r.png").stat().st_size > 1000
        # a sample file: TOML with a [sample] table, inside the domain
        sample = Domain.default().draw(1, seed=8)[0]
        toml = "[sample]\n" + "".join(
            f"{k} = {json.dumps(v) if isinstance(v, str) else repr(v)}\n" for k, v in sample.items()
        )
        (tmp_path / "s.toml").write_text(toml)
        result = self.invoke("predict", tmp_path / "s.toml", "--model", path)
        assert result.exit_code == 0, result.output
        expected = model.predict(sample)[0]
        assert f"{expected[0]:.4f}" in result.output and "reflectance of s" in result.output
        # it names the model that answered and its (here missing) hold-out score
        assert "model spectral: 13 parameters, 3 forms; no hold-out score" in result.output
        assert "extrapolated" not in result.output


def test_the_engine_simulator_traces_any_traceable():
    from sandlight import reflectance
    from sandlight.physics.powder import Powder
    from sandlight.predictor.training import engine_simulate

    powder = Powder("goethite", 2.5)
    got = engine_simulate(powder, np.array([450.0, 650.0]), rays=1000, seed=4)
    want = reflectance(powder, [450.0, 650.0], rays=1000, seed=4, incidence_deg=0.0, threads=1, progress=False)
    np.testing.assert_array_equal(got.values, want.values)
    assert got.sample == powder.describe()
    # A Traceable carries its own memory: asking for another is refused, not ignored.
    with pytest.raises(ParameterError, match="geometry"):
        engine_simulate(powder, np.array([450.0]), rays=10, seed=4, memory="cut")
