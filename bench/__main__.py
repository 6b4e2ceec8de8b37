"""``python -m bench [--smoke] [--only NAME ...]``: the performance figures as one JSON object.

Every figure is a ratio of two timings taken in the same run, interleaved pair by pair
(baseline, subject, baseline, subject, …) so that a busy machine slows both alike;
each figure reports the median of the per-pair ratios with their min and max.
``--smoke`` runs everything once at tiny sizes (CI: it must run, not meet targets).
"""

from __future__ import annotations

import argparse
import asyncio
import itertools
import json
import os
import platform
import re
import shutil
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import orjson

import camcore
from camcore.indexer import Indexer, Load, size
from camcore.indexer.sweep import size_sweep

from . import scalar_port

ROOT = Path(__file__).resolve().parent.parent
MS_BREAK_POINTS = [0.0, 0.125, 0.125, 0.5, 0.5, 0.875, 0.875, 1.0]
TABLE_BODY = {"curve": {"type": "named", "name": "MS"}, "samples": 101}

FIGURES = [
    "table_vs_sin_floor", "scalar_port_vs_table", "inverse_vs_table", "json_vs_orjson_floor",
    "http_table_vs_ceiling", "http_p99_ms", "workers_scaling", "sizing_sweep", "sweep_vs_single_sizings",
]


# --------------------------------------------------------------------------- helpers
def _timed(fn: Callable[[], Any]) -> float:
    start = time.perf_counter()
    fn()
    return time.perf_counter() - start


def paired_ratios(baseline: Callable[[], Any], subject: Callable[[], Any], repeats: int,
                  invert: bool = False) -> tuple[list[float], float, float]:
    """Per-pair ratios subject/baseline (baseline/subject when ``invert``), after one warm-up.

    Returns the ratios and the median times of baseline and subject [s].
    """
    baseline()
    subject()
    ratios, tb, ts = [], [], []
    for _ in range(repeats):
        b = _timed(baseline)
        s = _timed(subject)
        tb.append(b)
        ts.append(s)
        ratios.append(b / s if invert else s / b)
    return ratios, statistics.median(tb), statistics.median(ts)


def figure(ratios: list[float], target: str, **extra: Any) -> dict[str, Any]:
    """median/min/max of the ratios and whether the median meets ``target`` ("<= 3", ">= 80")."""
    med = statistics.median(ratios)
    op, bound = target.split()
    met = med <= float(bound) if op == "<=" else med >= float(bound)
    return {"median": round(med, 4), "min": round(min(ratios), 4), "max": round(max(ratios), 4),
            "runs": len(ratios), "target": target, "met": bool(met), **extra}


def machine_info() -> dict[str, Any]:
    model = platform.processor() or "unknown"
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, timeout=10).stdout
        m = re.search(r"Model name:\s*(.+)", out)
        if m:
            model = m.group(1).strip()
    except (OSError, subprocess.SubprocessError):
        pass
    return {
        "cpu_model": model,
        "cpus": os.cpu_count(),
        "loadavg_at_start": [round(x, 2) for x in os.getloadavg()],
        "python": platform.python_version(),
        "numpy": np.__version__,
        "orjson": orjson.__version__,
        "platform": platform.platform(),
        "date": time.strftime("%Y-%m-%d"),
    }


# --------------------------------------------------------------------------- core figures
def table_vs_sin_floor(n: int, repeats: int) -> dict[str, Any]:
    ms = camcore.named_curve("MS")
    t = np.linspace(0.0, 1.0, n)
    ratios, tb, ts = paired_ratios(lambda: np.sin(t), lambda: ms.derivatives(t, 3), repeats)
    return figure(ratios, "<= 3", points=n, sin_ms=round(tb * 1e3, 3), table_ms=round(ts * 1e3, 3),
                  what="S, V, A, J of MS (Curve.derivatives(t, 3)) ÷ one np.sin, same points")


