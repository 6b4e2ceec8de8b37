"""POST /v1/profiles/dynamics and GET /v1/profiles/dynamics/plot through httpx.ASGITransport.

The numbers themselves are checked against hand derivations in tests/camcore/profile/test_dynamics.py; here:
the answer is camcore's (same cam, same figures), JSON and CSV agree, the rules of the body give
a 422 with the sentence and the field, limits give 413, and the chart is a real image.
"""

from __future__ import annotations

import copy
import csv
import io
import re

import httpx
import numpy as np
import pytest

from camcore.profile import Follower, Segment, make_cam
from camcore.profile.dynamics import RollerMaterials, TranslatingLoad, follower_dynamics
from service.profiles.dynamics_specs import DYNAMICS_EXAMPLES, OSCILLATING_PROFILE
from tests.service.test_charts import check_png, check_svg, svg_texts

pytestmark = pytest.mark.anyio

URL = "/v1/profiles/dynamics"
PLOT = "/v1/profiles/dynamics/plot"
CYCLOID_CAM = {"follower": {"type": "roller", "roller_radius_mm": 10}, "base_radius_mm": 40,
               "segments": [{"type": "rise", "angle_deg": 120, "lift_mm": 20}, {"type": "dwell", "angle_deg": 60},
                            {"type": "return", "angle_deg": 180, "lift_mm": 20}]}
BODY = {"profile": CYCLOID_CAM, "speed_rpm": 800, "mass_kg": 0.5, "spring_rate_n_mm": 2, "preload_n": 30,
        "safety_margin_n": 5, "roller": {"width_mm": 12}, "samples": 37}
OSC_BODY = {"profile": OSCILLATING_PROFILE, "speed_rpm": 400, "inertia_kgm2": 0.004, "spring_rate_nm_rad": 20,
            "preload_nm": 3, "samples": 19}
COLUMNS = ["cam_angle_deg", "time_s", "lift", "velocity", "acceleration", "spring_force", "contact_force_n",
           "normal_force_n", "camshaft_torque_nm", "contact_stress_mpa"]


async def test_the_answer_is_camcore_s(client: httpx.AsyncClient) -> None:
    r = await client.post(URL, json=BODY)
    assert r.status_code == 200, r.text
    body = r.json()
    cam = make_cam(Follower("roller", roller_radius_mm=10), 40, segments=[
        Segment("rise", 120, 20), Segment("dwell", 60), Segment("return", 180, 20)])
    core = follower_dynamics(cam, TranslatingLoad(0.5, 2, 30), 800, 37, safety_margin_n=5,
                             roller=RollerMaterials(12))
    assert body["unit"] == "mm"
    assert [k for k in body if k not in ("unit", "summary")] == COLUMNS
    for name, column in core.table.columns().items():
        assert body[name] == column.tolist(), name
    summary = body["summary"]
    assert summary == vars(core.summary)
    # the hand-derived minimum of tests/camcore/profile/test_dynamics.py at 800 rpm: −34.38 N on the rise, so it jumps
    assert summary["separates"] is True and summary["min_contact_force_n"] == pytest.approx(-34.38, abs=0.01)
    assert summary["jump_speed_rpm"] < 800
    assert body["time_s"][-1] == pytest.approx(60 / 800)  # one turn


async def test_csv_has_the_columns_at_full_precision(client: httpx.AsyncClient) -> None:
    js = (await client.post(URL, json=BODY)).json()
    for response in (await client.post(URL, json=BODY, headers={"Accept": "text/csv"}),
                     await client.post(f"{URL}?format=csv", json=BODY),
                     await client.post(f"{URL}/table.csv", json=BODY)):
        assert response.status_code == 200
        assert response.headers["content-type"].startswith("text/csv")
        rows = list(csv.reader(io.StringIO(response.text)))
        assert rows[0] == COLUMNS and len(rows) == 38
        for i, name in enumerate(COLUMNS):
            assert [float(row[i]) for row in rows[1:]] == js[name]


async def test_oscillating_follower_answers_about_the_pivot(client: httpx.AsyncClient) -> None:
    r = await client.post(URL, json=OSC_BODY)
    assert r.status_code == 200, r.text
    body = r.json()
    assert body["unit"] == "deg" and "contact_stress_mpa" not in body
    # contact force = pivot torque / arm length (45 mm)
    assert np.allclose(np.array(body["contact_torque_nm"]) / 0.045, body["contact_force_n"], rtol=1e-12)
    assert body["summary"]["min_preload_nm"] is not None and body["summary"]["min_preload_n"] is None


