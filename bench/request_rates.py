"""Request rates of the operations designers use most, and the start-up time, over real HTTP.

One server (``python -m service``, one worker, core 0) answers wrk (one thread, 32
connections, core 1) run after run, each run taking /health (the ceiling) and every request
below in turn: a 361-sample profile (the request example: the same cam each time, as a
designer's page reloads it; and a new cam each time, its base radius changed), the
characteristic values of a new universal curve each time, the same curve's (cached), and an
indexer sizing (the request example). The base-circle sizing is timed one request at a time
(its figure is a latency). The request bodies are the OpenAPI document's request examples.
"""

from __future__ import annotations

import compileall
import json
import statistics
import tempfile
import time
from pathlib import Path
from typing import Any

import httpx

from .servers import PINNING, ROOT, WRK_MISSING, Server, have_wrk, wrk
from .timing import figure

#: a new curve per request: Makino's universal curve with MS's break points, T1 moved a little
CHARACTERISTICS_LUA = """
counter = 0
request = function()
  counter = counter + 1
  local t1 = 0.1 + (counter % 1000000) * 1e-8
  local body = string.format(
    '{"curve":{"type":"universal","t":[0,%.10f,%.10f,0.5,0.5,0.875,0.875,1]}}', t1, t1)
  return wrk.format("POST", "/v1/curves/characteristics", {["Content-Type"] = "application/json"}, body)
end
"""


def _example(spec: dict[str, Any], path: str) -> dict[str, Any]:
    content = spec["paths"][path]["post"]["requestBody"]["content"]["application/json"]
    if "examples" in content:
        return dict(next(iter(content["examples"].values()))["value"])
    return dict(content["example"])


def _fixed_body(tmp: Path, name: str, path: str, body: dict[str, Any]) -> str:
    lua = tmp / f"{name}.lua"
    lua.write_text('wrk.method = "POST"\nwrk.headers["Content-Type"] = "application/json"\n'
                   f"wrk.body = '{json.dumps(body)}'\nwrk.path = '{path}'\n")
    return str(lua)


def _varied(tmp: Path, name: str, path: str, body: dict[str, Any], field: str, value: float) -> str:
    """The body with the number ``"field": value`` changed by 1e-6 per request (a new request
    every time: nothing comes from an answer cache)."""
    template = json.dumps(body).replace(f'"{field}": {value}', f'"{field}": %.6f')
    assert "%.6f" in template, f"{field} not in the body"
    lua = tmp / f"{name}.lua"
    lua.write_text("counter = 0\nrequest = function()\n  counter = counter + 1\n"
                   f"  local body = string.format('{template}', {value} + (counter % 1000000) * 1e-6)\n"
                   f'  return wrk.format("POST", "{path}", {{["Content-Type"] = "application/json"}}, body)\nend\n')
    return str(lua)


