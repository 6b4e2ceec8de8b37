"""The cell form (``GET /v1/cell/{operation}``, service.operations.cells): every POST computation
by GET, one field of its answer as text.

The independent side of each check is the operation's own POST with the same body: the cell's
text must be that JSON answer's value, to the last digit (both are the same float; the text is
its shortest round-trip form), and a body the POST refuses must be refused by the cell with
the same messages, at the query parameter the user wrote.
"""

from __future__ import annotations

import copy
from collections.abc import Iterator
from typing import Any
from urllib.parse import urlencode

import httpx
import pytest

from service.app import create_app
from service.operations import Operation
from service.operations.cells import (
    ERROR_STATUS_HEADER,
    OPERATION_ID,
    RESERVED,
    cell_operations,
    cell_text,
    pick,
    query_value,
    request_body,
)
from service.registry import OPERATIONS

pytestmark = pytest.mark.anyio

CELLS = cell_operations(OPERATIONS)
CASES = [(op, name) for op in CELLS for name in op.examples]


def query_fields(body: Any, prefix: str = "") -> Iterator[tuple[str, str]]:
    """The documented naming, written independently of the service's reader: a JSON body as
    query parameters (dots between names, list indices), each value as its JSON text."""
    if isinstance(body, dict):
        for key, value in body.items():
            yield from query_fields(value, f"{prefix}{key}.")
    elif isinstance(body, list):
        for index, value in enumerate(body):
            yield from query_fields(value, f"{prefix}{index}.")
    elif isinstance(body, bool):
        yield prefix[:-1], "true" if body else "false"
    elif body is None:
        yield prefix[:-1], "null"
    else:
        yield prefix[:-1], str(body)  # str of a Python int/float is JSON's number text


def leaves(answer: Any, prefix: str = "") -> Iterator[tuple[str, Any]]:
    """Every picked path of a JSON answer with its value: scalars, and lists of scalars (columns)."""
    if isinstance(answer, dict):
        for key, value in answer.items():
            yield from leaves(value, f"{prefix}{key}.")
    elif isinstance(answer, list) and any(isinstance(item, dict | list) for item in answer):
        for index, item in enumerate(answer[:1]):
            yield from leaves(item, f"{prefix}{index}.")
    else:
        yield prefix[:-1], answer


def as_text(value: Any) -> str:
    """What a cell shows for a JSON value, spelled out here from the documented rules."""
    if isinstance(value, list):
        return "".join(as_text(item) + "\n" for item in value)
    if value is None:
        return ""
    if isinstance(value, bool):
        return "TRUE" if value else "FALSE"
    return value if isinstance(value, str) else repr(value)


@pytest.fixture(scope="module")
async def client() -> Iterator[httpx.AsyncClient]:
    async with httpx.AsyncClient(transport=httpx.ASGITransport(app=create_app()), base_url="http://t") as c:
        yield c


def test_every_post_computation_has_a_cell_form_and_nothing_else() -> None:
    posts = {op.id for op in OPERATIONS if op.method == "POST"}
    assert {op.id for op in CELLS} == posts
    assert len(CELLS) >= 17
    for op in CELLS:
        assert op.request is not None and not set(RESERVED) & set(op.request.model_fields)


def test_the_document_has_one_cell_operation_listing_every_computation() -> None:
    doc = create_app().openapi()
    cells = [(path, item) for path, methods in doc["paths"].items() for item in methods.values()
             if item.get("operationId") == OPERATION_ID]
    assert len(cells) == 1 and cells[0][0] == "/v1/cell/{operation}"
    params = {p["name"]: p for p in cells[0][1]["parameters"]}
    assert params["operation"]["schema"]["enum"] == [op.id for op in CELLS]
    assert params["fields"]["style"] == "form" and params["fields"]["explode"] is True
    assert set(params) == {"operation", "pick", "errors", "fields"}


