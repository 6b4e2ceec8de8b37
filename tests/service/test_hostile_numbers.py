"""Hostile numbers in every request example: each number of each operation's examples (the
registry's, service.registry.OPERATIONS, and the examples of a format that needs more in its body)
replaced, one at a time, by NaN, ±Infinity, 1e309 (over the largest double), 1e-310 and 5e-324
(subnormal), 0, its negative and 1e30.

Source: issue 34, point 4 ("the last 500s"): such values answered 500 (a kernel's construction
error, a division by an underflowed quotient) or a 422 naming no field. What must hold for every
one of these requests, in-process over ASGI on one app (its caches warm as a worker's do):

- the answer is 200 or 4xx, never 5xx;
- a 4xx names the field: its first error's ``loc`` goes beyond ``["body"]`` / ``["query"]``,
  except a body that is not JSON at all (NaN, Infinity: JSON has no such numbers; 400 naming the
  body as a whole, the parser's position in the sentence);
- each request is answered within ``BOUND_S``.

The body is written as text, so the tokens reach the parser as a client would send them
(``json.dumps`` would write 1e309 as ``Infinity``). All 3 900-odd variants run, in a fixed order.
"""

from __future__ import annotations

import copy
import json
import time
from collections.abc import AsyncIterator, Iterator
from typing import Any

import httpx
import jsonschema
import pytest

from service.app import create_app
from service.operations import Format, Operation
from service.registry import OPERATIONS
from service.settings import Settings
from service.specs import NOT_SUBNORMAL

pytestmark = pytest.mark.anyio

#: the JSON text of each hostile value; "-" is the original number negated
HOSTILE: tuple[str, ...] = ("NaN", "Infinity", "-Infinity", "1e309", "1e-310", "5e-324", "0", "-", "1e30")
#: not JSON numbers: a body holding one is not JSON (400), a query value holding one is a 422
NOT_JSON = {"NaN", "Infinity", "-Infinity"}
#: seconds a request may take: the work deadline (1.5 s) from admission, plus parsing, converting,
#: estimating and encoding outside it, on a 2-core machine that the quick tier shares with a second
#: test process (the slowest measured alone: see docs/robustness.md, "Hostile numbers")
BOUND_S = Settings().work_deadline_s + 1.5

Path = tuple[str | int, ...]


def numbers(value: Any, path: Path = ()) -> Iterator[tuple[Path, float]]:
    """Every number in a JSON value (not booleans), with its path."""
    if isinstance(value, bool):
        return
    if isinstance(value, int | float):
        yield path, value
    elif isinstance(value, dict):
        for key, item in value.items():
            yield from numbers(item, (*path, key))
    elif isinstance(value, list):
        for i, item in enumerate(value):
            yield from numbers(item, (*path, i))


def replaced(value: Any, path: Path, token: str) -> Any:
    """The value with a marker at ``path`` (written as ``token`` by :func:`text`)."""
    out = copy.deepcopy(value)
    holder = out
    for key in path[:-1]:
        holder = holder[key]
    holder[path[-1]] = MARK
    return out


MARK = "\x00hostile\x00"


def text(value: Any, token: str) -> str:
    return json.dumps(value).replace(json.dumps(MARK), token)


def examples(operation: Operation) -> Iterator[tuple[str, Format | None, Any]]:
    """(name, format, value): the operation's examples (its default format), and a format's own."""
    for name, ex in operation.examples.items():
        yield name, None, ex["value"]
    for fmt_name, exs in operation.format_examples.items():
        for name, ex in exs.items():
            yield f"{name}.{fmt_name}", operation.format(fmt_name), ex["value"]


def variants(operation: Operation) -> Iterator[tuple[str, str, dict[str, Any]]]:
    """(what, the token, httpx request arguments) for every number of every example and every hostile value."""
    for name, fmt, value in examples(operation):
        url = operation.path if fmt is None else operation.twin_path(fmt)
        for path, number in numbers(value):
            for hostile in HOSTILE:
                token = json.dumps(-number) if hostile == "-" else hostile
                what = f"{name}: {'.'.join(map(str, path))} = {token}"
                if operation.method == "POST":
                    yield what, token, {"method": "POST", "url": url, "content": text(replaced(value, path, token), token),
                                 "headers": {"Content-Type": "application/json"}}
                    continue
                query = {k: str(v) for k, v in value.items()}
                query[str(path[0])] = token
                target = url
                for param in operation.path_parameters:
                    target = target.replace("{" + param + "}", query.pop(param))
                yield what, token, {"method": "GET", "url": target, "params": query}