def scalar_port_vs_table(n: int, repeats: int) -> dict[str, Any]:
    ms = camcore.named_curve("MS")
    t = np.linspace(0.0, 1.0, n)
    t_list = t.tolist()
    port = scalar_port.table(t_list, MS_BREAK_POINTS)
    ref = ms.derivatives(t, 3)
    # Makino's CURVE takes section VIII (J = 0) at T = T7; camcore the last piece's left limit
    inside = t < 1.0
    errors = {}
    for name, col, r in zip("svaj", port, ref):
        diff = np.abs(np.asarray(col) - r)[inside if name == "j" else slice(None)]
        errors[name] = float(diff.max() / max(np.abs(r).max(), 1.0))
    agrees = max(errors.values()) <= 1e-12
    if not agrees:
        raise AssertionError(f"the scalar port of CURVE disagrees with camcore: relative errors {errors}")
    # camcore takes about a millisecond here, so one timing of it is mostly the transient
    # after the port's long run: each pair times camcore as the mean of back-to-back calls
    # filling ~20 ms (its first call, right after the port, is reported beside it)
    def camcore_calls() -> list[float]:
        return [_timed(lambda: ms.derivatives(t, 3)) for _ in range(loops)]

    loops = max(1, min(50, int(0.02 / max(_timed(lambda: ms.derivatives(t, 3)), 1e-6))))
    camcore_calls()
    ratios, camcore_mean, first_call, port = [], [], [], []
    for _ in range(repeats):
        calls = camcore_calls()
        port.append(_timed(lambda: scalar_port.table(t_list, MS_BREAK_POINTS)))
        camcore_mean.append(statistics.mean(calls))
        first_call.append(calls[0])
        ratios.append(port[-1] / camcore_mean[-1])
    def median_ms(xs: list[float]) -> float:
        return round(statistics.median(xs) * 1e3, 3)

    return figure(ratios, ">= 80", points=n, port_ms=median_ms(port), camcore_ms=median_ms(camcore_mean),
                  camcore_loops=loops, camcore_first_call_after_port_ms=median_ms(first_call),
                  ratio_to_first_call=round(statistics.median([p / f for p, f in zip(port, first_call)]), 2),
                  agrees_with_camcore=agrees, max_relative_error=errors,
                  what="pure-Python port of Makino's CURVE, one T per call ÷ camcore (mean of back-to-back "
                       "calls), same points")


def inverse_vs_table(n: int, repeats: int) -> dict[str, Any]:
    ms = camcore.named_curve("MS")
    t = np.linspace(0.0, 1.0, n)
    s = ms.derivatives(t, 0)[0]
    t_inv = ms.inverse(s)
    err_s = float(np.max(np.abs(ms.derivatives(t_inv, 0)[0] - s)))
    ratios, tb, ts = paired_ratios(lambda: ms.derivatives(t, 3), lambda: ms.inverse(s), repeats)
    # the figure times a curve whose start table exists; a new curve builds it on its first
    # inverse (the service keeps built curves in its cache): what that first call costs
    cold = statistics.median(
        _timed(lambda: camcore.universal_curve(MS_BREAK_POINTS).inverse(s)) for _ in range(min(repeats, 5))
    )
    return figure(ratios, "<= 5", points=n, forward_ms=round(tb * 1e3, 3), inverse_ms=round(ts * 1e3, 3),
                  first_inverse_new_curve_ms=round(cold * 1e3, 3), max_abs_s_residual=err_s,
                  what="exact inverse T(S) of n S values ÷ forward table (S, V, A, J) of n points")


