"""The job runner: determinism, resume after interruption, failures, settings check."""

import functools
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import jobs_fakes
import numpy as np
import pytest
import xarray as xr

from sandlight.errors import Cancelled, ParameterError
from sandlight.jobs import (
    InProcessExecutor,
    Job,
    JobError,
    JobSettingsError,
    LocalExecutor,
    derive_seed,
    make_executor,
    task_seed,
)

N = 24
SETTINGS = {"rays": 1000, "wavelengths_nm": [400.0, 500.0, 600.0]}


def make_job(path, fn=jobs_fakes.noisy_square, n=N, seed=7, settings=SETTINGS):
    return Job(
        path,
        fn,
        jobs_fakes.payloads(n),
        seed=seed,
        settings=settings,
        dims={"value": ("wavelength",)},
        coords={"wavelength": [400.0, 500.0, 600.0]},
        var_attrs={"value": {"units": "1"}},
        attrs={"title": "test job", "meta": {"a": 1}},
        task_dim="sample",
    )


def read_bytes(status):
    return Path(status.dataset_path).read_bytes()


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """An uninterrupted in-process run: the dataset every other run must reproduce."""
    status = make_job(tmp_path_factory.mktemp("ref") / "store").run(InProcessExecutor(), progress=False)
    assert status.complete
    with xr.open_dataset(status.dataset_path) as ds:
        return ds.load(), read_bytes(status)


def assert_same_dataset(status, reference):
    ref_ds, ref_bytes = reference
    with xr.open_dataset(status.dataset_path) as ds:
        xr.testing.assert_identical(ds.load(), ref_ds)
    assert read_bytes(status) == ref_bytes


class TestSeeds:
    def test_deterministic_distinct_and_in_range(self):
        seeds = [task_seed(7, i) for i in range(1000)]
        assert seeds == [task_seed(7, i) for i in range(1000)]
        assert len(set(seeds)) == 1000
        assert all(0 <= s < 2**63 for s in seeds)
        assert task_seed(8, 0) != task_seed(7, 0)

    def test_string_keys_are_stable_across_processes(self):
        # crc32, not the per-process salted hash(): a fresh interpreter gives the same seed.
        code = "from sandlight.jobs import derive_seed; print(derive_seed(5, 'holdout', 3))"
        env = {**os.environ, "PYTHONPATH": str(Path(__file__).parents[2] / "python")}
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True).stdout
        assert int(out) == derive_seed(5, "holdout", 3)
        assert derive_seed(5, "holdout") != derive_seed(5, "training")

    def test_negative_seed_refused(self):
        with pytest.raises(ValueError):
            derive_seed(-1, 0)


class TestDataset:
    def test_contents(self, reference):
        ds, _ = reference
        assert ds.sizes == {"sample": N, "wavelength": 3}
        np.testing.assert_array_equal(ds["sample"], np.arange(N))
        np.testing.assert_allclose(ds["x"], 0.1 * np.arange(N))
        assert ds["label"].values[5] == "ss"
        np.testing.assert_array_equal(ds["seed"], [task_seed(7, i) for i in range(N)])
        # values are the task function's, in index order
        for i in (0, 5, N - 1):
            expected = jobs_fakes.noisy_square(jobs_fakes.payloads(N)[i], task_seed(7, i))
            np.testing.assert_array_equal(ds["value"][i], expected["value"])
        assert ds["value"].attrs["units"] == "1"
        assert json.loads(ds.attrs["meta"]) == {"a": 1}
        assert json.loads(ds.attrs["job_settings"])["rays"] == 1000

    def test_rerun_of_complete_job_does_nothing(self, tmp_path, reference):
        job = make_job(tmp_path / "store")
        first = job.run(InProcessExecutor(), progress=False)
        mtime = first.dataset_path.stat().st_mtime_ns
        again = make_job(tmp_path / "store", fn=functools.partial(jobs_fakes.always_fails_at, 0)).run(
            InProcessExecutor(), progress=False
        )
        assert again.complete and again.dataset_path.stat().st_mtime_ns == mtime
        assert_same_dataset(again, reference)
        assert not list((tmp_path / "store" / "shards").iterdir())  # superseded by dataset.nc


