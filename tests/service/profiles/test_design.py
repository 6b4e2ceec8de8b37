"""POST /v1/profiles/design through httpx.ASGITransport.

The design's numbers are checked against brute-force grids and the existing checks in
tests/camcore/profile/test_design.py; here: the answer is camcore's, its profile is computeProfile's
answer for the designed cam to the last digit, a base radius alone is sizeBaseCircle's answer, the
constraints agree with computeFollowerDynamics, and bad bodies are 422 (or 413) at the field.
"""

from __future__ import annotations

import copy
from typing import Any

import httpx
import pytest

from service.profiles.design_specs import DESIGN_EXAMPLE, DESIGN_EXAMPLES, DESIGN_SEGMENTS, OSCILLATING_DESIGN

pytestmark = pytest.mark.anyio

URL = "/v1/profiles/design"


def body(**changes: Any) -> dict[str, Any]:
    """The roller example with fields changed (None removes one)."""
    out = copy.deepcopy(DESIGN_EXAMPLE) | changes
    return {k: v for k, v in out.items() if v is not None}


async def test_the_profile_is_compute_profile_s_answer_for_the_design(client: httpx.AsyncClient) -> None:
    r = await client.post(URL, json=DESIGN_EXAMPLE)
    assert r.status_code == 200, r.text
    answer = r.json()
    design = answer["design"]
    follower = {**DESIGN_EXAMPLE["follower"], "offset_mm": design["offset_mm"],
                "roller_radius_mm": design["roller_radius_mm"]}
    profile = await client.post("/v1/profiles", json={"profile": {
        "follower": follower, "base_radius_mm": design["base_radius_mm"], "segments": DESIGN_SEGMENTS}, "samples": 361})
    assert profile.status_code == 200, profile.text
    assert answer["profile"] == profile.json()  # the same cam, the same numbers
    # the example's limits hold by computeProfile's own checks
    checks = profile.json()["checks"]
    assert checks["max_pressure_angle_deg"] <= 30 * (1 + 1e-12) and checks["min_radius_of_curvature_mm"] >= 15 * (1 - 1e-12)
    assert answer["search"]["variables"] == ["offset_mm", "roller_radius_mm"]
    assert answer["search"]["evaluations"] > 0


async def test_the_spring_keeps_the_margin_by_compute_follower_dynamics(client: httpx.AsyncClient) -> None:
    answer = (await client.post(URL, json=DESIGN_EXAMPLE)).json()
    design = answer["design"]
    follower = {**DESIGN_EXAMPLE["follower"], "offset_mm": design["offset_mm"],
                "roller_radius_mm": design["roller_radius_mm"]}
    dynamics = await client.post("/v1/profiles/dynamics", json={
        "profile": {"follower": follower, "base_radius_mm": design["base_radius_mm"], "segments": DESIGN_SEGMENTS},
        "speed_rpm": 600, "mass_kg": 0.5, "spring_rate_n_mm": design["spring_rate_n_mm"],
        "preload_n": design["preload_n"], "safety_margin_n": 5, "samples": 3})
    assert dynamics.status_code == 200, dynamics.text
    summary = dynamics.json()["summary"]
    margin = next(c for c in answer["constraints"] if c["name"] == "safety_margin_n")
    # the same extreme, found by the same refinement: equal to rounding (1e-9 of forces of ~200 N)
    assert summary["min_contact_force_n"] == pytest.approx(margin["value"], abs=1e-9 * 200)
    assert not summary["separates"]
    # the softest rate is its lower bound here, and the preload the smallest that holds: dynamics' own
    assert design["spring_rate_n_mm"] == 0.5
    assert design["preload_n"] == pytest.approx(summary["min_preload_n"], abs=1e-9 * 200)


async def test_the_base_radius_alone_is_size_base_circle_s(client: httpx.AsyncClient) -> None:
    example = DESIGN_EXAMPLES["geometry"]["value"]
    r = await client.post(URL, json=example)
    assert r.status_code == 200, r.text
    sized = await client.post("/v1/profiles/base-circle", json={
        "profile": {"follower": example["follower"], "base_radius_mm": 10, "segments": DESIGN_SEGMENTS},
        "max_pressure_angle_deg": 30, "min_radius_of_curvature_mm": 0})
    # the roller must not undercut: a curvature limit of 0, as the design applies it
    assert r.json()["design"]["base_radius_mm"] == sized.json()["base_radius_mm"]  # to the last digit


async def test_an_oscillating_arm_is_designed_in_its_own_units(client: httpx.AsyncClient) -> None:
    r = await client.post(URL, json=OSCILLATING_DESIGN)
    assert r.status_code == 200, r.text
    design = r.json()["design"]
    assert design["offset_mm"] is None and design["spring_rate_n_mm"] is None
    assert design["spring_rate_nm_rad"] is not None and design["preload_nm"] is not None
    assert "swing_deg" in r.json()["profile"]