def json_vs_orjson_floor(n: int, repeats: int) -> dict[str, Any]:
    import httpx

    from service.app import create_app
    from service.settings import Settings

    app = create_app(Settings())
    body = {"curve": {"type": "named", "name": "MS"}, "samples": n}
    columns = camcore.named_curve("MS").table(n).columns()
    loop = asyncio.new_event_loop()
    client = httpx.AsyncClient(transport=httpx.ASGITransport(app=app), base_url="http://bench")

    def service_answer() -> bytes:
        async def post() -> bytes:
            r = await client.post("/v1/curves/table", json=body)
            r.raise_for_status()
            return r.content

        return loop.run_until_complete(post())

    def orjson_floor() -> bytes:
        return orjson.dumps(columns, option=orjson.OPT_SERIALIZE_NUMPY)

    try:
        answer, floor = service_answer(), orjson_floor()
        ratios, tb, ts = paired_ratios(orjson_floor, service_answer, repeats)
    finally:
        loop.run_until_complete(client.aclose())
        loop.close()
    return figure(ratios, "<= 2", rows=n, service_ms=round(ts * 1e3, 3), orjson_ms=round(tb * 1e3, 3),
                  service_body_bytes=len(answer), orjson_bytes=len(floor),
                  what="in-process POST /v1/curves/table (httpx.ASGITransport, body bytes) ÷ orjson.dumps of the columns")


def sizing_sweep(n: int, chunks: int) -> dict[str, Any]:
    ms = camcore.named_curve("MS")
    indexer = Indexer(indexing_angle_deg=120.0, stops=8, speed_rpm=60.0, curve=ms)
    per_chunk = max(n // chunks, 1)
    loads = [Load(inertia_kgm2=0.5 + 0.001 * i, friction_torque_nm=0.01 * (i % 50)) for i in range(per_chunk)]

    def sizings() -> None:
        for load in loads:
            size(indexer, load)

    def tables() -> None:
        for _ in range(per_chunk):
            ms.table(101)

    ratios, tb, ts = paired_ratios(tables, sizings, chunks)
    return {**figure(ratios, "<= inf", sizings=per_chunk * chunks, per_sizing_ms=round(ts / per_chunk * 1e3, 4),
                     per_table_ms=round(tb / per_chunk * 1e3, 4),
                     what="indexer sizings (camcore.indexer.size, MS, varying load) ÷ as many 101-point tables"),
            "target": "report", "met": None}


def sweep_vs_single_sizings(repeats: int) -> dict[str, Any]:
    """36 designs (2 stops × 2 angles × 3 curves × 3 speeds) in one size_sweep ÷ 36 size() calls."""
    names = ["MS", "MCV50", "TR"]
    curves = [camcore.named_curve(name) for name in names]
    load = Load(inertia_kgm2=2.25, friction_torque_nm=9.81, work_torque_nm=4.0)
    designs = list(itertools.product([4, 6], [120.0, 270.0], curves, [30.0, 60.0, 90.0]))
    indexers = [Indexer(stops=n, indexing_angle_deg=theta, speed_rpm=speed, curve=curve)
                for n, theta, curve, speed in designs]

    def singles() -> None:
        for indexer in indexers:
            size(indexer, load)

    def sweep() -> None:
        size_sweep(load, [4, 6], [120.0, 270.0], curves, names, speed_rpm=[30.0, 60.0, 90.0])

    ratios, tb, ts = paired_ratios(singles, sweep, repeats, invert=True)
    return figure(ratios, ">= 5", singles_ms=round(tb * 1e3, 3), sweep_ms=round(ts * 1e3, 3),
                  what="36 single sizings (camcore.indexer.size: each also builds its torque table and RMS, which "
                       "the sweep leaves out) ÷ one size_sweep of the same 36 designs (identical figures)")


# --------------------------------------------------------------------------- HTTP figures
WRK_MISSING = "wrk not installed: apt-get install wrk"
PINNING = ("2 cores: the server runs under `taskset -c 0` with 1 worker and `taskset -c 0,1` with 2 "
           "workers; wrk runs with 1 thread under `taskset -c 1` (it shares core 1 with the second worker)")


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])


