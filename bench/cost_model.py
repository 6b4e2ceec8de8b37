"""``python -m bench.cost_model [--smoke]``: the cost model against the real run, at its edges.

For every computing operation, the largest request the default settings accept (found
from the service's own estimates: the size is bisected on a gate that only estimates),
then that request answered for real by a fresh app, in-process (``httpx.ASGITransport``,
body encoded beforehand), three times: its estimate, the time in the computation (the
gate's thread) and the whole answer, cold (a new app each time: no curve or table
cached). Then the next size up, which must be refused (413), and how long the refusal
took. One JSON object on stdout; the figures go in docs/robustness.md.

A figure, not a test: the worst case per endpoint depends on the machine (the reference
is the 2-core machine the coefficients were measured on). ``--smoke`` runs every case
once at small sizes (tests/project/test_bench_smoke.py runs it: it must run, not meet targets).
"""

from __future__ import annotations

import argparse
import asyncio
import json
import logging
import statistics
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import httpx
import orjson

from service.admission import WorkGate
from service.app import create_app
from service.cams.barrel_specs import BARREL_EXAMPLE
from service.cams.parallel_specs import PARALLEL_EXAMPLE
from service.cams.roller_gear_specs import ROLLER_GEAR_EXAMPLE
from service.settings import Settings

MS = {"type": "named", "name": "MS"}
BEZIER_20 = {"type": "bezier", "control_points": [[i / 20, (1 - (1 - i / 20) ** 2) if i < 20 else 1.0]
                                                  for i in range(21)]}
INDEXER = {"stops": 6, "indexing_angle_deg": 270, "speed_rpm": 60, "curve": MS}
LOAD = {"parts": [{"shape": "disc", "mass_kg": 50, "diameter_mm": 600}], "friction_coefficient": 0.1,
        "friction_radius_mm": 200, "service_factor": 1.5}


def points_curve(n: int) -> dict[str, Any]:
    """A rise through ``n`` points of the cycloid (a measured-points curve)."""
    import math

    t = [i / (n - 1) for i in range(n)]
    return {"type": "points", "t": t, "s": [x - math.sin(2 * math.pi * x) / (2 * math.pi) for x in t]}