async def test_the_separating_example_separates_and_the_first_holds(client: httpx.AsyncClient) -> None:
    holds = (await client.post(URL, json=DYNAMICS_EXAMPLES["roller"]["value"])).json()["summary"]
    lost = (await client.post(URL, json=DYNAMICS_EXAMPLES["separates"]["value"])).json()["summary"]
    assert not holds["separates"] and lost["separates"]
    assert holds["jump_speed_rpm"] == lost["jump_speed_rpm"]  # a property of the cam and spring, not the speed
    assert 600 < holds["jump_speed_rpm"] < 1500


def with_(body: dict[str, object], **changes: object) -> dict[str, object]:
    out = copy.deepcopy(body)
    for key, value in changes.items():
        if value is None:
            out.pop(key, None)
        else:
            out[key] = value
    return out


@pytest.mark.parametrize(("body", "field", "words"), [
    (with_(BODY, mass_kg=0), "mass_kg", "greater than 0"),
    (with_(BODY, mass_kg=-1), "mass_kg", "greater than 0"),
    (with_(BODY, spring_rate_n_mm=0), "spring_rate_n_mm", "greater than 0"),
    (with_(BODY, damping_n_s_mm=-0.1), "damping_n_s_mm", "greater than or equal to 0"),
    (with_(BODY, speed_rpm=0), "speed_rpm", "greater than or equal to 0.000001"),
    (with_(BODY, safety_margin_n=-1), "safety_margin_n", "greater than or equal to 0"),
    (with_(BODY, samples=1), "samples", "greater than or equal to 2"),
    (with_(BODY, roller={"width_mm": 12, "poisson_ratio": 0.7}), "poisson_ratio", "less than or equal to 0.5"),
    (with_(BODY, roller={"width_mm": 0}), "width_mm", "greater than 0"),
    (with_(OSC_BODY, inertia_kgm2=0), "inertia_kgm2", "greater than 0"),
])
async def test_out_of_range_is_422_naming_the_field(client: httpx.AsyncClient, body: dict[str, object], field: str,
                                                    words: str) -> None:
    r = await client.post(URL, json=body)
    assert r.status_code == 422, r.text
    assert any(e["loc"][-1] == field and words in e["msg"] for e in r.json()["errors"]), r.text


@pytest.mark.parametrize(("body", "words"), [
    (with_(BODY, mass_kg=None), "a translating follower's load is mass_kg and spring_rate_n_mm"),
    (with_(BODY, spring_rate_n_mm=None), "(missing spring_rate_n_mm)"),
    (with_(BODY, inertia_kgm2=0.01), "(inertia_kgm2 given)"),
    (with_(BODY, preload_nm=2), "(preload_nm given)"),
    (with_(OSC_BODY, mass_kg=1), "an oscillating follower's load is inertia_kgm2 and spring_rate_nm_rad"),
    (with_(OSC_BODY, spring_rate_nm_rad=None, spring_rate_n_mm=2), "(missing spring_rate_nm_rad)"),
    (with_(BODY, profile={**CYCLOID_CAM, "follower": {"type": "knife-edge"}}), "roller (width and materials"),
])
async def test_a_load_of_the_other_motion_is_422_with_the_sentence(client: httpx.AsyncClient,
                                                                   body: dict[str, object], words: str) -> None:
    r = await client.post(URL, json=body)
    assert r.status_code == 422, r.text
    assert words in r.json()["detail"], r.text


