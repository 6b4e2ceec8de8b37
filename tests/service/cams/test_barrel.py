"""POST /v1/cams/barrel (computeBarrelCam) and its CSV twin, over ASGI in-process.

The answer's numbers are checked from the answer itself by independent means: the pressure
angle against a numerical derivative of the answered lift column; the flank points against the
roller's axis rebuilt from the answered swing and cam angle; CSV against JSON. Bad geometry is
a 422 naming the field and the rule; an undercut groove is a failed check, as for plate cams.
"""

from __future__ import annotations

import copy
import math
from typing import Any

import httpx
import numpy as np
import pytest

from service.app import create_app
from service.cams.barrel_specs import BARREL_EXAMPLE, CONICAL_BARREL_EXAMPLE, OSCILLATING_BARREL_EXAMPLE
from service.settings import Settings

pytestmark = pytest.mark.anyio

CYCLOID_BODY: dict[str, Any] = {
    "pitch_radius_mm": 50, "roller_radius_mm": 10, "roller_length_mm": 12,
    "segments": [{"type": "rise", "angle_deg": 120, "lift_mm": 30}, {"type": "dwell", "angle_deg": 60},
                 {"type": "return", "angle_deg": 120, "lift_mm": 30}, {"type": "dwell", "angle_deg": 60}],
    "samples": 3601}


def body(base: dict[str, Any], **changes: Any) -> dict[str, Any]:
    out = copy.deepcopy(base)
    out.update(changes)
    return {k: v for k, v in out.items() if v is not None}


async def test_pressure_angle_is_atan_of_the_answered_lifts_slope_over_the_pitch_radius(
        client: httpx.AsyncClient) -> None:
    r = await client.post("/v1/cams/barrel", json=CYCLOID_BODY)
    assert r.status_code == 200, r.text
    a = r.json()
    deg, lift = np.array(a["cam_angle_deg"]), np.array(a["lift_mm"])
    step = math.radians(deg[1] - deg[0])
    slope = (lift[2:] - lift[:-2]) / (2 * step)
    # away from the breaks at multiples of 60° (the slope's second derivative jumps there); the
    # difference errs by h²/6·|s'''| ≤ (1.7e-3)²/6·130 ≈ 7e-5 mm/rad: 1e-6 rad of angle at R = 50
    inner = np.abs(((deg[1:-1] + 30) % 60) - 30) > 0.2
    expected = np.degrees(np.arctan(slope / 50))
    assert np.abs(np.array(a["pressure_angle_deg"])[1:-1][inner] - expected[inner]).max() < 1e-4
    assert np.array(a["u_mm"]) == pytest.approx(50 * np.radians(deg), abs=1e-12)
    assert a["y_mm"] == a["lift_mm"]
    assert a["checks"]["max_pressure_angle_deg"] == pytest.approx(math.degrees(math.atan(60 / (2 * math.pi / 3) / 50)),
                                                                   abs=1e-9)
    assert not a["checks"]["undercut"]


async def test_oscillating_flank_points_lie_at_the_roller_radius_from_its_axis(client: httpx.AsyncClient) -> None:
    spec = OSCILLATING_BARREL_EXAMPLE
    r = await client.post("/v1/cams/barrel", json=spec)
    assert r.status_code == 200, r.text
    a = r.json()
    length, psi0 = float(spec["arm_length_mm"]), float(spec["initial_arm_angle_deg"])  # type: ignore[arg-type]
    positions = np.array(a["roller_position_mm"])
    assert positions == pytest.approx(np.linspace(55, 65, 3))
    for i, (deg, swing) in enumerate(zip(a["cam_angle_deg"], a["swing_deg"], strict=True)):
        theta, arm = math.radians(deg), math.radians(psi0 + swing)
        # the roller's axis in the fixed frame (pivot (x, −L, 0), arm turned by ψa), turned into the cam's
        point = np.array([0.0, length * math.cos(arm) - length, length * math.sin(arm)])
        turn = np.array([[math.cos(theta), -math.sin(theta), 0], [math.sin(theta), math.cos(theta), 0], [0, 0, 1]])
        q, e = turn @ point, turn @ np.array([1.0, 0.0, 0.0])
        for name in ("upper", "lower"):
            flank = a["flanks"][name]
            for j, x in enumerate(positions):
                p = np.array([flank["x_mm"][i][j], flank["y_mm"][i][j], flank["z_mm"][i][j]])
                w = p - q
                # on the roller (8 mm) at position x along its axis; ~1e-13 mm of rounding in ~70 mm
                assert float(w @ e) == pytest.approx(x, abs=1e-9)
                assert float(np.linalg.norm(w - (w @ e) * e)) == pytest.approx(8.0, abs=1e-9)
        # the upper wall is on the +z side of the roller's axis, the lower one on the −z side
        assert a["flanks"]["upper"]["z_mm"][i][1] > q[2] > a["flanks"]["lower"]["z_mm"][i][1]


async def test_csv_has_the_json_columns(client: httpx.AsyncClient) -> None:
    spec = body(BARREL_EXAMPLE, samples=13)
    js = (await client.post("/v1/cams/barrel", json=spec)).json()
    for csv in [await client.post("/v1/cams/barrel?format=csv", json=spec),
                await client.post("/v1/cams/barrel", json=spec, headers={"Accept": "text/csv"}),
                await client.post("/v1/cams/barrel.csv", json=spec)]:
        assert csv.status_code == 200 and csv.headers["content-type"].startswith("text/csv")
        lines = csv.text.strip().split("\n")
        header = lines[0].split(",")
        assert header[:8] == ["cam_angle_deg", "lift_mm", "u_mm", "y_mm", "pressure_angle_deg",
                              "pressure_angle_inner_deg", "pressure_angle_outer_deg", "pitch_radius_of_curvature_mm"]
        rows = [line.split(",") for line in lines[1:]]
        assert len(rows) == 13
        for k, name in enumerate(header[:7]):
            assert [float(row[k]) for row in rows] == js[name]  # shortest round-trip text both ways
        upper = [None if row[8] == "" else float(row[8]) for row in rows]
        assert upper == js["flanks"]["upper"]["radius_of_curvature_mm"]


