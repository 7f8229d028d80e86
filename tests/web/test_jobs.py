"""Background jobs: the Monte Carlo refinement and the preview, their progress events, cancel,
stop on disconnect, and the limits on jobs per client (rays ≤ 2000, fixed seeds)."""

import base64
import io
import json
import time

import httpx
import numpy as np
import pytest
from PIL import Image

import sandlight
from sandlight.web.jobs import JobManager

WAVELENGTHS = [450.0, 550.0, 650.0]
LONG_RUN = {"sample": "red-dune", "rays": 2000, "wavelengths_nm": list(np.arange(350.0, 2501.0, 10.0))}


def _events(text: str) -> list[tuple[str, dict]]:
    """The (event, data) pairs of a text/event-stream body."""
    out = []
    for block in text.strip().split("\n\n"):
        lines = dict(line.split(": ", 1) for line in block.splitlines())
        out.append((lines["event"], json.loads(lines["data"])))
    return out


def _wait(client, job_id, timeout=60.0):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        status = client.get(f"/api/jobs/{job_id}").json()
        if status["state"] in ("done", "cancelled", "failed"):
            return status
        time.sleep(0.05)
    raise AssertionError(f"job {job_id} did not finish: {status}")


def test_a_refinement_is_the_engines_spectrum_with_its_standard_errors(client):
    res = client.post(
        "/api/jobs/reflectance", json={"sample": "red-dune", "rays": 1500, "wavelengths_nm": WAVELENGTHS, "seed": 7}
    )
    assert res.status_code == 202, res.text
    job = res.json()
    events = _events(client.get(job["events"]).text)  # the stream ends when the job does
    names = [name for name, _ in events]
    assert names[-1] == "done" and "progress" in names
    fractions = [data["fraction"] for name, data in events if name == "progress"]
    assert fractions == sorted(fractions) and fractions[-1] == 1.0
    result = events[-1][1]["result"]
    direct = sandlight.reflectance("red-dune", WAVELENGTHS, rays=1500, seed=7, progress=False)
    np.testing.assert_array_equal(result["reflectance"], direct.values)  # the same seed, the same numbers
    np.testing.assert_array_equal(result["stderr"], direct.stderr)
    # the iron-oxide absorption edge: red sand reflects far more at 650 nm than at 450 nm
    r, se = np.array(result["reflectance"]), np.array(result["stderr"])
    assert r[2] - r[0] > 10 * np.hypot(se[0], se[2])
    assert client.get(job["status"]).json()["state"] == "done"


def test_the_refined_spectrum_exports_with_its_standard_errors(client):
    job = client.post(
        "/api/jobs/reflectance", json={"sample": "red-dune", "rays": 500, "wavelengths_nm": WAVELENGTHS}
    ).json()
    status = _wait(client, job["id"])
    text = client.post("/api/export/spectrum.csv", json={"sample": "red-dune", "job": job["id"]}).text
    rows = [line.split(",") for line in text.splitlines() if line and not line.startswith("#")]
    assert rows[0][:3] == ["wavelength_nm", "reflectance", "stderr"]
    np.testing.assert_allclose([float(r[2]) for r in rows[1:]], status["result"]["stderr"], rtol=1e-6)


def test_cancel_stops_a_run_within_a_batch(client):
    job = client.post("/api/jobs/reflectance", json=LONG_RUN).json()
    while client.get(job["status"]).json()["state"] == "queued":
        time.sleep(0.02)
    res = client.delete(f"/api/jobs/{job['id']}")
    assert res.status_code == 202 and res.json()["cancel_requested"]
    started = time.monotonic()
    status = _wait(client, job["id"])
    assert status["state"] == "cancelled" and "result" not in status
    assert 0 < status["progress"]["done"] < status["progress"]["total"]  # it had started, and stopped early
    assert time.monotonic() - started < 8.0  # an uncancelled run takes about 9 s here
    assert _events(client.get(job["events"]).text)[-1][0] == "cancelled"


def test_a_client_may_have_two_unfinished_jobs_and_no_more(client):
    ids = [client.post("/api/jobs/reflectance", json=LONG_RUN).json()["id"] for _ in range(2)]
    res = client.post("/api/jobs/reflectance", json=LONG_RUN)
    assert res.status_code == 429 and res.json()["error"] == "limit" and "2 unfinished jobs" in res.json()["message"]
    for job_id in ids:
        client.delete(f"/api/jobs/{job_id}")
    assert [_wait(client, j)["state"] for j in ids] == ["cancelled", "cancelled"]
    assert (
        client.post(
            "/api/jobs/reflectance", json={"sample": "red-dune", "rays": 10, "wavelengths_nm": [500]}
        ).status_code
        == 202
    )


