"""/v1/motions through httpx.ASGITransport (docs/api.md MotionSpec; Makino (1977) §5.3).

The answers are compared with camcore.motion called directly (the numbers themselves are
checked against independent derivations in tests/test_motion*.py), and the errors for their
status, their location and their sentence.
"""

from __future__ import annotations

import copy
import csv
import io
from typing import Any

import anyio
import httpx
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from camcore.motion import SOLVE, Law, MotionSegment, MotionSpec, resolve_motion
from service.app import create_app
from service.motions.specs import FEED_CYCLE, MAKINO_CYCLE
from service.settings import Settings
from tests.service.apps import app_client

pytestmark = pytest.mark.anyio
APP = create_app()

CORE_MAKINO = MotionSpec([
    MotionSegment(60, to=40, law=Law("makino", {"number": 1, "z": 0.9})),
    MotionSegment(120, to=SOLVE, law=Law("makino", {"number": 2})),
    MotionSegment(90, to=0, law=Law("named", {"name": "48"}, "return")),
    MotionSegment(90, type="dwell")])


async def test_makino_cycle_answers_columns_segments_joins_and_characteristics(client: httpx.AsyncClient) -> None:
    r = await client.post("/v1/motions", json={"motion": MAKINO_CYCLE, "samples": 361})
    assert r.status_code == 200, r.text
    body = r.json()
    assert set(body) == {"x_deg", "s", "v", "a", "j", "unit", "period_deg", "segments", "joins", "characteristics"}
    assert len(body["x_deg"]) == 361 and body["x_deg"][0] == 0 and body["x_deg"][-1] == 360
    core = resolve_motion(CORE_MAKINO)
    s, v, a, j = core.derivatives(np.linspace(0, 360, 361))
    assert body["s"] == s.tolist() and body["v"] == v.tolist() and body["a"] == a.tolist() and body["j"] == j.tolist()
    cutting = body["segments"][1]
    assert cutting["curve"] == "makino 2" and cutting["from"] == 40
    assert cutting["solved"]["t4"] == pytest.approx(0.956864006167049, abs=1e-13)  # tests/camcore/motion/test_makino_cycle.py
    assert cutting["solved"]["stroke"] == pytest.approx(13.374929897542256, rel=1e-13)
    assert body["segments"][2]["curve"] == "one-dwell-modified-sine" and body["segments"][2]["direction"] == "return"
    assert [jn["at_deg"] for jn in body["joins"]] == [60, 180, 270, 360]
    assert all(jn["continuity"] in ("C2", "C3") for jn in body["joins"])
    assert body["characteristics"]["s_max"] == pytest.approx(53.374929897542256, rel=1e-13)
    assert body["characteristics"]["s_max_at_deg"] == 180 and body["unit"] == "mm" and body["period_deg"] == 360


async def test_speed_adds_the_time_columns(client: httpx.AsyncClient) -> None:
    r = await client.post("/v1/motions", json={"motion": FEED_CYCLE, "x_deg": [45, 150, 400], "speed_rpm": 30})
    assert r.status_code == 200, r.text
    body = r.json()
    omega = 180.0  # deg/s at 30 rpm
    assert body["x_deg"] == [45, 150, 400] and body["time_s"] == pytest.approx([45 / omega, 150 / omega, 400 / omega])
    assert body["v"][1] == pytest.approx(40 / 120) and body["v_per_s"][1] == pytest.approx(40 / 120 * omega)
    assert body["a_per_s2"] == pytest.approx([a * omega**2 for a in body["a"]])
    assert body["j_per_s3"] == pytest.approx([j * omega**3 for j in body["j"]])
    # 400° wraps to 40° of the next cycle; the program closes, so s(400) = s(40)
    again = (await client.post("/v1/motions", json={"motion": FEED_CYCLE, "x_deg": [40]})).json()
    assert body["s"][2] == pytest.approx(again["s"][0], abs=1e-12)