class TestResume:
    def test_max_tasks_then_resume(self, tmp_path, reference):
        job = make_job(tmp_path / "store")
        status = job.run(InProcessExecutor(), max_tasks=10, progress=False)
        assert (status.n_done, status.complete, status.dataset_path) == (10, False, None)
        status = job.run(LocalExecutor(workers=2), max_tasks=5, progress=False)
        assert status.n_done == 15
        status = job.run(InProcessExecutor(), progress=False)
        assert status.complete
        assert_same_dataset(status, reference)

    def test_ctrl_c_keeps_finished_tasks(self, tmp_path, reference):
        job = make_job(tmp_path / "store", fn=functools.partial(jobs_fakes.interrupt_after, str(tmp_path), 9))
        with pytest.raises(Cancelled, match="run the same command again to resume"):
            job.run(InProcessExecutor(), progress=True)
        assert job.status().n_done == 9  # every finished task was stored, none twice
        status = make_job(tmp_path / "store").run(InProcessExecutor(), progress=False)
        assert_same_dataset(status, reference)

    @pytest.mark.parametrize(
        "executor, signum",
        [
            (lambda: LocalExecutor(workers=2), signal.SIGINT),
            (InProcessExecutor, signal.SIGTERM),
        ],
    )
    def test_signal_stops_cleanly(self, tmp_path, reference, executor, signum):
        # A real signal to this process while tasks run: the pool is stopped, the tasks in
        # flight are dropped, and every finished one is stored exactly once.
        # The signal comes from inside task 3 (in a worker process, or in this one), after
        # earlier tasks have been stored.
        fn = functools.partial(jobs_fakes.signal_at, os.getpid(), signum, 3, 0.1)
        job = make_job(tmp_path / "store", fn=fn)
        with pytest.raises(Cancelled, match="resume"):
            job.run(executor(), progress=False)
        assert 0 < job.status().n_done < N
        assert signal.getsignal(signal.SIGTERM) == signal.SIG_DFL  # handler restored
        assert_same_dataset(make_job(tmp_path / "store").run(InProcessExecutor(), progress=False), reference)

    def test_kill_9_loses_only_tasks_in_flight(self, tmp_path, reference):
        store = tmp_path / "store"
        root = Path(__file__).parents[2]
        script = f"""
import functools, sys
import jobs_fakes
from test_jobs_runner import make_job
from sandlight.jobs import InProcessExecutor
make_job({str(store)!r}, fn=functools.partial(jobs_fakes.slow_square, 0.1)).run(
    InProcessExecutor(), progress=False)
"""
        env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(root / "python"), str(Path(__file__).parent)])}
        proc = subprocess.Popen([sys.executable, "-c", script], env=env)
        try:
            deadline = time.monotonic() + 30
            while time.monotonic() < deadline:
                shards = store / "shards"
                if shards.exists() and len(list(shards.glob("shard-*.nc"))) >= 4:
                    break
                time.sleep(0.02)
            os.kill(proc.pid, signal.SIGKILL)
        finally:
            proc.wait()
        assert proc.returncode == -signal.SIGKILL
        job = make_job(store)
        n_done = job.status().n_done
        assert 4 <= n_done < N
        status = job.run(InProcessExecutor(), progress=False)
        assert_same_dataset(status, reference)

    def test_duplicate_results_in_shards_are_read_once(self, tmp_path, reference):
        job = make_job(tmp_path / "store")
        job.run(InProcessExecutor(), max_tasks=6, progress=False)
        store = job.open_store()
        index, results = store.read_results()
        # The same tasks stored again (as after a kill between two writes): same values.
        store.write_shard(
            index[:3], {k: v[:3] for k, v in results.items()}, {"value": ("wavelength",), "label_length": ()}
        )
        assert job.status().n_done == 6
        status = job.run(InProcessExecutor(), progress=False)
        assert_same_dataset(status, reference)


