"""POST /v1/cams/barrel/toolpath (computeBarrelToolpath) over ASGI in-process.

The answer is camcore's toolpath as it is (camcore.cams.barrel.toolpath, checked against the
exact geometry in tests/camcore/cams/test_barrel_toolpath.py): here the nodes of the JSON answer
lie on the groove's centre line computed from the answered columns of POST /v1/cams/barrel
(a second operation of the service), the G-code of ``?format=``, the body's ``format`` and the
twin is the same program, the defaults of the heights are the cam's radii, refusals name their
field, the limits answer 413, and the estimate bounds the work of every example.
"""

from __future__ import annotations

import copy
import gc
import math
import time
from typing import Any

import httpx
import numpy as np
import pytest

from camcore.export.barrel_toolpath import BARREL_TOOLPATH_FORMATS
from service.app import create_app
from service.cams import barrel_toolpath
from service.cams.barrel_specs import BARREL_EXAMPLE, OSCILLATING_BARREL_EXAMPLE
from service.cams.barrel_toolpath import BARREL_TOOLPATH_EXAMPLES
from service.context import Context
from service.operations import JSON
from service.settings import Settings
from tests.estimates import within_estimate
from tests.toolpath_reference import parse_gcode

pytestmark = pytest.mark.anyio

ROLLER = {"cam": BARREL_EXAMPLE, "tool_radius_mm": 10, "tolerance_mm": 0.01}


def changed(base: dict[str, Any], **fields: Any) -> dict[str, Any]:
    out = copy.deepcopy(base)
    out.update(fields)
    return out


async def test_the_nodes_lie_on_the_groove_centre_line_of_the_barrel_operation(client: httpx.AsyncClient) -> None:
    r = await client.post("/v1/cams/barrel/toolpath", json=ROLLER)
    assert r.status_code == 200, r.text
    answer = r.json()
    (one,) = answer["passes"]
    assert one["wall"] == "groove" and one["offset_mm"] == 0 and one["direction"] == "A rising"
    assert answer["moves_count"] == one["moves_count"] == len(one["a_deg"]) - 1
    assert 0 < answer["max_deviation_mm"] <= 0.01 and answer["wrap_diameter_mm"] == 100
    # the cam's own answer at 0.01°: its developed centre line (u = R·θ, y = s), interpolated at the
    # nodes; a cubic's error at that spacing is ~h⁴·s''''/384 < 1e-12 mm
    groove = (await client.post("/v1/cams/barrel", json=changed(BARREL_EXAMPLE, samples=36001,
                                                                 length_samples=2))).json()
    theta = np.asarray(groove["cam_angle_deg"])
    y = np.asarray(groove["y_mm"])
    nodes = np.asarray(one["cam_angle_deg"])
    k = np.clip(np.searchsorted(theta, nodes), 2, len(theta) - 2)
    coefficients = [np.polyfit(theta[i - 2:i + 2], y[i - 2:i + 2], 3) for i in k]
    expected = np.array([np.polyval(c, t) for c, t in zip(coefficients, nodes)])
    assert np.asarray(one["x_mm"]) == pytest.approx(expected, abs=1e-9)
    assert one["a_deg"] == pytest.approx(one["cam_angle_deg"], abs=1e-12)  # the cutter is the roller: A = θ
    assert (answer["safe_z_mm"], answer["cut_z_mm"]) == (56 + 5, 56 - 12)  # outer radius + 5, the groove's bottom


async def test_the_program_by_format_by_body_and_by_its_twin(client: httpx.AsyncClient) -> None:
    fmt = BARREL_TOOLPATH_FORMATS["gcode"]
    body = changed(ROLLER, tool_radius_mm=8, safe_z_mm=70, cut_z_mm=50)
    answers = [await client.post("/v1/cams/barrel/toolpath?format=gcode", json=body),
               await client.post("/v1/cams/barrel/toolpath", json={**body, "format": "gcode"}),
               await client.post("/v1/cams/barrel/toolpath.gcode", json=body)]
    for r in answers:
        assert r.status_code == 200, r.text
        assert r.headers["content-type"] == fmt.media_type
        assert r.headers["content-disposition"] == f'attachment; filename="{fmt.file_name}"'
    assert answers[0].content == answers[1].content == answers[2].content
    moves = parse_gcode(answers[0].text)
    assert {m["z"] for m in moves} == {70.0, 50.0}
    json_answer = (await client.post("/v1/cams/barrel/toolpath", json=body)).json()
    # the tests' own reader keeps X Y Z: every feed move is at the cutting depth but the plunges, one a pass
    feeds = [m for m in moves if m["g"] == 1.0]
    assert all(m["z"] == 50.0 for m in feeds)
    assert len(feeds) == json_answer["moves_count"] + len(json_answer["passes"])
    assert "G93" in answers[0].text and "wrap diameter 100 mm" in answers[0].text


