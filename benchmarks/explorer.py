"""Latency of the sand explorer's API on a loopback server (prints figures; asserts nothing).

    python3 benchmarks/explorer.py [--requests 2000] [--max-seconds 60] [--previews 5]

Starts ``sandlight.web.create_app`` under uvicorn in a separate process on 127.0.0.1 (a free
port), then, from this process with httpx:

- p50 / p95 / max latency of ``POST /api/spectrum`` and ``POST /api/colour`` with 1 and with 20
  concurrent clients (each request a different sample: the red-dune preset with a random iron
  oxide fraction and hematite ratio, seeded), ``--requests`` requests per case or
  ``--max-seconds``, whichever comes first; target p95 ≤ 20 ms with 20 clients;
- the time from ``POST /api/jobs/preview`` to the first image on the job's event stream, for
  ``--previews`` new samples (each a new `SandAppearance`, so nothing is cached); target ≤ 1 s.

Latency is wall time seen by the client, request sent to answer read, loopback only. The CPU time
the server process and this client spent per request (user + system) is printed beside it: on a
small machine the two share the cores, and a closed loop of 20 clients waits on both.
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

import httptools
import httpx
import numpy as np
import psutil

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


class _Answer:
    """httptools callbacks: the status and whether the response is complete."""

    def __init__(self) -> None:
        self.complete = False

    def on_message_complete(self) -> None:
        self.complete = True


async def _post(reader: asyncio.StreamReader, writer: asyncio.StreamWriter, request: bytes) -> int:
    """Send one pre-encoded HTTP/1.1 request on a kept-alive connection, read the whole answer."""
    answer = _Answer()
    parser = httptools.HttpResponseParser(answer)
    writer.write(request)
    while not answer.complete:
        data = await reader.read(65536)
        if not data:
            raise SystemExit("the server closed the connection")
        parser.feed_data(data)
    return parser.get_status_code()


def _request(port: int, path: str, body: dict) -> bytes:
    data = json.dumps(body).encode()
    head = (
        f"POST {path} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nContent-Type: application/json\r\n"
        f"Content-Length: {len(data)}\r\n\r\n"
    )
    return head.encode() + data


async def latencies(port: int, path: str, clients: int, n_requests: int, max_seconds: float) -> np.ndarray:
    """Latencies (ms) of ``clients`` closed-loop clients, each on its own kept-alive connection.

    The client is lean on purpose (requests encoded before the clock starts, responses parsed by
    httptools, the C parser uvicorn uses): on two cores a heavier client (httpx costs ~1.5–3 ms
    of CPU per request) would measure itself rather than the server."""
    extra = {"compare": "yellow-dune"} if path == "/api/colour" else {}
    todo = [_request(port, path, {"sample": s, **extra}) for s in samples(n_requests, seed=clients)]
    warm = _request(port, path, {"sample": "red-dune", **extra})
    times: list[float] = []
    stop_at = time.monotonic() + max_seconds

    async def client() -> None:
        reader, writer = await asyncio.open_connection("127.0.0.1", port)
        try:
            for _ in range(3):  # warm-up: the connection, the first model evaluation
                await _post(reader, writer, warm)
            await ready.wait()
            while todo and time.monotonic() < stop_at:
                request = todo.pop()
                t0 = time.perf_counter()
                status = await _post(reader, writer, request)
                times.append(time.perf_counter() - t0)
                if status != 200:
                    raise SystemExit(f"{path} answered {status}")
        finally:
            writer.close()

    ready = asyncio.Event()
    tasks = [asyncio.create_task(client()) for _ in range(clients)]
    await asyncio.sleep(0.5)
    ready.set()
    await asyncio.gather(*tasks)
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
    parser.add_argument("--requests", type=int, default=2000, help="requests per endpoint and concurrency")
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
        print(
            f"{'endpoint':<16} {'clients':>7} {'requests':>8} {'p50 ms':>8} {'p95 ms':>8} {'max ms':>8} {'req/s':>8}"
            f" {'server CPU ms/req':>18} {'client CPU ms/req':>18}"
        )
        server = psutil.Process(process.pid)
        for path in ("/api/spectrum", "/api/colour"):
            for clients in (1, 20):
                t0, server0, client0 = time.perf_counter(), server.cpu_times(), time.process_time()
                ms = asyncio.run(latencies(port, path, clients, args.requests, args.max_seconds))
                rate = ms.size / (time.perf_counter() - t0)
                server_ms = 1000 * (sum(server.cpu_times()[:2]) - sum(server0[:2])) / ms.size
                client_ms = 1000 * (time.process_time() - client0) / ms.size
                p50, p95 = np.percentile(ms, [50, 95])
                print(
                    f"{path:<16} {clients:>7} {ms.size:>8} {p50:>8.2f} {p95:>8.2f} {ms.max():>8.2f} {rate:>8.0f}"
                    f" {server_ms:>18.2f} {client_ms:>18.2f}"
                )
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
