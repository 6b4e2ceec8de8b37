"""Every JSON answer is an instance of the model its route declares.

Routes hand the encoded answer straight to the client (orjson from numpy, no second pass
through Pydantic), so FastAPI never checks a ``response_model`` itself. Here each POST's
request examples and a request to each GET are answered in-process, and each JSON body is
validated by the route's own ``response_model`` — the model the OpenAPI document shows, for
the answers derived from camcore's result classes (service.models) as for the others. (The
schema fuzzer, tests/service/test_fuzz.py, checks the same against the document.)
"""

from __future__ import annotations

from typing import Any

import httpx
import pytest
from fastapi.routing import APIRoute

from service.app import create_app

pytestmark = pytest.mark.anyio

APP = create_app()
DOC = APP.openapi()
ROUTES = {(route.path, method.lower()): route
          for route in APP.routes if isinstance(route, APIRoute) for method in route.methods}
GETS = {
    "/v1/curves": {},
    "/v1/curves/{name}": {},
    "/v1/curves/{name}/table": {"samples": 11},
    "/v1/curves/{name}/inverse": {"s": "0.1833,0.5"},
    "/v1/indexers/accuracy": {"arc_seconds": 30, "radius_mm": 200},
    "/health": {},
}


def cases() -> list[tuple[str, str, dict[str, Any] | None, dict[str, Any]]]:
    out: list[tuple[str, str, dict[str, Any] | None, dict[str, Any]]] = []
    for path, ops in DOC["paths"].items():
        for method, op in ops.items():
            route = ROUTES[(path, method)]
            if route.response_model is None or "application/json" not in op["responses"]["200"]["content"]:
                continue
            if method == "post":
                for example in op["requestBody"]["content"]["application/json"]["examples"].values():
                    out.append((path, method, example["value"], {}))
            elif path in GETS:
                out.append((path, method, None, GETS[path]))
    return out


CASES = cases()


def test_every_json_operation_is_covered() -> None:
    covered = {(path, method) for path, method, _, _ in CASES}
    json_ops = {(path, method) for path, ops in DOC["paths"].items() for method, op in ops.items()
                if ROUTES[(path, method)].response_model is not None
                and "application/json" in op["responses"]["200"]["content"]}
    assert json_ops - covered == set()


@pytest.mark.parametrize(("path", "method", "body", "query"), CASES, ids=[f"{m} {p}" for p, m, _, _ in CASES])
async def test_answer_is_an_instance_of_the_declared_model(path: str, method: str, body: Any,
                                                           query: dict[str, Any]) -> None:
    url = path.replace("{name}", "MS")
    async with httpx.AsyncClient(transport=httpx.ASGITransport(app=APP), base_url="http://test") as client:
        response = await client.request(method.upper(), url, json=body, params=query)
    assert response.status_code == 200, response.text
    model = ROUTES[(path, method)].response_model
    assert model is not None
    model.model_validate(response.json())  # raises (with the field) when the answer drifts from the model
