"""End to end: a live ``python -m service`` (the CAD kernel loaded as it starts) answers a
toolpath as G-code and the cam as STEP, each within the request deadline of the defaults."""

from __future__ import annotations

import httpx
import pytest

from service.profiles.specs import ROLLER_PROFILE_EXAMPLE
from tests.camcore.export.test_solid import read_step
from tests.toolpath_reference import cutting_polylines, parse_gcode

pytestmark = pytest.mark.e2e


def test_live_server_cuts_and_models_a_cam(base_url: str) -> None:
    with httpx.Client(base_url=base_url, timeout=20) as client:
        r = client.post("/v1/profiles/toolpath", json={"profile": ROLLER_PROFILE_EXAMPLE, "tool_radius_mm": 8,
                                                        "tolerance_mm": 0.005, "side": "groove", "format": "gcode"})
        assert r.status_code == 200, r.text
        assert r.headers["content-type"].startswith("text/x-gcode")
        # two closed paths, one per wall of the track
        polylines = cutting_polylines(parse_gcode(r.text), 0.1)
        assert len(polylines) == 2 and all(abs(p[1] - p[-2]).max() < 1e-6 for p in polylines)
        # the first solid request: the kernel was loaded at start-up, not inside this deadline
        r = client.post("/v1/profiles?format=step", json={"profile": ROLLER_PROFILE_EXAMPLE,
                                                           "solid": {"thickness_mm": 12, "bore_diameter_mm": 20}})
        assert r.status_code == 200, r.text
        solids, volume, _ = read_step(r.content)
        assert solids == 1 and volume > 0
        r = client.post("/v1/motions?format=cam-table", json={"motion": {"segments": [
            {"span_deg": 180, "to": 10}, {"span_deg": 180, "to": 0}]}, "samples": 5})
        assert r.status_code == 200 and r.text.splitlines()[0].startswith("master_deg,slave_mm,")
