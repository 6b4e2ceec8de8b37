"""The characteristic values' acceleration jumps and the catalog's Qm conventions over HTTP (issue 22 item 3)."""

from __future__ import annotations

import httpx
import pytest

pytestmark = pytest.mark.anyio


async def test_constant_acceleration_answers_its_jumps(client: httpx.AsyncClient) -> None:
    r = await client.post("/v1/curves/characteristics", json={"curve": {"type": "named", "name": "constant-acceleration"}})
    assert r.status_code == 200, r.text
    ch = r.json()["characteristics"] if "characteristics" in r.json() else r.json()
    assert ch["a_jumps"] == [{"t": 0.0, "before": 0.0, "after": 4.0}, {"t": 0.5, "before": 4.0, "after": -4.0},
                             {"t": 1.0, "before": -4.0, "after": 0.0}]
    assert ch["jm_pos"] == 0.0  # the finite jerk is zero: the jumps are the whole story


async def test_the_catalog_says_which_qm_is_which(client: httpx.AsyncClient) -> None:
    body = (await client.get("/v1/curves")).json()
    assert set(body["conventions"]) == {"qm", "qm_raw"}
    assert "A·V/Am" in body["conventions"]["qm"] and "Makino" in body["conventions"]["qm_raw"]
    cycloid = next(c for c in body["curves"] if c["id"] == "cycloid")["characteristics"]
    assert round(cycloid["qm_raw_pos"], 2) == 8.16 and round(cycloid["qm_pos"], 2) == 1.30
    assert cycloid["a_jumps"] == []