class Server:
    """``python -m service`` on 127.0.0.1 and a free port, pinned with taskset; stopped on exit."""

    def __init__(self, workers: int, cpus: str, **settings: str):
        self.port = _free_port()
        # the figures time computation and HTTP, not admission: no computation is turned away
        # for its wait (with the default 0.5 s, 32 connections of uncached tables shed some)
        env = {**os.environ, "CAMCORE_HOST": "127.0.0.1", "CAMCORE_PORT": str(self.port),
               "CAMCORE_WORKERS": str(workers), "CAMCORE_LOG_LEVEL": "warning", "CAMCORE_MAX_QUEUE_WAIT_S": "60",
               **settings}
        cmd = [sys.executable, "-m", "service"]
        if shutil.which("taskset"):
            cmd = ["taskset", "-c", cpus, *cmd]
        self.proc = subprocess.Popen(cmd, cwd=ROOT, env=env, start_new_session=True,
                                     stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        self.url = f"http://127.0.0.1:{self.port}"

    def __enter__(self) -> Server:
        import httpx

        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            if self.proc.poll() is not None:
                raise RuntimeError(f"server exited: {self.proc.stderr.read().decode()[-2000:]}")  # type: ignore[union-attr]
            try:
                if httpx.get(self.url + "/health", timeout=1).status_code == 200:
                    return self
            except httpx.HTTPError:
                pass
            time.sleep(0.2)
        self.__exit__()
        raise RuntimeError("server did not answer /health within 60 s")

    def __exit__(self, *_exc: Any) -> None:
        if self.proc.poll() is None:
            os.killpg(self.proc.pid, signal.SIGTERM)  # the server's own session: it and its workers
            try:
                self.proc.wait(timeout=15)
            except subprocess.TimeoutExpired:
                os.killpg(self.proc.pid, signal.SIGKILL)
                self.proc.wait(timeout=5)


_UNITS = {"us": 1e-3, "ms": 1.0, "s": 1e3}


def wrk(url: str, seconds: int, lua: str | None = None) -> dict[str, float]:
    """One wrk run (1 thread, 32 connections, pinned to core 1): req/s and p99 latency [ms]."""
    cmd = ["wrk", "-t1", "-c32", f"-d{seconds}s", "--latency"]
    if lua:
        cmd += ["-s", lua]
    if shutil.which("taskset"):
        cmd = ["taskset", "-c", "1", *cmd]
    out = subprocess.run([*cmd, url], capture_output=True, text=True, timeout=seconds + 60).stdout
    rps = re.search(r"Requests/sec:\s*([\d.]+)", out)
    p99 = re.search(r"^\s*99%\s+([\d.]+)(us|ms|s)\s*$", out, re.MULTILINE)
    errors = re.search(r"Non-2xx or 3xx responses:\s*(\d+)", out)
    if not rps or not p99:
        raise RuntimeError(f"could not read wrk output:\n{out}")
    if errors:
        raise RuntimeError(f"wrk saw error responses:\n{out}")
    return {"rps": float(rps.group(1)), "p99_ms": float(p99.group(1)) * _UNITS[p99.group(2)]}


def http_figures(seconds: int, runs: int) -> dict[str, Any]:
    if not shutil.which("wrk"):
        return {name: {"skipped": WRK_MISSING} for name in ("http_table_vs_ceiling", "http_p99_ms", "workers_scaling")}
    with tempfile.TemporaryDirectory() as tmp:
        lua = Path(tmp) / "table.lua"
        lua.write_text(
            'wrk.method = "POST"\n'
            'wrk.headers["Content-Type"] = "application/json"\n'
            f"wrk.body = '{json.dumps(TABLE_BODY)}'\n"
        )
        health, table1, table2, uncached = [], [], [], []
        # the servers are up at once (an idle one costs nothing) so that the runs interleave:
        # /health and the table on one worker, the table on two, and the table on one worker
        # with the table cache off (every request computes and encodes it), run after run
        with Server(workers=1, cpus="0") as one, Server(workers=2, cpus="0,1") as two, \
                Server(workers=1, cpus="0", CAMCORE_TABLE_CACHE_SIZE="0") as no_cache:
            # warm-up: a fresh server is slower for its first seconds under load
            warm = min(3, seconds)
            wrk(one.url + "/health", warm)
            for server in (one, two, no_cache):
                wrk(server.url + "/v1/curves/table", warm, str(lua))
            for _ in range(runs):
                health.append(wrk(one.url + "/health", seconds))
                table1.append(wrk(one.url + "/v1/curves/table", seconds, str(lua)))
                table2.append(wrk(two.url + "/v1/curves/table", seconds, str(lua)))
                uncached.append(wrk(no_cache.url + "/v1/curves/table", seconds, str(lua)))
    p99 = [r["p99_ms"] for r in table1]
    return {
        "http_table_vs_ceiling": figure(
            [t["rps"] / h["rps"] for t, h in zip(table1, health)], ">= 0.5",
            table_rps=[t["rps"] for t in table1], health_rps=[h["rps"] for h in health],
            # every wrk request sends the same body, so the figure's table comes from the cache;
            # what a request that misses it costs, for comparison
            uncached_table_rps=[u["rps"] for u in uncached],
            uncached_ratio=round(statistics.median(u["rps"] / h["rps"] for u, h in zip(uncached, health)), 4),
            uncached_p99_ms=[u["p99_ms"] for u in uncached],
            what="req/s of POST /v1/curves/table (101 rows, MS) ÷ req/s of GET /health; 1 worker, 32 connections, "
                 f"wrk -d{seconds}s", pinning=PINNING),
        "http_p99_ms": figure(p99, "<= 20", unit="ms", two_workers_p99_ms=[t["p99_ms"] for t in table2],
                              what="p99 latency of POST /v1/curves/table (101 rows) at 32 connections, 1 worker "
                                   "(two_workers_p99_ms: the same with CAMCORE_WORKERS=2)"),
        "workers_scaling": figure(
            [b["rps"] / a["rps"] for a, b in zip(table1, table2)], ">= 1.4",
            one_worker_rps=[t["rps"] for t in table1], two_workers_rps=[t["rps"] for t in table2],
            what="req/s of the 101-row table with CAMCORE_WORKERS=2 ÷ with 1", pinning=PINNING),
    }


# --------------------------------------------------------------------------- main
def run(smoke: bool, only: set[str] | None) -> dict[str, Any]:
    sizes = {
        "table": 1_000 if smoke else 1_000_000, "scalar": 1_000 if smoke else 100_000,
        "inverse": 1_000 if smoke else 1_000_000, "json": 1_000 if smoke else 100_000,
        "sizing": 20 if smoke else 10_000, "repeats": 1 if smoke else 15,
        "http_seconds": 1 if smoke else 5, "http_runs": 1 if smoke else 5,
    }
    r = sizes["repeats"]
    jobs: dict[str, Callable[[], Any]] = {
        "table_vs_sin_floor": lambda: table_vs_sin_floor(sizes["table"], r),
        "scalar_port_vs_table": lambda: scalar_port_vs_table(sizes["scalar"], 1 if smoke else 5),
        "inverse_vs_table": lambda: inverse_vs_table(sizes["inverse"], r),
        "json_vs_orjson_floor": lambda: json_vs_orjson_floor(sizes["json"], r),
        "sizing_sweep": lambda: sizing_sweep(sizes["sizing"], 1 if smoke else 5),
        "sweep_vs_single_sizings": lambda: sweep_vs_single_sizings(1 if smoke else 15),
    }
    out: dict[str, Any] = {"mode": "smoke" if smoke else "full", "machine": machine_info()}
    figures: dict[str, Any] = {}
    for name, job in jobs.items():
        if only is None or name in only:
            figures[name] = job()
    http_names = {"http_table_vs_ceiling", "http_p99_ms", "workers_scaling"}
    if only is None or only & http_names:
        figures.update(http_figures(sizes["http_seconds"], sizes["http_runs"]))
    out["figures"] = {name: figures[name] for name in FIGURES if name in figures}
    out["machine"]["loadavg_at_end"] = [round(x, 2) for x in os.getloadavg()]
    return out


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog="python -m bench", description=__doc__.splitlines()[0])
    parser.add_argument("--smoke", action="store_true", help="run everything once at tiny sizes (CI)")
    parser.add_argument("--only", nargs="+", choices=FIGURES, help="run only these figures")
    args = parser.parse_args(argv)
    result = run(args.smoke, set(args.only) if args.only else None)
    print(json.dumps(result, indent=2, ensure_ascii=False))


if __name__ == "__main__":
    main()
