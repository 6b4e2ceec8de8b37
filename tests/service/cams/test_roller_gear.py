"""POST /v1/cams/roller-gear (computeRollerGearCam) and its CSV and STL twins, over ASGI in-process.

The answer is checked from itself: every flank point is at the roller radius from its roller's axis,
placed from the answered turret angle; the CSV columns equal the JSON's; the STL is a closed mesh of
the announced size; bad geometry is a 422 naming the field and the rule, too much work a 413.
"""

from __future__ import annotations

import csv
import io
import math
from typing import Any

import httpx
import numpy as np
import pytest

from service.app import create_app
from service.cams.roller_gear_specs import ROLLER_GEAR_EXAMPLE, UNDERCUT_EXAMPLE
from service.settings import Settings
from tests.stl_mesh import directed_edges, read_stl

pytestmark = pytest.mark.anyio
PATH = "/v1/cams/roller-gear"


async def test_flank_points_sit_on_their_rollers(client: httpx.AsyncClient) -> None:
    r = await client.post(PATH, json=ROLLER_GEAR_EXAMPLE)
    assert r.status_code == 200, r.text
    a = r.json()
    c, rr = ROLLER_GEAR_EXAMPLE["center_distance_mm"], ROLLER_GEAR_EXAMPLE["roller_radius_mm"]
    h = 2 * math.pi / ROLLER_GEAR_EXAMPLE["stops"]  # type: ignore[operator]
    theta = np.radians(a["cam_angle_deg"])[:, None]
    phi = np.radians(a["turret_angle_deg"])[:, None]
    for name, alpha in (("forward", phi), ("back", phi - h)):
        f = a["flanks"][name]
        x, y, z = (np.array(f[k]) for k in ("x_mm", "y_mm", "z_mm"))
        # out of the cam's frame, then the distance from the roller's axis A + t·(−cos α, 0, sin α)
        px, py = np.cos(theta) * x - np.sin(theta) * y - c, np.sin(theta) * x + np.cos(theta) * y
        t = -px * np.cos(alpha) + z * np.sin(alpha)
        d = np.sqrt((px + t * np.cos(alpha)) ** 2 + py**2 + (z - t * np.sin(alpha)) ** 2)
        # JSON carries 17 significant digits: the distance holds to rounding of ~100 mm coordinates
        assert np.abs(d - rr).max() < 1e-9, name
        assert np.abs(t - np.array(a["roller_position_mm"])).max() < 1e-9
        assert all(all(row) for row in f["regular"])
    checks = a["checks"]
    assert checks["undercut"] is False and checks["undercut_cam_angles_deg"] == []
    assert 40 < checks["max_pressure_angle_deg"] < checks["max_pressure_angle_along_roller_deg"] < 60
    # the dwell: the turret stands and the pressure angle is 0
    dwell = np.array(a["cam_angle_deg"]) > 120
    assert np.all(np.array(a["pressure_angle_deg"])[dwell] == 0)


async def test_a_short_index_is_reported_undercut(client: httpx.AsyncClient) -> None:
    a = (await client.post(PATH, json=UNDERCUT_EXAMPLE)).json()
    assert a["checks"]["undercut"] is True and a["checks"]["min_regularity"] < 0
    assert 0 < len(a["checks"]["undercut_cam_angles_deg"]) <= 10
    assert not all(all(row) for row in a["flanks"]["forward"]["regular"])


async def test_csv_is_the_json_columns(client: httpx.AsyncClient) -> None:
    body = {**ROLLER_GEAR_EXAMPLE, "samples": 31}
    a = (await client.post(PATH, json=body)).json()
    for r in (await client.post(PATH + "?format=csv", json=body), await client.post(PATH + ".csv", json=body),
              await client.post(PATH, json=body, headers={"Accept": "text/csv"})):
        assert r.status_code == 200 and r.headers["content-type"].startswith("text/csv")
        rows = list(csv.DictReader(io.StringIO(r.text)))
        assert len(rows) == 31
        for column in ("cam_angle_deg", "turret_angle_deg", "pressure_angle_deg", "back_pressure_angle_deg"):
            assert [float(x[column]) for x in rows] == pytest.approx(a[column], rel=1e-15), column


