"""Profiles driven by a motion program and indexers driven by a timing chart, over HTTP
(docs/api.md: ProfileSpec ``motion``, IndexerSpec ``timing``).

The numbers are checked against the service's own other answers: a program's lift must be
/v1/motions' position at the same angles, a program equal to a segment schedule must give the
segment schedule's cam, and a timing chart of one index must size like the single-curve
indexer (the guide's example); camcore's own tests check the formulas behind them.
"""

from __future__ import annotations

from typing import Any

import httpx
import numpy as np
import pytest

from service.indexers.specs import INDEXER_EXAMPLE, LOAD_EXAMPLE, TIMING_INDEXER_EXAMPLE
from service.motions.specs import MAKINO_CYCLE
from service.profiles.specs import ROLLER_PROFILE_EXAMPLE

pytestmark = pytest.mark.anyio

ROLLER = {"type": "roller", "roller_radius_mm": 10}
#: ROLLER_PROFILE_EXAMPLE's schedule as a program: 20 mm over 120° (MS), dwell, back (the
#: default law of both: the cycloid), dwell
SCHEDULE_AS_PROGRAM = {"unit": "mm", "segments": [
    {"span_deg": 120, "to": 20, "curve": {"type": "named", "name": "MS"}}, {"span_deg": 60, "type": "dwell"},
    {"span_deg": 120, "to": 0}, {"span_deg": 60, "type": "dwell"}]}
#: the guide's indexer (6 stops, θh = 270°, MS, 60 rpm) as a timing chart
ONE_INDEX = {"speed_rpm": 60, "timing": {"unit": "deg", "segments": [
    {"span_deg": 270, "stroke": 60, "curve": {"type": "named", "name": "MS"}}, {"span_deg": 90, "type": "dwell"}]}}


def profile(**fields: Any) -> dict[str, Any]:
    return {"follower": ROLLER, "base_radius_mm": 60, **fields}


async def test_a_profile_follows_makinos_cutting_cycle(client: httpx.AsyncClient) -> None:
    angles = [0, 30, 60, 100, 180, 225, 270, 300, 359]
    r = await client.post("/v1/profiles", json={"profile": profile(motion=MAKINO_CYCLE), "cam_angle_deg": angles})
    assert r.status_code == 200, r.text
    cam = r.json()
    m = await client.post("/v1/motions", json={"motion": MAKINO_CYCLE, "x_deg": angles})
    # one cam turn = one period of master angle (rotation_ratio 1); the cam angle goes to radians
    # and back, a rounding of the angle (1e-16 relative) times the slope
    assert cam["lift_mm"] == pytest.approx(m.json()["s"], rel=1e-13, abs=1e-13)
    assert cam["checks"]["undercut"] is False


async def test_a_program_equal_to_a_schedule_gives_the_same_cam(client: httpx.AsyncClient) -> None:
    schedule = await client.post("/v1/profiles", json={"profile": ROLLER_PROFILE_EXAMPLE, "samples": 73})
    program = await client.post("/v1/profiles", json={
        "profile": {**ROLLER_PROFILE_EXAMPLE, "segments": None, "motion": SCHEDULE_AS_PROGRAM}, "samples": 73})
    assert schedule.status_code == program.status_code == 200, program.text
    ours, theirs = program.json(), schedule.json()
    # the same closed forms through two chain rules (program: x in degrees; schedule: radians)
    for name in ("lift_mm", "x_mm", "y_mm", "pressure_angle_deg", "radius_of_curvature_mm"):
        assert np.allclose(ours[name], theirs[name], rtol=1e-12, atol=1e-9), name
    assert ours["checks"]["max_pressure_angle_deg"] == pytest.approx(theirs["checks"]["max_pressure_angle_deg"],
                                                                     rel=1e-9)
    base = await client.post("/v1/profiles/base-circle", json={
        "profile": {**ROLLER_PROFILE_EXAMPLE, "segments": None, "motion": SCHEDULE_AS_PROGRAM},
        "max_pressure_angle_deg": 30})
    base_schedule = await client.post("/v1/profiles/base-circle", json={"profile": ROLLER_PROFILE_EXAMPLE,
                                                                        "max_pressure_angle_deg": 30})
    assert base.json()["base_radius_mm"] == pytest.approx(base_schedule.json()["base_radius_mm"], rel=1e-9)


