"""Characteristic values and table ends as the API answers them.

``am_abs`` / ``t_am_abs`` give the largest |A| with its T like every other extreme (``am``
stays, the bare number); a table's first and last rows are the law's end conditions
exactly (INDEXMAN MS table: T = 1 → S = 1, V = 0, A = 0).
"""

from __future__ import annotations

import csv
import io

import httpx
import pytest

pytestmark = pytest.mark.anyio


async def test_characteristics_report_am_abs_with_its_time(client: httpx.AsyncClient) -> None:
    r = await client.post("/v1/curves/characteristics", json={"curve": {"type": "named", "name": "TR"}})
    assert r.status_code == 200, r.text
    c = r.json()
    assert c["am_abs"] == c["am"] == max(c["am_pos"], -c["am_neg"])
    # trapecloid: Amp = Amm by the law, reached first at Ta = 1/8 (INDEXMAN TR, Ta = 1/8)
    assert c["t_am_abs"] == 0.125
    # the schema lists it like every other extreme
    schema = (await client.get("/openapi.json")).json()["components"]["schemas"]["CharacteristicsAnswer"]
    assert {"am", "am_abs", "t_am_abs"} <= set(schema["required"])


@pytest.mark.parametrize("direction", ["rise", "return"])
async def test_table_ends_are_exact_in_json_and_csv(client: httpx.AsyncClient, direction: str) -> None:
    body = {"curve": {"type": "named", "name": "MS", "direction": direction}, "samples": 101}
    table = (await client.post("/v1/curves/table", json=body)).json()
    s_end = 1.0 if direction == "rise" else 0.0
    assert [table[k][-1] for k in "sva"] == [s_end, 0.0, 0.0]
    assert [table[k][0] for k in "sva"] == [1.0 - s_end, 0.0, 0.0]
    text = (await client.post("/v1/curves/table", json=body, headers={"Accept": "text/csv"})).text
    last = list(csv.DictReader(io.StringIO(text)))[-1]
    # the CSV cell is the plain text a spreadsheet shows: "0.0", not "2.7755575615628914e-16" or "-0.0"
    assert (last["t"], last["s"], last["v"], last["a"]) == ("1.0", repr(s_end), "0.0", "0.0")
