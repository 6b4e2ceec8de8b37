"""/v1/indexers through httpx.ASGITransport (docs/api.md IndexerSpec, LoadSpec; INDEXMAN guide)."""

from __future__ import annotations

import math
from typing import Any

import httpx
import pytest

pytestmark = pytest.mark.anyio

# INDEXMAN guide, worked example before 凸轮曲线的特性值一览: n = 6, θh = 270°, MS, 60 rpm
GUIDE = {"stops": 6, "indexing_angle_deg": 270, "speed_rpm": 60}


async def test_motion_summary_and_table(client: httpx.AsyncClient) -> None:
    r = await client.post("/v1/indexers/motion", json={"indexer": GUIDE, "samples": 101})
    assert r.status_code == 200, r.text
    body = r.json()
    s = body["summary"]
    # th = (θh/360)(60/N) = 0.75 s; t0 = 60/(N z) = 1 s; h = 360/6 = 60°
    assert s["indexing_time_s"] == 0.75 and s["cycle_time_s"] == 1.0 and s["dwell_time_s"] == 0.25
    assert s["displacement_deg"] == 60.0
    # peak ω = (h/th)·Vm = (π/3 / 0.75)·1.7596034 (MS Vm, exact)
    assert math.isclose(s["omega_rad_s"], math.pi / 3 / 0.75 * 1.7596033859537705, rel_tol=1e-14)
    table = body["table"]
    assert len(table["input_angle_deg"]) == 101 and table["input_angle_deg"][-1] == 270.0
    assert math.isclose(table["output_angle_deg"][-1], 60.0, rel_tol=1e-14)


async def test_motion_csv(client: httpx.AsyncClient) -> None:
    r = await client.post("/v1/indexers/motion", json={"indexer": GUIDE, "samples": 5}, headers={"Accept": "text/csv"})
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/csv")
    lines = r.text.strip().split("\n")
    assert lines[0].startswith("input_angle_deg,time_s,output_angle_deg,omega_rad_s,alpha_rad_s2,jerk_rad_s3")
    assert len(lines) == 6


async def test_position_reproduces_the_guide_by_table_and_exactly(client: httpx.AsyncClient) -> None:
    # the guide rounds S = 11/60 to 0.1833 and interpolates rows 0.30/0.31 → T = 0.304, θ = 82.08°,
    # ω = 1.8696 rad/s. Our table method works from S = 11/60 unrounded, so T differs in the 5th digit.
    r = await client.post("/v1/indexers/position", json={"indexer": GUIDE, "output_angle_deg": [11],
                                                         "method": "table", "table_decimals": 5})
    assert r.status_code == 200
    body = r.json()
    assert round(body["t"][0], 3) == 0.304 and round(body["v"][0], 3) == 1.339
    assert round(body["input_angle_deg"][0], 1) == 82.1
    exact = (await client.post("/v1/indexers/position", json={"indexer": GUIDE, "output_angle_deg": [11]})).json()
    # exact and table agree to the table's interpolation error (a few 1e-5 in T for 0.01 rows)
    assert abs(exact["t"][0] - body["t"][0]) < 5e-5


async def test_position_csv_and_range_error(client: httpx.AsyncClient) -> None:
    r = await client.post("/v1/indexers/position", json={"indexer": GUIDE, "output_angle_deg": [0, 30, 60]},
                          headers={"Accept": "text/csv"})
    assert r.status_code == 200 and r.text.startswith("output_angle_deg,input_angle_deg,time_s")
    r = await client.post("/v1/indexers/position", json={"indexer": GUIDE, "output_angle_deg": [61]})
    assert r.status_code == 422 and "outside the index" in r.json()["detail"]


async def test_sizing_disc_with_friction(client: httpx.AsyncClient) -> None:
    # disc 50 kg, Ø600 mm: I = m D²/8 = 50 · 0.36 / 8 = 2.25 kg·m²
    # α max = (h/th²)·Am = (π/3)/0.5625 · 5.52795707 = 10.2913 rad/s²; Ti = 2.25 · 10.2913 = 23.1555 N·m
    # Tf = μ m g R = 0.1 · 50 · 9.80665 · 0.2 = 9.80665 N·m; Tt = 32.9621; fc·Tt = 49.4432
    load = {"parts": [{"shape": "disc", "mass_kg": 50, "diameter_mm": 600}],
            "friction_coefficient": 0.1, "friction_radius_mm": 200}
    r = await client.post("/v1/indexers/sizing", json={"indexer": GUIDE, "load": load})
    assert r.status_code == 200, r.text
    b = r.json()
    assert math.isclose(b["inertia_kgm2"], 2.25, rel_tol=1e-15)
    alpha = math.pi / 3 / 0.75**2 * 5.52795707054409
    assert math.isclose(b["alpha_max_rad_s2"], alpha, rel_tol=1e-13)
    assert math.isclose(b["friction_torque_nm"], 9.80665, rel_tol=1e-15)
    assert math.isclose(b["output_torque_nm"], 2.25 * alpha + 9.80665, rel_tol=1e-13)
    assert math.isclose(b["design_output_torque_nm"], 1.5 * (2.25 * alpha + 9.80665), rel_tol=1e-13)
    # catalog short form 360/(n θh)·Qm·fc·Tt with MS Qm = 0.9873001351
    assert math.isclose(b["input_torque_catalog_nm"], 360 / (6 * 270) * 0.987300135126085 * b["design_output_torque_nm"],
                        rel_tol=1e-13)
    assert b["input_torque_nm"] >= b["input_torque_catalog_nm"]  # friction peaks at Vm, not at Qm
    assert math.isclose(b["input_power_kw"], 2 * math.pi * 60 * b["input_torque_nm"] / 60 / 1000, rel_tol=1e-13)


