"""Domain errors say where they are, like validation errors: ``errors: [{loc, msg}]``.

An unknown curve (404), a value off the stroke (422), a request over a limit (413) and any
other CamError (422) name the request field they are about: the path's ``name``, the body's
``curve.name`` or ``s[1]``, the query's ``samples``; the sentence of ``detail`` is the ``msg``.
An error about the request as a whole points at ``["body"]`` (or the part the service knows).
"""

from __future__ import annotations

from collections.abc import AsyncIterator
from typing import Any

import httpx
import pytest

from service.app import create_app
from service.settings import Settings

pytestmark = pytest.mark.anyio

MS = {"type": "named", "name": "MS"}
TYPO = {"type": "named", "name": "cycloyd"}
INDEXER = {"stops": 6, "indexing_angle_deg": 270, "speed_rpm": 60}
ROLLER_ON_AN_ARM = {"type": "roller", "motion": "oscillating", "roller_radius_mm": 5, "arm_length_mm": 10,
                    "pivot_distance_mm": 100}


def segments(curve: dict[str, Any] | None = None, rise_mm: float = 20, return_mm: float = 20) -> list[dict[str, Any]]:
    rise: dict[str, Any] = {"type": "rise", "angle_deg": 180, "lift_mm": rise_mm}
    if curve is not None:
        rise["curve"] = curve
    return [rise, {"type": "return", "angle_deg": 180, "lift_mm": return_mm}]


def only_error(r: httpx.Response, status: int) -> dict[str, Any]:
    assert r.status_code == status, r.text
    body = r.json()
    assert len(body["errors"]) == 1, body
    error = body["errors"][0]
    assert error["msg"] == body["detail"], body  # the same sentence, now with its place
    return error


# (method, url, body, status, loc, words of the message)
CASES = [
    ("GET", "/v1/curves/cycloyd", None, 404, ["path", "name"], "No curve named 'cycloyd'"),
    ("GET", "/v1/curves/cycloyd/table?samples=11", None, 404, ["path", "name"], "No curve named"),
    ("GET", "/v1/curves/cycloyd/inverse?s=0.5", None, 404, ["path", "name"], "No curve named"),
    ("GET", "/v1/curves/cycloyd/plot", None, 404, ["path", "name"], "No curve named"),
    ("GET", "/v1/indexers/plot?stops=6&indexing_angle_deg=270&speed_rpm=60&curve=cycloyd", None, 404,
     ["query", "curve"], "No curve named"),
    ("GET", "/v1/profiles/plot?curve=cycloyd", None, 404, ["query", "curve"], "No curve named"),
    ("POST", "/v1/curves/characteristics", {"curve": TYPO}, 404, ["body", "curve", "name"], "No curve named"),
    ("POST", "/v1/indexers/motion", {"indexer": {**INDEXER, "curve": TYPO}}, 404,
     ["body", "indexer", "curve", "name"], "No curve named"),
    ("POST", "/v1/profiles", {"profile": {"follower": {}, "base_radius_mm": 15, "segments": segments(TYPO)}}, 404,
     ["body", "profile", "segments", 0, "curve", "name"], "No curve named"),
    # off the stroke: the index of the offending value
    ("POST", "/v1/curves/inverse", {"curve": MS, "s": [0.5, 1.5]}, 422, ["body", "s", 1], "s[1] = 1.5 is outside"),
    ("GET", "/v1/curves/MS/inverse?s=0.5,1.5", None, 422, ["query", "s", 1], "s[1] = 1.5 is outside"),
    ("POST", "/v1/indexers/position", {"indexer": INDEXER, "output_angle_deg": [11, 90]}, 422,
     ["body", "output_angle_deg", 1], "output_angle_deg[1] = 90.0 is outside the index"),
    # other domain errors: the part of the request they are about
    ("POST", "/v1/curves/characteristics", {"curve": {"type": "universal", "t": [0, .25, .25, .5, 1, 1, 1, 1]}}, 422,
     ["body", "curve"], "no ratio m"),
    ("POST", "/v1/curves/characteristics", {"curve": {"type": "makino", "number": 4, "t1": 0.3, "t3": 0.2}}, 422,
     ["body", "curve"], "T1 ≤ T3"),
    ("POST", "/v1/curves/inverse", {"curve": {"type": "points", "t": [0, 1, 2, 3], "s": [0, 5, 10, 5]}, "s": [1]},
     422, ["body", "curve"], "not monotone"),
    ("POST", "/v1/profiles", {"profile": {"follower": {}, "base_radius_mm": 15, "segments": segments(return_mm=10)}},
     422, ["body", "profile", "segments"], "does not close"),
    ("POST", "/v1/profiles", {"profile": {"follower": ROLLER_ON_AN_ARM, "base_radius_mm": 20, "segments": [
        {"type": "rise", "angle_deg": 180, "swing_deg": 10}, {"type": "return", "angle_deg": 180, "swing_deg": 10}]}},
     422, ["body", "profile"], "arm cannot be assembled"),
]