@pytest.mark.parametrize(("op", "example"), CASES, ids=[f"{op.id}-{name}" for op, name in CASES])
async def test_a_cell_gives_the_json_answers_value_to_the_last_digit(
        client: httpx.AsyncClient, op: Operation, example: str) -> None:
    body = copy.deepcopy(op.examples[example]["value"])
    posted = await client.post(op.path, json=body)
    assert posted.status_code == 200, posted.text
    answer = posted.json()
    fields = list(query_fields(body))
    picked = list(leaves(answer))
    scalars = [(path, value) for path, value in picked if not isinstance(value, list)]
    columns = [(path, value) for path, value in picked if isinstance(value, list)]
    # a scalar, a column and one item of that column: the three kinds a cell answers
    chosen = scalars[-1:] + columns[:1] + [(f"{path}.{len(value) // 2}", value[len(value) // 2])
                                           for path, value in columns[:1] if value]
    assert chosen
    for path, value in chosen:
        got = await client.get(f"/v1/cell/{op.id}", params=[*fields, ("pick", path)])
        assert got.status_code == 200, (path, got.text)
        assert got.headers["content-type"] == "text/plain; charset=utf-8"
        assert got.text == as_text(value), path


def test_query_values_are_read_as_json_reads_them() -> None:
    assert query_value("6") == 6 and isinstance(query_value("6"), int)
    assert query_value("0.1833") == 0.1833 and query_value("-2.5e-3") == -0.0025
    assert query_value("true") is True and query_value("null") is None
    assert query_value('"6"') == "6"  # a quoted string stays text
    assert query_value("MS") == "MS" and query_value("3-4-5") == "3-4-5"
    assert query_value("0,1833") == "0,1833"  # a decimal comma is text: the model refuses it
    assert query_value("NaN") == "NaN" and query_value("1e999x") == "1e999x"


def test_fields_become_the_body_they_name() -> None:
    body = request_body([("load.parts.1.mass_kg", "5"), ("load.parts.0.mass_kg", "50"), ("indexer.curve.name", "MS"),
                         ("motor.rated_torque_nm", ""), ("x_deg.0", "150")])
    assert body == {"load": {"parts": [{"mass_kg": 50}, {"mass_kg": 5}]}, "indexer": {"curve": {"name": "MS"}},
                    "x_deg": [150]}


@pytest.mark.parametrize(("fields", "where", "rule"), [
    ([("x_deg.0", "1"), ("x_deg.2", "3")], "x_deg", "without a gap"),
    ([("load.parts.0.mass_kg", "1"), ("load.parts.a", "3")], "load.parts", "by their index alone"),
    ([("load", "5"), ("load.parts.0.mass_kg", "1")], "load.parts.0.mass_kg", "as a value and as an object"),
    ([("load.parts.0.mass_kg", "1"), ("load", "5")], "load", "as a value and as an object"),
    ([("a..b", "1")], "a..b", "single dots"),
    ([("a", "1"), ("a", "2")], "a", "given twice"),
])
def test_fields_that_name_no_body_are_refused_at_the_parameter(fields: list[tuple[str, str]], where: str,
                                                               rule: str) -> None:
    from fastapi.exceptions import RequestValidationError
    with pytest.raises(RequestValidationError) as caught:
        request_body(fields)
    (error,) = caught.value.errors()
    assert error["loc"] == ("query", where) and rule in error["msg"]


def test_pick_walks_names_indices_and_columns_of_rows() -> None:
    answer = {"a": 1.5, "t": {"x": [1.0, 2.0]}, "rows": [{"n": 1, "m": "p"}, {"n": 2, "m": "q"}], "ok": True}
    assert pick(answer, "t.x.1") == 2.0 and pick(answer, "rows.1.m") == "q"
    assert pick(answer, "rows.n") == [1, 2]  # one field of every row: a column
    assert cell_text(pick(answer, "t.x"), "t.x") == "1.0\n2.0\n"
    assert cell_text(True, "ok") == "TRUE" and cell_text(None, "z") == "" and cell_text(0.1, "a") == "0.1"
    from fastapi.exceptions import RequestValidationError
    for path, rule in [("b", "no field 'b'"), ("t.x.2", "past its end"), ("a.b", "names nothing"),
                       ("rows.z", "names nothing")]:
        with pytest.raises(RequestValidationError) as caught:
            pick(answer, path)
        assert rule in caught.value.errors()[0]["msg"], path
    with pytest.raises(RequestValidationError):
        cell_text(pick(answer, "t"), "t")  # an object: pick one of its fields
    with pytest.raises(RequestValidationError):
        cell_text(pick(answer, "rows"), "rows")


INVALID = [
    # (operation, example, change to the body, the field a user must fix)
    ("sizeIndexer", "guide", lambda b: b["indexer"].update(stops=0), "indexer.stops"),
    ("sizeIndexer", "guide", lambda b: b["load"]["parts"][0].update(mass_kg=-5), "load.parts.0.mass_kg"),
    ("sizeIndexer", "guide", lambda b: b["indexer"].update(cycle_time_s=1), "indexer"),  # a cross-field rule
    ("computeProfile", "roller", lambda b: b["profile"].update(base_radius_mm=0), "profile.base_radius_mm"),
]


@pytest.mark.parametrize(("op_id", "example", "change", "where"), INVALID, ids=[c[3] for c in INVALID])
async def test_a_spec_rule_refuses_the_cell_as_it_refuses_the_body(
        client: httpx.AsyncClient, op_id: str, example: str, change: Any, where: str) -> None:
    op = next(op for op in CELLS if op.id == op_id)
    body = copy.deepcopy(op.examples[example]["value"])
    change(body)
    posted = await client.post(op.path, json=body)
    cell = await client.get(f"/v1/cell/{op.id}", params=[*query_fields(body), ("pick", "x")])
    assert posted.status_code == cell.status_code == 422
    want = [(".".join(str(p) for p in e["loc"][1:]), e["msg"]) for e in posted.json()["errors"]]
    got = [(e["loc"][1], e["msg"]) for e in cell.json()["errors"]]
    assert got == want and any(loc == where for loc, _ in got), (got, want)
    # as text for a spreadsheet: 200, one line naming the field and the rule, the status in a header
    text = await client.get(f"/v1/cell/{op.id}",
                            params=[*query_fields(body), ("pick", "x"), ("errors", "text")])
    assert text.status_code == 200 and text.headers[ERROR_STATUS_HEADER] == "422"
    assert text.text.startswith("Error 422: ") and f"{where}: " in text.text and "\n" not in text.text


async def test_refusals_that_are_not_about_the_spec_keep_their_status(client: httpx.AsyncClient) -> None:
    unknown = await client.get("/v1/cell/sizeIndexr?pick=x")
    assert unknown.status_code == 422 and "Did you mean: sizeIndexer" in unknown.json()["detail"]
    curve = {"curve.type": "named", "curve.name": "MZ", "pick": "vm"}
    missing = await client.get("/v1/cell/getCurveCharacteristics?" + urlencode(curve))
    assert missing.status_code == 404  # the catalog has no such curve, as POST answers
    as_text_ = await client.get("/v1/cell/getCurveCharacteristics?" + urlencode({**curve, "errors": "text"}))
    assert as_text_.status_code == 200 and as_text_.headers[ERROR_STATUS_HEADER] == "404"
    assert as_text_.text.startswith("Error 404: curve.name: No curve named 'MZ'")
    no_pick = await client.get("/v1/cell/getCurveCharacteristics?curve.type=named&curve.name=MS")
    assert no_pick.status_code == 422 and "its fields: " in no_pick.json()["errors"][0]["msg"]
    over = await client.get("/v1/cell/sampleCurve?" + urlencode(
        {"curve.type": "named", "curve.name": "MS", "samples": 10**9, "pick": "s.0"}))
    assert over.status_code in (413, 422)  # the operation's own bound, before any work
    too_many = await client.get("/v1/cell/sampleCurve?" + urlencode([(f"t.{i}", "0.5") for i in range(201)]))
    assert too_many.status_code == 422 and "at most 200 fields" in too_many.text
