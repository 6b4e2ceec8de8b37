"""Small tables on a built curve are answered on the event loop, other work in a worker
thread (service/curves/operations.py); the answer is the same bytes either way."""

from __future__ import annotations

from collections.abc import AsyncIterator
from typing import Any

import httpx
import pytest

from service.admission import WorkGate
from service.app import create_app
from service.curves.operations import QUICK_TABLE_ROWS
from service.settings import Settings

pytestmark = pytest.mark.anyio

MS = {"type": "named", "name": "MS"}
BEZIER = {"type": "bezier", "control_points": [[0, 0], [30, 0], [60, 10], [90, 10]]}


@pytest.fixture
def thread_calls(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """The names of the functions the curve routes sent through the work gate (to a thread)."""
    calls: list[str] = []
    real = WorkGate.run

    async def counting(self: WorkGate, request: Any, estimate: Any, func: Any, *args: Any) -> Any:
        calls.append(func.__name__)
        return await real(self, request, estimate, func, *args)

    monkeypatch.setattr(WorkGate, "run", counting)
    return calls


@pytest.fixture
async def uncached_client() -> AsyncIterator[httpx.AsyncClient]:
    """No table cache: every sampled table is computed."""
    app = create_app(Settings(table_cache_size=0))
    async with httpx.AsyncClient(transport=httpx.ASGITransport(app=app), base_url="http://t") as c:
        yield c


@pytest.mark.parametrize("curve", [MS, BEZIER])
@pytest.mark.parametrize("body", [{"samples": 101}, {"t": [0.0, 0.1, 0.5, 0.9, 1.0]}])
async def test_first_request_builds_in_a_thread_then_the_loop_answers(
    uncached_client: httpx.AsyncClient, thread_calls: list[str], curve: dict, body: dict
) -> None:
    request = {"curve": curve, **body}
    if curve is BEZIER and "t" in body:
        request["t"] = [0.0, 10.0, 45.0, 80.0, 90.0]  # a Bezier curve's time is its drive angle
    first = await uncached_client.post("/v1/curves/table", json=request)
    assert first.status_code == 200, first.text
    assert len(thread_calls) == 1  # the curve was not built yet
    for _ in range(2):
        again = await uncached_client.post("/v1/curves/table", json=request)
        assert again.content == first.content
    assert len(thread_calls) == 1  # built now, and the table is small: no more hops
    csv = await uncached_client.post("/v1/curves/table", json=request, headers={"Accept": "text/csv"})
    assert csv.status_code == 200 and csv.headers["content-type"].startswith("text/csv")
    assert len(thread_calls) == 1


async def test_large_tables_still_go_to_a_thread(uncached_client: httpx.AsyncClient, thread_calls: list[str]) -> None:
    small = await uncached_client.post("/v1/curves/table", json={"curve": MS, "samples": QUICK_TABLE_ROWS})
    assert small.status_code == 200 and thread_calls == ["_table"]
    large = await uncached_client.post("/v1/curves/table", json={"curve": MS, "samples": QUICK_TABLE_ROWS + 1})
    assert large.status_code == 200 and thread_calls == ["_table", "_table"]
    many_t = [i / QUICK_TABLE_ROWS for i in range(QUICK_TABLE_ROWS + 1)]
    at_times = await uncached_client.post("/v1/curves/table", json={"curve": MS, "t": many_t})
    assert at_times.status_code == 200 and len(thread_calls) == 3
    # the same rows answered on the loop and in a thread are the same numbers
    assert at_times.json()["s"][:5] == (await uncached_client.post(
        "/v1/curves/table", json={"curve": MS, "t": many_t[:5]})).json()["s"]


@pytest.mark.parametrize("how", ["post", "get"])
async def test_exact_inverse_is_quick_once_the_start_table_is_built(
    uncached_client: httpx.AsyncClient, thread_calls: list[str], how: str
) -> None:
    async def ask(s: list[float], method: str = "exact") -> httpx.Response:
        if how == "post":
            return await uncached_client.post("/v1/curves/inverse", json={"curve": MS, "s": s, "method": method})
        return await uncached_client.get("/v1/curves/MS/inverse", params={"s": s, "method": method})

    # INDEXMAN technical guide, worked example: S = 0.1833 on MS (T ≈ 0.304)
    first = await ask([0.1833])
    assert first.status_code == 200 and thread_calls == ["_inverse"]  # builds the start table
    again = await ask([0.1833])
    assert again.content == first.content and thread_calls == ["_inverse"]
    assert abs(again.json()["t"][0] - 0.304) < 5e-4  # the guide prints T to 3 decimals
    await ask([0.1833], method="table")  # the catalog's method builds its table each time
    assert thread_calls == ["_inverse", "_inverse"]
    many = [i / (QUICK_TABLE_ROWS + 1) for i in range(QUICK_TABLE_ROWS + 1)]
    if how == "post":
        assert (await ask(many)).status_code == 200
        assert len(thread_calls) == 3
    outside = await ask([1.5])  # outside the stroke: the same 422 on the quick path
    assert outside.status_code == 422 and "errors" in outside.json()