@pytest.mark.parametrize(("method", "url", "body", "status", "loc", "words"), CASES,
                         ids=[f"{c[0]} {c[1][:40]} {'.'.join(map(str, c[4]))}" for c in CASES])
async def test_domain_error_names_its_field(client: httpx.AsyncClient, method: str, url: str,
                                            body: dict[str, Any] | None, status: int, loc: list[str | int],
                                            words: str) -> None:
    error = only_error(await client.request(method, url, json=body), status)
    assert error["loc"] == loc
    assert words in error["msg"]


@pytest.fixture
async def limited() -> AsyncIterator[httpx.AsyncClient]:
    app = create_app(Settings(max_table_samples=50, max_inverse_points=3, max_bezier_degree=3, max_curve_points=4))
    async with httpx.AsyncClient(transport=httpx.ASGITransport(app=app), base_url="http://testserver") as c:
        yield c


LIMITS = [
    ("POST", "/v1/curves/table", {"curve": MS, "samples": 51}, ["body", "samples"], "table samples is 51"),
    ("GET", "/v1/curves/MS/table?samples=51", None, ["query", "samples"], "table samples is 51"),
    ("POST", "/v1/curves/table", {"curve": MS, "t": [0.5] * 51}, ["body", "t"], "number of times t is 51"),
    ("POST", "/v1/curves/inverse", {"curve": MS, "s": [0.1, 0.2, 0.3, 0.4]}, ["body", "s"], "number of s values is 4"),
    ("GET", "/v1/curves/MS/inverse?s=0.1,0.2,0.3,0.4", None, ["query", "s"], "number of s values is 4"),
    ("POST", "/v1/curves/inverse", {"curve": MS, "s": [0.5], "method": "table", "table_step": 0.01}, ["body", "table_step"],
     "inverse table rows is 101"),
    ("POST", "/v1/curves/table", {"curve": {"type": "bezier", "control_points": [[i, i] for i in range(5)]}},
     ["body", "curve", "control_points"], "Bezier degree is 4"),
    ("POST", "/v1/curves/table", {"curve": {"type": "points", "t": [0, 1, 2, 3, 4], "s": [0, 1, 2, 3, 4]}},
     ["body", "curve", "t"], "number of points is 5"),
    ("POST", "/v1/indexers/motion", {"indexer": INDEXER, "samples": 51}, ["body", "samples"], "table samples is 51"),
    ("POST", "/v1/indexers/position", {"indexer": INDEXER, "output_angle_deg": [1, 2, 3, 4]},
     ["body", "output_angle_deg"], "number of output angles is 4"),
    ("POST", "/v1/profiles", {"profile": {"follower": {}, "base_radius_mm": 15, "segments": segments(
        {"type": "bezier", "control_points": [[i, i] for i in range(5)]})}, "samples": 11},
     ["body", "profile", "segments", 0, "curve", "control_points"], "Bezier degree is 4"),
    ("POST", "/v1/profiles", {"profile": {"follower": {}, "base_radius_mm": 15, "segments": segments()},
                              "cam_angle_deg": [1.0] * 51}, ["body", "cam_angle_deg"], "profile samples is 51"),
]


