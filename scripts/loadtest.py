"""Load test: concurrent connections against a real uvicorn, for a bounded time.

    python -m scripts.loadtest                    # starts `python -m service` on a free loopback port
    python -m scripts.loadtest --seconds 20       # shorter run
    python -m scripts.loadtest --connections 256 --workers 2 --runs 3   # three consecutive runs, one server
    python -m scripts.loadtest --largest 32       # 32 concurrent largest tables: peak and settled RSS
    python -m scripts.loadtest --url http://127.0.0.1:8000   # an already running server (loopback only)

503 answers (the service shedding load, with Retry-After) are counted apart from errors:
the report gives their share, and the latency of the accepted (200) answers (whole answer
received, also per kind of request) and their wait (until the answer's first byte: a large
table streams after that), with how many took or waited over 2 s; and the wait the server
itself measured (its Server-Timing header), which leaves out the client's and the kernel's. RSS is reported per
worker process (uvicorn's children with --workers > 1).

The client is scripts/rawhttp.py, not httpx: at ~1 ms of CPU per request httpx measured
itself on a machine whose cores it shares with the server. A 503 is followed at once by
the next request (a client that ignores Retry-After: the hard case); --client-processes
spreads the connections over several client processes.

The mix (many distinct specs, drawn from a fixed seed): POST /v1/curves/table (random
universal break points, Makino curve 4 with random T1 ≤ T3, named curves; JSON or CSV),
POST /v1/curves/characteristics, POST /v1/curves/inverse (exact and table method),
GET /v1/curves/{name}/table?format=csv. It reports requests, errors, p50/p99 latency,
the server's RSS (VmRSS from /proc/<pid>/status, when this script started the server)
at start and end, the cache statistics of /health, and checks that a sample of answers
is identical to the same requests against a freshly started (cold) server — or, with
--url, to camcore computing them directly.

It stops by itself: after --seconds, or after --max-requests, whichever comes first.
Exit status 1 when there were errors or mismatches.
"""

from __future__ import annotations

import argparse
import asyncio
import ipaddress
import json
import math
import multiprocessing
import os
import random
import socket
import subprocess
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any
from urllib.parse import urlsplit

import httpx

from scripts.rawhttp import Connection, encode_request

ROOT = Path(__file__).resolve().parents[1]
NAMED = ["MS", "MCV50", "MCV25", "MT", "TR", "cycloid", "simple-harmonic", "3-4-5", "4-5-6-7",
         "trapecloid-2", "one-dwell-cycloid", "asymmetric-cycloid", "constant-velocity"]


# ----------------------------------------------------------------------------- the server
def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def require_loopback(url: str) -> str:
    host = urlsplit(url).hostname or ""
    try:
        loopback = ipaddress.ip_address(host).is_loopback
    except ValueError:
        loopback = host == "localhost"
    if not loopback:
        raise SystemExit(f"refusing to load-test {host!r}: only loopback hosts (127.0.0.0/8, ::1, localhost)")
    return url.rstrip("/")


class Server:
    """`python -m service` on a free loopback port, as the README runs it."""

    def __init__(self, extra_env: dict[str, str] | None = None, workers: int = 1):
        self.port = free_port()
        self.url = f"http://127.0.0.1:{self.port}"
        env = {**os.environ, "CAMCORE_HOST": "127.0.0.1", "CAMCORE_PORT": str(self.port),
               "CAMCORE_WORKERS": str(workers), "CAMCORE_LOG_LEVEL": "warning", **(extra_env or {})}
        self.proc = subprocess.Popen([sys.executable, "-m", "service"], cwd=ROOT, env=env,
                                     stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)

    def wait_ready(self, timeout: float = 30.0) -> None:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if self.proc.poll() is not None:
                err = self.proc.stderr.read().decode() if self.proc.stderr else ""
                raise RuntimeError(f"server exited: {err}")
            try:
                if httpx.get(f"{self.url}/health", timeout=1).status_code == 200:
                    return
            except httpx.TransportError:
                pass
            time.sleep(0.1)
        raise RuntimeError("server did not start in time")

    def rss_kib(self) -> int | None:
        return rss_kib(self.proc.pid)

    def worker_rss_kib(self) -> list[int]:
        """VmRSS of each process serving requests: the server, or its worker children."""
        pids = children(self.proc.pid) or [self.proc.pid]
        return [kib for kib in (rss_kib(pid) for pid in pids) if kib is not None]

    def stop(self) -> None:
        self.proc.terminate()
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        if self.proc.stderr:
            self.proc.stderr.close()