@pytest.fixture(scope="module")
async def client() -> AsyncIterator[httpx.AsyncClient]:
    async with httpx.AsyncClient(transport=httpx.ASGITransport(app=create_app()), base_url="http://testserver",
                                 timeout=60) as c:
        yield c


def problem(r: httpx.Response, elapsed_s: float, not_json: bool) -> str | None:
    """What is wrong with an answer, or None."""
    if elapsed_s > BOUND_S:
        return f"took {elapsed_s:.2f} s"
    if r.status_code == 200:
        return None
    if not 400 <= r.status_code < 500:
        return f"{r.status_code}: {r.text[:300]}"
    body = r.json()
    if r.status_code == 400 and not_json:
        return None  # the body is not JSON: there is no field to name
    errors = body.get("errors") or []
    if not errors or len(errors[0]["loc"]) < 2:
        return f"{r.status_code} names no field: {body['detail'][:300]}"
    return None


@pytest.mark.parametrize("operation", [op for op in OPERATIONS if any(True for _ in variants(op))],
                         ids=lambda op: op.id)
async def test_hostile_numbers_answer_200_or_a_4xx_naming_the_field(client: httpx.AsyncClient,
                                                                   operation: Operation) -> None:
    found = []
    for what, token, request in variants(operation):
        start = time.perf_counter()
        try:
            r = await client.request(**request)
        except Exception as exc:  # noqa: BLE001 - through the transport: a warning (pytest makes it an error), a bug
            found.append(f"{what} → raised {type(exc).__name__}: {exc}")
            continue
        elapsed = time.perf_counter() - start
        wrong = problem(r, elapsed, operation.method == "POST" and token in NOT_JSON)
        if wrong:
            found.append(f"{what} → {wrong}")
    assert not found, f"{len(found)} of the hostile requests:\n" + "\n".join(found)


async def test_a_subnormal_number_is_refused_at_its_index_and_the_schema_says_so(client: httpx.AsyncClient) -> None:
    # the rule every spec keeps (service.specs.SUBNORMAL_RULE), located down to a list's item
    body = '{"curve": {"type": "named", "name": "MS"}, "s": [0.1, -1e-310, 0.0]}'
    r = await client.post("/v1/curves/inverse", content=body, headers={"Content-Type": "application/json"})
    assert r.status_code == 422, r.text
    assert r.json()["errors"][0]["loc"] == ["body", "s", 1] and "subnormal" in r.json()["detail"]
    # 0 and the smallest normal double pass the rule (0.0 is not on the stroke's edge: S(0) = 0)
    ok = '{"curve": {"type": "named", "name": "MS"}, "s": [0.0, 2.2250738585072014e-308]}'
    assert (await client.post("/v1/curves/inverse", content=ok, headers={"Content-Type": "application/json"})
            ).status_code == 200
    # the document states it on the field's items, so a schema-driven client builds no such body
    items = create_app().openapi()["components"]["schemas"]["InverseRequest"]["properties"]["s"]["items"]
    assert items["not"] == NOT_SUBNORMAL["not"]
    assert not jsonschema.Draft202012Validator(items).is_valid(-1e-310)
    assert jsonschema.Draft202012Validator(items).is_valid(0.0)


@pytest.mark.parametrize(("path", "change", "loc"), [
    # camcore's geometry checks, called by the specs' validators, name the argument they are about
    ("/v1/cams/parallel", {"center_distance_mm": 70}, ["body", "center_distance_mm"]),
    ("/v1/cams/parallel", {"roller_radius_mm": 0.01}, ["body", "roller_radius_mm"]),
    ("/v1/cams/parallel", {"rollers_per_plate": 6}, ["body", "rollers_per_plate"]),
    ("/v1/cams/roller-gear", {"center_distance_mm": 69}, ["body", "center_distance_mm"]),
    ("/v1/cams/roller-gear", {"roller_length_mm": 0.05}, ["body", "roller_length_mm"]),
    ("/v1/profiles/toolpath", {"cut_z_mm": 10}, ["body", "cut_z_mm"]),
])
async def test_rules_between_fields_name_the_field(client: httpx.AsyncClient, path: str, change: dict[str, Any],
                                                  loc: list[str]) -> None:
    # before issue 34 these 422s named only ["body"]; the hostile values above met them
    operation = next(op for op in OPERATIONS if op.path == path)
    body = {**next(iter(operation.examples.values()))["value"], **change}
    r = await client.post(path, json=body)
    assert r.status_code == 422, r.text
    assert r.json()["errors"][0]["loc"] == loc, r.text