@pytest.mark.parametrize(("method", "url", "body", "loc", "words"), LIMITS,
                         ids=[f"{c[0]} {c[1][:40]} {'.'.join(map(str, c[3]))}" for c in LIMITS])
async def test_limit_names_the_field_that_asked_for_it(limited: httpx.AsyncClient, method: str, url: str,
                                                       body: dict[str, Any] | None, loc: list[str | int],
                                                       words: str) -> None:
    r = await limited.request(method, url, json=body)
    error = only_error(r, 413)
    assert error["loc"] == loc
    assert words in error["msg"]
    assert r.json()["limit"]["requested"] > r.json()["limit"]["limit"]


async def test_get_inverse_reads_numbers_and_names_a_bad_one(client: httpx.AsyncClient) -> None:
    # ?s= takes numbers, repeated or comma-separated; a bad one is a validation error at its index
    ok = await client.get("/v1/curves/MS/inverse?s=0&s=0.5,1")
    assert ok.status_code == 200 and ok.json()["s"] == [0.0, 0.5, 1.0]
    bad = await client.get("/v1/curves/MS/inverse?s=0.5,abc")
    assert bad.status_code == 422
    assert bad.json()["errors"] == [{"loc": ["query", "s", 1], "msg": "'abc' is not a number"}]
    # and the document types it as numbers, so generated clients send numbers (not list[str])
    spec = (await client.get("/openapi.json")).json()
    s = next(p for p in spec["paths"]["/v1/curves/{name}/inverse"]["get"]["parameters"] if p["name"] == "s")
    assert s["schema"]["type"] == "array" and s["schema"]["items"]["type"] == "number"


def _with_speed(body: dict[str, Any], path: tuple[str | int, ...], speed: Any) -> dict[str, Any]:
    import copy

    out = copy.deepcopy(body)
    node: Any = out
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = speed
    return out


def _speed_cases() -> list[Any]:
    from service.machines.specs import MACHINE_EXAMPLES
    from service.profiles.design_specs import OSCILLATING_DESIGN
    from service.profiles.dynamics_specs import DYNAMICS_EXAMPLE

    machine = next(iter(MACHINE_EXAMPLES.values()))["value"]
    return [
        pytest.param("/v1/profiles/dynamics", DYNAMICS_EXAMPLE, ("speed_rpm",), id="dynamics"),
        pytest.param("/v1/profiles/design", OSCILLATING_DESIGN, ("speed_rpm", 0), id="design-range"),
        pytest.param("/v1/machines", machine, ("master", "speed_rpm"), id="machine-master"),
        pytest.param("/v1/machines", {**machine, "speeds_rpm": [30, 60]}, ("speeds_rpm", 1), id="machine-sweep"),
    ]


@pytest.mark.parametrize(("path", "body", "where"), _speed_cases())
async def test_a_speed_below_a_micro_rpm_is_refused_at_its_field(client: httpx.AsyncClient, path: str,
                                                                 body: dict[str, Any], where: tuple[Any, ...]) -> None:
    # the smallest normal double passed a "> 0" bound, and the machine's flywheel divided by its ω² (which
    # underflows to 0): a 500; every speed now has the indexers' bound, 1e-6 rpm (a turn in 1.9 years)
    for speed in (2.2250738585072014e-308, 9.9e-7):
        r = await client.post(path, json=_with_speed(body, where, speed))
        assert r.status_code == 422, r.text
        errors = r.json()["errors"]
        # at the field (a union's branch named between, as pydantic reports a union: the design's one speed or range)
        assert any(e["loc"][:2] == ["body", where[0]] and e["loc"][-1] == where[-1]
                   and "greater than or equal to 0.000001" in e["msg"] for e in errors), errors
    assert (await client.post(path, json=_with_speed(body, where, 1e-6))).status_code in (200, 422)
