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
import shutil
import statistics
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

import httpx
import numpy as np
import orjson

import camcore
from camcore.curves.batch import characteristic_values
from camcore.indexer import Indexer, Load, size
from camcore.indexer.sweep import size_sweep

from . import peers, readme_routes, request_rates, scalar_port
from .servers import PINNING, WRK_MISSING, Server, wrk
from .timing import figure, machine_info, paired_ratios, timed

ROOT = Path(__file__).resolve().parent.parent
MS_BREAK_POINTS = [0.0, 0.125, 0.125, 0.5, 0.5, 0.875, 0.875, 1.0]
TABLE_BODY = {"curve": {"type": "named", "name": "MS"}, "samples": 101}

FIGURES = [
    "table_vs_sin_floor", "scalar_port_vs_table", "inverse_vs_table", "ms_table_vs_numpy", "cycloid_table_vs_mechanism",
    "json_vs_orjson_floor", "http_table_vs_ceiling", "http_cached_vs_bare", "http_p99_ms", "workers_scaling",
    "profile_rps",
    "characteristics_new_curve_rps", "sizing_rps", "base_circle_ms", "cold_start_vs_bare_fastapi", "sizing_sweep",
    "sweep_vs_single_sizings", "characteristics_sweep_vs_single", "readme_routes_ms",
]
HTTP_FIGURES = {"http_table_vs_ceiling", "http_cached_vs_bare", "http_p99_ms", "workers_scaling"}
REQUEST_FIGURES = {"profile_rps", "characteristics_new_curve_rps", "sizing_rps", "base_circle_ms"}


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
        return [timed(lambda: ms.derivatives(t, 3)) for _ in range(loops)]

    loops = max(1, min(50, int(0.02 / max(timed(lambda: ms.derivatives(t, 3)), 1e-6))))
    camcore_calls()
    ratios, camcore_mean, first_call, port = [], [], [], []
    for _ in range(repeats):
        calls = camcore_calls()
        port.append(timed(lambda: scalar_port.table(t_list, MS_BREAK_POINTS)))
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
        timed(lambda: camcore.universal_curve(MS_BREAK_POINTS).inverse(s)) for _ in range(min(repeats, 5))
    )
    # sorted targets walk the start table in order; random ones (a lookup service's traffic) do
    # not, and take longer: the same n S values shuffled, with V and A from the solve
    shuffled = np.random.default_rng(0).permutation(s)
    random_ratios, _, tr = paired_ratios(lambda: ms.derivatives(t, 3), lambda: ms.inverse_with_rates(shuffled),
                                         repeats)
    return figure(ratios, "<= 5", points=n, forward_ms=round(tb * 1e3, 3), inverse_ms=round(ts * 1e3, 3),
                  first_inverse_new_curve_ms=round(cold * 1e3, 3), max_abs_s_residual=err_s,
                  random_targets_ratio=round(statistics.median(random_ratios), 4),
                  random_targets_with_rates_ms=round(tr * 1e3, 3),
                  what="exact inverse T(S) of n sorted S values ÷ forward table (S, V, A, J) of n points; "
                       "random_targets_ratio: the same S values shuffled, T with V and A (inverse_with_rates)")


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


def characteristics_sweep_vs_single(repeats: int) -> dict[str, Any]:
    """Appendix 3-2's grid of curve 4 (T3 = I/32, T1 = J/64, T1 ≤ T3: 72 curves): each curve built and
    its characteristics found one by one ÷ the same curves built and their values found together."""
    grid = [(j / 64, i / 32) for i in range(1, 9) for j in range(1, 17) if j / 64 <= i / 32]

    def curves() -> list[camcore.Curve]:
        return [camcore.build_curve("makino", {"number": 4, "t1": t1, "t3": t3}) for t1, t3 in grid]

    def singles() -> None:
        for curve in curves():
            _ = curve.characteristics

    def together() -> None:
        characteristic_values(curves())

    ratios, tb, ts = paired_ratios(singles, together, repeats, invert=True)
    return figure(ratios, ">= 2", curves=len(grid), singles_ms=round(tb * 1e3, 3), together_ms=round(ts * 1e3, 3),
                  what="72 curves of appendix 3-2 built and their characteristics found one by one ÷ built and "
                       "found together (camcore.curves.batch.characteristic_values; identical values)")


