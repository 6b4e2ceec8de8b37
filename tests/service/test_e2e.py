"""End to end: the real uvicorn on a loopback port, called with httpx.Client.

Starts ``python -m service`` exactly as the README says (settings from the environment),
so the command users run is the one tested.
"""

from __future__ import annotations

from pathlib import Path

import httpx
import pytest

ROOT = Path(__file__).resolve().parents[2]
pytestmark = pytest.mark.e2e


def test_live_server_answers_tables_csv_and_errors(base_url: str) -> None:
    with httpx.Client(base_url=base_url, timeout=10) as client:
        health = client.get("/health").json()
        assert health["status"] == "ok"
        r = client.post("/v1/curves/table", json={"curve": {"type": "named", "name": "MS"}, "samples": 101})
        assert r.status_code == 200
        # INDEXMAN MS table row T = 0.30: S = 0.17789
        assert round(r.json()["s"][30], 5) == 0.17789
        r = client.get("/v1/curves/MS/inverse", params={"s": "0.1833", "method": "table",
                                                        "table_decimals": 5, "format": "csv"})
        assert r.status_code == 200 and r.text.startswith("s,t,v,a\n")
        assert client.get("/v1/curves/nope").status_code == 404
        r = client.post("/v1/curves/table", content=b"{", headers={"content-type": "application/json"})
        assert r.status_code == 400


def test_live_server_resolves_makino_s_cutting_cycle(base_url: str) -> None:
    from service.motions.specs import MAKINO_CYCLE

    with httpx.Client(base_url=base_url, timeout=10) as client:
        r = client.post("/v1/motions", json={"motion": MAKINO_CYCLE, "samples": 37, "speed_rpm": 30})
        assert r.status_code == 200, r.text
        body = r.json()
        # T4 and the cutting stroke as tests/camcore/motion/test_makino_cycle.py derives them independently
        assert abs(body["segments"][1]["solved"]["t4"] - 0.956864006167049) < 1e-12
        assert all(join["continuity"] in ("C2", "C3") for join in body["joins"])
        assert body["time_s"][-1] == 2.0  # 360° at 30 rpm
        r = client.post("/v1/motions?format=csv", json={"motion": MAKINO_CYCLE, "samples": 5})
        assert r.status_code == 200 and r.text.startswith("x_deg,s,v,a,j\n")
        r = client.post("/v1/motions", json={"motion": {**MAKINO_CYCLE, "period_deg": 300}})
        assert r.status_code == 422 and "must add up to period_deg = 300" in r.text
