"""OpenAPI fuzzing: schemathesis drives every operation of the app in-process.

For each operation in the app's own OpenAPI document (the one ``create_app()`` serves
at /openapi.json and ``openapi/openapi.json`` commits), schemathesis generates requests
from the schema — valid ones (positive mode) and deliberately invalid ones (negative
mode: wrong types, out-of-range numbers, missing or extra fields) — sends them over
ASGI with its own in-process client (no network, no Starlette TestClient), half of the
POSTs with ``Accept: text/csv``, and checks every answer:

- ``not_a_server_error``: no 5xx, whatever the input;
- ``status_code_conformance``: the status code is one the operation documents;
- ``content_type_conformance``: the Content-Type is one the operation documents;
- ``response_schema_conformance``: the body validates against the documented schema;
- ``negative_data_rejection``: schema-invalid input is answered 4xx, never 2xx.

``positive_data_acceptance`` is deliberately not checked: a schema-valid request may be
refused with a documented 4xx (eight valid numbers that describe no cam, a passed
limit, an unknown curve name).

Bounded for CI: ``CAMCORE_FUZZ_EXAMPLES`` valid examples per operation (default 25) and
``CAMCORE_FUZZ_NEGATIVE_EXAMPLES`` invalid ones (default half as many; as many valid ones for a
file twin or an older path, whose main route gets all of its own), derandomized (the same
requests on every run), no example database, no Hypothesis deadline, the app's work deadline
out of the verdict (tests/service/apps.py). An invalid example costs schemathesis a new
canonical form of the mutated body schema, ~1 s for the largest bodies (a machine's) on a
2-vCPU VM: at 25 the invalid examples were ~220 s of the gate's CPU time, more than the valid
ones. For a long run raise both, e.g. ``CAMCORE_FUZZ_EXAMPLES=400`` (see docs/robustness.md);
``CAMCORE_FUZZ_REPORT=path.json`` writes the request and status counts there.

The operations are parametrized by pytest here (rather than with ``schema.parametrize()``)
because schemathesis 4.32's plugin gives every operation the same node id under
pytest 9, which makes failures hard to attribute and ``-k`` useless.
"""

from __future__ import annotations

import json
import os
from collections import Counter, defaultdict
from collections.abc import Iterator

import hypothesis
import pytest
import schemathesis
from hypothesis import HealthCheck, given
from hypothesis import strategies as st
from schemathesis import GenerationMode
from schemathesis.checks import not_a_server_error
from schemathesis.specs.openapi.checks import (
    content_type_conformance,
    negative_data_rejection,
    response_schema_conformance,
    status_code_conformance,
)

import camcore
from service.app import create_app
from service.operations.cells import ERROR_STATUS_HEADER
from tests.service.apps import UNHURRIED

pytestmark = pytest.mark.fuzz