async def test_what_the_cam_turns_out_to_be_is_a_422_at_the_profile(client: httpx.AsyncClient) -> None:
    cv = {"type": "named", "name": "constant-velocity"}
    stepped = {**CYCLOID_CAM, "segments": [{"type": "rise", "angle_deg": 180, "lift_mm": 20, "curve": cv},
                                           {"type": "return", "angle_deg": 180, "lift_mm": 20, "curve": cv}]}
    r = await client.post(URL, json=with_(BODY, profile=stepped))
    assert r.status_code == 422
    assert "velocity jumps at 0°, 180°" in r.json()["detail"]
    assert r.json()["errors"][0]["loc"] == ["body", "profile"]
    sharp = {"follower": {"type": "roller", "roller_radius_mm": 8}, "base_radius_mm": 10,
             "segments": [{"type": "rise", "angle_deg": 40, "lift_mm": 20}, {"type": "return", "angle_deg": 40,
                                                                              "lift_mm": 20},
                          {"type": "dwell", "angle_deg": 280}]}
    r = await client.post(URL, json=with_(BODY, profile=sharp))
    assert r.status_code == 422 and "undercuts" in r.json()["detail"]
    assert r.json()["errors"][0]["loc"] == ["body", "profile"]


async def test_limits_are_413(client: httpx.AsyncClient) -> None:
    r = await client.post(URL, json=with_(BODY, samples=200_001))
    assert r.status_code == 413
    assert r.json()["limit"]["name"] == "dynamics samples" and r.json()["errors"][0]["loc"] == ["body", "samples"]
    # 360 Bezier segments of degree 20: the estimate is over the 1 s work budget, refused before it runs
    bezier = {"type": "bezier", "control_points": [[i * 10.0, min(1.0, max(0.0, (i - 2) / 15))] for i in range(21)]}
    many = {**CYCLOID_CAM, "follower": {"type": "knife-edge"}, "base_radius_mm": 400,
            "segments": [{"type": t, "angle_deg": 1, "lift_mm": 5, "curve": bezier}
                         for _ in range(180) for t in ("rise", "return")]}
    r = await client.post(URL, json=with_(BODY, profile=many, roller=None))
    assert r.status_code == 413 and "work" in r.json()["detail"], r.text


# ----------------------------------------------------------------------------- the chart
PLOT_Q = {"speed_rpm": 800, "mass_kg": 0.5, "spring_rate_n_mm": 2, "preload_n": 30, "safety_margin_n": 5,
          "rise_deg": 120, "dwell_deg": 60, "return_deg": 180, "lift_mm": 20}


async def test_chart_png_and_svg(client: httpx.AsyncClient) -> None:
    r = await client.get(PLOT, params={**PLOT_Q, "format": "png"})
    assert r.status_code == 200, r.text
    assert r.headers["content-type"] == "image/png"
    width, height = check_png(r.content)
    assert width >= 700 and height >= 500
    svg = await client.get(PLOT, params=PLOT_Q)
    assert svg.headers["content-type"].startswith("image/svg+xml")
    check_svg(svg.content)
    assert (await client.get(PLOT, params=PLOT_Q)).content == svg.content  # no date stamp


async def test_chart_says_what_the_numbers_say(client: httpx.AsyncClient) -> None:
    summary = (await client.post(URL, json={**BODY, "samples": 721})).json()["summary"]
    texts = svg_texts((await client.get(PLOT, params=PLOT_Q)).content)
    for label in ("cam angle [deg]", "lift [mm]", "force along the follower's motion [N]", "contact force",
                  "spring force k·s + F0", "safety margin 5 N", "contact lost (force below the margin)"):
        assert label in texts, label
    jump = f"{summary['jump_speed_rpm']:.5g} rpm"
    assert any("the follower LEAVES the cam" in t and jump in t for t in texts), texts
    low = f"{summary['min_contact_force_n']:.4g}".replace("-", "\N{MINUS SIGN}")
    assert any(t.startswith(f"min {low} N at") for t in texts), texts
    # slow enough to hold: no shaded region, and the verdict says so
    texts = svg_texts((await client.get(PLOT, params={**PLOT_Q, "speed_rpm": 300})).content)
    assert "contact lost (force below the margin)" not in texts
    assert any("the follower stays on the cam" in t for t in texts)


async def test_chart_of_an_oscillating_follower(client: httpx.AsyncClient) -> None:
    params = {"motion": "oscillating", "arm_length_mm": 45, "pivot_distance_mm": 60, "base_radius_mm": 25,
              "roller_radius_mm": 6, "swing_deg": 20, "speed_rpm": 400, "inertia_kgm2": 0.004,
              "spring_rate_nm_rad": 20, "preload_nm": 3}
    r = await client.get(PLOT, params=params)
    assert r.status_code == 200, r.text
    texts = svg_texts(r.content)
    assert "swing [deg]" in texts and any("N·m" in t for t in texts)