def children(pid: int) -> list[int]:
    try:
        return [int(c) for c in Path(f"/proc/{pid}/task/{pid}/children").read_text().split()]
    except OSError:
        return []


def rss_kib(pid: int) -> int | None:
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    except OSError:
        return None
    return None


# ----------------------------------------------------------------------------- the requests
@dataclass(frozen=True, eq=False)
class Req:
    kind: str
    method: str
    path: str
    json: Any = None
    params: dict[str, Any] | None = None
    csv: bool = False

    def headers(self) -> dict[str, str]:
        return {"Accept": "text/csv"} if self.csv else {}


def random_universal(rng: random.Random) -> dict[str, Any]:
    while True:
        inner = sorted(rng.choice([rng.random(), rng.randint(0, 32) / 32]) for _ in range(6))
        t = [0.0, *inner, 1.0]
        if t[3] >= 1 / 32 and 1 - t[4] >= 1 / 32:
            return {"type": "universal", "t": t}


def random_spec(rng: random.Random) -> dict[str, Any]:
    r = rng.random()
    if r < 0.45:
        return random_universal(rng)
    if r < 0.75:
        t3 = rng.uniform(1 / 32, 0.5)
        return {"type": "makino", "number": 4, "t1": rng.uniform(t3 / 8, t3), "t3": t3}
    spec: dict[str, Any] = {"type": "named", "name": rng.choice(NAMED)}
    if rng.random() < 0.3:
        spec["direction"] = "return"
    return spec


PROFILE = {"follower": {"type": "roller", "roller_radius_mm": 10}, "base_radius_mm": 40,
           "segments": [{"type": "rise", "angle_deg": 120, "lift_mm": 20}, {"type": "dwell", "angle_deg": 60},
                        {"type": "return", "angle_deg": 120, "lift_mm": 20}, {"type": "dwell", "angle_deg": 60}]}


def make_request(rng: random.Random) -> Req:
    spec = random_spec(rng)
    if rng.random() < 0.05:  # heavy work: profiles, sizing, a large streamed table
        heavy = rng.random()
        if heavy < 0.4:
            return Req("profile", "POST", "/v1/profiles", {"profile": PROFILE, "samples": rng.choice([361, 3601])})
        if heavy < 0.7:
            return Req("base-circle", "POST", "/v1/profiles/base-circle",
                       {"profile": PROFILE, "max_pressure_angle_deg": rng.choice([25, 30, 35])})
        return Req("large-table", "POST", "/v1/curves/table", {"curve": spec, "samples": 50_001}, csv=True)
    r = rng.random()
    if r < 0.35:
        return Req("table", "POST", "/v1/curves/table", {"curve": spec, "samples": rng.choice([11, 101, 361, 1001])},
                   csv=rng.random() < 0.3)
    if r < 0.55:
        return Req("characteristics", "POST", "/v1/curves/characteristics", {"curve": spec})
    if r < 0.80:
        body: dict[str, Any] = {"curve": spec, "s": sorted(rng.random() for _ in range(rng.choice([1, 8, 64])))}
        if rng.random() < 0.3:
            body.update(method="table", table_decimals=5)
        return Req("inverse", "POST", "/v1/curves/inverse", body)
    params = {"samples": rng.choice([101, 361, 1001]), "format": "csv"}
    return Req("csv", "GET", f"/v1/curves/{rng.choice(NAMED)}/table", params=params)


