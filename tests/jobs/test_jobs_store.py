"""A damaged or foreign job store is refused with a message that says what is wrong, before
any task is computed (issue 24 #12)."""

import json
import os
import shutil

import pytest
import xarray as xr
from test_jobs_runner import make_job

from sandlight.jobs import InProcessExecutor, JobError


@pytest.fixture
def store(tmp_path):
    """A store with 3 of its 24 tasks done, in 3 shards."""
    path = tmp_path / "store"
    for _ in range(3):
        make_job(path).run(InProcessExecutor(), max_tasks=1, progress=False)
    return path


def _rewrite_shard(store, change):
    shard = sorted((store / "shards").glob("shard-*.nc"))[-1]
    with xr.open_dataset(shard) as ds:
        changed = change(ds.load())
    shard.unlink()
    changed.to_netcdf(shard)


def _counting_run(store):
    """Run the job; returns (raised error, number of tasks computed)."""
    calls = []

    def fn(payload, seed):
        calls.append(payload)
        from jobs_fakes import noisy_square

        return noisy_square(payload, seed)

    job = make_job(store)
    job.fn = fn
    with pytest.raises(JobError) as info:
        job.run(InProcessExecutor(), progress=False)
    return info.value, len(calls)


def test_a_shard_with_task_indices_outside_the_job(store):
    # The run computed everything, then failed with AttributeError.
    _rewrite_shard(store, lambda ds: ds.assign(index=ds["index"] + 100))
    error, computed = _counting_run(store)
    assert computed == 0 and "holds task indices [102]... outside 0..23" in str(error)


def test_shards_of_different_results(store):
    _rewrite_shard(store, lambda ds: ds.rename({"value": "other"}))
    error, computed = _counting_run(store)
    assert computed == 0 and "hold different results" in str(error) and "use another output directory" in str(error)


def test_foreign_shards_are_named_as_the_store_s_fault(store):
    for shard in (store / "shards").glob("shard-*.nc"):
        with xr.open_dataset(shard) as ds:
            changed = ds.load().rename({"value": "other"})
        shard.unlink()
        changed.to_netcdf(shard)
    error, computed = _counting_run(store)
    assert computed == 1 and f"the shards in {store / 'shards'} hold results" in str(error)
    assert "they are not of this job" in str(error)


@pytest.mark.parametrize("content", ["[1, 2]", '"a string"', "7"])
def test_job_json_that_is_not_an_object(store, content):
    (store / "job.json").write_text(content)
    error, computed = _counting_run(store)
    assert computed == 0 and "is not a sandlight job settings file" in str(error)


def test_shards_that_is_a_file(store):
    shutil.rmtree(store / "shards")
    (store / "shards").write_text("x")
    error, computed = _counting_run(store)
    assert computed == 0 and "shards is a file" in str(error)


def test_a_store_path_that_is_a_file(tmp_path):
    (tmp_path / "store").write_text("x")
    error, computed = _counting_run(tmp_path / "store")
    assert computed == 0 and "is a file, not a job store directory" in str(error)


@pytest.fixture
def complete(tmp_path):
    path = tmp_path / "complete"
    make_job(path).run(InProcessExecutor(), progress=False)
    return path


def test_an_unreadable_dataset(complete):
    (complete / "dataset.nc").write_bytes(os.urandom(2000))
    for call in (make_job(complete).status, make_job(complete).dataset):
        with pytest.raises(JobError, match="dataset.nc is not a readable dataset"):
            call()


def test_the_dataset_of_another_job(complete, tmp_path):
    # A foreign dataset.nc passed for complete and failed later, e.g. "R = (1,) is not allowed".
    other = tmp_path / "other"
    make_job(other, n=5).run(InProcessExecutor(), progress=False)
    shutil.copy(other / "dataset.nc", complete / "dataset.nc")
    with pytest.raises(JobError, match="is not the dataset of this job store's job"):
        make_job(complete).status()
    assert json.loads((complete / "job.json").read_text())["settings"]["n_tasks"] == 24