@pytest.mark.parametrize(("url", "headers", "with_speed"), [
    ("/v1/motions?format=csv", {}, False),
    ("/v1/motions", {"Accept": "text/csv"}, True),
    ("/v1/motions/table.csv", {}, True),
])
async def test_csv_is_the_table(client: httpx.AsyncClient, url: str, headers: dict[str, str], with_speed: bool) -> None:
    body: dict[str, Any] = {"motion": FEED_CYCLE, "samples": 13}
    if with_speed:
        body["speed_rpm"] = 10
    r = await client.post(url, json=body, headers=headers)
    assert r.status_code == 200, r.text
    assert r.headers["content-type"].startswith("text/csv")
    rows = list(csv.reader(io.StringIO(r.text)))
    expected = ["x_deg", "s", "v", "a", "j"] + (["time_s", "v_per_s", "a_per_s2", "j_per_s3"] if with_speed else [])
    assert rows[0] == expected and len(rows) == 14
    json_body = (await client.post("/v1/motions", json=body)).json()
    assert [float(row[1]) for row in rows[1:]] == json_body["s"]  # shortest round-trip floats, as the JSON


def makino_with(**changes: Any) -> dict[str, Any]:
    spec = copy.deepcopy(MAKINO_CYCLE)
    for path, value in changes.items():
        index, key = path.split("__")
        spec["segments"][int(index)][key] = value
    return spec


@pytest.mark.parametrize(("motion", "status", "loc", "words"), [
    ({"segments": [{"span_deg": 100, "to": 1}, {"span_deg": 200, "type": "dwell"}]}, 422,
     ["body", "motion", "segments"], "must add up to period_deg = 360"),  # camcore's field, carried (issue 34)
    (makino_with(**{"0__stroke": 5}), 422, ["body", "motion", "segments", 0], "not both"),
    ({"segments": [{"span_deg": 180, "type": "dwell", "curve": {"type": "named", "name": "MS"}},
                   {"span_deg": 180, "to": 1}]}, 422, ["body", "motion", "segments", 0], "a dwell holds its position"),
    ({"segments": [{"span_deg": 90, "type": "dwell"}, {"span_deg": 90, "to": 0}, {"span_deg": 180, "type": "dwell"}]},
     422, ["body", "motion", "segments", 1, "to"], "a stroke of 0 with the law 'cycloid'"),
    (makino_with(**{"1__curve": {"type": "named", "name": "cycloid"}}), 422, ["body", "motion", "segments", 1, "to"],
     "starts at rest"),
    (makino_with(**{"1__span_deg": 20, "2__span_deg": 260, "3__span_deg": 20}), 422,
     ["body", "motion", "segments", 1, "curve", "t4"], "no t4 in [0, 1)"),
    ({"segments": [{"span_deg": 180, "to": 5, "curve": {"type": "polynomial", "start": {"s": 0.5}}},
                   {"span_deg": 180, "to": 0}]}, 422, ["body", "motion", "segments", 0, "curve"], "contradict"),
    ({"segments": [{"span_deg": 120, "to": 5, "curve": {"type": "makino", "number": 2}},
                   {"span_deg": 120, "to": 10, "curve": {"type": "polynomial"}}, {"span_deg": 120, "to": 0}]}, 422,
     ["body", "motion", "segments", 1], "each take their conditions from the other"),
    (makino_with(**{"0__curve": {"type": "named", "name": "MSS"}}), 404, ["body", "motion", "segments", 0, "curve", "name"],
     "Did you mean: MS"),
])
async def test_invalid_programs_name_the_segment(client: httpx.AsyncClient, motion: dict[str, Any], status: int,
                                                 loc: list[Any], words: str) -> None:
    r = await client.post("/v1/motions", json={"motion": motion})
    assert r.status_code == status, r.text
    error = r.json()["errors"][0]
    assert error["loc"] == loc and words in error["msg"], error
    if len(loc) > 3:  # the sentence names the segment too (validation errors: their location does)
        assert r.json()["detail"].startswith(f"segments[{loc[3]}]") or "Invalid request — motion.segments" in \
            r.json()["detail"]