async def test_stl_is_the_closed_rib(client: httpx.AsyncClient) -> None:
    body = {**ROLLER_GEAR_EXAMPLE, "samples": 61, "length_samples": 3}
    one = await client.post(PATH + "?format=stl", json=body)
    twin = await client.post(PATH + ".stl", json=body)
    assert one.status_code == twin.status_code == 200, one.text
    assert one.headers["content-type"] == "model/stl" and one.content == twin.content
    assert 'filename="roller-gear-rib.stl"' in one.headers["content-disposition"]
    count = int(np.frombuffer(one.content, "<u4", 1, 80)[0])
    # two facets per quad between 61 rings of 6 points, two caps of 2 quads
    assert count == 2 * 60 * 6 + 4 * 2 and len(one.content) == 84 + 50 * count
    facets = read_stl(one.content)
    edges = directed_edges(facets, decimals=None)
    assert all(n == 1 for n in edges.values()) and all(edges[(q, p)] == 1 for p, q in edges)
    assert np.einsum("ij,ij->i", facets[:, 0], np.cross(facets[:, 1], facets[:, 2])).sum() > 0


async def test_turret_angle_is_the_index_law(client: httpx.AsyncClient) -> None:
    """The turret column inverted by POST /v1/indexers/position gives back the cam angles."""
    a = (await client.post(PATH, json={**ROLLER_GEAR_EXAMPLE, "samples": 37})).json()
    pairs = [(t, f) for t, f in zip(a["cam_angle_deg"], a["turret_angle_deg"], strict=True) if 0 < f < 45]
    assert len(pairs) >= 8
    indexer = {"stops": 8, "indexing_angle_deg": 120, "speed_rpm": 60, "curve": ROLLER_GEAR_EXAMPLE["curve"]}
    r = await client.post("/v1/indexers/position", json={"indexer": indexer, "output_angle_deg": [f for _, f in pairs]})
    assert r.status_code == 200, r.text
    # the exact inverse is good to a few ulps of T; over θh = 120° that is ~1e-12°
    assert r.json()["input_angle_deg"] == pytest.approx([t for t, _ in pairs], abs=1e-9)


@pytest.mark.parametrize("change, words", [
    ({"stops": 4}, "stops"),
    ({"roller_radius_mm": 25}, "The rollers leave no room for the rib"),
    ({"roller_pitch_radius_mm": 95}, "The rollers reach the cam axis"),
    ({"roller_length_mm": 130}, "The rollers cross the turret's axis"),
    ({"indexing_angle_deg": 360}, "indexing_angle_deg"),
    ({"samples": 1}, "samples"),
    ({"length_samples": 42}, "length_samples"),
])
async def test_bad_geometry_is_a_422_with_the_rule(client: httpx.AsyncClient, change: dict[str, Any],
                                                    words: str) -> None:
    r = await client.post(PATH, json={**ROLLER_GEAR_EXAMPLE, **change})
    assert r.status_code == 422, r.text
    assert words in r.text


async def test_an_unknown_curve_is_a_404_naming_it(client: httpx.AsyncClient) -> None:
    r = await client.post(PATH, json={**ROLLER_GEAR_EXAMPLE, "curve": {"type": "named", "name": "nope"}})
    assert r.status_code == 404 and r.json()["errors"][0]["loc"] == ["body", "curve", "name"]


async def test_too_many_facets_is_a_413_before_the_work() -> None:
    app = create_app(Settings(max_stl_triangles=1000))
    async with httpx.AsyncClient(transport=httpx.ASGITransport(app=app), base_url="http://test") as c:
        r = await c.post(PATH + ".stl", json=ROLLER_GEAR_EXAMPLE)
        assert r.status_code == 413, r.text
        assert "STL facets" in r.text and "samples" in r.text
        assert (await c.post(PATH, json=ROLLER_GEAR_EXAMPLE)).status_code == 200  # JSON has no facets