@pytest.mark.parametrize(("params", "field"), [
    ({**PLOT_Q, "speed_rpm": 0}, "speed_rpm"),
    ({k: v for k, v in PLOT_Q.items() if k != "speed_rpm"}, "speed_rpm"),
    ({**PLOT_Q, "mass_kg": -1}, "mass_kg"),
    ({**PLOT_Q, "samples": 5000}, "samples"),
    ({**PLOT_Q, "safety_margin_n": "nan"}, "safety_margin_n"),
])
async def test_chart_query_errors_are_422_naming_the_field(client: httpx.AsyncClient, params: dict[str, object],
                                                           field: str) -> None:
    r = await client.get(PLOT, params=params)
    assert r.status_code == 422, r.text
    assert any(e["loc"][-1] == field for e in r.json()["errors"]), r.text


async def test_chart_rules_are_422_with_the_sentence(client: httpx.AsyncClient) -> None:
    r = await client.get(PLOT, params={**PLOT_Q, "inertia_kgm2": 0.1})
    assert r.status_code == 422 and "(inertia_kgm2 given)" in r.json()["detail"]
    assert r.json()["errors"][0]["loc"] == ["query"]
    r = await client.get(PLOT, params={**PLOT_Q, "curve": "cycloyd"})
    assert r.status_code == 404
    r = await client.get(PLOT, params={**PLOT_Q, "curve": "constant-velocity"})
    assert r.status_code == 422 and "velocity jumps" in r.json()["detail"]


async def test_operations_are_in_the_openapi_document(client: httpx.AsyncClient) -> None:
    spec = (await client.get("/openapi.json")).json()
    assert spec["paths"][URL]["post"]["operationId"] == "computeFollowerDynamics"
    assert spec["paths"][f"{URL}.csv"]["post"]["operationId"] == "computeFollowerDynamicsCsv"
    old = spec["paths"][f"{URL}/table.csv"]["post"]  # the path it had before the twins were regular
    assert old["operationId"] == "computeFollowerDynamicsTableCsv" and old["deprecated"] is True
    plot = spec["paths"][PLOT]["get"]
    assert plot["operationId"] == "plotFollowerDynamics"
    assert set(plot["responses"]["200"]["content"]) == {"image/svg+xml", "image/png"}
    answer = spec["components"]["schemas"]["DynamicsAnswer"]["properties"]
    # the unit-less lift columns say their units
    assert re.search(r"\[mm\].*\[deg\]", answer["lift"]["description"])


async def test_a_profile_driven_by_a_motion_program(client: httpx.AsyncClient) -> None:
    """Makino's cutting-unit cycle (1977, §5.3) as the lift: the dynamics' lift and acceleration are
    computeMotion's s and a_per_s2 at the same speed, and the contact force is m·a/1000 + k·s + F0
    computed from them."""
    from service.motions.specs import MAKINO_CYCLE

    profile = {"follower": {"type": "roller", "roller_radius_mm": 10}, "base_radius_mm": 60, "motion": MAKINO_CYCLE}
    body = {"profile": profile, "speed_rpm": 60, "mass_kg": 2, "spring_rate_n_mm": 1, "preload_n": 50, "samples": 73}
    r = await client.post(URL, json=body)
    assert r.status_code == 200, r.text
    dyn = r.json()
    motion = (await client.post("/v1/motions", json={"motion": MAKINO_CYCLE, "samples": 73, "speed_rpm": 60})).json()
    assert np.allclose(dyn["lift"], motion["s"], rtol=1e-12, atol=1e-12)
    assert np.allclose(dyn["acceleration"], motion["a_per_s2"], rtol=1e-12, atol=1e-9)
    force = 2 * np.array(motion["a_per_s2"]) / 1000 + 1 * np.array(motion["s"]) + 50
    assert np.allclose(dyn["contact_force_n"], force, rtol=1e-12, atol=1e-9)
    summary = dyn["summary"]
    assert summary["min_contact_force_n"] <= min(dyn["contact_force_n"])
    # the rapid feed (curve 1 over 0-60°) decelerates hardest: the follower would leave the cam there first
    assert 0 < summary["jump_at_deg"] < 60 and summary["jump_speed_rpm"] > 60