async def test_accuracy_conversion_matches_the_guide_table(client: httpx.AsyncClient) -> None:
    # guide, 计算分度精度: 30″ at 200 mm → 0.029 mm (printed to 3 decimals)
    r = await client.get("/v1/indexers/accuracy", params={"arc_seconds": 30, "radius_mm": 200})
    assert r.status_code == 200 and round(r.json()["accuracy_mm"], 3) == 0.029


@pytest.mark.parametrize("indexer, words", [
    ({"stops": 0, "indexing_angle_deg": 120, "speed_rpm": 60}, "stops"),
    ({"stops": 6, "indexing_angle_deg": 0, "speed_rpm": 60}, "indexing_angle_deg"),
    ({"stops": 6, "indexing_angle_deg": 400, "speed_rpm": 60}, "indexing_angle_deg"),
    ({"stops": 6, "indexing_angle_deg": 200, "dwells": 2, "speed_rpm": 60}, "θt = θh·z must not exceed 360°"),
    ({"stops": 6, "indexing_angle_deg": 120}, "exactly one of speed_rpm"),
    ({"stops": 6, "indexing_angle_deg": 120, "speed_rpm": 60, "cycle_time_s": 1}, "exactly one of speed_rpm"),
    ({"indexing_angle_deg": 120, "speed_rpm": 60}, "exactly one of stops"),
])
async def test_indexer_validation_names_field_and_rule(client: httpx.AsyncClient, indexer: dict, words: str) -> None:
    r = await client.post("/v1/indexers/motion", json={"indexer": indexer})
    assert r.status_code == 422
    assert words in r.json()["detail"]


@pytest.mark.parametrize("load, words", [
    ({"parts": [{"shape": "disc", "mass_kg": -1, "diameter_mm": 100}]}, "mass_kg"),
    ({"efficiency": 0}, "efficiency"),
    ({"efficiency": 1.2}, "efficiency"),
    ({"service_factor": 0.9}, "service_factor"),
    ({"parts": [{"shape": "ring", "mass_kg": 1, "diameter_mm": 100}]}, "inner_diameter_mm"),
    ({"friction_coefficient": 0.1}, "go together"),
])
async def test_load_validation(client: httpx.AsyncClient, load: dict, words: str) -> None:
    r = await client.post("/v1/indexers/sizing", json={"indexer": GUIDE, "load": load})
    assert r.status_code == 422
    assert words in r.json()["detail"]


async def test_the_same_sizing_again_comes_from_the_cache(client: httpx.AsyncClient) -> None:
    """Issue 21: a repeated sizing request is answered from the cache, byte for byte; another
    load is another request and is computed."""
    body = {"indexer": {"stops": 8, "indexing_angle_deg": 240, "speed_rpm": 45, "curve": {"type": "named", "name": "MS"}},
            "load": {"parts": [{"shape": "disc", "mass_kg": 20, "diameter_mm": 400}]}}
    before = (await client.get("/health")).json()["caches"]["sizings"]
    first = await client.post("/v1/indexers/sizing", json=body)
    again = await client.post("/v1/indexers/sizing", json=body)
    other = await client.post("/v1/indexers/sizing", json={**body, "load": {"parts": [
        {"shape": "disc", "mass_kg": 21, "diameter_mm": 400}]}})
    after = (await client.get("/health")).json()["caches"]["sizings"]
    assert first.status_code == again.status_code == other.status_code == 200
    assert again.content == first.content and again.headers["content-type"] == "application/json"
    assert after["hits"] - before["hits"] == 1 and after["misses"] - before["misses"] == 2
    assert other.json()["inertia_kgm2"] > first.json()["inertia_kgm2"]


async def test_the_chart_query_keeps_the_bounds_the_indexer_spec_checks(client: httpx.AsyncClient) -> None:
    # issue 34, point 4: ?indexing_angle_deg=5e-7 was answered "≥ 0.000001" (IndexerSpec's bound, the
    # query is checked against it again) where the document said only > 0 for the query parameter
    doc = (await client.get("/openapi.json")).json()
    spec = doc["components"]["schemas"]["IndexerSpec"]["properties"]
    params = {p["name"]: p["schema"] for p in doc["paths"]["/v1/indexers/plot"]["get"]["parameters"]}

    def bounds(schema: dict[str, Any]) -> dict[str, Any]:
        number = next((s for s in schema.get("anyOf", [schema]) if s.get("type") == "number"), {})
        return {k: number.get(k) for k in ("minimum", "exclusiveMinimum", "maximum", "exclusiveMaximum")}

    shared = [name for name in params if name in spec and bounds(spec[name])["minimum"] is not None]
    assert {"indexing_angle_deg", "swing_angle_deg", "speed_rpm", "cycle_time_s"} <= set(shared)
    for name in shared:
        assert bounds(params[name]) == bounds(spec[name]), name
    r = await client.get("/v1/indexers/plot", params={**GUIDE, "indexing_angle_deg": 5e-7})
    assert r.status_code == 422 and r.json()["errors"][0]["loc"] == ["query", "indexing_angle_deg"]
    assert params["indexing_angle_deg"]["minimum"] == 1e-6 and "greater than or equal to 0.000001" in r.text