def cam(segments: int) -> dict[str, Any]:
    """A roller cam of ``segments`` alternating MS rises and returns over 360°."""
    span = 360 / segments
    kinds = ["rise", "return"] * (segments // 2) + ["dwell"] * (segments % 2)
    return {"follower": {"type": "roller", "roller_radius_mm": 10}, "base_radius_mm": 40,
            "segments": [{"type": k, "angle_deg": span, **({"lift_mm": 5, "curve": MS} if k != "dwell" else {})}
                         for k in kinds]}


@dataclass(frozen=True)
class Case:
    """One operation, and its request as a function of one size."""

    name: str
    method: str
    path: str
    body: Callable[[int], Any]  # size → JSON body (None for a GET)
    size: str  # what the size counts
    largest: int  # scan sizes up to this (past the settings limit where there is one)
    query: Callable[[int], dict[str, Any]] = lambda n: {}
    csv: bool = False


CASES = [
    Case("curve table, MS, CSV", "POST", "/v1/curves/table", lambda n: {"curve": MS, "samples": n},
         "samples", 400_000, csv=True),
    Case("curve table, Bezier degree 20, CSV", "POST", "/v1/curves/table",
         lambda n: {"curve": BEZIER_20, "samples": n}, "samples", 400_000, csv=True),
    Case("curve table, 10 000 points, JSON", "POST", "/v1/curves/table",
         lambda n: {"curve": points_curve(10_000), "samples": n}, "samples", 400_000),
    Case("catalog table, GET CSV", "GET", "/v1/curves/MS/table", lambda n: None, "samples", 400_000,
         query=lambda n: {"samples": n, "format": "csv"}),
    Case("characteristics, Bezier", "POST", "/v1/curves/characteristics",
         lambda n: {"curve": {"type": "bezier", "control_points": [[i / n, i / n] for i in range(n + 1)]}},
         "degree", 40),
    Case("inverse, exact", "POST", "/v1/curves/inverse",
         lambda n: {"curve": MS, "s": [(i + 0.5) / n for i in range(n)]}, "S values", 400_000),
    Case("inverse, table method", "POST", "/v1/curves/inverse",
         lambda n: {"curve": MS, "s": [(i + 0.5) / n for i in range(n)], "method": "table", "table_step": 1e-4},
         "S values", 400_000),
    Case("indexer motion, CSV", "POST", "/v1/indexers/motion", lambda n: {"indexer": INDEXER, "samples": n},
         "samples", 400_000, csv=True),
    Case("indexer position", "POST", "/v1/indexers/position",
         lambda n: {"indexer": INDEXER, "output_angle_deg": [60 * (i + 0.5) / n for i in range(n)]},
         "angles", 400_000),
    Case("indexer sizing, points curve", "POST", "/v1/indexers/sizing",
         lambda n: {"indexer": {**INDEXER, "curve": points_curve(n)}, "load": LOAD}, "curve points", 20_000),
    Case("profile, JSON", "POST", "/v1/profiles", lambda n: {"profile": cam(4), "samples": n}, "samples", 400_000),
    Case("profile contour, DXF", "POST", "/v1/profiles/contour.dxf", lambda n: {"profile": cam(4), "samples": n},
         "samples", 400_000),
    Case("base circle, pressure angle", "POST", "/v1/profiles/base-circle",
         lambda n: {"profile": cam(n), "max_pressure_angle_deg": 30}, "segments", 200),
    Case("base circle, both limits", "POST", "/v1/profiles/base-circle",
         lambda n: {"profile": cam(n), "max_pressure_angle_deg": 30, "min_radius_of_curvature_mm": 5},
         "segments", 200),
    Case("follower dynamics", "POST", "/v1/profiles/dynamics",
         lambda n: {"profile": cam(n), "speed_rpm": 300, "mass_kg": 0.5, "spring_rate_n_mm": 2, "preload_n": 30,
                    "safety_margin_n": 5}, "segments", 360),
    Case("residual vibration, MS, τ 0.5-20", "POST", "/v1/curves/vibration",
         lambda n: {"curve": MS, "tau_range": {"start": 0.5, "stop": 20, "samples": n}}, "τ values", 20_000),
    Case("residual vibration, 1 000 points, τ 0.001-1", "POST", "/v1/curves/vibration",
         lambda n: {"curve": points_curve(1000), "tau_range": {"start": 0.001, "stop": 1, "samples": n}},
         "τ values", 1000),
    Case("residual vibration, Bezier degree 20, τ 900-1000", "POST", "/v1/curves/vibration",
         lambda n: {"curve": BEZIER_20, "tau_range": {"start": 900, "stop": 1000, "samples": n}}, "τ values", 1000),
    Case("indexer vibration, CSV", "POST", "/v1/indexers/vibration",
         lambda n: {"indexer": INDEXER, "inertia_kgm2": 2.25, "stiffness_nm_rad": 2e5, "damping_ratio": 0.05,
                    "tolerance_arcsec": 10, "samples": n}, "samples", 400_000, csv=True),
    Case("vibration chart, PNG", "GET", "/v1/curves/vibration/plot", lambda n: None, "τ values per curve", 2001,
         query=lambda n: {"format": "png", "samples": n}),
    # manufacturing: the size is the tolerance, 10^(−n/10) mm (n = 40: 1e-4 mm, the smallest allowed)
    Case("toolpath, groove, G-code", "POST", "/v1/profiles/toolpath.nc",
         lambda n: {"profile": cam(4), "tool_radius_mm": 6, "side": "groove", "tolerance_mm": 10 ** (-n / 10)},
         "tenths of a decade of tolerance", 40),
    Case("solid, STEP", "POST", "/v1/profiles/solid.step",
         lambda n: {"profile": cam(4), "solid": {"thickness_mm": 10, "bore_diameter_mm": 20,
                                                 "tolerance_mm": 10 ** (-n / 10)}},
         "tenths of a decade of tolerance", 40),
    Case("solid, STL", "POST", "/v1/profiles/solid.stl",
         lambda n: {"profile": cam(4), "solid": {"thickness_mm": 10, "bore_diameter_mm": 20,
                                                 "tolerance_mm": 10 ** (-n / 10)}},
         "tenths of a decade of tolerance", 40),
    Case("motion cam table", "POST", "/v1/motions/cam-table.csv",
         lambda n: {"motion": {"segments": [{"span_deg": 180, "to": 10, "curve": MS}, {"span_deg": 180, "to": 0}]},
                    "samples": n}, "samples", 400_000),
    # cams: the barrel's and the roller-gear's grids of samples × 5 and × 41 points; the parallel cam's
    # size is its samples less 15 (it takes 16 to 3601); the schema's largest samples are the edge there
    # (the next size up is a 422)
    Case("barrel cam, JSON", "POST", "/v1/cams/barrel", lambda n: {**BARREL_EXAMPLE, "samples": n}, "samples",
         400_000),
    Case("parallel cam, JSON", "POST", "/v1/cams/parallel", lambda n: {**PARALLEL_EXAMPLE, "samples": 15 + n},
         "samples over 15", 3586),
    Case("parallel cam, 8 stops × 3 plates, JSON", "POST", "/v1/cams/parallel",
         lambda n: {**PARALLEL_EXAMPLE, "stops": 8, "roller_radius_mm": 10, "samples": 15 + n}, "samples over 15",
         3586),
    Case("roller-gear cam, JSON", "POST", "/v1/cams/roller-gear",
         lambda n: {**ROLLER_GEAR_EXAMPLE, "samples": n, "length_samples": 41}, "samples", 3601),
    Case("roller-gear rib, STL", "POST", "/v1/cams/roller-gear.stl",
         lambda n: {**ROLLER_GEAR_EXAMPLE, "samples": n, "length_samples": 41}, "samples", 3601),
    # machines: the size is the axes (plate cams at phases 360/n apart), each at the machine's speed and 4 swept
    Case("machine, plate cams, 4-speed sweep", "POST", "/v1/machines",
         lambda n: {"master": {"speed_rpm": 120}, "speeds_rpm": [60, 90, 150, 180],
                    "axes": [{"name": f"cam{i}", "phase_deg": 360 * i / n, "plate_cam": {
                        "profile": cam(4), "mass_kg": 0.5, "spring_rate_n_mm": 2, "preload_n": 30}}
                             for i in range(n)]}, "axes", 16),
    Case("machine, indexers with a motor", "POST", "/v1/machines",
         lambda n: {"master": {"speed_rpm": 60}, "flywheel": {"speed_fluctuation": 0.05},
                    "drive": {"gear_ratio": 2, "motor": {"rated_torque_nm": 1, "peak_torque_nm": 3,
                                                         "rotor_inertia_kgm2": 3e-4, "max_speed_rpm": 3000,
                                                         "reduction_ratio": 10}},
                    "axes": [{"name": f"t{i}", "phase_deg": 360 * i / n, "indexer": {
                        "indexer": {"stops": 6, "indexing_angle_deg": 90}, "load": LOAD}} for i in range(n)]},
         "axes", 16),
    Case("curve plot, PNG", "GET", "/v1/curves/MS/plot", lambda n: None, "dpi", 300,
         query=lambda n: {"format": "png", "dpi": n}),
    Case("profile plot, PNG", "GET", "/v1/profiles/plot", lambda n: None, "dpi", 300,
         query=lambda n: {"format": "png", "dpi": n}),
]


class _Estimated(Exception):
    """Raised by the estimating gate instead of running the work."""


class EstimatingGate(WorkGate):
    """Checks the budget as the real gate does, then stops: the size scan runs nothing. The stop is an
    exception, which the service answers as a 500 (it ends the request there); the estimate is kept here."""

    estimated: float | None = None

    async def run(self, request: Any, estimate: Any, work: Any, *args: Any) -> Any:
        self.check_budget(estimate)
        self.estimated = estimate.seconds
        raise _Estimated(estimate.seconds)


class TimingGate(WorkGate):
    """The real gate, recording each estimate and the time its work took."""

    def __init__(self, settings: Settings):
        super().__init__(settings)
        self.records: list[tuple[float, float]] = []

    async def run(self, request: Any, estimate: Any, work: Any, *args: Any) -> Any:
        start = time.perf_counter()
        try:
            return await super().run(request, estimate, work, *args)
        finally:
            self.records.append((estimate.seconds, time.perf_counter() - start))


async def _send(app: Any, case: Case, n: int, content: bytes | None = None) -> tuple[httpx.Response, float]:
    headers = {"Accept": "text/csv"} if case.csv else {}
    if content is None and case.method == "POST":
        content = orjson.dumps(case.body(n))
    if content is not None:
        headers["Content-Type"] = "application/json"
    transport = httpx.ASGITransport(app=app, raise_app_exceptions=True)
    async with httpx.AsyncClient(transport=transport, base_url="http://bench", timeout=120) as client:
        start = time.perf_counter()
        response = await client.request(case.method, case.path, content=content, params=case.query(n),
                                        headers=headers)
        return response, time.perf_counter() - start


async def accepted(case: Case, n: int) -> float | None:
    """The estimate [s] when the default settings accept size ``n``; None when refused."""
    app = create_app(Settings())
    gate = EstimatingGate(app.state.settings)
    app.state.context.gate = gate
    log = logging.getLogger("camcore.service")
    log.disabled = True  # the service logs the stop as an unexpected error: expected here
    try:
        response, _ = await _send(app, case, n)
    except _Estimated as estimated:
        return float(estimated.args[0])
    finally:
        log.disabled = False
    if gate.estimated is not None:  # answered 500 by the service's last-resort handler: the stop above
        return gate.estimated
    if response.status_code == 413:
        return None
    raise RuntimeError(f"{case.name} at {n}: {response.status_code} {response.text[:300]}")


async def edge(case: Case, smallest: int = 2) -> int:
    """The largest accepted size (bisection: the estimates grow with the size)."""
    low, high = smallest, case.largest
    if await accepted(case, low) is None:
        raise RuntimeError(f"{case.name}: even size {low} is refused")
    if await accepted(case, high) is not None:
        return high
    while high - low > 1:
        mid = (low + high) // 2
        if await accepted(case, mid) is None:
            high = mid
        else:
            low = mid
    return low


async def measure(case: Case, n: int, repeats: int) -> dict[str, Any]:
    content = orjson.dumps(case.body(n)) if case.method == "POST" else None
    work, total, estimates = [], [], []
    for _ in range(repeats):
        app = create_app(Settings())  # cold: nothing cached
        gate = TimingGate(app.state.settings)
        app.state.context.gate = gate
        response, seconds = await _send(app, case, n, content)
        if response.status_code != 200:
            raise RuntimeError(f"{case.name} at {n}: {response.status_code} {response.text[:300]}")
        total.append(seconds)
        work.append(sum(w for _, w in gate.records))
        estimates.append(sum(e for e, _ in gate.records))
    refusals = []
    for _ in range(repeats):
        refused, refusal_s = await _send(create_app(Settings()), case, n + 1)
        refusals.append(refusal_s)
    return {"operation": f"{case.method} {case.path}", "size": f"{n} {case.size}",
            "estimate_s": round(estimates[0], 4), "work_s_median": round(statistics.median(work), 4),
            "answer_s_median": round(statistics.median(total), 4), "answer_s_max": round(max(total), 4),
            "next_size_up": {"status": refused.status_code, "answer_s_median": round(statistics.median(refusals), 4),
                             "answer_s_max": round(max(refusals), 4)}}


async def main_async(smoke: bool) -> dict[str, Any]:
    figures: dict[str, Any] = {}
    for case in CASES:
        if smoke:
            n = min(case.largest, 101 if case.largest > 1000 else 100 if case.size == "dpi" else 4)
            figures[case.name] = await measure(case, n, repeats=1)
        else:
            n = await edge(case, smallest=60 if case.size == "dpi" else 2)
            figures[case.name] = await measure(case, n, repeats=3)
        print(case.name, json.dumps(figures[case.name]), flush=True, file=sys.stderr)
    return {"mode": "smoke" if smoke else "full", "budget_s": Settings().max_work_s, "cases": figures}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--smoke", action="store_true", help="every case once, at small sizes")
    args = parser.parse_args(argv)
    print(json.dumps(asyncio.run(main_async(args.smoke)), indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
