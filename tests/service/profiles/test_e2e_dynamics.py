"""End to end: follower dynamics from a real ``python -m service`` on a loopback port, with httpx.Client."""

from __future__ import annotations

import httpx
import pytest

from tests.service.test_charts import check_png

pytestmark = pytest.mark.e2e

#: the README's request: a roller follower on a cycloid cam (rise 120°, dwell 60°, return 180°) at 700 rpm
BODY = {"profile": {"follower": {"type": "roller", "roller_radius_mm": 10}, "base_radius_mm": 40,
                    "segments": [{"type": "rise", "angle_deg": 120, "lift_mm": 20}, {"type": "dwell", "angle_deg": 60},
                                 {"type": "return", "angle_deg": 180, "lift_mm": 20}]},
        "speed_rpm": 700, "mass_kg": 0.5, "spring_rate_n_mm": 2, "preload_n": 30, "safety_margin_n": 5,
        "roller": {"width_mm": 12}}


def test_live_server_answers_follower_dynamics(base_url: str) -> None:
    with httpx.Client(base_url=base_url, timeout=20) as client:
        r = client.post("/v1/profiles/dynamics", json=BODY)
        assert r.status_code == 200, r.text
        summary = r.json()["summary"]
        # tests/camcore/profile/test_dynamics.py derives the jump speed of this cam by hand (mpmath): 623.14136 rpm
        assert summary["jump_speed_rpm"] == pytest.approx(623.1413590659018, rel=1e-9)
        assert summary["separates"] is True and summary["min_preload_n"] > 30
        r = client.post("/v1/profiles/dynamics/table.csv", json={**BODY, "samples": 5})
        assert r.status_code == 200 and r.text.startswith("cam_angle_deg,time_s,lift,velocity,acceleration,")
        assert len(r.text.strip().splitlines()) == 6
        r = client.get("/v1/profiles/dynamics/plot", params={
            "speed_rpm": 700, "mass_kg": 0.5, "spring_rate_n_mm": 2, "preload_n": 30, "safety_margin_n": 5,
            "return_deg": 180, "format": "png"})
        assert r.status_code == 200 and r.headers["content-type"] == "image/png"
        check_png(r.content)
        r = client.post("/v1/profiles/dynamics", json={**BODY, "mass_kg": 0})
        assert r.status_code == 422 and r.json()["errors"][0]["loc"] == ["body", "mass_kg"]