async def test_too_many_segments_is_413() -> None:
    async with app_client(Settings(max_motion_segments=3)) as client:
        r = await client.post("/v1/motions", json={"motion": MAKINO_CYCLE})
    assert r.status_code == 413, r.text
    assert r.json()["limit"] == {"name": "motion segments", "requested": 4, "limit": 3}
    assert r.json()["errors"][0]["loc"] == ["body", "motion", "segments"]


async def test_request_rules(client: httpx.AsyncClient) -> None:
    r = await client.post("/v1/motions", json={"motion": MAKINO_CYCLE, "samples": 10, "x_deg": [1]})
    assert r.status_code == 422 and "not both" in r.text
    r = await client.post("/v1/motions", json={"motion": MAKINO_CYCLE, "samples": 300_000})
    assert r.status_code == 413 and r.json()["limit"]["name"] == "motion samples"
    r = await client.post("/v1/motions", json={"motion": MAKINO_CYCLE, "speed_rpm": 0})
    assert r.status_code == 422
    r = await client.post("/v1/motions", content=b"{not json", headers={"Content-Type": "application/json"})
    assert r.status_code == 400


# ----------------------------------------------------------------------------- never a 500
#: laws of every kind, some leaving their ends or T4 to the program
LAWS = [None, {"type": "named", "name": "MS"}, {"type": "named", "name": "simple-harmonic", "direction": "return"},
        {"type": "named", "name": "constant-velocity"}, {"type": "makino", "number": 2},
        {"type": "makino", "number": 2, "t4": 0.5}, {"type": "makino", "number": 1, "z": 0.5},
        {"type": "universal", "t": [0, 0.1, 0.1, 0.3, 0.5, 0.75, 0.75, 1]},
        {"type": "universal", "t": [0, 0.1, 0.1, 0.3, 0.5, 0.75, 0.75, 1], "v0": 0, "direction": "return"},
        {"type": "polynomial"}, {"type": "polynomial", "start": {"s": 0, "v": 0, "a": 0}},
        {"type": "polynomial", "end": {"s": 1, "j": 0}}, {"type": "polynomial", "name": "3-4-5"},
        {"type": "points", "t": [0, 1, 2, 3], "s": [0, 0.2, 0.9, 1]},
        {"type": "bezier", "control_points": [[0, 0], [30, 0], [60, 10], [90, 10]]}]


@st.composite
def programs(draw: st.DrawFn) -> dict[str, Any]:
    n = draw(st.integers(1, 6))
    weights = draw(st.lists(st.sampled_from([1, 3, 10, 50, 100]), min_size=n, max_size=n))
    segments = []
    for i, w in enumerate(weights):
        span = 360 * w / sum(weights) if i < n - 1 else 360 - sum(360 * x / sum(weights) for x in weights[:-1])
        if draw(st.integers(0, 5)) == 0:
            segments.append({"span_deg": span, "type": "dwell"})
            continue
        seg: dict[str, Any] = {"span_deg": span}
        end = draw(st.sampled_from(["to", "stroke", "null"]))
        value = draw(st.sampled_from([-20.0, 0.0, 5.0, 40.0, 1e6]))
        seg.update({"to": value} if end == "to" else {"stroke": value} if end == "stroke" else {"to": None})
        law = draw(st.sampled_from(LAWS))
        if law is not None:
            seg["curve"] = law
        if draw(st.booleans()) and law is not None and law.get("type") == "polynomial":
            seg["match"] = "jerk"
        segments.append(seg)
    return {"motion": {"segments": segments, "start": draw(st.sampled_from([0.0, 3.0]))},
            "samples": 7, "speed_rpm": draw(st.sampled_from([None, 1e-6, 60.0, 1e6]))}


