"""The Dask executor on a real LocalCluster gives the same dataset as a local run."""

import functools

import pytest
import xarray as xr

pytest.importorskip("distributed")

import jobs_fakes  # noqa: E402
from test_jobs_runner import make_job  # noqa: E402

from sandlight.jobs import DaskExecutor, InProcessExecutor  # noqa: E402


@pytest.fixture(scope="module")
def local_dataset(tmp_path_factory):
    status = make_job(tmp_path_factory.mktemp("local") / "store").run(InProcessExecutor(), progress=False)
    with xr.open_dataset(status.dataset_path) as ds:
        return ds.load()


@pytest.fixture(scope="module")
def cluster_client():
    from distributed import Client, LocalCluster

    # Threads rather than processes: quick to start, and the test's task functions need no
    # importing on the workers. Two workers, so tasks really are spread.
    with (
        LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=":0") as cluster,
        Client(cluster) as client,
    ):
        yield client


def test_dask_run_equals_local_run(tmp_path, local_dataset, cluster_client):
    status = make_job(tmp_path / "store").run(DaskExecutor(client=cluster_client), progress=False)
    with xr.open_dataset(status.dataset_path) as ds:
        xr.testing.assert_identical(ds.load(), local_dataset)
    assert cluster_client.status == "running"  # a client passed in is not closed


def test_dask_task_failure_is_resubmitted_without_loss_or_duplicates(tmp_path, local_dataset, cluster_client):
    fn = functools.partial(jobs_fakes.fail_once, str(tmp_path), 7, "raise")
    job = make_job(tmp_path / "store", fn=fn)
    status = job.run(DaskExecutor(client=cluster_client), progress=False)
    assert (tmp_path / "attempted-7").exists()
    with xr.open_dataset(status.dataset_path) as ds:
        xr.testing.assert_identical(ds.load(), local_dataset)


def test_dask_resume_of_a_partial_local_run(tmp_path, local_dataset):
    job = make_job(tmp_path / "store")
    job.run(InProcessExecutor(), max_tasks=9, progress=False)
    # An executor that starts (and closes) its own LocalCluster.
    status = job.run(DaskExecutor(n_workers=2, processes=False), progress=False)
    with xr.open_dataset(status.dataset_path) as ds:
        xr.testing.assert_identical(ds.load(), local_dataset)


def test_dask_worker_process_dying_mid_task(tmp_path, local_dataset):
    # Worker processes this time: the one computing task 5 dies (os._exit). The nanny restarts
    # it, the scheduler reruns the task, and the dataset is unchanged.
    fn = functools.partial(jobs_fakes.fail_once, str(tmp_path), 5, "exit")
    status = make_job(tmp_path / "store", fn=fn).run(DaskExecutor(n_workers=2, processes=True), progress=False)
    assert (tmp_path / "attempted-5").exists()
    with xr.open_dataset(status.dataset_path) as ds:
        xr.testing.assert_identical(ds.load(), local_dataset)
