"""POST /v1/cams/parallel (computeParallelIndexingCam) and its CSV twin, over ASGI in-process.

The answer is checked from itself: every contour vertex is at the roller radius from its roller,
placed from the answered start angles and the answered turret angle (the index law); the CSV
columns equal the JSON's; bad geometry is a 422 naming the field and the rule, too much work a 413.
"""

from __future__ import annotations

import csv
import io
from typing import Any

import httpx
import numpy as np
import pytest

from service.cams.parallel_specs import PARALLEL_EXAMPLE, TWO_PLATE_EXAMPLE

pytestmark = pytest.mark.anyio
PATH = "/v1/cams/parallel"


async def test_three_plates_hold_the_turret_and_touch_their_rollers(client: httpx.AsyncClient) -> None:
    r = await client.post(PATH, json=PARALLEL_EXAMPLE)
    assert r.status_code == 200, r.text
    a = r.json()
    assert a["checks"]["conjugate"] is True and a["checks"]["unheld_cam_angles_deg"] == []
    assert len(a["plates"]) == 3
    c, rp, rr = (PARALLEL_EXAMPLE[k] for k in ("center_distance_mm", "roller_pitch_radius_mm", "roller_radius_mm"))
    cam_angle = np.radians(a["cam_angle_deg"])
    turret = np.radians(a["turret_angle_deg"])
    for plate in a["plates"]:
        # each contact: its roller placed from the answered turret angle at that sampled cam angle
        contacts = plate["contacts"]
        k = np.rint(np.array(contacts["cam_angle_deg"]) / (360 / len(cam_angle))).astype(int)
        alpha = np.radians(plate["roller_start_angle_deg"])[contacts["roller"]] + turret[k]
        bx, by = c - rp * np.cos(alpha), rp * np.sin(alpha)
        th = cam_angle[k]
        cx, cy = np.cos(th) * bx + np.sin(th) * by, -np.sin(th) * bx + np.cos(th) * by
        x, y = np.array(plate["x_mm"]), np.array(plate["y_mm"])
        nearest = np.sqrt(((x[None] - cx[:, None]) ** 2 + (y[None] - cy[:, None]) ** 2).min(axis=1))
        # the nearest vertex, not the polyline: within the vertex spacing's half (≤ 0.5 mm) of the radius,
        # and never inside it by more than the chords' sagitta (5e-3 mm, tests/camcore/cams/test_parallel.py)
        assert np.all(nearest >= rr - 5e-3) and np.all(nearest <= rr + 0.5)
        assert set(plate["checks"]) >= {"undercut", "min_radius_mm", "max_radius_mm"}
    assert 0 < a["checks"]["max_pressure_angle_deg"] < 60


async def test_two_plates_name_where_the_turret_is_loose(client: httpx.AsyncClient) -> None:
    a = (await client.post(PATH, json=TWO_PLATE_EXAMPLE)).json()
    assert a["checks"]["conjugate"] is False
    loose = [t for t, f, b in zip(a["cam_angle_deg"], a["held_forward"], a["held_back"]) if not (f and b)]
    assert a["checks"]["unheld_cam_angles_deg"] == pytest.approx(loose[:10])
    # where no contact drives (or holds), its pressure angle column is null
    for f, p in zip(a["held_forward"], a["drive_pressure_angle_deg"]):
        assert (p is None) == (not f)


async def test_csv_is_the_json_columns(client: httpx.AsyncClient) -> None:
    body = {**PARALLEL_EXAMPLE, "samples": 31}
    a = (await client.post(PATH, json=body)).json()
    for r in (await client.post(PATH + "?format=csv", json=body), await client.post(PATH + ".csv", json=body)):
        assert r.status_code == 200 and r.headers["content-type"].startswith("text/csv")
        rows = list(csv.DictReader(io.StringIO(r.text)))
        assert len(rows) == 31
        assert [float(x["turret_angle_deg"]) for x in rows] == pytest.approx(a["turret_angle_deg"], rel=1e-15)
        assert [x["held_forward"] == "1.0" for x in rows] == a["held_forward"]


@pytest.mark.parametrize("change, status, words", [
    ({"rollers_per_plate": 6}, 422, "rollers_per_plate must be a multiple of stops"),
    ({"roller_radius_mm": 40}, 422, "The rollers reach the cam axis"),
    ({"rollers_per_plate": 8, "roller_radius_mm": 24}, 422, "The rollers of a plate collide"),
    ({"stops": 2, "center_distance_mm": 80}, 422, "reaches the turret's axis"),
    ({"plates": 4}, 422, "plates"),
    ({"indexing_angle_deg": 360}, 422, "indexing_angle_deg"),
    ({"samples": 8}, 422, "samples"),
    ({"samples": 3601, "stops": 36, "rollers_per_plate": 72, "roller_radius_mm": 1}, 413, "reduce"),
    ({"samples": 3602}, 422, "samples"),
])
async def test_bad_requests(client: httpx.AsyncClient, change: dict[str, Any], status: int, words: str) -> None:
    r = await client.post(PATH, json={**PARALLEL_EXAMPLE, **change})
    assert r.status_code == status, r.text
    assert words in r.text


async def test_turret_angle_is_the_index_law(client: httpx.AsyncClient) -> None:
    """The turret column inverted by POST /v1/indexers/position (the indexer's exact inverse of the same
    law) gives back the cam angles: the plates turn the turret as the indexer's motion."""
    a = (await client.post(PATH, json={**PARALLEL_EXAMPLE, "samples": 31})).json()
    pairs = [(t, f) for t, f in zip(a["cam_angle_deg"], a["turret_angle_deg"]) if 0 < f < 90]
    assert len(pairs) >= 8
    indexer = {"stops": 4, "indexing_angle_deg": 120, "speed_rpm": 60, "curve": PARALLEL_EXAMPLE["curve"]}
    r = await client.post("/v1/indexers/position", json={"indexer": indexer, "output_angle_deg": [f for _, f in pairs]})
    assert r.status_code == 200, r.text
    # the exact inverse is good to a few ulps of T; over θh = 120° that is ~1e-12°
    assert r.json()["input_angle_deg"] == pytest.approx([t for t, _ in pairs], abs=1e-9)
