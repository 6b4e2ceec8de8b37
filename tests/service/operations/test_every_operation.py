"""Checks common to every operation of the registry (scikit-learn's ``parametrize_with_checks``
is the model): what is declared once must hold for each operation, present and future.

For each operation (service.registry.OPERATIONS):

- it has a request example, and each example answers 200;
- it answers its first example in every format it declares, by ``?format=``, by its file twin
  ``{path}.{format}`` and by ``Accept`` where the format takes it (its older paths are replayed byte
  for byte by tests/service/test_answer_replay.py), each time with the media type the document
  declares for that route (and only that one for a twin), in bytes the reader of that media type
  takes back (tests/readers.py);
- a request it cannot take is refused with a 4xx whose ``loc`` names the field;
- its estimate bounds the work it then does, in each format (cold caches, warm imports; the work
  is the CPU time of the thread that does it).
"""

from __future__ import annotations

import copy
import gc
import time
from collections.abc import Iterator
from typing import Any

import httpx
import pytest

from service.app import create_app
from service.context import Context
from service.operations import Format, Operation, cells
from service.operations.factory import Route, routes_of
from service.registry import OPERATIONS
from service.settings import Settings
from tests.estimates import within_estimate
from tests.readers import read

pytestmark = pytest.mark.anyio

APP = create_app()
DOC = APP.openapi()
IDS = [op.id for op in OPERATIONS]


def example(operation: Operation, fmt: Format | None = None) -> dict[str, Any]:
    """The operation's first example (for a format that needs more in the body, that format's)."""
    examples = operation.examples
    if fmt is not None and fmt.name in operation.format_examples:
        examples = operation.format_examples[fmt.name]
    return copy.deepcopy(next(iter(examples.values()))["value"])


def request_of(operation: Operation, path: str, value: dict[str, Any]) -> dict[str, Any]:
    """httpx keyword arguments of a request to ``path`` with an example's value: the body of a
    POST; the path and query parameters of a GET."""
    if operation.method == "POST":
        return {"url": path, "json": value}
    query = dict(value)
    url = path
    for name in operation.path_parameters:
        url = url.replace("{" + name + "}", str(query.pop(name)))
    return {"url": url, "params": query}


def declared(route: Route) -> dict[str, Any]:
    return DOC["paths"][route.path][route.operation.method.lower()]["responses"]["200"].get("content", {})


def ways(operation: Operation) -> Iterator[tuple[str, Route, Format, dict[str, Any], dict[str, str]]]:
    """Every way to ask for each format: (how, route, format, query additions, headers)."""
    for route in routes_of(operation):
        if route.kind == "alias":  # an older path: its bytes are replayed (tests/service/test_answer_replay.py)
            continue
        if route.kind != "operation":
            yield route.kind, route, route.formats[0], {}, {}
            continue
        for fmt in route.formats:
            yield "default" if fmt is route.formats[0] else "?format", route, fmt, \
                ({} if fmt is route.formats[0] else {"format": fmt.name}), {}
            if fmt.accept:
                yield "Accept", route, fmt, {}, {"Accept": fmt.bare_media_type}


WAYS = [(op, *way) for op in OPERATIONS for way in ways(op)]


@pytest.fixture(scope="module")
async def client() -> Any:
    async with httpx.AsyncClient(transport=httpx.ASGITransport(app=APP), base_url="http://testserver",
                                 timeout=120) as c:
        yield c


@pytest.fixture(scope="module")
def anyio_backend() -> str:
    return "asyncio"


def test_the_registry_holds_every_operation_once() -> None:
    assert len(IDS) == len(set(IDS)) >= 30
    documented = {op["operationId"] for ops in DOC["paths"].values() for op in ops.values()}
    made = [route.id for op in OPERATIONS for route in routes_of(op)]
    # the document is the registry and the cell form made from it, nothing else
    assert len(made) == len(set(made)) and documented == {*made, cells.OPERATION_ID}


@pytest.mark.parametrize("operation", OPERATIONS, ids=IDS)
async def test_each_example_answers_200(client: httpx.AsyncClient, operation: Operation) -> None:
    assert operation.examples, f"{operation.id} has no request example"
    for name, ex in operation.examples.items():
        r = await client.request(operation.method, **request_of(operation, operation.path, copy.deepcopy(ex["value"])))
        assert r.status_code == 200, (name, r.text)


@pytest.mark.timing
@pytest.mark.parametrize(("operation", "how", "route", "fmt", "query", "headers"), WAYS,
                         ids=[f"{w[0].id}-{w[1]}-{w[3].name}" for w in WAYS])