async def test_an_oscillating_follower_takes_a_program_in_degrees(client: httpx.AsyncClient) -> None:
    follower = {"type": "roller", "motion": "oscillating", "roller_radius_mm": 5, "arm_length_mm": 50,
                "pivot_distance_mm": 70}
    swing = {**SCHEDULE_AS_PROGRAM, "unit": "deg"}
    r = await client.post("/v1/profiles", json={"profile": profile(follower=follower, base_radius_mm=30,
                                                                   motion=swing), "samples": 13})
    assert r.status_code == 200, r.text
    assert max(r.json()["swing_deg"]) == 20 and "lift_mm" not in r.json()
    wrong = await client.post("/v1/profiles", json={"profile": profile(follower=follower, base_radius_mm=30,
                                                                       motion=SCHEDULE_AS_PROGRAM)})
    assert wrong.status_code == 422 and "motion program is in deg" in wrong.json()["detail"]


async def test_program_errors_name_their_place_in_the_profile(client: httpx.AsyncClient) -> None:
    open_program = {"segments": [{"span_deg": 180, "to": 20}, {"span_deg": 180, "to": 10}]}
    r = await client.post("/v1/profiles", json={"profile": profile(motion=open_program)})
    assert r.status_code == 422 and "does not close" in r.json()["detail"]
    assert r.json()["errors"][0]["loc"] == ["body", "profile", "motion", "segments"]
    two_lobes = {"period_deg": 180, "segments": [{"span_deg": 90, "to": 20}, {"span_deg": 90, "to": 0}]}
    assert (await client.post("/v1/profiles", json={"profile": profile(motion=two_lobes)})).status_code == 200
    odd = {"period_deg": 300, "segments": [{"span_deg": 150, "to": 20}, {"span_deg": 150, "to": 0}]}
    r = await client.post("/v1/profiles", json={"profile": profile(motion=odd)})
    assert r.status_code == 422 and "whole number of times" in r.json()["detail"]
    assert r.json()["errors"][0]["loc"] == ["body", "profile", "motion"]
    bad_law = {"segments": [{"span_deg": 180, "to": 20, "curve": {"type": "named", "name": "nope"}},
                            {"span_deg": 180, "to": 0}]}
    r = await client.post("/v1/profiles", json={"profile": profile(motion=bad_law)})
    assert r.status_code == 404  # an unknown curve name, as everywhere
    assert r.json()["errors"][0]["loc"][:6] == ["body", "profile", "motion", "segments", 0, "curve"]


async def test_a_timing_chart_of_one_index_sizes_like_the_guides_indexer(client: httpx.AsyncClient) -> None:
    chart = await client.post("/v1/indexers/sizing", json={"indexer": ONE_INDEX, "load": LOAD_EXAMPLE})
    single = await client.post("/v1/indexers/sizing", json={"indexer": INDEXER_EXAMPLE, "load": LOAD_EXAMPLE})
    assert chart.status_code == single.status_code == 200, chart.text
    for name, value in single.json().items():
        if value is not None and name != "input_torque_table":  # two orders of the same products: rounding only
            assert chart.json()[name] == pytest.approx(value, rel=1e-12, abs=1e-12), name
    for name, column in single.json()["input_torque_table"].items():
        assert chart.json()["input_torque_table"][name] == pytest.approx(column, rel=1e-12, abs=1e-12), name
    motion = await client.post("/v1/indexers/motion", json={"indexer": ONE_INDEX, "samples": 5})
    assert motion.json()["table"]["input_angle_deg"] == [0, 90, 180, 270, 360]  # the whole input turn
    position = await client.post("/v1/indexers/position", json={"indexer": ONE_INDEX, "output_angle_deg": [11]})
    guide = await client.post("/v1/indexers/position", json={"indexer": INDEXER_EXAMPLE, "output_angle_deg": [11]})
    assert position.json()["input_angle_deg"] == pytest.approx(guide.json()["input_angle_deg"], rel=1e-14)


async def test_the_oscillating_units_chart(client: httpx.AsyncClient) -> None:
    r = await client.post("/v1/indexers/motion", json={"indexer": TIMING_INDEXER_EXAMPLE, "samples": 7})
    assert r.status_code == 200, r.text
    summary, table = r.json()["summary"], r.json()["table"]
    assert (summary["displacement_deg"], summary["dwells"], summary["stops"]) == (90, 2, 4)
    assert table["output_angle_deg"][0] == 0 and table["output_angle_deg"][2] == 90  # out by 120°
    assert table["output_angle_deg"][-1] == 0  # and back
    r = await client.post("/v1/indexers/position", json={"indexer": TIMING_INDEXER_EXAMPLE,
                                                         "output_angle_deg": [45], "method": "table"})
    assert r.status_code == 422 and r.json()["errors"][0]["loc"] == ["body", "method"]
    r = await client.post("/v1/indexers/position", json={"indexer": TIMING_INDEXER_EXAMPLE, "output_angle_deg": [100]})
    assert r.status_code == 422 and "between 0.0° and 90.0°" in r.json()["detail"]


