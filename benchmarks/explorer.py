"""Latency of the sand explorer's API on a loopback server (prints figures; asserts nothing).

    python3 benchmarks/explorer.py [--requests 400] [--max-seconds 60] [--previews 5]

Starts ``sandlight.web.create_app`` under uvicorn in a separate process on 127.0.0.1 (a free
port), then, from this process with httpx:

- p50 / p95 / max latency of ``POST /api/spectrum`` and ``POST /api/colour`` with 1 and with 20
  concurrent clients (each request a different sample: the red-dune preset with a random iron
  oxide fraction and hematite ratio, seeded), ``--requests`` requests per case or
  ``--max-seconds``, whichever comes first; target p95 ≤ 20 ms with 20 clients;
- the time from ``POST /api/jobs/preview`` to the first image on the job's event stream, for
  ``--previews`` new samples (each a new `SandAppearance`, so nothing is cached); target ≤ 1 s.

Latency is wall time seen by the client, request sent to answer read, loopback only.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import os
import socket
import subprocess
import sys
import time

import httpx
import numpy as np

from sandlight.machine import describe

SERVER = (
    "import uvicorn; uvicorn.run('sandlight.web:create_app', factory=True, host='127.0.0.1', port={port}, "
    "log_level='warning')"
)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_until_up(url: str, process: subprocess.Popen, timeout_s: float = 60.0) -> None:
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if process.poll() is not None:
            raise SystemExit("the server stopped before answering")
        try:
            if httpx.get(url + "/api/schema", timeout=1.0).status_code == 200:
                return
        except httpx.TransportError:
            time.sleep(0.1)
    raise SystemExit("the server did not answer within a minute")


def samples(n: int, seed: int) -> list[dict]:
    rng = np.random.default_rng(seed)
    return [
        {"preset": "red-dune", "iron_oxide": float(x), "hematite_ratio": float(h)}
        for x, h in zip(rng.uniform(0.007, 0.06, n), rng.uniform(0.0, 1.0, n))
    ]


async def latencies(url: str, path: str, clients: int, n_requests: int, max_seconds: float) -> np.ndarray:
    todo = samples(n_requests, seed=clients)
    times: list[float] = []
    stop_at = time.monotonic() + max_seconds

    async def client(http: httpx.AsyncClient) -> None:
        while todo and time.monotonic() < stop_at:
            body = {"sample": todo.pop()}
            if path == "/api/colour":
                body["compare"] = "yellow-dune"
            t0 = time.perf_counter()
            res = await http.post(path, json=body)
            times.append(time.perf_counter() - t0)
            res.raise_for_status()

    limits = httpx.Limits(max_connections=clients, max_keepalive_connections=clients)
    async with httpx.AsyncClient(base_url=url, limits=limits, timeout=30.0) as http:
        for _ in range(3):  # warm-up: connections, first model evaluation
            await http.post(path, json={"sample": "red-dune"})
        await asyncio.gather(*(client(http) for _ in range(clients)))
    return np.array(times) * 1000.0


def first_image_s(url: str, sample: dict) -> float:
    with httpx.Client(base_url=url, timeout=60.0) as http:
        t0 = time.perf_counter()
        job = http.post("/api/jobs/preview", json={"sample": sample}).json()
        with http.stream("GET", job["events"]) as events:
            for line in events.iter_lines():
                if line == "event: image":
                    elapsed = time.perf_counter() - t0
                    break
        http.delete(job["status"])
        return elapsed


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--requests", type=int, default=400, help="requests per endpoint and concurrency")
    parser.add_argument("--max-seconds", type=float, default=60.0, help="time bound per endpoint and concurrency")
    parser.add_argument("--previews", type=int, default=5, help="previews of new samples timed")
    args = parser.parse_args()

    port = free_port()
    url = f"http://127.0.0.1:{port}"
    process = subprocess.Popen([sys.executable, "-c", SERVER.format(port=port)])
    try:
        wait_until_up(url, process)
        load = ", ".join(f"{x:.1f}" for x in os.getloadavg())
        print(f"sandlight explorer on {url}; {describe()}; load average {load} (1, 5, 15 min)")
        print(f"{'endpoint':<16} {'clients':>7} {'requests':>8} {'p50 ms':>8} {'p95 ms':>8} {'max ms':>8} {'req/s':>8}")
        for path in ("/api/spectrum", "/api/colour"):
            for clients in (1, 20):
                t0 = time.perf_counter()
                ms = asyncio.run(latencies(url, path, clients, args.requests, args.max_seconds))
                rate = ms.size / (time.perf_counter() - t0)
                p50, p95 = np.percentile(ms, [50, 95])
                print(f"{path:<16} {clients:>7} {ms.size:>8} {p50:>8.2f} {p95:>8.2f} {ms.max():>8.2f} {rate:>8.0f}")
        firsts = [first_image_s(url, s) for s in samples(args.previews, seed=99)]
        print(
            f"first preview image (160×96 px, 1 sample per pixel, new sample each): median {np.median(firsts):.2f} s, "
            f"max {max(firsts):.2f} s over {len(firsts)}: {json.dumps([round(f, 2) for f in firsts])}"
        )
    finally:
        process.terminate()
        process.wait(timeout=10)


if __name__ == "__main__":
    main()