MAX_EXAMPLES = int(os.environ.get("CAMCORE_FUZZ_EXAMPLES", "25"))
NEGATIVE_EXAMPLES = int(os.environ.get("CAMCORE_FUZZ_NEGATIVE_EXAMPLES", str(max(1, MAX_EXAMPLES // 2))))
REPORT = os.environ.get("CAMCORE_FUZZ_REPORT")

APP = create_app(UNHURRIED)  # its answers are not the machine's speed (tests/service/apps.py)
SCHEMA = schemathesis.openapi.from_asgi("/openapi.json", APP)
OPERATIONS = [result.ok() for result in SCHEMA.get_all_operations()]
_PATHS = APP.openapi()["paths"]
#: each documented operation's document entry, by (METHOD, path)
_DOCUMENTED = {(method.upper(), path): op for path, item in _PATHS.items() for method, op in item.items()}
#: what each operation takes: its body schema and parameters
_TAKES = {key: (op.get("requestBody"), op.get("parameters")) for key, op in _DOCUMENTED.items()}
#: operations with an input to corrupt (no parameter and no body: nothing negative to send)
TAKES_INPUT = {key for key, (body, parameters) in _TAKES.items() if body or parameters}
#: the older paths (deprecated aliases), kept for the check that each still takes what a current one does
OLDER_PATHS = {key for key, op in _DOCUMENTED.items() if op.get("deprecated")}


def _stand_ins() -> dict[tuple[str, str], tuple[str, str]]:
    """Each operation whose body schema another, current one takes too, and no parameter that one
    does not take, by that one (the current one taking the most parameters: the computation's own
    route, ``?format=`` beside the body): a file twin or an older path, made with its computation from
    one declaration (service.operations.factory)."""
    by_body: dict[str, list[tuple[str, str]]] = {}
    for key, (body, _parameters) in _TAKES.items():
        if body:
            by_body.setdefault(json.dumps(body, sort_keys=True), []).append(key)
    stand_ins = {}
    for keys in by_body.values():
        current = [key for key in keys if key not in OLDER_PATHS]
        if not current:
            continue
        main = max(current, key=lambda key: (len(_TAKES[key][1] or []), -len(key[1])))
        for key in keys:
            if key != main and all(p in (_TAKES[main][1] or []) for p in (_TAKES[key][1] or [])):
                stand_ins[key] = main
    return stand_ins


#: the file twins (a computation's other routes, ``.csv``, ``.svg``, …) and the older paths: each takes
#: its main route's body schema and no parameter the main route does not (the same request model and
#: validation), so invalid input is sent to the main route only; their valid input is still sent (the
#: 34 twins' negative cases were 62 s of this file's 284 s on both cores of a 2-vCPU VM, the ten older
#: paths' ~125 s of the gate's CPU time)
STAND_INS = _stand_ins()

CHECKS = [
    not_a_server_error,
    status_code_conformance,
    content_type_conformance,
    response_schema_conformance,
    negative_data_rejection,
]

#: Random numbers rarely describe a cam, so schema-valid bodies are mostly (rightly)
#: refused with 422; to reach the computations too, half of the positive cases get a
#: curve spec that is valid by construction (a catalog name, random universal break
#: points, Makino curve 4 with random T1 ≤ T3) and half of the {name} paths a catalog name.
CATALOG_NAMES = sorted({n for e in camcore.CATALOG.values() for n in (e.id, *e.aliases)})


@st.composite
def _universal(draw: st.DrawFn) -> dict[str, object]:
    inner = sorted(draw(st.lists(st.integers(0, 64), min_size=6, max_size=6)))
    t = [0.0, *(k / 64 for k in inner), 1.0]
    hypothesis.assume(t[3] > 0 and t[4] < 1)
    return {"type": "universal", "t": t}


@st.composite
def _makino4(draw: st.DrawFn) -> dict[str, object]:
    t3 = draw(st.floats(1 / 64, 0.5))
    return {"type": "makino", "number": 4, "t1": draw(st.floats(t3 / 8, t3)), "t3": t3}


VALID_CURVE = st.one_of(
    st.builds(lambda n, d: {"type": "named", "name": n, "direction": d},
              st.sampled_from(CATALOG_NAMES), st.sampled_from(["rise", "return"])),
    _universal(),
    _makino4(),
)

#: (operation, mode) → status code → count, for the report
STATUS_COUNTS: dict[tuple[str, str], Counter[int]] = defaultdict(Counter)


@pytest.fixture(scope="module", autouse=True)
def _write_report() -> Iterator[None]:
    yield
    if REPORT:
        rows = [{"operation": op, "mode": mode, "requests": sum(c.values()), "statuses": dict(sorted(c.items()))}
                for (op, mode), c in sorted(STATUS_COUNTS.items())]
        total = sum(r["requests"] for r in rows)
        with open(REPORT, "w", encoding="utf-8") as f:
            json.dump({"max_examples": MAX_EXAMPLES, "max_negative_examples": NEGATIVE_EXAMPLES, "total_requests": total, "operations": rows}, f, indent=1)


def test_every_operation_of_the_app_is_fuzzed() -> None:
    assert {(op.method.upper(), op.path) for op in OPERATIONS} == set(_DOCUMENTED)
    assert len(OPERATIONS) >= 8
    # an older path takes what a current one takes (its twin's body schema and parameters), so the
    # twin's negative cases stand for it
    current = [value for key, value in _TAKES.items() if key not in OLDER_PATHS]
    assert OLDER_PATHS and all(_TAKES[key] in current for key in OLDER_PATHS)
    # every older path and file twin takes its main route's body and a part of its parameters, and the
    # main route's negative cases are run
    assert OLDER_PATHS <= set(STAND_INS) and set(STAND_INS) - OLDER_PATHS
    assert all(_TAKES[twin][0] == _TAKES[main][0] and main in TAKES_INPUT and main not in STAND_INS
               and main not in OLDER_PATHS and all(p in (_TAKES[main][1] or []) for p in (_TAKES[twin][1] or []))
               for twin, main in STAND_INS.items())


#: every operation with valid input; with invalid input only those that take any input
#: (an operation with no parameters and no body has no invalid request to generate), older paths and
#: file twins aside
CASES = [
    pytest.param(op, mode, id=f"{op.label}-{mode.value}")
    for op in OPERATIONS
    for mode in (GenerationMode.POSITIVE, GenerationMode.NEGATIVE)
    if mode == GenerationMode.POSITIVE
    or ((op.method.upper(), op.path) in TAKES_INPUT and (op.method.upper(), op.path) not in STAND_INS)
]


@pytest.mark.parametrize("operation, mode", CASES)
def test_operation_conforms_to_its_schema(operation: schemathesis.APIOperation, mode: GenerationMode) -> None:
    counts = STATUS_COUNTS[(operation.label, mode.value)]
    csv_choice = st.booleans() if operation.method.upper() == "POST" else st.just(False)
    positive = mode == GenerationMode.POSITIVE
    # a file twin or an older path computes what its main route does (one declaration) and takes its
    # body: half as many valid examples exercise its own part, the encoder or the alias
    stand_in = (operation.method.upper(), operation.path) in STAND_INS
    examples = MAX_EXAMPLES if positive and not stand_in else NEGATIVE_EXAMPLES
    valid_curve = st.one_of(st.none(), VALID_CURVE) if positive else st.none()
    valid_name = st.one_of(st.none(), st.sampled_from(CATALOG_NAMES)) if positive else st.none()

    @hypothesis.settings(
        max_examples=examples,
        deadline=None,
        derandomize=True,
        database=None,
        suppress_health_check=list(HealthCheck),
        phases=[hypothesis.Phase.explicit, hypothesis.Phase.generate],  # no shrinking: report the first failure
    )
    @given(case=operation.as_strategy(mode), csv=csv_choice, curve=valid_curve, name=valid_name)
    def run(case: schemathesis.Case, csv: bool, curve: dict[str, object] | None, name: str | None) -> None:
        # new dicts, not edits in place: an explicit example (the document's request examples)
        # is the same object on every run, and editing it would change the next run's data
        if curve is not None and isinstance(case.body, dict) and isinstance(case.body.get("curve"), dict):
            case.body = {**case.body, "curve": curve}
        if name is not None and case.path_parameters and "name" in case.path_parameters:
            case.path_parameters = {**case.path_parameters, "name": name}
        headers = {"Accept": "text/csv"} if csv else None
        if (case.query or {}).get("errors") == "text":
            # the cell form answers a refusal 200 as one line when asked to (a spreadsheet shows
            # nothing else): the refusal is then checked in the header that carries its status
            checks = [check for check in CHECKS if check is not negative_data_rejection]
            response = case.call_and_validate(headers=headers, checks=checks)
            found = {name.lower(): value for name, value in response.headers.items()}.get(ERROR_STATUS_HEADER.lower())
            refused = found[0] if isinstance(found, list) else found  # (schemathesis keeps a list per header)
            assert response.status_code == 200 or refused is None
            if not positive:
                assert refused is not None and refused.startswith("4"), (refused, response.text)
                assert response.text.startswith(f"Error {refused}: ")
        else:
            response = case.call_and_validate(headers=headers, checks=CHECKS)
        counts[response.status_code] += 1

    run()


# ----------------------------------------------------------------------------- found by fuzzing
#: Each was found by this module or by tests/camcore/curves/test_universal_properties.py. Open bugs are strict
#: xfails, so the test starts failing (XPASS) when the bug is fixed — then drop the mark.
FOUND = [
    # 413 body used to carry requested=10**30, which orjson refuses (ints beyond 64 bits) → 500;
    # fixed in service/errors.py
    pytest.param("GET", "/v1/curves/MS/table", {"params": {"samples": 10**30}}, id="huge-samples-get"),
    pytest.param("POST", "/v1/curves/table", {"json": {"curve": {"type": "named", "name": "MS"}, "samples": 10**30}},
                 id="huge-samples-post"),
    pytest.param("POST", "/v1/curves/table",
                 {"json": {"curve": {"type": "universal", "t": [0, 1e-160, 1e-160, 0.5, 0.5, 0.875, 0.875, 1]},
                           "samples": 5}},
                 id="vanishing-section"),  # fixed: camcore merges sections under 1e-9 of the stroke
]


@pytest.mark.anyio
@pytest.mark.parametrize("anyio_backend", ["asyncio"])
@pytest.mark.parametrize("method, path, kwargs", FOUND)
async def test_found_by_fuzzing_is_answered_4xx_or_200(method: str, path: str, kwargs: dict[str, object],
                                                       anyio_backend: str) -> None:
    import httpx

    transport = httpx.ASGITransport(app=create_app(), raise_app_exceptions=False)
    async with httpx.AsyncClient(transport=transport, base_url="http://testserver") as client:
        r = await client.request(method, path, **kwargs)  # type: ignore[arg-type]
    assert r.status_code < 500, r.text
