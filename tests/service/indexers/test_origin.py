"""input_angle_origin over HTTP (issue 22 item 4): the guide's worked example from the keyway."""

from __future__ import annotations

import httpx
import pytest

pytestmark = pytest.mark.anyio

GUIDE = {"stops": 6, "indexing_angle_deg": 270, "speed_rpm": 60, "curve": {"type": "named", "name": "MS"}}


async def test_motion_and_position_from_the_dwell_centre(client: httpx.AsyncClient) -> None:
    start = (await client.post("/v1/indexers/motion", json={"indexer": GUIDE, "samples": 3})).json()
    centre = (await client.post("/v1/indexers/motion", json={
        "indexer": {**GUIDE, "input_angle_origin": "dwell-centre"}, "samples": 3})).json()
    assert start["table"]["input_angle_deg"] == [0.0, 135.0, 270.0]
    assert centre["table"]["input_angle_deg"] == [45.0, 180.0, 315.0]
    assert centre["summary"]["omega_input_angle_deg"] == 180.0
    r = await client.post("/v1/indexers/position", json={
        "indexer": {**GUIDE, "input_angle_origin": "dwell-centre"}, "output_angle_deg": [30]})
    assert r.json()["input_angle_deg"][0] == pytest.approx(180.0, abs=1e-12)


async def test_sizing_torque_table_from_the_dwell_centre(client: httpx.AsyncClient) -> None:
    load = {"parts": [{"shape": "disc", "mass_kg": 50, "diameter_mm": 600}]}
    a = (await client.post("/v1/indexers/sizing", json={"indexer": GUIDE, "load": load})).json()
    b = (await client.post("/v1/indexers/sizing", json={
        "indexer": {**GUIDE, "input_angle_origin": "dwell-centre"}, "load": load})).json()
    assert b["input_torque_input_angle_deg"] == pytest.approx(a["input_torque_input_angle_deg"] + 45)
    assert b["input_torque_nm"] == a["input_torque_nm"]
    assert b["input_torque_table"]["input_angle_deg"][0] == 0.0


async def test_a_timing_chart_keeps_its_own_origin(client: httpx.AsyncClient) -> None:
    timing = {"unit": "deg", "period_deg": 360,
              "segments": [{"span_deg": 270, "stroke": 60, "curve": {"type": "named", "name": "MS"}},
                           {"span_deg": 90, "type": "dwell"}]}
    r = await client.post("/v1/indexers/motion", json={
        "indexer": {"timing": timing, "speed_rpm": 60, "input_angle_origin": "dwell-centre"}, "samples": 3})
    assert r.status_code == 422 and "timing chart starts at its own 0°" in r.text
