"""End to end: the residual-vibration operations on the real uvicorn, called with httpx.Client."""

from __future__ import annotations

import httpx
import pytest

pytestmark = pytest.mark.e2e


def test_live_server_answers_vibration_spectra_indexers_and_the_chart(base_url: str) -> None:
    with httpx.Client(base_url=base_url, timeout=30) as client:
        r = client.post("/v1/curves/vibration", json={"curve": {"type": "named", "name": "cycloid"}, "tau": [1, 2]})
        assert r.status_code == 200, r.text
        residual = r.json()["residual_amplitude"]
        assert abs(residual[0] - 0.5) < 1e-13 and residual[1] < 1e-13  # the undamped cycloid's known values
        r = client.post("/v1/curves/vibration.csv",
                        json={"curve": {"type": "named", "name": "MS"}, "tau_range": {"start": 1, "stop": 5, "samples": 5}})
        assert r.status_code == 200 and r.text.startswith("tau,residual_amplitude,peak_deviation\n")
        assert len(r.text.strip().splitlines()) == 6
        r = client.post("/v1/indexers/vibration",
                        json={"indexer": {"stops": 6, "indexing_angle_deg": 270, "speed_rpm": 60}, "inertia_kgm2": 2.25,
                              "stiffness_nm_rad": 2e5, "damping_ratio": 0.05, "tolerance_arcsec": 10, "samples": 11})
        assert r.status_code == 200, r.text
        assert abs(r.json()["natural_frequency_hz"] - 47.4508) < 1e-4 and len(r.json()["table"]["time_s"]) == 11
        r = client.get("/v1/curves/vibration/plot", params={"format": "png", "samples": 101})
        assert r.status_code == 200 and r.content.startswith(b"\x89PNG")
        r = client.post("/v1/curves/vibration", json={"curve": {"type": "named", "name": "MS"}, "tau": [1],
                                                      "damping_ratio": 1})
        assert r.status_code == 422 and r.json()["errors"][0]["loc"] == ["body", "damping_ratio"]
