"""Overload at the door: time to first byte as a client sees it, connect included (issue 34).

    python -m scripts.overload                          # starts `python -m service`, 256 connections, 20 s
    python -m scripts.overload --connections 256 --seconds 30 --json out.json
    python -m scripts.overload --url http://127.0.0.1:8000   # an already running server (loopback only)

scripts/loadtest.py times a request from when it is written on a connection that is already
open; what a connection waits in the kernel's listen queue before the server accepts it is
outside that, and outside the server's own Server-Timing (the app never sees it). Here the
probes are timed from before their ``connect()``: on loopback the kernel completes the
handshake by itself and queues the connection until the server's ``accept()``, so the request
is written at once and then waits, unseen, for the server to take it.

Load: wrk (C, so the load client takes little of the cores it shares with the server) with
``--connections`` keep-alive connections posting the README's toolpath request as G-code, each
with its own base radius (no cached answers), one after the other; a 503 is followed at once
by the next request (a client that ignores Retry-After: the hard case). From wrk's first second
on, every ``--probe-every`` seconds:

- a fresh connection asks ``GET /health``, as a Kubernetes readiness probe does
  (deploy/kubernetes/deployment.yaml: timeoutSeconds 3), timed to its answer's first byte;
- a fresh connection posts a toolpath (or, one time in eight each, a 3 601-sample profile, a
  base-circle sizing, a 101-row table), timed to its answer's first byte;
- the listen queue's length (the LISTEN socket's rx_queue in /proc/net/tcp: connections the
  kernel holds and the server has not accepted) is sampled every 0.1 s.

wrk's own report (latency from each request's write, connect excluded) is printed with them.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import math
import subprocess
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any
from urllib.parse import urlsplit

from scripts.loadtest import Server, require_loopback
from scripts.rawhttp import encode_request


def profile(base_radius_mm: float, follower: str = "roller") -> dict[str, Any]:
    """The README's cam: a 20 mm rise and return over 180° each."""
    return {"follower": {"type": follower, **({"roller_radius_mm": 10} if follower == "roller" else {})},
            "base_radius_mm": base_radius_mm,
            "segments": [{"type": "rise", "angle_deg": 180, "lift_mm": 20},
                         {"type": "return", "angle_deg": 180, "lift_mm": 20}]}


def toolpath(base_radius_mm: float) -> dict[str, Any]:
    """The README's toolpath request: a 6 mm tool within 0.005 mm, as G-code."""
    return {"profile": profile(base_radius_mm), "tool_radius_mm": 6, "tolerance_mm": 0.005, "feed_mm_min": 300,
            "format": "gcode"}


def mix(k: int) -> tuple[str, str, Any]:
    """The ``k``-th request (method, path, body): the README's requests, each with its own base
    radius (so no answer comes from a cache): toolpaths, with a 3 601-sample profile, a base-circle
    sizing and a 101-row table every 8th request each."""
    radius = 40 + k * 1e-6  # distinct bodies: no cached answer
    kind = 0 if k % 8 >= 3 else k % 8 + 1
    if kind == 0:
        return "POST", "/v1/profiles/toolpath", toolpath(radius)
    if kind == 1:
        return "POST", "/v1/profiles", {"profile": profile(radius), "samples": 3601}
    if kind == 2:
        return "POST", "/v1/profiles/base-circle", {"profile": profile(radius - 25, "knife-edge"),
                                                    "max_pressure_angle_deg": 30}
    return "POST", "/v1/curves/table", {"curve": {"type": "named", "name": "MS"}, "samples": 101}

PROBE_TIMEOUT_S = 3.0  # the readiness probe's timeoutSeconds


def percentile(values: list[float], q: float) -> float:
    if not values:
        return math.nan
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(q * len(ordered)))]



async def read_answer(reader: asyncio.StreamReader) -> tuple[int, dict[str, str], float]:
    """Status, headers and when the first byte came (time.perf_counter()); the body read and dropped."""
    head = await reader.readuntil(b"\r\n\r\n")
    first_byte = time.perf_counter()
    status_line, *lines = head.decode("latin-1").split("\r\n")
    headers = {}
    for line in lines:
        if line:
            name, _, value = line.partition(":")
            headers[name.strip().lower()] = value.strip()
    if "content-length" in headers:
        await reader.readexactly(int(headers["content-length"]))
    elif headers.get("transfer-encoding") == "chunked":
        while True:
            size = int((await reader.readuntil(b"\r\n")).split(b";")[0], 16)
            await reader.readexactly(size + 2)
            if size == 0:
                break
    return int(status_line.split(" ", 2)[1]), headers, first_byte


def listen_queue(port: int) -> int | None:
    """Connections waiting in the listen queue of the LISTEN socket on ``port`` (IPv4)."""
    for line in Path("/proc/net/tcp").read_text().splitlines()[1:]:
        cols = line.split()
        if cols[3] == "0A" and int(cols[1].rsplit(":", 1)[1], 16) == port:
            return int(cols[4].split(":")[1], 16)
    return None


WRK_SCRIPT = """
-- the README's toolpath request as G-code, each with its own base radius: no cached answers
counter = 0
function setup(thread) thread:set("id", counter); counter = counter + 1 end
function init(args) n = 0 end
request = function()
  n = n + 1
  local body = string.format(%s, 40 + (id * 1000000 + n) * 1e-7)
  return wrk.format("POST", "/v1/profiles/toolpath", {["Content-Type"] = "application/json"}, body)
end
statuses = {}
response = function(status, headers, body) statuses[status] = (statuses[status] or 0) + 1 end
"""