async def test_timing_chart_errors_name_their_place(client: httpx.AsyncClient) -> None:
    still = {"speed_rpm": 60, "timing": {"unit": "deg", "segments": [{"span_deg": 360, "type": "dwell"}]}}
    r = await client.post("/v1/indexers/motion", json={"indexer": still})
    assert r.status_code == 422 and "never moves" in r.json()["detail"]
    assert r.json()["errors"][0]["loc"] == ["body", "indexer", "timing", "segments"]
    r = await client.post("/v1/indexers/motion", json={"indexer": {**ONE_INDEX, "stops": 6}})
    assert r.status_code == 422 and "a timing chart replaces stops" in r.json()["detail"]
    too_many = {"speed_rpm": 60, "timing": {"unit": "deg", "segments": [{"span_deg": 1, "stroke": 1}] * 360}}
    r = await client.post("/v1/indexers/sizing", json={"indexer": too_many, "load": LOAD_EXAMPLE})
    assert r.status_code == 413 and r.json()["errors"][0]["loc"] == ["body", "indexer", "timing", "segments"]


def _compressed(program: dict[str, Any], period_deg: float) -> dict[str, Any]:
    """The program with its spans scaled to a cycle of ``period_deg``."""
    scale = period_deg / program.get("period_deg", 360)
    return {**program, "period_deg": period_deg,
            "segments": [{**s, "span_deg": s["span_deg"] * scale} for s in program["segments"]]}


async def test_a_program_repeated_over_1000_times_a_turn_is_a_422_at_its_period(client: httpx.AsyncClient) -> None:
    """Found by fuzzing (2026-12-07): a barrel cam's solid estimated its stations over a list of the
    program's copies on one turn, 360°/period of them, before anything refused the period: at
    1e-6° (a span's least) 3.6e8 copies, gigabytes and minutes in the estimate; at 0.01° a 413 about
    the tolerance. The JSON answer named motion.rotation_ratio, a field a barrel cam has not. Now
    every cam with a program refuses over 1000 periods a turn (camcore.profile.lift) with a 422 at
    the field the user can change: the period, or a plate cam's rotation_ratio."""
    from service.cams.barrel_specs import CONICAL_BARREL_EXAMPLE
    from service.machines.specs import FOUR_KINDS_EXAMPLE

    solid = {"tolerance_mm": 0.05, "bore_diameter_mm": 20}
    # the feed cycle in 0.01°, and the shortest program of all: one dwell of the least span
    least = {"unit": "mm", "period_deg": 1e-6, "segments": [{"span_deg": 1e-6, "type": "dwell"}]}
    for program in (_compressed(CONICAL_BARREL_EXAMPLE["motion"], 0.01), least):
        barrel = {**CONICAL_BARREL_EXAMPLE, "motion": program}
        for path, body in (("/v1/cams/barrel", barrel), ("/v1/cams/barrel.step", {**barrel, "solid": solid}),
                           ("/v1/cams/barrel.stl", {**barrel, "solid": solid})):
            r = await client.post(path, json=body)
            assert r.status_code == 422, (path, program["period_deg"], r.text)
            assert r.json()["errors"][0]["loc"] == ["body", "motion", "period_deg"], r.text
            assert "more than 1000 periods of the motion program" in r.json()["detail"]
    # a machine's motion axis: one camshaft turn a cycle
    axes = [dict(axis) for axis in FOUR_KINDS_EXAMPLE["axes"]]
    pusher = next(i for i, axis in enumerate(axes) if "motion" in axis)
    axis_motion = axes[pusher]["motion"]
    axes[pusher] = {**axes[pusher], "motion": {**axis_motion, "motion": _compressed(axis_motion["motion"], 0.01)}}
    r = await client.post("/v1/machines", json={**FOUR_KINDS_EXAMPLE, "axes": axes})
    assert r.status_code == 422, r.text
    assert r.json()["errors"][0]["loc"] == ["body", "axes", pusher, "motion", "motion", "period_deg"], r.text
    # a plate cam: γ sets the master angle of a cam turn, so γ is the field to change
    r = await client.post("/v1/profiles", json={"profile": profile(motion=SCHEDULE_AS_PROGRAM, rotation_ratio=1e-4)})
    assert r.status_code == 422, r.text
    assert r.json()["errors"][0]["loc"] == ["body", "profile", "rotation_ratio"], r.text
    assert "raise rotation_ratio" in r.json()["detail"]