@pytest.mark.property
@settings(max_examples=150, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(body=programs())
def test_any_program_is_answered_200_or_a_4xx_with_a_sentence(body: dict[str, Any]) -> None:
    # programs valid in form, of every law and kind of end: the resolver answers or says why, never a 500
    async def call() -> httpx.Response:
        transport = httpx.ASGITransport(app=APP, raise_app_exceptions=False)
        async with httpx.AsyncClient(transport=transport, base_url="http://testserver") as c:
            return await c.post("/v1/motions", json=body)

    response = anyio.run(call)
    assert response.status_code in (200, 404, 413, 422), (body, response.text)
    if response.status_code != 200:
        assert response.json()["detail"], response.text
    else:
        answer = response.json()
        assert len(answer["joins"]) == len(body["motion"]["segments"])


def polynomials(n: int) -> dict[str, Any]:
    """A closed program of ``n`` matched quintics over 360°, to 5 and back."""
    return {"segments": [{"span_deg": 360 / n, "to": 5.0 * (i % 2 == 0) if i < n - 1 else 0.0,
                          "curve": {"type": "polynomial"}} for i in range(n)]}


async def test_work_past_the_budget_is_refused_before_any_law_is_built(client: httpx.AsyncClient) -> None:
    from service.context import Context
    from service.motions.specs import MotionProgramRequest
    from service.registry import operation

    ctx = Context.create(Settings())

    def estimate(n: int) -> float:
        body = MotionProgramRequest.model_validate({"motion": polynomials(n), "samples": 361})
        return float(operation("computeMotion").work(ctx, body).seconds)

    budget = Settings().max_work_s
    n = max(k for k in range(2, 60) if estimate(k) <= budget)
    assert n < 59 and estimate(n + 1) > budget  # matched laws are built afresh: each counts
    refused = await client.post("/v1/motions", json={"motion": polynomials(n + 1)})
    assert refused.status_code == 413, refused.text
    assert f"building the laws of {n + 1} segments" in refused.json()["detail"]
    assert refused.json()["errors"][0]["loc"] == ["body", "motion", "segments"]
    accepted = await client.post("/v1/motions", json={"motion": polynomials(n)})
    assert accepted.status_code == 200, accepted.text
    assert all(j["continuity"] in ("C2", "C3") for j in accepted.json()["joins"])


async def test_one_request_builds_its_core_spec_once(client: httpx.AsyncClient, monkeypatch: pytest.MonkeyPatch) -> None:
    """The spec is converted to camcore's terms once per request and every step (the rules, the
    estimate, the resolution) reads that one: the program and each segment are built once, and a
    segment's rules are checked once by the spec and once more by camcore's resolver (which checks
    its own input)."""
    import camcore.motion.spec as core_spec
    import service.motions.specs as motion_specs

    built = {"programs": 0, "segments": 0, "checks": 0}

    def counted(kind: str, make: Any) -> Any:
        def build(*args: Any, **kwargs: Any) -> Any:
            built[kind] += 1
            return make(*args, **kwargs)
        return build

    real_check = core_spec.check_segment

    def counted_check(*args: Any) -> None:
        built["checks"] += 1
        real_check(*args)

    monkeypatch.setattr(motion_specs, "CoreMotionSpec", counted("programs", core_spec.MotionSpec))
    monkeypatch.setattr(motion_specs, "MotionSegment", counted("segments", core_spec.MotionSegment))
    monkeypatch.setattr(motion_specs, "check_segment", counted_check)
    monkeypatch.setattr(core_spec, "check_segment", counted_check)
    segments = len(MAKINO_CYCLE["segments"])
    r = await client.post("/v1/motions", json={"motion": MAKINO_CYCLE, "samples": 361})
    assert r.status_code == 200, r.text
    assert built == {"programs": 1, "segments": segments, "checks": 2 * segments}