@pytest.mark.parametrize(
    ("body", "named"),
    [
        ({"rays": 6000}, "rays"),
        ({"rays": 0}, "rays"),
        ({"rays": "many"}, "rays"),
        ({"wavelengths_nm": [300]}, "wavelengths_nm"),
        ({"wavelengths_nm": list(range(350, 2500, 5))}, "wavelengths_nm"),
        ({"wavelengths_nm": [600, 500]}, "wavelengths_nm"),
        ({"seed": -1}, "seed"),
        ({"threads": 4}, "threads"),
    ],
)
def test_bad_refinements_are_refused_before_any_work(client, body, named):
    res = client.post("/api/jobs/reflectance", json={"sample": "red-dune", "rays": 100, **body})
    assert res.status_code == 400 and res.json()["parameter"] == named, res.text


def test_unknown_jobs_and_kinds_are_refused(client):
    assert client.get("/api/jobs/nope").status_code == 404
    assert client.delete("/api/jobs/nope").status_code == 404
    assert client.get("/api/jobs/nope/events").status_code == 404
    res = client.post("/api/jobs/render", json={})
    assert res.status_code == 400 and res.json()["parameter"] == "job kind"


def _png(url: str) -> Image.Image:
    assert url.startswith("data:image/png;base64,")
    return Image.open(io.BytesIO(base64.b64decode(url.split(",", 1)[1])))


def _preview(client, sample, **options):
    body = {"sample": sample, "width": 32, "height": 20, "spp": 4, **options}
    job = client.post("/api/jobs/preview", json=body)
    assert job.status_code == 202, job.text
    return _events(client.get(job.json()["events"]).text)


def test_a_preview_streams_images_of_more_and_more_samples(client):
    events = _preview(client, "red-dune", spp=16)
    images = [data for name, data in events if name == "image"]
    assert [i["index"] for i in images] == [0, 1, 2]  # 1, 1 + 3, 4 + 12 samples per pixel
    assert events[-1][0] == "done" and events[-1][1]["result"]["spp"] == 16
    first = _png(images[0]["url"])
    assert first.size == (32, 20) and first.mode == "RGB"


def test_white_quartz_sand_looks_brighter_than_red_dune_sand(client):
    def mean_pixel(sample):
        events = _preview(client, sample, terrain="flat", time_h=12.0)
        image = np.asarray(_png([d for n, d in events if n == "image"][-1]["url"]), dtype=float)
        return image[-8:].mean(axis=(0, 1))  # the bottom rows see the ground

    quartz, red = mean_pixel("ottawa-quartz"), mean_pixel("red-dune")
    assert quartz.mean() > red.mean() + 10
    assert red[0] > red[2] + 20  # the red dune is red: R well above B


@pytest.mark.parametrize(
    ("options", "named"),
    [
        ({"width": 4000}, "width"),
        ({"terrain": "mountains"}, "terrain"),
        ({"time_h": 23.0}, "time_h"),
        ({"day_of_year": 400}, "day_of_year"),
        ({"latitude_deg": 95}, "latitude_deg"),
    ],
)
def test_bad_previews_are_refused_naming_the_option(client, options, named):
    res = client.post("/api/jobs/preview", json={"sample": "red-dune", **options})
    assert res.status_code == 400 and res.json()["parameter"] == named, res.text


def test_closing_the_event_stream_cancels_the_job(live_server):
    url, app = live_server
    with httpx.Client(base_url=url, timeout=30) as http:
        job = http.post("/api/jobs/reflectance", json=LONG_RUN).json()
        with http.stream("GET", job["events"]) as stream:
            first = next(stream.iter_lines())
            assert first.startswith("event: ")
        # the stream is closed: the server sees the disconnect and cancels the run
        deadline = time.monotonic() + 20
        while http.get(job["status"]).json()["state"] not in ("cancelled", "done", "failed"):
            assert time.monotonic() < deadline
            time.sleep(0.1)
        assert http.get(job["status"]).json()["state"] == "cancelled"


def test_a_job_queued_behind_another_waits_and_work_that_raises_is_reported():
    jobs = JobManager(max_running=1, max_per_client=3, max_kept=2)
    release = []

    def slow(context):
        while not release:
            context.report(0, 1, "waiting")
            time.sleep(0.01)
        return {"answer": 1}

    def broken(context):
        raise RuntimeError("a secret detail of a bug")

    first = jobs.submit("test", "me", slow)
    second = jobs.submit("test", "me", broken)
    time.sleep(0.2)
    assert first.state == "running" and second.state == "queued"
    release.append(True)
    deadline = time.monotonic() + 10
    while not second.finished:
        assert time.monotonic() < deadline
        time.sleep(0.01)
    assert first.status()["result"] == {"answer": 1}
    assert second.state == "failed" and second.error["error"] == "internal"
    assert "secret" not in json.dumps(second.status())
    jobs.shutdown()