# --------------------------------------------------------------------------- HTTP figures
def http_figures(seconds: int, runs: int) -> dict[str, Any]:
    if not shutil.which("wrk"):
        return {name: {"skipped": WRK_MISSING} for name in HTTP_FIGURES}
    with tempfile.TemporaryDirectory() as tmp:
        lua = Path(tmp) / "table.lua"
        lua.write_text(
            'wrk.method = "POST"\n'
            'wrk.headers["Content-Type"] = "application/json"\n'
            f"wrk.body = '{json.dumps(TABLE_BODY)}'\n"
        )
        answer = Path(tmp) / "table.json"
        health, table1, table2, uncached, bare = [], [], [], [], []
        # the servers are up at once (an idle one costs nothing) so that the runs interleave:
        # /health and the table on one worker, the table on two, the table on one worker with the
        # table cache off (every request computes and encodes it), and a bare FastAPI app answering
        # the table's bytes (the floor for a cached answer), run after run
        with Server(workers=1, cpus="0") as one, Server(workers=2, cpus="0,1") as two, \
                Server(workers=1, cpus="0", CAMCORE_TABLE_CACHE_SIZE="0") as no_cache:
            answer.write_bytes(httpx.post(one.url + "/v1/curves/table", json=TABLE_BODY, timeout=60).content)
            with Server(workers=1, cpus="0", bare=True, BENCH_BARE_ANSWER=str(answer)) as floor:
                # warm-up: a fresh server is slower for its first seconds under load
                warm = min(3, seconds)
                wrk(one.url + "/health", warm)
                for server in (one, two, no_cache, floor):
                    wrk(server.url + "/v1/curves/table", warm, str(lua))
                for _ in range(runs):
                    health.append(wrk(one.url + "/health", seconds))
                    table1.append(wrk(one.url + "/v1/curves/table", seconds, str(lua)))
                    bare.append(wrk(floor.url + "/v1/curves/table", seconds, str(lua)))
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
        "http_cached_vs_bare": figure(
            [t["rps"] / b["rps"] for t, b in zip(table1, bare)], ">= 0.6",
            table_rps=[t["rps"] for t in table1], bare_rps=[b["rps"] for b in bare],
            what="req/s of POST /v1/curves/table (101 rows, MS; its answer from the cache) ÷ req/s of a bare FastAPI "
                 "app's POST route answering the same bytes (bench/bare_app.py); 1 worker each, 32 connections, "
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
        "characteristics_sweep_vs_single": lambda: characteristics_sweep_vs_single(1 if smoke else 15),
        "ms_table_vs_numpy": lambda: peers.ms_table_vs_numpy(sizes["table"], r),
        "cycloid_table_vs_mechanism": lambda: peers.cycloid_table_vs_mechanism(sizes["table"], r),
        "cold_start_vs_bare_fastapi": lambda: request_rates.cold_start(1 if smoke else 5),
        "readme_routes_ms": lambda: readme_routes.readme_routes_ms(1 if smoke else 30),
    }
    out: dict[str, Any] = {"mode": "smoke" if smoke else "full", "machine": machine_info()}
    figures: dict[str, Any] = {}
    for name, job in jobs.items():
        if only is None or name in only:
            figures[name] = job()
    if only is None or only & HTTP_FIGURES:
        figures.update(http_figures(sizes["http_seconds"], sizes["http_runs"]))
    if only is None or only & REQUEST_FIGURES:
        figures.update(request_rates.request_figures(sizes["http_seconds"], sizes["http_runs"], 3 if smoke else 20))
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
