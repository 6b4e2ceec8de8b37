"""End to end: the barrel cam on the real uvicorn, called with httpx.Client."""

from __future__ import annotations

import math

import httpx
import pytest

pytestmark = pytest.mark.e2e

BARREL = {"pitch_radius_mm": 50, "roller_radius_mm": 10, "roller_length_mm": 12,
          "segments": [{"type": "rise", "angle_deg": 120, "lift_mm": 30}, {"type": "dwell", "angle_deg": 60},
                       {"type": "return", "angle_deg": 120, "lift_mm": 30}, {"type": "dwell", "angle_deg": 60}],
          "samples": 13}


def test_live_server_answers_the_barrel_cam(base_url: str) -> None:
    with httpx.Client(base_url=base_url, timeout=30) as client:
        r = client.post("/v1/cams/barrel", json=BARREL)
        assert r.status_code == 200, r.text
        answer = r.json()
        # the cycloid's steepest slope, 2h/β = 60/(2π/3) mm/rad, over R = 50 mm: the checks refine to 1e-9 rad
        assert abs(answer["checks"]["max_pressure_angle_deg"] - math.degrees(math.atan(60 / (2 * math.pi / 3) / 50))) < 1e-9
        assert len(answer["flanks"]["upper"]["x_mm"]) == 13 and len(answer["flanks"]["upper"]["x_mm"][0]) == 5
        r = client.post("/v1/cams/barrel.csv", json=BARREL)
        assert r.status_code == 200 and r.text.startswith("cam_angle_deg,lift_mm,u_mm,y_mm,")
        assert len(r.text.strip().splitlines()) == 14
        r = client.post("/v1/cams/barrel", json={**BARREL, "roller_length_mm": 100})
        assert r.status_code == 422 and "must be less than twice pitch_radius_mm" in r.text


#: the README's roller-gear example, as written there
ROLLER_GEAR = {"stops": 8, "center_distance_mm": 100, "roller_pitch_radius_mm": 60, "roller_radius_mm": 10,
               "roller_length_mm": 20, "indexing_angle_deg": 120}


def test_live_server_answers_the_roller_gear_cam_and_its_rib(base_url: str) -> None:
    with httpx.Client(base_url=base_url, timeout=30) as client:
        r = client.post("/v1/cams/roller-gear", json=ROLLER_GEAR)
        assert r.status_code == 200, r.text
        answer = r.json()
        assert len(answer["cam_angle_deg"]) == 361 and len(answer["flanks"]["forward"]["x_mm"][0]) == 5
        assert answer["checks"]["undercut"] is False
        assert 40 < answer["checks"]["max_pressure_angle_deg"] < 45
        r = client.post("/v1/cams/roller-gear?format=stl", json=ROLLER_GEAR)
        assert r.status_code == 200 and r.headers["content-type"] == "model/stl"
        # 360 × 10 quads and two caps of 4 quads, two facets each, 50 bytes per facet after the 84-byte head
        facets = 2 * 360 * 10 + 4 * 4
        assert int.from_bytes(r.content[80:84], "little") == facets and len(r.content) == 84 + 50 * facets
