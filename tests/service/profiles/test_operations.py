"""/v1/profiles through httpx.ASGITransport (docs/api.md ProfileSpec; Shinzato (1988); valve-cam notes)."""

from __future__ import annotations

import io

import ezdxf
import httpx
import pytest

pytestmark = pytest.mark.anyio

CV = {"type": "named", "name": "constant-velocity"}
# Shinzato 1988, table 1: knife-edge, in-line, base circle Ø30, 20 mm uniform rise over 180°, return over 180°
PAPER = {"follower": {"type": "knife-edge"}, "base_radius_mm": 15,
         "segments": [{"type": "rise", "angle_deg": 180, "lift_mm": 20, "curve": CV},
                      {"type": "return", "angle_deg": 180, "lift_mm": 20, "curve": CV}]}
ROLLER = {"follower": {"type": "roller", "roller_radius_mm": 10}, "base_radius_mm": 40,
          "segments": [{"type": "rise", "angle_deg": 120, "lift_mm": 20, "curve": {"type": "named", "name": "MS"}},
                       {"type": "dwell", "angle_deg": 60},
                       {"type": "return", "angle_deg": 120, "lift_mm": 20},
                       {"type": "dwell", "angle_deg": 60}]}


async def test_paper_table_1_pressure_angles(client: httpx.AsyncClient) -> None:
    r = await client.post("/v1/profiles", json={"profile": PAPER, "cam_angle_deg": [10, 30, 45, 120, 270]})
    assert r.status_code == 200, r.text
    # table 1 (analytic column, 2 decimals): 21.56, 19.15, 17.66, 12.66; numerical column at 270°: −14.29
    assert [round(x, 2) for x in r.json()["pressure_angle_deg"]] == [21.56, 19.15, 17.66, 12.66, -14.29]


async def test_profile_json_columns_and_checks(client: httpx.AsyncClient) -> None:
    r = await client.post("/v1/profiles", json={"profile": ROLLER, "samples": 361})
    assert r.status_code == 200, r.text
    body = r.json()
    for col in ("cam_angle_deg", "lift_mm", "x_mm", "y_mm", "pitch_x_mm", "pitch_y_mm", "pressure_angle_deg",
                "radius_of_curvature_mm"):
        assert len(body[col]) == 361, col
    checks = body["checks"]
    assert checks["convex"] is True and checks["undercut"] is False
    assert 0 < checks["max_pressure_angle_deg"] < 90
    # on the dwell after the rise the roller centre is at Rb + Rr + h = 70 mm from the cam centre
    i = 150
    assert abs((body["pitch_x_mm"][i] ** 2 + body["pitch_y_mm"][i] ** 2) ** 0.5 - 70.0) < 1e-9


async def test_checks_are_kept_by_cam(client: httpx.AsyncClient) -> None:
    """Issue 21: a cam asked again at other samples or as a file reuses its checks (they
    depend on neither); another base radius is another cam and computes its own."""
    cam = {**ROLLER, "base_radius_mm": 41.25}
    before = (await client.get("/health")).json()["caches"]["profile_checks"]
    first = (await client.post("/v1/profiles", json={"profile": cam, "samples": 361})).json()
    again = (await client.post("/v1/profiles", json={"profile": cam, "samples": 17})).json()
    assert (await client.post("/v1/profiles?format=dxf", json={"profile": cam, "samples": 73})).status_code == 200
    other = (await client.post("/v1/profiles", json={"profile": {**cam, "base_radius_mm": 45}, "samples": 17})).json()
    after = (await client.get("/health")).json()["caches"]["profile_checks"]
    assert after["hits"] - before["hits"] == 2 and after["misses"] - before["misses"] == 2
    assert again["checks"] == first["checks"]
    assert other["checks"]["max_pressure_angle_deg"] < first["checks"]["max_pressure_angle_deg"]


async def test_profile_csv_and_contour_downloads(client: httpx.AsyncClient) -> None:
    r = await client.post("/v1/profiles", json={"profile": ROLLER, "samples": 5}, headers={"Accept": "text/csv"})
    assert r.status_code == 200 and r.text.startswith("cam_angle_deg,lift_mm,x_mm,y_mm")
    r = await client.post("/v1/profiles?format=xyz", json={"profile": ROLLER, "samples": 5})
    assert r.status_code == 200 and r.text.split("\n")[0] == "0.0 40.0 0.0"
    r = await client.post("/v1/profiles?format=dxf", json={"profile": ROLLER, "samples": 73})
    assert r.status_code == 200 and r.headers["content-type"] == "application/dxf"
    doc = ezdxf.read(io.StringIO(r.content.decode()))
    polylines = doc.modelspace().query("LWPOLYLINE")
    assert len(polylines) == 1 and polylines[0].closed and len(polylines[0]) == 72  # 73 samples, end = start


async def test_base_circle_for_pressure_angle(client: httpx.AsyncClient) -> None:
    # knife-edge in-line, constant-velocity rise h = 20 mm over β = π: tan φ = (h/β)/(Rb + s) is largest at
    # s = 0, so Rb_min = (h/β)/tan φ_max = (20/π)/tan 30° = 11.0266 mm
    r = await client.post("/v1/profiles/base-circle", json={"profile": PAPER, "max_pressure_angle_deg": 30})
    assert r.status_code == 200, r.text
    import math
    assert math.isclose(r.json()["base_radius_mm"], 20 / math.pi / math.tan(math.radians(30)), rel_tol=1e-8)
    assert r.json()["active_constraint"] == "pressure_angle"


async def test_bezier_lift_for_a_flat_faced_follower(client: httpx.AsyncClient) -> None:
    prof = {"follower": {"type": "flat-faced"}, "base_radius_mm": 30,
            "lift": {"type": "bezier", "control_points": [[0, 0], [90, 0], [180, 10], [270, 0], [360, 0]]}}
    r = await client.post("/v1/profiles", json={"profile": prof, "samples": 37})
    assert r.status_code == 200, r.text
    body = r.json()
    assert body["pressure_angle_deg"] == [0.0] * 37  # a face perpendicular to the motion
    assert "contact_offset_mm" in body and body["checks"]["face_width_mm"] > 0


@pytest.mark.parametrize("profile, words", [
    ({**PAPER, "segments": PAPER["segments"][:1]}, "must add to 360°"),
    ({**ROLLER, "follower": {"type": "roller"}}, "roller_radius_mm > 0"),
    ({**PAPER, "follower": {"type": "knife-edge", "offset_mm": 20}}, "offset must be smaller"),
    ({**PAPER, "segments": None}, "as segments, as one lift curve"),
    ({**PAPER, "follower": {"type": "knife-edge", "motion": "oscillating", "arm_length_mm": 50}}, "pivot_distance_mm"),
])
async def test_profile_validation(client: httpx.AsyncClient, profile: dict, words: str) -> None:
    r = await client.post("/v1/profiles", json={"profile": profile})
    assert r.status_code == 422
    assert words in r.json()["detail"]
