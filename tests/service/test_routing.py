"""Request bodies parsed by orjson, with the standard library where orjson refuses
(service/routing.py): the same values and the same errors as before, for every route."""

from __future__ import annotations

import asyncio
import json
import subprocess
import sys
import threading
from pathlib import Path

import httpx
import pytest
from fastapi.routing import APIRoute

from service import routing
from service.app import create_app
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
    app = create_app()
    routes = [r for r in app.routes if isinstance(r, APIRoute)]
    operations = sum(len(ops) for ops in app.openapi()["paths"].values())
    # every operation of the document is an API route (the file twins and aliases included); HEAD /health
    # and the documentation pages are the routes outside the document
    assert len([r for r in routes if r.include_in_schema]) == operations >= 53
    api = [r for r in routes if r.path.startswith(("/v1", "/health"))]
    assert all(isinstance(r, OrjsonRoute) for r in api), [r.path for r in api if not isinstance(r, OrjsonRoute)]


# ----------------------------------------------------------------------------- large bodies
def _inverse_body(values: int, bad_at: int | None = None) -> bytes:
    s: list[object] = [i / values + 1e-9 for i in range(values)]  # ~20 bytes per number
    if bad_at is not None:
        s[bad_at] = "0.5"  # a string where a number belongs: a 422 naming body.s.<index>
    return json.dumps({"curve": {"type": "named", "name": "MS"}, "s": s}).encode()


async def _post(app: object, body: bytes) -> tuple[int, bytes]:
    transport = httpx.ASGITransport(app=app)  # type: ignore[arg-type]
    async with httpx.AsyncClient(transport=transport, base_url="http://t") as client:
        response = await client.post("/v1/curves/inverse", content=body, headers={"Content-Type": "application/json"})
    return response.status_code, response.content


@pytest.mark.anyio
@pytest.mark.parametrize("bad_at", [None, 19_999])
async def test_large_bodies_are_validated_in_a_thread_with_the_same_answers(
        bad_at: int | None, monkeypatch: pytest.MonkeyPatch) -> None:
    body = _inverse_body(20_000, bad_at)  # ~400 KB: over LARGE_BODY_BYTES
    assert len(body) > routing.LARGE_BODY_BYTES
    app = create_app()
    threads: list[str] = []
    real_loads = routing.loads

    def recording_loads(raw: bytes) -> object:
        threads.append(threading.current_thread().name)
        return real_loads(raw)

    monkeypatch.setattr(routing, "loads", recording_loads)
    large = await _post(app, body)
    assert threads and threads[0] != threading.main_thread().name  # parsed off the event loop's thread
    assert len(threads) == 1  # and only once: FastAPI took the validated model (or the errors)
    monkeypatch.setattr(routing, "LARGE_BODY_BYTES", 1 << 30)  # every body small: FastAPI parses and validates
    threads.clear()
    small = await _post(app, body)
    assert threads == [threading.main_thread().name]
    assert large == small  # the same status and the same bytes: the values, or the 422 naming body.s.19999
    assert large[0] == (200 if bad_at is None else 422)
    if bad_at is not None:
        assert b'"s",19999' in large[1].replace(b" ", b"")


@pytest.mark.anyio
async def test_a_large_malformed_body_is_the_same_error(monkeypatch: pytest.MonkeyPatch) -> None:
    body = _inverse_body(20_000)[:-5]  # cut short
    app = create_app()
    large = await _post(app, body)
    assert large[0] == 400, large  # the service answers a body that is not JSON with 400
    monkeypatch.setattr(routing, "LARGE_BODY_BYTES", 1 << 30)
    assert await _post(app, body) == large


def test_error_answers_are_documented_by_one_field_per_status_code() -> None:
    """FastAPI would make a field (a TypeAdapter) of each further response's model per route;
    the routes share one per status code and model (start-up), and the document still names
    the error answer under every one of those codes on every route."""
    app = create_app()
    routes = [r for r in app.router.routes if isinstance(r, OrjsonRoute) and r.include_in_schema]
    fields = [(code, field) for r in routes for code, field in r.response_fields.items()]
    codes = {code for code, _ in fields}
    assert len(routes) > 50 and codes == {400, 404, 413, 422, 503}
    assert len({id(field) for _, field in fields}) == len(codes)  # one field per code, not per route
    document = app.openapi()
    for r in routes:
        for method in r.methods:
            answers = document["paths"][r.path_format][method.lower()]["responses"]
            for code in codes:
                assert answers[str(code)]["content"]["application/json"]["schema"] == {
                    "$ref": "#/components/schemas/ErrorAnswer"}, (r.path, code)