async def test_a_free_pivot_places_the_arm_of_compute_profile_s_cam(client: httpx.AsyncClient) -> None:
    # the pivot's search is checked against a grid of pivots in tests/camcore/profile/test_design.py; here the
    # answer's profile is computeProfile's for the arm at the designed pivot, and that cam meets the limit
    example = DESIGN_EXAMPLES["pivot"]["value"]
    r = await client.post(URL, json=example)
    assert r.status_code == 200, r.text
    answer = r.json()
    design = answer["design"]
    assert 30 < design["pivot_distance_mm"] < 120 and design["offset_mm"] is None
    assert answer["search"]["variables"] == ["pivot_distance_mm"]
    follower = {**example["follower"], "pivot_distance_mm": design["pivot_distance_mm"]}
    profile = await client.post("/v1/profiles", json={"profile": {
        "follower": follower, "base_radius_mm": design["base_radius_mm"], "segments": example["segments"]},
        "samples": 361})
    assert profile.status_code == 200, profile.text
    assert answer["profile"] == profile.json()  # the same cam, the same numbers
    assert profile.json()["checks"]["max_pressure_angle_deg"] <= 30 * (1 + 1e-12)
    active = {c["name"] for c in answer["constraints"] if c["active"]}
    assert "max_pressure_angle_deg" in active and "free.pivot_distance_mm" not in active


async def test_a_limit_no_design_meets_is_named_with_its_best_value(client: httpx.AsyncClient) -> None:
    r = await client.post(URL, json=body(free={**DESIGN_EXAMPLE["free"], "base_radius_mm": [10, 25]}))
    assert r.status_code == 422, r.text
    error = r.json()["errors"][0]
    assert error["loc"] == ["body", "limits", "max_pressure_angle_deg"]
    assert "the smallest reachable within the bounds is" in error["msg"]


@pytest.mark.parametrize(("change", "loc", "words"), [
    ({"free": {**DESIGN_EXAMPLE["free"], "offset_mm": [30, -30]}}, ["body", "free", "offset_mm"],
     "is above the upper bound"),
    ({"follower": {"type": "knife-edge"}, "free": {"base_radius_mm": [10, 200], "roller_radius_mm": [5, 20]},
      "mass_kg": None, "speed_rpm": None, "limits": {"max_pressure_angle_deg": 30}},
     ["body", "free", "roller_radius_mm"], "needs a roller follower"),
    ({"free": {"base_radius_mm": [10, 200], "pivot_distance_mm": [50, 60]}}, ["body", "free", "pivot_distance_mm"],
     "is an oscillating follower's"),
    ({"free": {"base_radius_mm": [10, 200], "arm_length_mm": [50, 60]}}, ["body", "free", "arm_length_mm"],
     "is not searched"),
    ({"mass_kg": None, "speed_rpm": None}, ["body", "free", "spring_rate_n_mm"], "need the follower's mass_kg"),
    ({"free": {"offset_mm": [-5, 5]}, "base_radius_mm": 40, "mass_kg": None, "speed_rpm": None,
      "limits": {"max_pressure_angle_deg": 30}}, ["body", "free"], "nothing to minimise"),
    ({"free": {"offset_mm": [-5, 5]}}, ["body", "base_radius_mm"], "give base_radius_mm, or free it"),
    ({"speed_rpm": None}, ["body", "speed_rpm"], "needs speed_rpm"),
    ({"speed_rpm": [900, 600]}, ["body", "speed_rpm"], "0 < lo ≤ hi"),
    ({"limits": {"allowed_stress_mpa": 300}}, ["body", "roller"], "needs roller"),
    ({"inertia_kgm2": 0.004}, ["body", "inertia_kgm2"], "not the torques of an oscillating one"),
    ({"samples": 10**6}, ["body", "samples"], "over the limit"),
], ids=["bounds", "no-roller", "pivot", "arm", "no-mass", "nothing-moves", "no-base-radius", "no-speed", "speed-order",
        "stress-without-roller", "other-motion", "samples"])
async def test_bad_bodies_name_the_field(client: httpx.AsyncClient, change: dict[str, Any], loc: list[Any],
                                         words: str) -> None:
    r = await client.post(URL, json=body(**change))
    assert r.status_code in (413, 422), r.text
    error = r.json()["errors"][0]
    assert error["loc"] == loc, r.text
    assert words in error["msg"], r.text


async def test_the_estimate_refuses_a_stress_search_over_the_budget_before_the_work(client: httpx.AsyncClient) -> None:
    # a stress limit with the offset, the roller and both spring values free: the search may run twice (the
    # geometry, then at the rate that presses least) and the stress solves with it, estimated over 1 s
    r = await client.post(URL, json=body(roller={"width_mm": 12},
                                         limits={**DESIGN_EXAMPLE["limits"], "allowed_stress_mpa": 220}))
    assert r.status_code == 413, r.text
    assert r.json()["errors"][0]["loc"] == ["body", "free"]
