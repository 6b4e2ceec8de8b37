"""POST /v1/indexers/design through httpx.ASGITransport: the ranked candidates as JSON and CSV, the best the
same as sizeIndexer's figures for that design, and 422s naming the requirement or the field."""

from __future__ import annotations

import csv
import io

import httpx
import pytest

from service.indexers.design import DESIGN_EXAMPLE

pytestmark = pytest.mark.anyio


async def test_the_best_is_sized_as_size_indexer_sizes_it(client: httpx.AsyncClient) -> None:
    r = await client.post("/v1/indexers/design", json=DESIGN_EXAMPLE)
    assert r.status_code == 200, r.text
    best = r.json()["best"]
    motor = next(m for m in DESIGN_EXAMPLE["motors"] if m["name"] == best["motor"])
    sizing = await client.post("/v1/indexers/sizing", json={
        "indexer": {"stops": 6, "indexing_angle_deg": best["indexing_angle_deg"], "cycle_time_s": 1.0,
                    "curve": {"type": "named", "name": best["curve"]}},
        "load": DESIGN_EXAMPLE["load"], "motor": {k: v for k, v in motor.items() if k != "name"}})
    s = sizing.json()
    for name in ("input_torque_nm", "rms_input_torque_nm", "input_power_kw", "design_output_torque_nm",
                 "motor_peak_torque_nm", "motor_rms_torque_nm", "rms_utilisation"):
        assert best[name] == s[name], name


async def test_the_csv_is_the_ranked_candidates(client: httpx.AsyncClient) -> None:
    as_json = (await client.post("/v1/indexers/design", json=DESIGN_EXAMPLE)).json()["candidates"]
    r = await client.post("/v1/indexers/design?format=csv", json=DESIGN_EXAMPLE)
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/csv")
    rows = list(csv.DictReader(io.StringIO(r.text)))
    assert len(rows) == len(as_json) == 9 * 4 * 3
    for row, item in zip(rows, as_json, strict=True):
        assert row["curve"] == item["curve"] and row["motor"] == item["motor"]
        assert float(row["input_torque_nm"]) == item["input_torque_nm"]
        assert row["feasible"] == str(item["feasible"]).lower()
        assert row["reason"] == (item["reason"] or "")


async def test_nothing_feasible_names_the_requirement(client: httpx.AsyncClient) -> None:
    body = {k: v for k, v in DESIGN_EXAMPLE.items() if k != "motors"} | {"rated_output_torque_nm": 1.0}
    r = await client.post("/v1/indexers/design", json=body)
    assert r.status_code == 422
    error = r.json()["errors"][0]
    assert error["loc"] == ["body", "rated_output_torque_nm"]
    assert "no candidate meets every requirement" in error["msg"] and "exceeds the rated 1 N·m" in error["msg"]


@pytest.mark.parametrize(("change", "loc"), [
    ({"min_dwell_s": 1.0}, ["body", "min_dwell_s"]),
    ({"motors": [DESIGN_EXAMPLE["motors"][0], DESIGN_EXAMPLE["motors"][0]]}, ["body", "motors", 1, "name"]),
    ({"motors": [], "criterion": "motor"}, ["body", "criterion"]),
    ({"indexing_angles_deg": list(range(1, 361)), "curves": [{"type": "named", "name": "MS"}] * 50},
     ["body", "indexing_angles_deg"]),
])
async def test_bad_requests_name_the_field(client: httpx.AsyncClient, change: dict, loc: list) -> None:
    r = await client.post("/v1/indexers/design", json=DESIGN_EXAMPLE | change)
    assert r.status_code in (413, 422), r.text
    assert r.json()["errors"][0]["loc"] == loc
