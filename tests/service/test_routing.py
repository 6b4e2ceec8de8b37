"""Request bodies parsed by orjson, with the standard library where orjson refuses
(service/routing.py): the same values and the same errors as before, for every route."""

from __future__ import annotations

import asyncio
import json

import pytest

import service.health as health
from service.app import create_app
from service.curves import routes as curves
from service.indexers import routes as indexers
from service.motions import routes as motions
from service.plots import routes as plots
from service.profiles import routes as profiles
from service.routing import OrjsonRequest, OrjsonRoute


def parse(body: bytes) -> object:
    async def receive() -> dict[str, object]:
        return {"type": "http.request", "body": body, "more_body": False}

    request = OrjsonRequest({"type": "http", "method": "POST", "headers": []}, receive)
    return asyncio.run(request.json())


@pytest.mark.parametrize("body", [
    b'{"curve": {"type": "named", "name": "MS"}, "s": [0.1, 0.25, 1e-300, -0.0]}',
    b'{"s": [NaN, Infinity, -Infinity]}',          # orjson refuses these literals
    b'{"samples": 1000000000000000000000000000}',   # orjson reads integers beyond 64 bits as floats
    b'{"samples": [-12345678901234567890123, 18446744073709551615]}',
    b'{"samples": -9223372036854775809}',           # 19 digits, below -2**63: orjson reads a float
    b'{"samples": [9223372036854775807, -9223372036854775808, 1234567890123456789]}',
    b'{"t": [0.00010500052500262501, 1e-310, 12345678901234567890.5, 1.5e-00000000000000000000001]}',
    b'{"samples": 12345678901234567890123, "s": [0.00010500052500262501]}',
    '{"name": "Modified Sine \u00e9"}'.encode(),
])
def test_bodies_parse_as_the_standard_library_parses_them(body: bytes) -> None:
    got, want = parse(body), json.loads(body)
    assert json.dumps(got) == json.dumps(want)  # NaN-safe comparison


@pytest.mark.parametrize("body", [b'{"s": [0.1,', b"\xff\xfe{", b"", b'{"a": 1} x'])
def test_malformed_bodies_raise_what_the_standard_library_raises(body: bytes) -> None:
    with pytest.raises(ValueError) as ours:
        parse(body)
    with pytest.raises(ValueError) as stdlib:
        json.loads(body)
    assert type(ours.value) is type(stdlib.value) and str(ours.value) == str(stdlib.value)


def test_every_api_operation_parses_with_orjson() -> None:
    routes = [r for module in (curves, health, indexers, motions, plots, profiles)
              for r in module.router.routes]
    operations = sum(len(ops) for ops in create_app().openapi()["paths"].values())
    # every operation of the document is a route of these routers (30 with the file twins,
    # getCurveValue and computeMotion); HEAD /health is the one route outside the document
    assert len([r for r in routes if r.include_in_schema]) == operations >= 30
    assert all(isinstance(r, OrjsonRoute) for r in routes), [r.path for r in routes if not isinstance(r, OrjsonRoute)]