def run_fresh(program: str) -> subprocess.CompletedProcess[str]:
    """A program run by a fresh interpreter in the checkout (what a cold worker has built and imported)."""
    return subprocess.run([sys.executable, "-c", program], capture_output=True, text=True, check=True,
                          cwd=Path(__file__).resolve().parents[2], timeout=120)


def test_a_cold_app_answers_without_importing_pydantic_v1() -> None:
    # FastAPI asks of each parameter and each encoded value whether it is a pydantic v1 model, and
    # imported pydantic.v1 to ask (67 ms of a cold start); the routes make it ask only once something
    # has imported it. A fresh interpreter: the app made, a computation, a 422 and a 404 answered
    program = (
        "import asyncio, sys, httpx\n"
        "from service.app import create_app\n"
        "async def main():\n"
        "    app = create_app()\n"
        "    async with httpx.AsyncClient(transport=httpx.ASGITransport(app=app), base_url='http://t') as c:\n"
        "        ok = await c.post('/v1/curves/table', json={'curve': {'type': 'named', 'name': 'MS'}, 'samples': 5})\n"
        "        bad = await c.post('/v1/curves/table', json={'curve': 5})\n"
        "        missing = await c.get('/v1/nothing')\n"
        "    print(ok.status_code, bad.status_code, missing.status_code, 'pydantic.v1' in sys.modules)\n"
        "asyncio.run(main())\n")
    done = run_fresh(program)
    assert done.stdout.split() == ["200", "422", "404", "False"], done.stderr


def test_the_workers_parent_starts_without_the_app() -> None:
    # python -m service with several workers: the parent only reads the settings and runs uvicorn,
    # each worker imports the app. The door's protocol takes its headers from service.wire, so the
    # parent imports neither FastAPI nor numpy nor camcore (0.45 -> 0.17 s of its imports on the Intel VM)
    program = (
        "import sys\n"
        "import service.__main__\n"
        "print(*(name in sys.modules for name in ('fastapi', 'numpy', 'camcore', 'service.app')))\n")
    done = run_fresh(program)
    assert done.stdout.split() == ["False"] * 4, done.stderr


def test_the_served_app_leaves_the_garbage_collector_on_with_its_start_up_frozen() -> None:
    # service.main holds the cyclic collector off while the app is made (a cold start ~0.03 s sooner
    # on the Intel VM) and must turn it back on: a worker left without it would keep every request's
    # reference cycles. The start-up's objects are frozen (out of later passes), the request's are not
    program = (
        "import gc\n"
        "was_on = gc.isenabled()\n"
        "import service.main\n"
        "frozen = gc.get_freeze_count()\n"
        "class Cycle: pass\n"
        "a, b = Cycle(), Cycle()\n"
        "a.other, b.other = b, a\n"
        "del a, b\n"
        "print(was_on, gc.isenabled(), frozen > 100_000, gc.collect() >= 2)\n")
    done = run_fresh(program)
    assert done.stdout.split() == ["True", "True", "True", "True"], done.stderr


def test_a_cold_app_builds_a_model_when_a_request_first_needs_it() -> None:
    # the service's models defer their build (service.specs.DeferredModel): making the app built
    # none of them (2.23 -> 1.77 x a bare app's start on the slower VM). A fresh interpreter with
    # every warning an error: pydantic warns of FastAPI's alias when an adapter FastAPI made is built
    # outside FastAPI's filter, which the routes and the document build under (service.routing).
    # The body, the query model, the large body (validated in a thread) and the document still work
    program = (
        "import asyncio, json, sys, warnings\n"
        "warnings.simplefilter('error')\n"
        "import httpx\n"
        "from service import routing, specs\n"
        "from service.app import create_app\n"
        "def deferred(cls):\n"
        "    for sub in cls.__subclasses__():\n"
        "        yield sub\n"
        "        yield from deferred(sub)\n"
        "async def main():\n"
        "    app = create_app()\n"
        "    models = set(deferred(specs.DeferredModel))\n"
        "    built = sorted(m.__name__ for m in models if m.__pydantic_complete__)\n"
        "    numpy_ma = 'numpy.ma' in sys.modules\n"
        "    routing.LARGE_BODY_BYTES = 100\n"
        "    large = {'curve': {'type': 'named', 'name': 'MS'}, 's': [0.5] * 40}\n"
        "    async with httpx.AsyncClient(transport=httpx.ASGITransport(app=app), base_url='http://t') as c:\n"
        "        answers = [await c.post('/v1/curves/table', json={'curve': {'type': 'named', 'name': 'MS'}, 'samples': 5}),\n"
        "                   await c.post('/v1/curves/table', json={'curve': {'type': 'named', 'name': 'MS'}, 'samples': 1}),\n"
        "                   await c.get('/v1/curves/MS/table', params={'samples': 3}),\n"
        "                   await c.get('/v1/curves/MS/table', params={'samples': 'many'}),\n"
        "                   await c.post('/v1/curves/inverse', json=large),\n"
        "                   await c.post('/v1/curves/inverse', json={**large, 's': [2.0] * 40}),\n"
        "                   await c.get('/openapi.json')]\n"
        "    refused = answers[1].json()['errors'][0]['loc'], answers[3].json()['errors'][0]['loc']\n"
        "    print(json.dumps([len(models), built, [a.status_code for a in answers], refused,\n"
        "                      'TableRequest' in answers[-1].json()['components']['schemas'], numpy_ma]))\n"
        "asyncio.run(main())\n")
    done = run_fresh(program)
    count, built, codes, refused, documented, numpy_ma = json.loads(done.stdout)
    assert count > 100 and built == [], done.stderr
    assert codes == [200, 422, 200, 422, 200, 422, 200] and documented
    assert refused == [["body", "samples"], ["query", "samples"]]
    # a grid of motion/resolve.py is sorted, not np.unique'd: numpy.ma is imported at first use, not at start
    assert numpy_ma is False