def wrk_script() -> str:
    body = json.dumps(toolpath(40.0), separators=(",", ":")).replace('"base_radius_mm":40.0', '"base_radius_mm":%.7f')
    return WRK_SCRIPT % json.dumps(body)


@dataclass
class Stats:
    probes: list[float] = field(default_factory=list)  # /health: connect to whole answer (inf: none in 30 s)
    probe_statuses: dict[int, int] = field(default_factory=dict)
    newcomers: list[float] = field(default_factory=list)  # a fresh connection's toolpath: connect to first byte
    newcomer_statuses: dict[int, int] = field(default_factory=dict)
    queue: list[int] = field(default_factory=list)  # listen queue samples


async def timed(host: str, port: int, raw: bytes) -> tuple[float, int]:
    """A fresh connection sends ``raw``: seconds from before its connect to the answer's first
    byte (inf when none came within 30 s), and the status (0 then)."""
    started = time.perf_counter()
    try:
        async with asyncio.timeout(30):
            reader, writer = await asyncio.open_connection(host, port)
            writer.write(raw)
            status, _, first_byte = await read_answer(reader)
            writer.close()
        return first_byte - started, status
    except (TimeoutError, OSError, asyncio.IncompleteReadError):
        return math.inf, 0


async def observe(url: str, seconds: float, every: float) -> Stats:
    """The timed probes and the listen queue, for ``seconds``."""
    parts = urlsplit(url)
    host, port = parts.hostname or "127.0.0.1", parts.port or 80
    health = encode_request(f"{host}:{port}", "GET", "/health", headers={"Connection": "close"})
    stats = Stats()
    end = time.perf_counter() + seconds

    async def probe(raw: bytes, times: list[float], statuses: dict[int, int]) -> None:
        took, status = await timed(host, port, raw)
        times.append(took)
        statuses[status] = statuses.get(status, 0) + 1

    async def probes() -> None:
        """One of each every ``every`` seconds, not waiting for the ones before (as a prober does)."""
        started, k = [], 0
        while time.perf_counter() < end:
            k += 1
            newcomer = encode_request(f"{host}:{port}", *mix(10_000_000 + k), headers={"Connection": "close"})
            started += [asyncio.create_task(probe(health, stats.probes, stats.probe_statuses)),
                        asyncio.create_task(probe(newcomer, stats.newcomers, stats.newcomer_statuses))]
            await asyncio.sleep(every)
        await asyncio.gather(*started)

    async def sample_queue() -> None:
        while time.perf_counter() < end:
            depth = listen_queue(port)
            if depth is not None:
                stats.queue.append(depth)
            await asyncio.sleep(0.1)

    await asyncio.gather(probes(), sample_queue())
    return stats


def run(url: str, connections: int, seconds: float, every: float) -> tuple[Stats, str]:
    """wrk's ``connections`` for ``seconds`` and, from its second on, the probes: the probes'
    stats and wrk's report."""
    with tempfile.NamedTemporaryFile("w", suffix=".lua") as script:
        script.write(wrk_script())
        script.flush()
        wrk = subprocess.Popen(["wrk", "-t2", f"-c{connections}", f"-d{seconds + 2:g}s", "--timeout", "30s",
                                "--latency", "-s", script.name, url], stdout=subprocess.PIPE, text=True)
        time.sleep(1.0)  # every connection opened
        stats = asyncio.run(observe(url, seconds, every))
        out, _ = wrk.communicate(timeout=120)
    return stats, out


def figures(stats: Stats) -> dict[str, Any]:
    def ms(values: list[float]) -> dict[str, Any]:
        finite = [v for v in values if math.isfinite(v)]
        return {"n": len(values), "p50_ms": round(percentile(finite, 0.5) * 1000, 1),
                "p90_ms": round(percentile(finite, 0.9) * 1000, 1),
                "max_ms": round(max(finite, default=math.nan) * 1000, 1),
                "over_3s": sum(1 for v in values if v > PROBE_TIMEOUT_S), "none_in_30s": len(values) - len(finite)}

    return {
        "health_probe": {**ms(stats.probes), "statuses": stats.probe_statuses},
        "new_connection_toolpath_first_byte": {**ms(stats.newcomers), "statuses": stats.newcomer_statuses},
        "listen_queue": {"max": max(stats.queue, default=0),
                         "mean": round(sum(stats.queue) / len(stats.queue), 1) if stats.queue else 0.0},
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--url", help="a running server (loopback only); default: start one")
    parser.add_argument("--connections", type=int, default=256)
    parser.add_argument("--seconds", type=float, default=20.0)
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--probe-every", type=float, default=0.5, help="seconds between probes of each kind")
    parser.add_argument("--json", help="write the figures to this file too")
    args = parser.parse_args()
    if not 0 < args.seconds <= 3600:
        raise SystemExit("--seconds must be in (0, 3600]")
    server = None
    if args.url:
        url = require_loopback(args.url)
    else:
        server = Server(workers=args.workers)
        server.wait_ready()
        url = server.url
    try:
        stats, wrk_report = run(url, args.connections, args.seconds, args.probe_every)
        result = figures(stats)
    finally:
        if server is not None:
            server.stop()
    result = {"connections": args.connections, "seconds": args.seconds, "workers": args.workers, **result,
              "wrk": wrk_report.strip().splitlines()}
    text = json.dumps(result, indent=1)
    print(text)
    if args.json:
        Path(args.json).write_text(text + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
