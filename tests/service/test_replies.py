"""Replies kept by request (service.replies): a request answered before from its operation's own cache
is answered again with the same bytes before FastAPI solves its parameters; anything else is computed as
before, and the operations' cache settings still decide what is kept."""

from __future__ import annotations

import json

import httpx
import pytest

from service.replies import KEY_MAX_BYTES
from service.settings import Settings
from tests.service.apps import app_client

TABLE = {"curve": {"type": "named", "name": "MS"}, "samples": 101}
SIZING = {"indexer": {"stops": 8, "indexing_angle_deg": 240, "speed_rpm": 45, "curve": {"type": "named", "name": "MS"}},
          "load": {"parts": [{"shape": "disc", "mass_kg": 20, "diameter_mm": 400}]}}
PROFILE = {"profile": {"follower": {"type": "roller", "roller_radius_mm": 10}, "base_radius_mm": 40,
                       "segments": [{"type": "rise", "angle_deg": 180, "lift_mm": 20},
                                    {"type": "return", "angle_deg": 180, "lift_mm": 20}]}, "samples": 37}

pytestmark = pytest.mark.anyio


async def _caches(client: httpx.AsyncClient) -> dict[str, dict[str, int]]:
    caches: dict[str, dict[str, int]] = (await client.get("/health")).json()["caches"]
    return caches


def _same_reply(a: httpx.Response, b: httpx.Response) -> bool:
    """Status, body and every header but the per-request timing."""
    def headers(r: httpx.Response) -> dict[str, str]:
        return {k: v for k, v in r.headers.items() if k != "server-timing"}
    return a.status_code == b.status_code and a.content == b.content and headers(a) == headers(b)


async def test_a_cached_answer_asked_again_is_the_kept_reply() -> None:
    async with app_client(Settings()) as client:
        for path, body in (("/v1/curves/table", TABLE), ("/v1/curves/table?format=csv", TABLE),
                           ("/v1/indexers/sizing", SIZING)):
            computed = await client.post(path, json=body)  # computed: nothing kept yet
            from_cache = await client.post(path, json=body)  # the operation's cache: its reply is kept
            before = (await _caches(client))["replies"]
            kept = [await client.post(path, json=body) for _ in range(3)]
            after = (await _caches(client))["replies"]
            assert computed.status_code == 200, computed.text
            assert all(_same_reply(computed, r) for r in (from_cache, *kept)), path
            assert after["hits"] - before["hits"] == 3, path
        assert (await _caches(client))["replies"]["size"] == 3


async def test_a_different_request_is_never_given_a_kept_reply() -> None:
    async with app_client(Settings()) as client:
        for _ in range(3):
            await client.post("/v1/curves/table", json=TABLE)
        before = (await _caches(client))["replies"]
        # another query, another Accept, another body, the same body written otherwise: each its own answer
        csv = await client.post("/v1/curves/table?format=csv", json=TABLE)
        accept = await client.post("/v1/curves/table", json=TABLE, headers={"Accept": "text/csv"})
        other = await client.post("/v1/curves/table", json={**TABLE, "samples": 11})
        spaced = await client.post("/v1/curves/table", content=json.dumps(TABLE, indent=1),
                                   headers={"Content-Type": "application/json"})
        # the same bytes without a Content-Type: not JSON to FastAPI, 400 as without kept replies
        untyped = await client.post("/v1/curves/table", content=json.dumps(TABLE, separators=(",", ":")),
                                    headers={"Content-Type": ""})
        after = (await _caches(client))["replies"]
        assert after["hits"] == before["hits"]
        assert csv.headers["content-type"].startswith("text/csv") and len(other.json()["t"]) == 11
        assert accept.status_code == 200 and spaced.status_code == 200 and untyped.status_code == 400
        assert spaced.content == (await client.post("/v1/curves/table", json=TABLE)).content


async def test_the_operations_cache_settings_decide_what_is_kept() -> None:
    # no table cache: every table is computed, none kept (the bench's uncached server relies on it)
    async with app_client(Settings(table_cache_size=0)) as client:
        answers = [await client.post("/v1/curves/table", json=TABLE) for _ in range(4)]
        caches = await _caches(client)
        assert caches["replies"]["size"] == 0 and caches["replies"]["hits"] == 0
        assert len({r.content for r in answers}) == 1
    # no kept replies: the operation's own cache answers every time, the same bytes
    async with app_client(Settings(reply_cache_size=0)) as client:
        answers = [await client.post("/v1/curves/table", json=TABLE) for _ in range(4)]
        caches = await _caches(client)
        assert caches["replies"]["size"] == 0 and caches["tables"]["hits"] == 3
        assert len({r.content for r in answers}) == 1


async def test_answers_computed_every_time_and_errors_are_not_kept() -> None:
    async with app_client(Settings()) as client:
        profiles = [await client.post("/v1/profiles", json=PROFILE) for _ in range(3)]  # no cache of its own
        bad = [await client.post("/v1/curves/table", json={**TABLE, "samples": 1}) for _ in range(3)]
        # a sizing the sizing cache keeps, its body over the key's bound (400 parts): computed, kept, not a reply
        large = {**SIZING, "load": {"parts": SIZING["load"]["parts"] * 400}}  # type: ignore[index]
        assert len(json.dumps(large, separators=(",", ":"))) > KEY_MAX_BYTES  # as httpx sends it
        larges = [await client.post("/v1/indexers/sizing", json=large) for _ in range(3)]
        caches = await _caches(client)
        assert [r.status_code for r in profiles] == [200] * 3 and len({r.content for r in profiles}) == 1
        assert [r.status_code for r in bad] == [422] * 3
        assert [r.status_code for r in larges] == [200] * 3 and len({r.content for r in larges}) == 1
        assert caches["sizings"]["hits"] == 2
        assert caches["replies"]["size"] == 0 and caches["replies"]["hits"] == 0