@pytest.mark.parametrize(("change", "loc"), [
    ({"tool_radius_mm": 10.5}, ["body", "tool_radius_mm"]),
    ({"tool_radius_mm": 4}, ["body", "tool_radius_mm"]),
    ({"safe_z_mm": 56}, ["body", "safe_z_mm"]),
    ({"cut_z_mm": 43.9}, ["body", "cut_z_mm"]),
    ({"cut_z_mm": 56}, ["body", "cut_z_mm"]),
    ({"cam": changed(BARREL_EXAMPLE, roller="conical")}, ["body", "cam", "roller"]),
    ({"cam": OSCILLATING_BARREL_EXAMPLE, "tool_radius_mm": 8}, ["body", "cam", "follower"]),
    ({"cam": changed(BARREL_EXAMPLE, pitch_radius_mm=-1)}, ["body", "cam", "pitch_radius_mm"]),
    ({"tolerance_mm": 0}, ["body", "tolerance_mm"]),
])
async def test_refusals_name_the_field(client: httpx.AsyncClient, change: dict[str, Any], loc: list[str]) -> None:
    r = await client.post("/v1/cams/barrel/toolpath", json=changed(ROLLER, **change))
    assert r.status_code == 422, r.text
    assert r.json()["errors"][0]["loc"] == loc


async def test_a_corner_the_smaller_cutter_cannot_follow_is_a_422_at_the_tool_radius(client: httpx.AsyncClient) -> None:
    corner = changed(BARREL_EXAMPLE, segments=[
        {"type": "rise", "angle_deg": 180, "lift_mm": 20, "curve": {"type": "named", "name": "constant-velocity"}},
        {"type": "return", "angle_deg": 180, "lift_mm": 20, "curve": {"type": "named", "name": "constant-velocity"}}])
    r = await client.post("/v1/cams/barrel/toolpath", json=changed(ROLLER, cam=corner, tool_radius_mm=8))
    assert r.status_code == 422 and r.json()["errors"][0]["loc"] == ["body", "tool_radius_mm"], r.text
    r = await client.post("/v1/cams/barrel/toolpath", json=changed(ROLLER, cam=corner))
    assert r.status_code == 200 and r.json()["moves_count"] == 2


async def test_limits_are_413() -> None:
    app = create_app(Settings(max_toolpath_elements=100))
    async with httpx.AsyncClient(transport=httpx.ASGITransport(app=app), base_url="http://t") as client:
        r = await client.post("/v1/cams/barrel/toolpath", json=changed(ROLLER, tolerance_mm=1e-4))
        assert r.status_code == 413, r.text
        assert r.json()["errors"][0]["loc"] == ["body", "tolerance_mm"]
    app = create_app(Settings(max_work_s=0.005))
    async with httpx.AsyncClient(transport=httpx.ASGITransport(app=app), base_url="http://t") as client:
        r = await client.post("/v1/cams/barrel/toolpath", json=ROLLER)
        assert r.status_code == 413 and "estimated work" in r.text


@pytest.mark.timing
@pytest.mark.parametrize("value", [*(e["value"] for e in BARREL_TOOLPATH_EXAMPLES.values()),
                                   changed(ROLLER, tool_radius_mm=6, tolerance_mm=1e-4)],
                         ids=[*BARREL_TOOLPATH_EXAMPLES, "fine"])
@pytest.mark.parametrize("fmt", ["json", "gcode"])
def test_the_estimate_bounds_the_work(value: dict[str, Any], fmt: str) -> None:
    """The common test (tests/service/operations) runs the first example; here every one and a fine tolerance,
    from cold caches, the work the thread's CPU time."""
    (operation,) = barrel_toolpath.OPERATIONS
    assert operation.request is not None
    ctx = Context.create(Settings())
    core = operation.convert(ctx, operation.request.model_validate(value), {})
    chosen = JSON if fmt == "json" else operation.format(fmt)
    estimate = operation.estimate(ctx, core, chosen).seconds
    assert estimate <= Settings().max_work_s
    gc.disable()
    try:
        start = time.thread_time()
        operation.compute(ctx, core, chosen)
        seconds = time.thread_time() - start
    finally:
        gc.enable()
    assert within_estimate(seconds, estimate), f"{seconds:.4f} s, estimated {estimate:.4f} s"
    assert math.isfinite(estimate)