async def send(client: httpx.AsyncClient, req: Req) -> httpx.Response:
    return await client.request(req.method, req.path, json=req.json, params=req.params, headers=req.headers())


def encoded(req: Req, url: str) -> bytes:
    host = urlsplit(url).netloc
    return encode_request(host, req.method, req.path, req.json, req.params, req.headers())


# ----------------------------------------------------------------------------- the run
@dataclass
class Stats:
    latencies: list[float] = field(default_factory=list)  # accepted (200) answers
    kind_latencies: dict[str, list[float]] = field(default_factory=dict)
    waits: list[float] = field(default_factory=list)  # accepted answers: until their first byte
    server_waits: list[float] = field(default_factory=list)  # the same, in the server (Server-Timing)
    big_bodies: dict[str, int] = field(default_factory=dict)  # status of the 4 MB posts: count
    shed: int = 0  # 503 answers (with Retry-After)
    shed_why: dict[str, int] = field(default_factory=dict)  # kind of request: why (the detail's first words)
    errors: dict[str, int] = field(default_factory=dict)
    by_kind: dict[str, int] = field(default_factory=dict)
    answers: dict[int, bytes] = field(default_factory=dict)  # pool index → body

    def error(self, what: str) -> None:
        self.errors[what] = self.errors.get(what, 0) + 1

    def add(self, other: Stats) -> None:
        """Take in another client process's figures."""
        self.latencies += other.latencies
        self.waits += other.waits
        self.server_waits += other.server_waits
        self.shed += other.shed
        for mine, theirs in ((self.shed_why, other.shed_why), (self.errors, other.errors),
                             (self.by_kind, other.by_kind), (self.big_bodies, other.big_bodies)):
            for key, n in theirs.items():
                mine[key] = mine.get(key, 0) + n
        for kind, waits in other.kind_latencies.items():
            self.kind_latencies.setdefault(kind, []).extend(waits)
        self.answers.update(other.answers)


def percentile(values: list[float], q: float) -> float:
    if not values:
        return math.nan
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, max(0, math.ceil(q * len(ordered)) - 1))]


def request_pool(seed: int, specs: int) -> list[Req]:
    rng = random.Random(seed)
    return [make_request(rng) for _ in range(specs)]  # distinct specs, re-requested (the caches matter)


#: 4 MB of numbers for a curve that does not exist: all parsing and validation, then a 404 at
#: once (nothing computed), so a client can send them as fast as the loopback carries them
BIG_BODY = Req("big-body", "POST", "/v1/curves/inverse",
               {"curve": {"type": "named", "name": "no-such-curve"},
                "s": [(i + 0.5) / 200_000 + 1e-12 for i in range(200_000)]})