async def test_every_format_answers_as_declared_within_its_estimate(
        client: httpx.AsyncClient, operation: Operation, how: str, route: Route, fmt: Format, query: dict[str, Any],
        headers: dict[str, str]) -> None:
    kwargs = request_of(operation, route.path, example(operation, fmt))
    kwargs["params"] = {**kwargs.get("params", {}), **query}
    r = await client.request(operation.method, headers=headers, **kwargs)
    assert r.status_code == 200, r.text
    answered = r.headers["content-type"].split(";")[0].strip()
    assert answered == fmt.bare_media_type
    content = declared(route)
    assert answered in content and content[answered].get("schema"), (route.path, answered, list(content))
    if route.kind != "operation":
        assert list(content) == [answered]  # a twin or an alias answers its one file
    if fmt.file_name is not None:
        assert fmt.file_name in r.headers["content-disposition"]
    assert read(answered, r.content), "its reader found nothing in it"  # a second program takes it back
    if how in ("default", "?format"):  # once per format, the request above having loaded what it needs
        seconds, estimate = cold_run(operation, fmt)
        assert within_estimate(seconds, estimate), f"{operation.id} as {fmt.name}: {seconds:.4f} s, estimated " \
                                                  f"{estimate:.4f} s"


def _first_leaf(value: Any, kind: type | tuple[type, ...], at: tuple[str | int, ...] = ()
                ) -> tuple[str | int, ...] | None:
    """Where the first leaf of that kind is in an example (depth first; a tag ``type`` is not
    one: it chooses the model), or None."""
    if isinstance(value, kind) and not isinstance(value, bool) and at[-1:] != ("type",):
        return at
    items = value.items() if isinstance(value, dict) else enumerate(value) if isinstance(value, list) else ()
    for key, item in items:
        found = _first_leaf(item, kind, (*at, key))
        if found is not None:
            return found
    return None


def _set(value: Any, at: tuple[str | int, ...], new: Any) -> None:
    for key in at[:-1]:
        value = value[key]
    value[at[-1]] = new


#: operations that take nothing a request could get wrong
NO_INPUT = {"listCurves", "getHealth"}


@pytest.mark.parametrize("operation", [op for op in OPERATIONS if op.id not in NO_INPUT],
                         ids=[i for i in IDS if i not in NO_INPUT])
async def test_a_wrong_field_is_refused_naming_it(client: httpx.AsyncClient, operation: Operation) -> None:
    value = example(operation)
    if operation.method == "GET" and not (set(value) - set(operation.path_parameters)):
        value[next(iter(operation.path_parameters))] = "no-such-curve"  # only a path: a name nothing has
        r = await client.request(operation.method, **request_of(operation, operation.path, value))
        assert r.status_code == 404 and r.json()["errors"][0]["loc"][0] == "path", r.text
        return
    fields = {k: v for k, v in value.items() if k not in operation.path_parameters}
    at = _first_leaf(fields, (int, float))  # a number made text, or else a text made a list
    wrong: Any = "not a number"
    if at is None:
        at, wrong = _first_leaf(fields, str), [[]]
    assert at is not None, f"{operation.id}: its example has nothing to get wrong"
    _set(value, at, wrong)
    r = await client.request(operation.method, **request_of(operation, operation.path, value))
    assert r.status_code == 422, r.text
    where = "body" if operation.method == "POST" else "query"
    loc = r.json()["errors"][0]["loc"]
    # the field's path, in order (a curve spec's loc also names the kind its tag chose; a query list, the item)
    assert loc[0] == where and [p for p in loc if p in at] == list(at), (at, r.text)


#: work shorter than this is not compared with its estimate: a garbage collection or a first
#: call into a numpy routine costs a few milliseconds, far below the budget (1 s) and the
#: inline limit (3 ms) the estimates decide


def cold_run(operation: Operation, fmt: Format) -> tuple[float, float]:
    """The work of the operation's example in ``fmt`` from cold caches (every curve built; what a
    process loads once, the CAD kernel and matplotlib, already loaded), and its estimate [s]. The
    work is the CPU time of the thread that does it: another process's turn on the core is not
    this operation's work."""
    ctx = Context.create(Settings())
    spec, path = _spec(operation, fmt)
    core = operation.convert(ctx, spec, path)
    estimate = operation.estimate(ctx, core, fmt).seconds
    gc.disable()  # a collection of the objects earlier tests left is not this operation's work
    try:
        start = time.thread_time()
        operation.compute(ctx, core, fmt)
        return time.thread_time() - start, estimate
    finally:
        gc.enable()


def _spec(operation: Operation, fmt: Format) -> tuple[Any, dict[str, str]]:
    """The validated spec and the path values of the operation's example for ``fmt``."""
    value = example(operation, fmt)
    path = {name: str(value.pop(name)) for name in operation.path_parameters}
    model = operation.format_requests.get(fmt.name, operation.request)
    if model is None:
        return None, path
    if operation.method == "GET":
        value = {k: (v.split(",") if isinstance(v, str) and "," in v else v) for k, v in value.items()}
    return model.model_validate(value), path