def test_deferred_models_are_built_after_their_field_models_and_a_model_holding_itself_is_built() -> None:
    # service.specs.build_models: the field models first (built once, then taken as built by every
    # model holding one), a recursive model without recursing for ever. Models made here, unbuilt
    from pydantic import BaseModel

    from service.specs import DeferredModel, build_models

    order: list[str] = []

    class Recording(DeferredModel):
        @classmethod
        def model_rebuild(cls, **kwargs: object) -> bool | None:
            order.append(cls.__name__)
            return super().model_rebuild(**kwargs)  # type: ignore[arg-type]

    class Leaf(Recording):
        value: float

    class Branch(Recording):
        leaves: list[Leaf]
        first: Leaf | None = None

    class Tree(Recording):
        branches: dict[str, Branch]
        subtrees: list[Tree] | None = None

    assert not (Leaf.__pydantic_complete__ or Branch.__pydantic_complete__ or Tree.__pydantic_complete__)
    build_models(list[Tree])
    assert order == ["Leaf", "Branch", "Tree"]
    assert all(m.__pydantic_complete__ for m in (Leaf, Branch, Tree))
    tree = Tree.model_validate({"branches": {"a": {"leaves": [{"value": 1}]}}, "subtrees": [{"branches": {}}]})
    assert tree.subtrees is not None and tree.subtrees[0].branches == {} and tree.branches["a"].leaves[0].value == 1.0
    build_models(Tree)  # built: nothing again
    assert order == ["Leaf", "Branch", "Tree"] and issubclass(Tree, BaseModel)


def test_threads_first_using_a_model_at_once_all_get_it_built() -> None:
    # a model first used off the event loop (a spec made in a computation's thread) may be built by
    # several threads at once: pydantic leaves its mocks until a build is complete. A fresh
    # interpreter, every warning an error: six threads validate each of the ~150 unbuilt models together
    program = (
        "import sys, threading, warnings\n"
        "warnings.simplefilter('error')\n"
        "import service.app\n"
        "from pydantic import ValidationError\n"
        "from service import specs\n"
        "models = [m for m in specs.deferred_models() if not m.__pydantic_complete__]\n"
        "errors = []\n"
        "def validate(model, barrier):\n"
        "    barrier.wait()\n"
        "    try:\n"
        "        model.model_validate({})\n"
        "    except ValidationError:\n"
        "        pass\n"
        "    except Exception as exc:\n"
        "        errors.append(f'{model.__name__}: {exc!r}')\n"
        "for model in models:\n"
        "    barrier = threading.Barrier(6)\n"
        "    threads = [threading.Thread(target=validate, args=(model, barrier)) for _ in range(6)]\n"
        "    for t in threads:\n"
        "        t.start()\n"
        "    for t in threads:\n"
        "        t.join()\n"
        "print(len(models), sum(not m.__pydantic_complete__ for m in models), errors)\n")
    done = run_fresh(program)
    count, unbuilt, errors = done.stdout.split(maxsplit=2)
    assert int(count) > 100 and int(unbuilt) == 0 and errors.strip() == "[]", done.stdout + done.stderr


def test_the_pydantic_v1_checks_still_refuse_a_v1_model_once_it_is_imported() -> None:
    import warnings

    from fastapi._compat import shared

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # pydantic.v1 warns on Python 3.14; here it is the point
        from pydantic import v1

    class Old(v1.BaseModel):
        x: int = 0

    assert shared.is_pydantic_v1_model_class(Old) and shared.is_pydantic_v1_model_instance(Old())
    assert not shared.is_pydantic_v1_model_class(int)
