"""GET /v1/curves/{name}/value: one bare number for a spreadsheet cell (docs/api.md,
"Spreadsheet cells"), checked against camcore and the INDEXMAN MS table."""

from __future__ import annotations

import csv
from pathlib import Path

import httpx
import numpy as np
import pytest

import camcore

pytestmark = pytest.mark.anyio

MS = camcore.named_curve("MS")
DATA = Path(__file__).resolve().parents[3] / "tests" / "data"


def _indexman_row(t: float) -> dict[str, float]:
    with (DATA / "indexman_MS.csv").open(encoding="utf-8") as f:
        row = next(r for r in csv.DictReader(f) if float(r["T"]) == t)
    return {k.lower(): float(v) for k, v in row.items()}


async def _value(client: httpx.AsyncClient, **params: object) -> httpx.Response:
    return await client.get("/v1/curves/MS/value", params=params)


async def test_each_quantity_at_t_is_camcore_s_number_in_shortest_form(client: httpx.AsyncClient) -> None:
    want = MS.evaluate(np.array([0.3])).columns()
    published = _indexman_row(0.3)  # INDEXMAN MS table, T = 0.30, printed to 5 decimals
    for quantity in ("s", "v", "a", "j", "q"):
        r = await _value(client, t=0.3, quantity=quantity)
        assert r.status_code == 200, r.text
        assert r.headers["content-type"] == "text/plain; charset=utf-8"
        assert r.text == repr(float(want[quantity][0]))  # the whole body: one number, every digit
        assert round(float(r.text), 5) == published[quantity]
    default = await _value(client, t=0.3)
    assert default.text == repr(float(want["s"][0]))  # quantity defaults to s


async def test_s_gives_t_of_the_exact_inverse(client: httpx.AsyncClient) -> None:
    # INDEXMAN technical guide, worked example, exact method: S = 11/60 → T = 0.3040904
    r = await _value(client, s=11 / 60)
    assert r.status_code == 200 and r.headers["content-type"] == "text/plain; charset=utf-8"
    assert float(r.text) == pytest.approx(0.3040903772609671, abs=1e-13)  # as tests/camcore/indexer/test_indexer.py pins it
    assert float(r.text) == float(MS.inverse(np.array([11 / 60]))[0])
    # the guide's printed S = 0.1833 (4 decimals) is a slightly different point: T = 0.30407
    r = await _value(client, s=0.1833, quantity="t")
    assert r.text == repr(float(MS.inverse(np.array([0.1833]))[0]))
    assert 0.30 < float(r.text) < 0.31  # between the table rows the catalog interpolates


async def test_the_return_stroke(client: httpx.AsyncClient) -> None:
    back = camcore.ReturnCurve(MS)
    r = await _value(client, t=0.3, direction="return")
    assert r.text == repr(float(back.evaluate(np.array([0.3])).s[0]))
    r = await _value(client, s=0.5, direction="return")
    assert r.text == repr(float(back.inverse(np.array([0.5]))[0]))  # MS is symmetric: T = 0.5
    assert float(r.text) == pytest.approx(0.5, abs=1e-12)


@pytest.mark.parametrize("params, field, words", [
    ({"t": 0.3, "s": 0.1}, "s", "not both"),
    ({}, "t", "give t"),
    ({"quantity": "v"}, "t", "give t"),
    ({"s": 0.1, "quantity": "v"}, "quantity", "exact inverse, not v"),
    ({"t": 0.3, "quantity": "t"}, "quantity", "one of s, v, a, j, q"),
    ({"t": 0.3, "quantity": "x"}, "quantity", "Input should be"),
    ({"t": "nan"}, "t", "finite"),
    ({"s": "inf"}, "s", "finite"),
    ({"t": "0,3"}, "t", "valid number"),
])
async def test_bad_queries_answer_422_json_naming_the_field(client: httpx.AsyncClient, params: dict[str, object],
                                                            field: str, words: str) -> None:
    r = await _value(client, **params)
    assert r.status_code == 422 and r.headers["content-type"] == "application/json"
    body = r.json()
    assert [e["loc"] for e in body["errors"]] == [["query", field]]
    assert words in body["errors"][0]["msg"] and words in body["detail"]


async def test_out_of_stroke_and_unknown_curve_stay_json_errors(client: httpx.AsyncClient) -> None:
    r = await _value(client, s=1.5)
    assert r.status_code == 422 and r.headers["content-type"] == "application/json"
    assert "outside the stroke" in r.json()["detail"]
    r = await client.get("/v1/curves/no-such-curve/value", params={"t": 0.3})
    assert r.status_code == 404 and r.headers["content-type"] == "application/json"
    assert "no-such-curve" in r.json()["detail"]


def test_the_openapi_document_declares_text_for_200_and_json_for_errors() -> None:
    from service.app import create_app

    op = create_app().openapi()["paths"]["/v1/curves/{name}/value"]["get"]
    assert op["operationId"] == "getCurveValue"
    assert list(op["responses"]["200"]["content"]) == ["text/plain"]
    assert op["responses"]["200"]["content"]["text/plain"]["schema"] == {"type": "string"}
    for status in ("404", "422"):
        assert list(op["responses"][status]["content"]) == ["application/json"]