def request_figures(seconds: int, runs: int, latency_requests: int) -> dict[str, Any]:
    names = ("profile_rps", "characteristics_new_curve_rps", "sizing_rps", "base_circle_ms")
    if not have_wrk():
        return {name: {"skipped": WRK_MISSING} for name in names}
    rates: dict[str, list[float]] = {k: [] for k in ("health", "profile", "profile_new_cam", "characteristics_new",
                                                     "characteristics_cached", "sizing", "sizing_new_load")}
    with tempfile.TemporaryDirectory() as tmp_name, Server(workers=1, cpus="0") as server:
        tmp = Path(tmp_name)
        spec = httpx.get(server.url + "/openapi.json", timeout=30).json()
        profile = _example(spec, "/v1/profiles")
        sizing = _example(spec, "/v1/indexers/sizing")
        scripts = {
            "profile": (server.url + "/v1/profiles", _fixed_body(tmp, "profile", "/v1/profiles", profile)),
            "profile_new_cam": (server.url + "/v1/profiles", _varied(tmp, "new_cams", "/v1/profiles", profile,
                                                                     "base_radius_mm",
                                                                     profile["profile"]["base_radius_mm"])),
            "characteristics_new": (server.url + "/v1/curves/characteristics", str(_write(tmp, CHARACTERISTICS_LUA))),
            "characteristics_cached": (server.url + "/v1/curves/characteristics", _fixed_body(
                tmp, "cached", "/v1/curves/characteristics", _example(spec, "/v1/curves/characteristics"))),
            "sizing": (server.url + "/v1/indexers/sizing", _fixed_body(tmp, "sizing", "/v1/indexers/sizing", sizing)),
            "sizing_new_load": (server.url + "/v1/indexers/sizing", _varied(
                tmp, "new_loads", "/v1/indexers/sizing", sizing, "mass_kg", sizing["load"]["parts"][0]["mass_kg"])),
        }
        warm = min(2, seconds)
        for url, lua in scripts.values():
            wrk(url, warm, lua)
        for _ in range(runs):
            rates["health"].append(wrk(server.url + "/health", seconds)["rps"])
            for name, (url, lua) in scripts.items():
                rates[name].append(wrk(url, seconds, lua)["rps"])
        base = _example(spec, "/v1/profiles/base-circle")
        latencies = []
        with httpx.Client(base_url=server.url, timeout=30) as client:
            client.post("/v1/profiles/base-circle", json=base).raise_for_status()
            for _ in range(latency_requests):
                start = time.perf_counter()
                client.post("/v1/profiles/base-circle", json=base).raise_for_status()
                latencies.append((time.perf_counter() - start) * 1e3)
    beside = {"health_rps": rates["health"], "pinning": PINNING}
    return {
        "profile_rps": figure(rates["profile"], ">= 150", unit="req/s", new_cam_rps=rates["profile_new_cam"], **beside,
                              what="POST /v1/profiles, the 361-sample roller example (the same cam each time: its "
                                   "checks come from the cache); new_cam_rps: its base radius changed every "
                                   "request (checks computed every time); 1 worker, wrk 32 connections"),
        "characteristics_new_curve_rps": figure(
            rates["characteristics_new"], ">= 1000", unit="req/s", cached_curve_rps=rates["characteristics_cached"],
            **beside, what="POST /v1/curves/characteristics of a new universal curve every request (built and its "
                           "extrema solved); cached_curve_rps: MS, from the curve cache on the event loop"),
        "sizing_rps": figure(rates["sizing"], ">= 1500", unit="req/s", new_load_rps=rates["sizing_new_load"], **beside,
                             what="POST /v1/indexers/sizing, the request example sent over and over (its answer from "
                                  "the sizing cache after the first); new_load_rps: the load's mass changed every "
                                  "request (peaks, torque table and RMS computed every time)"),
        "base_circle_ms": figure(latencies, "<= 50", unit="ms",
                                 what=f"POST /v1/profiles/base-circle, the request example, {latency_requests} "
                                      "requests one after another (latency, ms)"),
    }


def _write(tmp: Path, text: str) -> Path:
    path = tmp / "characteristics.lua"
    path.write_text(text)
    return path


def cold_start(runs: int) -> dict[str, Any]:
    """Seconds from starting ``python -m service`` (1 worker) to its first 200 on /health ÷ the
    same for a bare FastAPI app under uvicorn, started alternately, each from its bytecode."""
    # as the image does (Dockerfile: compileall camcore service) and pip does for the libraries: with
    # PYTHONDONTWRITEBYTECODE set, a checkout would otherwise compile its ~200 modules at every start
    for package in ("camcore", "service", "bench"):
        compileall.compile_dir(ROOT / package, quiet=1)
    ours, bare = [], []
    with_imports: dict[str, list[float]] = {"numpy": [], "camcore": []}
    for _ in range(runs):
        with Server(workers=1, cpus="0", bare=True) as floor:
            bare.append(floor.first_answer_s)
        with Server(workers=1, cpus="0") as server:
            ours.append(server.first_answer_s)
        for module, times in with_imports.items():  # the floor importing what the service needs first
            with Server(workers=1, cpus="0", bare=True, BENCH_BARE_IMPORTS=module) as floor:
                times.append(floor.first_answer_s)
    with Server(workers=2, cpus="0,1") as two:
        two_workers = two.first_answer_s
    return figure([o / b for o, b in zip(ours, bare)], "<= 1.3", service_s=[round(x, 3) for x in ours],
                  bare_fastapi_s=[round(x, 3) for x in bare], two_workers_s=round(two_workers, 3),
                  median_service_s=round(statistics.median(ours), 3),
                  bare_importing_numpy_vs_bare=round(statistics.median(
                      n / b for n, b in zip(with_imports["numpy"], bare)), 3),
                  bare_importing_camcore_vs_bare=round(statistics.median(
                      c / b for c, b in zip(with_imports["camcore"], bare)), 3),
                  what="seconds from starting python -m service (1 worker) to its first 200 on /health ÷ the same "
                       "for a bare FastAPI app with one route under uvicorn (bench/bare_app.py), both from their "
                       "bytecode (compiled first, as the image's build does); two_workers_s: "
                       "CAMCORE_WORKERS=2 once (both workers answer /health only once up; the first one counts); "
                       "bare_importing_*_vs_bare: the bare app importing numpy, or camcore, first ÷ the bare app "
                       "(what the service's own dependencies cost before any route exists)")