async def test_the_conical_example_reports_its_half_angle(client: httpx.AsyncClient) -> None:
    r = await client.post("/v1/cams/barrel", json=CONICAL_BARREL_EXAMPLE)
    assert r.status_code == 200, r.text
    checks = r.json()["checks"]
    assert checks["cone_half_angle_deg"] == pytest.approx(math.degrees(math.atan(10 / 80)), rel=1e-15)
    assert checks["bottom_clearance_mm"] == 2.0 and checks["groove_bottom_radius_mm"] == 70.0


async def test_undercut_is_a_failed_check(client: httpx.AsyncClient) -> None:
    # the pitch curve's smallest radius is 64.1 mm (cycloid, 30 mm in 120° on R = 50): a 70 mm roller cannot cut it
    r = await client.post("/v1/cams/barrel", json=body(CYCLOID_BODY, roller_radius_mm=70, samples=37))
    assert r.status_code == 200, r.text
    checks = r.json()["checks"]
    assert checks["undercut"] and checks["undercut_upper"] and checks["undercut_lower"]
    assert checks["min_radius_of_curvature_upper_mm"] < 0


@pytest.mark.parametrize(("changes", "words"), [
    ({"roller_length_mm": 100}, "must be less than twice pitch_radius_mm"),
    ({"groove_depth_mm": 11}, "must be at least roller_length_mm"),
    ({"groove_depth_mm": 56}, "the groove would cut through the axis"),
    ({"roller": "conical", "follower": "oscillating", "arm_length_mm": 80}, "a conical roller rolls on a translating"),
    ({"follower": "oscillating"}, "needs arm_length_mm"),
    ({"motion": {"unit": "mm", "segments": [{"span_deg": 180, "to": 10}, {"span_deg": 180, "to": 0}]}},
     "as segments or as a motion program"),
])
async def test_bad_geometry_is_a_422_naming_the_rule(client: httpx.AsyncClient, changes: dict[str, Any],
                                                     words: str) -> None:
    r = await client.post("/v1/cams/barrel", json=body(CYCLOID_BODY, samples=5, **changes))
    assert r.status_code == 422, r.text
    assert words in r.text


async def test_an_arm_that_turns_too_far_is_a_422_naming_the_field(client: httpx.AsyncClient) -> None:
    spec = body(OSCILLATING_BARREL_EXAMPLE, initial_arm_angle_deg=70)
    r = await client.post("/v1/cams/barrel", json=spec)
    assert r.status_code == 422, r.text
    assert r.json()["errors"][0]["loc"] == ["body", "initial_arm_angle_deg"]
    assert "it must stay within ±89.0° of square to the cam axis" in r.text
    spec = body(OSCILLATING_BARREL_EXAMPLE, arm_length_mm=300, initial_arm_angle_deg=-40)
    r = await client.post("/v1/cams/barrel", json=spec)
    assert r.status_code == 422 and r.json()["errors"][0]["loc"] == ["body", "arm_length_mm"], r.text


#: issue 33: an oscillating follower's rules answered loc ["body"] (a model validator's error sits
#: at the model); each names the field that breaks it
MM_MOTION = {"unit": "mm", "segments": [{"span_deg": 180, "to": 10}, {"span_deg": 180, "to": 0}]}


@pytest.mark.parametrize(("changes", "loc"), [
    ({"follower": "oscillating"}, ["body", "arm_length_mm"]),
    ({"follower": "oscillating", "arm_length_mm": 80}, ["body", "segments", 0, "lift_mm"]),
    ({"roller": "conical", "follower": "oscillating", "arm_length_mm": 80}, ["body", "roller"]),
    ({"segments": None, "motion": MM_MOTION, "follower": "oscillating", "arm_length_mm": 80},
     ["body", "motion", "unit"]),
    ({"segments": [{"type": "rise", "angle_deg": 180, "swing_deg": 10}, {"type": "return", "angle_deg": 180,
                                                                         "lift_mm": 10}]},
     ["body", "segments", 0, "swing_deg"]),
    ({"segments": CYCLOID_BODY["segments"][:3]}, ["body", "segments"]),
])
async def test_a_broken_follower_rule_is_a_422_naming_the_field(client: httpx.AsyncClient, changes: dict[str, Any],
                                                                loc: list[str | int]) -> None:
    r = await client.post("/v1/cams/barrel", json=body(CYCLOID_BODY, samples=5, **changes))
    assert r.status_code == 422, r.text
    assert [e["loc"] for e in r.json()["errors"]] == [loc], r.text


async def test_the_flank_grid_is_bounded_by_the_table_limit() -> None:
    transport = httpx.ASGITransport(app=create_app(Settings(max_table_samples=1000)))
    async with httpx.AsyncClient(transport=transport, base_url="http://testserver") as client:
        r = await client.post("/v1/cams/barrel", json=body(BARREL_EXAMPLE, samples=201, length_samples=5))
        assert r.status_code == 413, r.text
        assert "barrel cam samples × length_samples is 1005, over the limit of 1000" in r.text
        r = await client.post("/v1/cams/barrel", json=body(BARREL_EXAMPLE, samples=200, length_samples=5))
        assert r.status_code == 200, r.text