async def run_load(url: str, pool: list[Req], seconds: float, connections: int, max_requests: int, seed: int,
                   sample_size: int, big_bodies: int = 0) -> Stats:
    """``connections`` keep-alive connections, each sending one request after the other
    (drawn from the pool) until the time is up; a 503 is answered at once by the next request.
    ``big_bodies`` more connections post BIG_BODY (4 MB) one after the other."""
    rng = random.Random(seed + 1)
    stats = Stats()
    sampled = set(rng.sample(range(len(pool)), min(sample_size, len(pool))))
    raw = [encoded(req, url) for req in pool]
    deadline = time.monotonic() + seconds
    issued = 0

    async def worker(wid: int) -> None:
        nonlocal issued
        local = random.Random(seed * 1000 + wid)
        connection = Connection(url)
        try:
            while time.monotonic() < deadline and issued < max_requests:
                issued += 1
                i = local.randrange(len(pool))
                t0 = time.perf_counter()
                try:
                    answer = await asyncio.wait_for(connection.request(raw[i]), 30.0)
                except (OSError, asyncio.IncompleteReadError, asyncio.LimitOverrunError, TimeoutError) as exc:
                    await connection.close()
                    stats.error(type(exc).__name__)
                    continue
                kind = pool[i].kind
                stats.by_kind[kind] = stats.by_kind.get(kind, 0) + 1
                if answer.status == 503 and "retry-after" in answer.headers:
                    stats.shed += 1
                    why = f"{kind}: {shed_reason(answer.body)}"
                    stats.shed_why[why] = stats.shed_why.get(why, 0) + 1
                    continue
                took = time.perf_counter() - t0
                stats.latencies.append(took)
                stats.waits.append(answer.headers_at - t0)
                timing = answer.headers.get("server-timing", "")
                if timing.startswith("app;dur="):
                    stats.server_waits.append(float(timing[len("app;dur="):]) / 1000)
                stats.kind_latencies.setdefault(kind, []).append(took)
                if answer.status != 200:
                    stats.error(f"HTTP {answer.status} {kind}")
                elif i in sampled and i not in stats.answers:
                    stats.answers[i] = answer.body
        finally:
            await connection.close()

    async def big_poster() -> None:
        connection, raw_big = Connection(url), encoded(BIG_BODY, url)
        try:
            while time.monotonic() < deadline:
                answer = await asyncio.wait_for(connection.request(raw_big), 60.0)
                why = f"{answer.status}"
                stats.big_bodies[why] = stats.big_bodies.get(why, 0) + 1
        finally:
            await connection.close()

    await asyncio.gather(*(worker(w) for w in range(connections)), *(big_poster() for _ in range(big_bodies)))
    return stats


