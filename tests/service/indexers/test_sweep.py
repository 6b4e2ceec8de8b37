"""POST /v1/indexers/sizing/sweep: every combination equals its single sizing (the same
arithmetic over arrays, camcore.indexer.sweep), row by row; limits and CSV."""

from __future__ import annotations

import csv
import io
import itertools

import httpx
import pytest

from service.indexers.specs import LOAD_EXAMPLE

pytestmark = pytest.mark.anyio

CURVES = [{"type": "named", "name": "MS"}, {"type": "named", "name": "MCV50"},
          {"type": "universal", "t": [0, 0.1, 0.1, 0.3, 0.5, 0.75, 0.75, 1], "v7": 0}]
LOAD = {**LOAD_EXAMPLE, "work_torque_nm": 4}


async def test_36_combinations_equal_36_single_sizings(client: httpx.AsyncClient) -> None:
    body = {"load": LOAD, "stops": [4, 6], "indexing_angle_deg": [120, 270], "curves": CURVES,
            "speed_rpm": [30, 60, 90]}
    r = await client.post("/v1/indexers/sizing/sweep", json=body)
    assert r.status_code == 200, r.text
    rows = r.json()
    assert len(rows["stops"]) == 36
    for i, (n, theta, curve, speed) in enumerate(itertools.product([4, 6], [120, 270], CURVES, [30, 60, 90])):
        assert (rows["stops"][i], rows["indexing_angle_deg"][i], rows["speed_rpm"][i]) == (n, theta, speed)
        single = (await client.post("/v1/indexers/sizing", json={
            "indexer": {"stops": n, "indexing_angle_deg": theta, "speed_rpm": speed, "curve": curve},
            "load": LOAD})).json()
        for name, column in rows.items():
            if name in single:
                # the same code over arrays: identical, not merely close
                assert column[i] == single[name], (i, name)


async def test_cycle_times_csv_and_limits(client: httpx.AsyncClient) -> None:
    body = {"load": LOAD, "stops": [8], "indexing_angle_deg": [180], "curves": CURVES[:1], "cycle_time_s": [1, 2]}
    r = await client.post("/v1/indexers/sizing/sweep", json=body, headers={"Accept": "text/csv"})
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/csv")
    table = list(csv.DictReader(io.StringIO(r.text)))
    assert [float(row["speed_rpm"]) for row in table] == [60, 30]
    assert [float(row["cycle_time_s"]) for row in table] == [1, 2]
    both = await client.post("/v1/indexers/sizing/sweep", json={**body, "speed_rpm": [60]})
    assert both.status_code == 422 and "exactly one of speed_rpm" in both.json()["detail"]
    big = {**body, "stops": list(range(1, 101)), "indexing_angle_deg": list(range(1, 101)), "cycle_time_s": [1, 2]}
    r = await client.post("/v1/indexers/sizing/sweep", json=big)
    assert r.status_code == 413 and "sizing combinations is 20000, over the limit of 10000" in r.json()["detail"]


async def test_the_chart_of_input_torque_over_speed(client: httpx.AsyncClient) -> None:
    body = {"load": LOAD, "stops": [4, 6], "indexing_angle_deg": [120, 270], "curves": CURVES,
            "speed_rpm": [30, 60, 90, 120]}
    png = await client.post("/v1/indexers/sizing/sweep?format=png", json=body)
    assert png.status_code == 200 and png.headers["content-type"] == "image/png"
    assert png.content.startswith(b"\x89PNG\r\n\x1a\n")
    svg = await client.post("/v1/indexers/sizing/sweep?format=svg", json=body)
    assert svg.status_code == 200 and svg.headers["content-type"].startswith("image/svg+xml")
    # one line per curve in each of the 4 panels, its legend naming the curves
    assert b"MCV50" in svg.content and b"universal" in svg.content and b"n = 6, \xce\xb8h = 270\xc2\xb0" in svg.content
    many = {**body, "stops": list(range(1, 18)), "indexing_angle_deg": [120]}
    r = await client.post("/v1/indexers/sizing/sweep?format=png", json=many)
    assert r.status_code == 422 and "at most 16, not 17" in r.json()["detail"]