class TestSettings:
    @pytest.mark.parametrize(
        "change, setting",
        [
            ({"settings": {**SETTINGS, "rays": 2000}}, "rays"),
            ({"settings": {**SETTINGS, "wavelengths_nm": [400.0, 500.0, 650.0]}}, "wavelengths_nm[2]"),
            ({"seed": 8}, "master_seed"),
            ({"n": N + 1}, "n_tasks"),
        ],
    )
    def test_resume_with_other_settings_is_refused(self, tmp_path, change, setting):
        make_job(tmp_path / "store").run(InProcessExecutor(), max_tasks=2, progress=False)
        with pytest.raises(JobSettingsError, match=setting.replace("[", r"\[")) as info:
            make_job(tmp_path / "store", **change).run(InProcessExecutor(), progress=False)
        assert info.value.setting == setting

    def test_other_payloads_are_refused(self, tmp_path):
        make_job(tmp_path / "store").run(InProcessExecutor(), max_tasks=2, progress=False)
        job = Job(
            tmp_path / "store",
            jobs_fakes.noisy_square,
            [{**p, "x": p["x"] + 1e-9} for p in jobs_fakes.payloads(N)],
            seed=7,
            settings=SETTINGS,
            dims={"value": ("wavelength",)},
            coords={"wavelength": [400.0, 500.0, 600.0]},
            task_dim="sample",
        )
        with pytest.raises(JobSettingsError, match="payloads_sha256"):
            job.run(InProcessExecutor(), progress=False)

    def test_foreign_directory_is_refused(self, tmp_path):
        (tmp_path / "store").mkdir()
        (tmp_path / "store" / "notes.txt").write_text("mine")
        with pytest.raises(JobError, match="not a sandlight job store"):
            make_job(tmp_path / "store").run(InProcessExecutor(), progress=False)

    def test_stale_temporary_files_are_removed(self, tmp_path, reference):
        job = make_job(tmp_path / "store")
        job.run(InProcessExecutor(), max_tasks=3, progress=False)
        stale = tmp_path / "store" / "shards" / ".shard-000099.nc.12345.0123456789ab.part"
        stale.write_bytes(b"half a file")
        assert job.status().n_done == 3 and not stale.exists()

    def test_bad_options(self, tmp_path):
        with pytest.raises(ParameterError, match="max_retries"):
            make_job(tmp_path / "s").run(InProcessExecutor(), max_retries=-1, progress=False)
        with pytest.raises(ParameterError, match="workers and scheduler"):
            make_executor(workers=2, scheduler="tcp://localhost:1")
        with pytest.raises(ParameterError, match="workers"):
            LocalExecutor(workers=0)


class TestFailures:
    def test_task_raising_once_is_retried(self, tmp_path, reference):
        fn = functools.partial(jobs_fakes.fail_once, str(tmp_path), 5, "raise")
        status = make_job(tmp_path / "store", fn=fn).run(InProcessExecutor(), progress=False)
        assert (tmp_path / "attempted-5").exists()  # the failure did happen
        assert_same_dataset(status, reference)

    def test_worker_process_dying_mid_task(self, tmp_path, reference):
        # The worker computing task 5 dies (os._exit): the pool breaks, is restarted, and
        # every task that was in flight is resubmitted; none lost, none duplicated.
        fn = functools.partial(jobs_fakes.fail_once, str(tmp_path), 5, "exit")
        status = make_job(tmp_path / "store", fn=fn).run(LocalExecutor(workers=2), progress=False)
        assert (tmp_path / "attempted-5").exists()
        assert_same_dataset(status, reference)

    def test_persistent_failure_is_reported_and_others_kept(self, tmp_path, reference):
        fn = functools.partial(jobs_fakes.always_fails_at, 3)
        with pytest.raises(
            JobError,
            match=r"1 task\(s\) failed after 3 attempts.*task 3: "
            r"ValueError: task 3 cannot be computed",
        ):
            make_job(tmp_path / "store", fn=fn).run(InProcessExecutor(), progress=False)
        assert make_job(tmp_path / "store").status().n_done == N - 1
        status = make_job(tmp_path / "store").run(InProcessExecutor(), progress=False)
        assert_same_dataset(status, reference)

    def test_results_of_changing_shape_are_refused(self, tmp_path):
        job = Job(tmp_path / "store", jobs_fakes.shape_depends_on_x, jobs_fakes.payloads(4), seed=1)
        with pytest.raises(JobError, match="must return the same names and shapes"):
            job.run(InProcessExecutor(), progress=False)

    def test_unsupported_payload_types_are_refused(self, tmp_path):
        job = Job(
            tmp_path / "store",
            jobs_fakes.noisy_square,
            [{"i": 0, "x": 1.0, "label": "a"}, {"i": 1, "x": np.array([1.0, 2.0]), "label": "b"}],
            seed=1,
        )
        with pytest.raises(JobError, match="unsupported types"):
            job.run(InProcessExecutor(), progress=False)


def test_process_pool_equals_in_process(tmp_path, reference):
    status = make_job(tmp_path / "store").run(LocalExecutor(workers=2), progress=False)
    assert_same_dataset(status, reference)