def run_load_in_processes(url: str, pool: list[Req], seconds: float, connections: int, max_requests: int,
                          seed: int, sample_size: int, processes: int, big_bodies: int = 0) -> Stats:
    """The connections shared out over ``processes`` client processes (one event loop each),
    their statistics merged."""
    if processes == 1:
        return asyncio.run(run_load(url, pool, seconds, connections, max_requests, seed, sample_size, big_bodies))
    shares = [connections // processes + (k < connections % processes) for k in range(processes)]
    with ProcessPoolExecutor(processes, mp_context=multiprocessing.get_context("fork")) as executor:
        parts = list(executor.map(_run_share, [(url, pool, seconds, share, max_requests // processes, seed + 7919 * k,
                                                sample_size, big_bodies if k == 0 else 0)
                                               for k, share in enumerate(shares)]))
    merged = Stats()
    for part in parts:
        merged.add(part)
    return merged


def _run_share(args: tuple[Any, ...]) -> Stats:
    return asyncio.run(run_load(*args))


async def cold_answers(url: str, pool: list[Req], indices: list[int]) -> dict[int, bytes]:
    out = {}
    async with httpx.AsyncClient(base_url=url, timeout=30.0) as client:
        for i in indices:
            r = await send(client, pool[i])
            out[i] = r.content if r.status_code == 200 else f"HTTP {r.status_code}".encode()
    return out


def direct_answer(req: Req) -> dict[str, list[float]] | None:
    """camcore's own numbers for a JSON table or characteristics request (for --url runs)."""
    import numpy as np

    from camcore.results import as_dict
    from service.context import Context
    from service.curves.operations import Sampling, table_columns
    from service.curves.specs import CharacteristicsRequest, TableRequest
    from service.settings import Settings

    ctx = Context.create(Settings())
    if req.kind == "table" and not req.csv:
        body = TableRequest.model_validate(req.json)
        cols = table_columns(ctx, Sampling(body.curve.core(), body.samples, body.t))
        return {k: np.asarray(v).tolist() for k, v in cols.items()}
    if req.kind == "characteristics":
        body2 = CharacteristicsRequest.model_validate(req.json)
        return dict(as_dict(ctx.curves.curve(body2.curve.core()).characteristics))
    return None


def shed_reason(body: bytes) -> str:
    """The kind of refusal, from a 503's detail (its numbers left out)."""
    try:
        detail = str(json.loads(body)["detail"])
    except (ValueError, KeyError, TypeError):
        return "?"
    for words in ("requests in progress", "s of estimated work", "of waiting at this worker's pace",
                  "for one of", "deadline", "client closed"):
        if words in detail:
            return words
    return detail[:40]


def run_figures(stats: Stats, elapsed: float) -> dict[str, Any]:
    accepted = len(stats.latencies)
    answered = accepted + stats.shed
    return {
        "requests": answered + sum(v for k, v in stats.errors.items() if not k.startswith("HTTP")),
        "elapsed_s": round(elapsed, 2),
        "throughput_rps": round(answered / elapsed, 1),
        "accepted_rps": round(accepted / elapsed, 1),
        "shed_503_share": round(stats.shed / answered, 4) if answered else 0.0,
        "by_kind": stats.by_kind,
        "shed_why": dict(sorted(stats.shed_why.items())),
        "big_bodies": stats.big_bodies,
        "errors": stats.errors,
        "p50_ms": round(percentile(stats.latencies, 0.50) * 1000, 2),
        "p99_ms": round(percentile(stats.latencies, 0.99) * 1000, 2),
        "max_ms": round(max(stats.latencies, default=math.nan) * 1000, 2),
        "accepted_over_2s": sum(1 for x in stats.latencies if x > 2.0),
        "wait_p99_ms": round(percentile(stats.waits, 0.99) * 1000, 2),
        "wait_max_ms": round(max(stats.waits, default=math.nan) * 1000, 2),
        "waited_over_2s": sum(1 for x in stats.waits if x > 2.0),
        "server_wait_p99_ms": round(percentile(stats.server_waits, 0.99) * 1000, 2),
        "server_wait_max_ms": round(max(stats.server_waits, default=math.nan) * 1000, 2),
        "server_waited_over_2s": sum(1 for x in stats.server_waits if x > 2.0),
        "accepted_by_kind": {kind: {"n": len(w), "p50_ms": round(percentile(w, 0.5) * 1000, 1),
                                    "p99_ms": round(percentile(w, 0.99) * 1000, 1), "max_ms": round(max(w) * 1000, 1)}
                             for kind, w in sorted(stats.kind_latencies.items())},
    }


async def largest_tables(url: str, server: Server, concurrent: int) -> dict[str, Any]:
    """``concurrent`` requests for the largest tables at once (200 000-row CSV curve tables
    and indexer motion tables), RSS polled every 20 ms; then RSS after 5 s of rest."""
    bodies = [("/v1/curves/table", {"curve": {"type": "named", "name": "MS"}, "samples": 200_000}),
              ("/v1/indexers/motion", {"indexer": {"stops": 8, "indexing_angle_deg": 120, "speed_rpm": 60,
                                                   "curve": {"type": "named", "name": "MS"}}, "samples": 200_000})]
    peak = max(server.worker_rss_kib(), default=0)
    start_rss = server.worker_rss_kib()
    statuses: dict[int, int] = {}
    done = asyncio.Event()

    async def poll() -> None:
        nonlocal peak
        while not done.is_set():
            peak = max([peak, *server.worker_rss_kib()])
            await asyncio.sleep(0.02)

    limits = httpx.Limits(max_connections=concurrent)
    async with httpx.AsyncClient(base_url=url, limits=limits, timeout=60.0) as client:
        async def one(i: int) -> None:
            path, body = bodies[i % 2]
            async with client.stream("POST", path, json=body, headers={"Accept": "text/csv"}) as r:
                async for _ in r.aiter_bytes():
                    await asyncio.sleep(0)  # a client reading as it comes
                statuses[r.status_code] = statuses.get(r.status_code, 0) + 1

        poller = asyncio.ensure_future(poll())
        await asyncio.gather(*(one(i) for i in range(concurrent)))
        done.set()
        await poller
    await asyncio.sleep(5.0)
    return {"concurrent": concurrent, "statuses": statuses, "rss_start_kib": start_rss, "rss_peak_kib": peak,
            "rss_after_5s_kib": server.worker_rss_kib()}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--url", help="target an already running server (loopback only)")
    ap.add_argument("--seconds", type=float, default=60.0, help="duration of each run (default 60)")
    ap.add_argument("--connections", type=int, default=64)
    ap.add_argument("--workers", type=int, default=1, help="uvicorn workers of the server this script starts")
    ap.add_argument("--client-processes", type=int, default=1, help="load-client processes sharing the connections")
    ap.add_argument("--big-bodies", type=int, default=0, help="more connections posting 4 MB bodies")
    ap.add_argument("--only", choices=["light-cached"], help="the mix: only cached GET tables (small answers)")
    ap.add_argument("--runs", type=int, default=1, help="consecutive runs against the same server")
    ap.add_argument("--largest", type=int, default=0, help="instead: this many concurrent largest tables")
    ap.add_argument("--max-requests", type=int, default=1_000_000, help="hard cap on requests per run")
    ap.add_argument("--specs", type=int, default=2000, help="distinct requests in the pool")
    ap.add_argument("--sample", type=int, default=200, help="answers compared with a cold run")
    ap.add_argument("--seed", type=int, default=20240601)
    ap.add_argument("--json", help="write the figures to this file as JSON")
    args = ap.parse_args(argv)
    if not 0 < args.seconds <= 3600 or not 1 <= args.runs <= 20 or not 1 <= args.connections <= 4096:
        ap.error("--seconds must be in (0, 3600], --runs in 1..20, --connections in 1..4096")
    if args.largest and args.url:
        ap.error("--largest measures the RSS of a server this script starts: no --url")

    server = None
    if args.url:
        url = require_loopback(args.url)
    else:
        server = Server(workers=args.workers)
        server.wait_ready()
        url = server.url
    report: dict[str, Any] = {"url": url, "connections": args.connections, "workers": args.workers,
                              "seconds": args.seconds, "runs": []}
    pool = request_pool(args.seed, args.specs)
    if args.only == "light-cached":
        pool = [req for req in pool if req.kind == "csv"]  # GET named tables: cached after their first answer
    stats = Stats()
    try:
        if args.largest:
            assert server is not None
            report["largest"] = asyncio.run(largest_tables(url, server, args.largest))
            print(json.dumps(report, indent=1))
            return 0
        if server:
            report["rss_start_kib"] = server.worker_rss_kib()
        for run in range(args.runs):
            t0 = time.monotonic()
            stats = run_load_in_processes(url, pool, args.seconds, args.connections, args.max_requests,
                                          args.seed + run, args.sample, args.client_processes, args.big_bodies)
            figures = run_figures(stats, time.monotonic() - t0)
            if server:
                figures["rss_end_kib"] = server.worker_rss_kib()
            report["runs"].append(figures)
            print(json.dumps(figures), file=sys.stderr)
        report["health"] = httpx.get(f"{url}/health", timeout=10).json()
    finally:
        if server:
            server.stop()

    # identical to a cold run (the last run's sampled answers)
    indices = sorted(stats.answers)
    mismatches = 0
    if args.url:
        checked = 0
        for i in indices:
            direct = direct_answer(pool[i])
            if direct is None:
                continue
            checked += 1
            if json.loads(stats.answers[i]) != json.loads(json.dumps(direct)):
                mismatches += 1
        report["cold_check"] = {"against": "camcore directly", "compared": checked, "mismatches": mismatches}
    else:
        cold = Server()
        try:
            cold.wait_ready()
            fresh = asyncio.run(cold_answers(cold.url, pool, indices))
        finally:
            cold.stop()
        mismatches = sum(1 for i in indices if fresh[i] != stats.answers[i])
        report["cold_check"] = {"against": "a freshly started server, byte for byte", "compared": len(indices),
                                "mismatches": mismatches}

    print(json.dumps(report, indent=1))
    if args.json:
        Path(args.json).write_text(json.dumps(report, indent=1) + "\n", encoding="utf-8")
    errors = any(run["errors"] for run in report["runs"])
    return 1 if (errors or mismatches) else 0


if __name__ == "__main__":
    raise SystemExit(main())
