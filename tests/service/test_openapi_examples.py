"""Every POST operation's request examples answer 200, and so does what Swagger UI pre-fills.

The interactive docs pre-fill "Try it out" with the first entry of the request body's
``examples`` (or its ``example``); without one, Swagger UI builds a body from the schema,
taking a schema's ``examples[0]``, else its ``default``, else its ``example``, the first
option of a ``oneOf``/``anyOf``, and every property of an object (swagger-ui 5,
json-schema-2020-12 samples: ``extractExample``, ``random_pick = s => s.at(0)``). Both are
posted here in-process to the app's own document; so is every example of every request-side
schema (validated by its model: the cross-field rules included).
"""

from __future__ import annotations

import copy
import json
from typing import Any

import httpx
import pytest
from pydantic import BaseModel

from service.app import create_app
from service.openapi_examples import models_of
from service.registry import OPERATIONS

pytestmark = pytest.mark.anyio

DOC = create_app().openapi()
ALL_POSTS = [(path, op) for path, ops in DOC["paths"].items() for method, op in ops.items() if method == "post"]


def _distinct_bodies() -> list[tuple[str, Any]]:
    """One route per distinct request body (a file twin and an older path take their operation's
    body and examples: one of them speaks for all)."""
    seen: dict[str, tuple[str, Any]] = {}
    for path, op in ALL_POSTS:
        seen.setdefault(json.dumps(op["requestBody"], sort_keys=True), (path, op))
    return list(seen.values())


POSTS = _distinct_bodies()
EXAMPLES = [(path, name, example["value"]) for path, op in POSTS
            for name, example in op["requestBody"]["content"]["application/json"].get("examples", {}).items()]


def resolve(schema: dict[str, Any]) -> dict[str, Any]:
    while "$ref" in schema:
        schema = DOC["components"]["schemas"][schema["$ref"].rsplit("/", 1)[-1]]
    return schema


def swagger_sample(schema: dict[str, Any]) -> Any:
    """The body Swagger UI builds from a schema (the rules above, for the keywords we use)."""
    schema = resolve(schema)
    if schema.get("examples"):
        return schema["examples"][0]
    for key in ("default", "example", "const"):
        if key in schema:
            return schema[key]
    for key in ("oneOf", "anyOf"):
        if schema.get(key):
            rest = {k: v for k, v in schema.items() if k not in (key, "discriminator")}
            return swagger_sample({**rest, **resolve(schema[key][0])})
    kind = schema.get("type")
    if kind == "object" or "properties" in schema:
        return {name: swagger_sample(prop) for name, prop in schema.get("properties", {}).items()}
    if kind == "array":
        items = schema.get("prefixItems") or [schema.get("items", {})]
        return [swagger_sample(item) for item in items]
    return {"string": "string", "number": 0, "integer": 0, "boolean": True, "null": None}[kind]


def prefill(op: dict[str, Any]) -> Any:
    """What Swagger UI puts in the body editor on "Try it out"."""
    media = op["requestBody"]["content"]["application/json"]
    if media.get("examples"):
        return next(iter(media["examples"].values()))["value"]
    if "example" in media:
        return media["example"]
    return swagger_sample(media["schema"])


def test_every_post_operation_has_request_examples() -> None:
    assert len(POSTS) >= 16, [p for p, _ in POSTS]  # the operations' distinct bodies were found
    missing = [path for path, op in ALL_POSTS if not op["requestBody"]["content"]["application/json"].get("examples")]
    assert not missing, f"POST operations without request examples: {missing}"
    for path, name, value in EXAMPLES:
        assert isinstance(value, dict) and value, (path, name)


@pytest.mark.parametrize(("path", "name", "body"), EXAMPLES, ids=[f"{p} {n}" for p, n, _ in EXAMPLES])
async def test_each_request_example_answers_200(client: httpx.AsyncClient, path: str, name: str, body: Any) -> None:
    r = await client.post(path, json=body)
    assert r.status_code == 200, r.text
    media = r.headers["content-type"].split(";")[0]
    assert media in DOC["paths"][path]["post"]["responses"]["200"]["content"], media
    assert r.json() if media == "application/json" else r.content


@pytest.mark.parametrize(("path", "op"), POSTS, ids=[p for p, _ in POSTS])
async def test_swagger_prefill_answers_200(client: httpx.AsyncClient, path: str, op: dict[str, Any]) -> None:
    r = await client.post(path, json=prefill(op))
    assert r.status_code == 200, r.text


@pytest.mark.parametrize(("path", "op"), POSTS, ids=[p for p, _ in POSTS])
async def test_body_built_from_the_schema_answers_200(client: httpx.AsyncClient, path: str, op: dict[str, Any]) -> None:
    # a tool that ignores the operation's examples and builds the body from the schema alone
    body = swagger_sample(op["requestBody"]["content"]["application/json"]["schema"])
    r = await client.post(path, json=body)
    assert r.status_code == 200, r.text


def request_side_schemas() -> set[str]:
    """Names of the component schemas a request body can contain."""
    seen: set[str] = set()

    def walk(node: Any) -> None:
        if isinstance(node, dict):
            ref = node.get("$ref")
            if ref:
                name = ref.rsplit("/", 1)[-1]
                if name not in seen:
                    seen.add(name)
                    walk(DOC["components"]["schemas"][name])
            for value in node.values():
                walk(value)
        elif isinstance(node, list):
            for value in node:
                walk(value)

    for _, op in POSTS:
        walk(op["requestBody"])
    return seen


def model_classes() -> dict[str, type[BaseModel]]:
    """Every model a request body of an operation of the registry can hold, by name."""
    out: dict[str, type[BaseModel]] = {}
    for operation in OPERATIONS:
        if operation.method == "POST":
            for model in (operation.request, *operation.format_requests.values()):
                out.update(models_of(model))
    return out


REQUEST_SCHEMAS = sorted(request_side_schemas())


@pytest.mark.parametrize("name", REQUEST_SCHEMAS)
def test_every_request_schema_has_valid_examples(name: str) -> None:
    schema = DOC["components"]["schemas"][name]
    assert schema.get("examples"), f"{name} has no examples: a schema-driven tool would combine field examples"
    model = model_classes()[name]
    for example in schema["examples"]:
        model.model_validate(copy.deepcopy(example))  # raises on a contradiction (the model's own rules)


CURVE_SPECS = [n for n in REQUEST_SCHEMAS if n.endswith("CurveSpec")]


@pytest.mark.parametrize("name", CURVE_SPECS)
async def test_curve_spec_examples_compute(client: httpx.AsyncClient, name: str) -> None:
    assert len(CURVE_SPECS) == 6
    for example in DOC["components"]["schemas"][name]["examples"]:
        r = await client.post("/v1/curves/characteristics", json={"curve": example})
        assert r.status_code == 200, (example, r.text)
