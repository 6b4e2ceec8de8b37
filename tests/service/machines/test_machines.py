"""POST /v1/machines (computeMachine) over ASGI in-process.

What a machine answers is checked against what is already trusted or by a second reader:

- one axis alone answers exactly what its own operation answers (computeFollowerDynamics, sizeIndexer,
  computeBarrelCam) at the camshaft's speed;
- the timing CSV and the cam table are read back with the csv module and equal the JSON columns; the cam
  table's velocity is the slope of its own slave column; the charts are real images (PIL, xml.etree);
- a bad request is a 422 whose loc names the field; too much work is a 413 before any of it is done,
  naming the field that drives it; the estimate bounds the work of the examples the registry-wide
  check (tests/service/operations/test_every_operation.py, the first example only) does not run;
- a timing rule's phase slack is where the rule breaks, to 0.05°.
"""

from __future__ import annotations

import copy
import csv
import gc
import io
import json
import math
import re
import struct
import time
import xml.etree.ElementTree as ET
from collections.abc import Callable
from pathlib import Path
from typing import Any

import httpx
import numpy as np
import pytest
from PIL import Image

from service.context import Context
from service.indexers.specs import INDEXER_SHAPE_EXAMPLE, LOAD_EXAMPLE
from service.machines import operations as machine_operations
from service.machines.specs import (
    FOUR_KINDS_EXAMPLE,
    MACHINE_EXAMPLE,
    MACHINE_EXAMPLES,
)
from service.operations import JSON
from service.profiles.specs import ROLLER_PROFILE_EXAMPLE
from service.settings import Settings
from tests.estimates import within_estimate

pytestmark = pytest.mark.anyio

URL = "/v1/machines"
#: the feed of the feed_and_table example: a spring-loaded roller follower (with its roller's width, so the
#: Hertz figures are compared too)
FEED_LOAD: dict[str, Any] = {"mass_kg": 0.8, "spring_rate_n_mm": 3, "preload_n": 40, "safety_margin_n": 10,
                             "roller": {"width_mm": 12}}
#: the four_kinds example's barrel cam slide and motion-program pusher (their specs' own examples)
BARREL_AXIS: dict[str, Any] = FOUR_KINDS_EXAMPLE["axes"][1]["barrel_cam"]
MOTION_AXIS: dict[str, Any] = FOUR_KINDS_EXAMPLE["axes"][3]["motion"]
CYCLOID = {"type": "named", "name": "cycloid"}
#: a cam rising 20 mm over 120° and returning over 120°, cycloid both ways: its jerk is known in closed form
CYCLOID_PROFILE: dict[str, Any] = {
    "follower": {"type": "roller", "roller_radius_mm": 10}, "base_radius_mm": 40,
    "segments": [{"type": "rise", "angle_deg": 120, "lift_mm": 20, "curve": CYCLOID}, {"type": "dwell", "angle_deg": 60},
                 {"type": "return", "angle_deg": 120, "lift_mm": 20, "curve": CYCLOID},
                 {"type": "dwell", "angle_deg": 60}]}


def machine(*axes: dict[str, Any], speed_rpm: float = 60.0, samples: int = 181, **more: Any) -> dict[str, Any]:
    return {"master": {"speed_rpm": speed_rpm}, "axes": [copy.deepcopy(a) for a in axes], "samples": samples, **more}


async def answer(client: httpx.AsyncClient, url: str, body: dict[str, Any], **params: str) -> Any:
    r = await client.post(url, json=body, params=params)
    assert r.status_code == 200, r.text
    return r


# ----------------------------------------------------------------------------- 1. one axis is its own operation
@pytest.mark.parametrize(("speed_rpm", "samples"), [(250.0, 181), (700.0, 73)])  # 700 rpm: past the jump speed
async def test_a_plate_cam_axis_answers_its_follower_dynamics_exactly(
        client: httpx.AsyncClient, speed_rpm: float, samples: int) -> None:
    m = (await answer(client, URL, machine({"name": "feed", "phase_deg": 0, "plate_cam": {
        "profile": ROLLER_PROFILE_EXAMPLE, **FEED_LOAD}}, speed_rpm=speed_rpm, samples=samples))).json()
    d = (await answer(client, "/v1/profiles/dynamics", {"profile": ROLLER_PROFILE_EXAMPLE, **FEED_LOAD,
                                                         "speed_rpm": speed_rpm, "samples": samples})).json()
    assert m["timing"]["x_deg"] == d["cam_angle_deg"]
    assert m["torque"]["feed_nm"] == d["camshaft_torque_nm"]
    assert m["axes"][0]["checks"]["dynamics"] == d["summary"]
    assert m["speed_limits"]["machine_top_speed_rpm"] == d["summary"]["jump_speed_rpm"]
    assert m["speed_limits"]["runs_within_limits"] is (not d["summary"]["separates"])


async def test_an_indexer_axis_answers_its_sizing_exactly(client: httpx.AsyncClient) -> None:
    shape = {**INDEXER_SHAPE_EXAMPLE, "internal_friction_torque_nm": 2}
    m = (await answer(client, URL, machine({"name": "table", "phase_deg": 0, "indexer": {
        "indexer": shape, "load": LOAD_EXAMPLE, "ratio": 1}}, speed_rpm=45.0))).json()
    s = (await answer(client, "/v1/indexers/sizing", {"indexer": {**shape, "speed_rpm": 45.0},
                                                       "load": LOAD_EXAMPLE})).json()
    sizing = m["axes"][0]["checks"]["sizing"]
    assert set(sizing) == set(s) - {"input_torque_table"}
    assert {k: s[k] for k in sizing} == sizing
    assert sizing["speed_rpm"] == 45.0


async def test_a_barrel_cam_axis_answers_its_barrel_cams_checks(client: httpx.AsyncClient) -> None:
    m = (await answer(client, URL, machine({"name": "slide", "phase_deg": 0, "barrel_cam": BARREL_AXIS}))).json()
    b = (await answer(client, "/v1/cams/barrel", BARREL_AXIS["cam"])).json()
    assert m["axes"][0]["checks"]["barrel"] == b["checks"]


# ----------------------------------------------------------------------------- 2. formats read back
def read_csv(text: str) -> tuple[list[str], list[list[float]]]:
    rows = list(csv.reader(io.StringIO(text)))
    return rows[0], [[float(cell) for cell in row] for row in rows[1:]]


async def test_timing_csv_is_the_json_timing(client: httpx.AsyncClient) -> None:
    js = (await answer(client, URL, FOUR_KINDS_EXAMPLE)).json()["timing"]
    r = await answer(client, URL, FOUR_KINDS_EXAMPLE, format="csv")
    assert r.headers["content-type"].startswith("text/csv")
    header, rows = read_csv(r.text)
    assert header == ["x_deg", "feed_mm", "feed_normalised", "slide_mm", "slide_normalised", "table_deg",
                      "table_normalised", "pusher_mm", "pusher_normalised"]
    assert len(rows) == FOUR_KINDS_EXAMPLE["samples"]
    for j, name in enumerate(header):
        assert [row[j] for row in rows] == js[name], name  # float(text) == value: written at full precision


#: a cycloid plate cam at phase 90° beside an indexer geared 2:1, on a 0.5° master step
CAM_MACHINE = machine(
    {"name": "cam", "phase_deg": 90, "plate_cam": {"profile": CYCLOID_PROFILE, "mass_kg": 0.5, "spring_rate_n_mm": 2,
                                                   "preload_n": 30}},
    {"name": "table", "phase_deg": 200, "indexer": {"indexer": {"stops": 4, "indexing_angle_deg": 90},
                                                    "load": LOAD_EXAMPLE, "ratio": 2}},
    speed_rpm=40.0, samples=721)


async def test_cam_table_is_the_timing_column_and_its_slope(client: httpx.AsyncClient) -> None:
    timing = (await answer(client, URL, CAM_MACHINE)).json()["timing"]
    step = 360.0 / (CAM_MACHINE["samples"] - 1)
    for name, unit in (("cam", "mm"), ("table", "deg")):
        r = await answer(client, URL, {**CAM_MACHINE, "cam_table_axis": name}, format="cam-table")
        header, rows = read_csv(r.text)
        assert header == ["master_deg", f"slave_{unit}", f"velocity_{unit}_per_deg", f"acceleration_{unit}_per_deg2"]
        table = np.array(rows)
        assert table[:, 0].tolist() == np.linspace(0.0, 360.0, CAM_MACHINE["samples"]).tolist()
        # the same lift at the same own angles, the table's from the call that also gives the derivatives and
        # the timing's from the position alone: at most a few ulp apart, 1e-12 is far above that and far below
        # a step's change of the lift (up to 0.17 mm in 0.5°)
        assert table[:, 1] == pytest.approx(timing[f"{name}_{unit}"], rel=1e-12)
        if name == "cam":
            slave, velocity = table[:, 1], table[:, 2]
            central = (slave[2:] - slave[:-2]) / (2 * step)
            # the central difference errs by at most h²/6·max|s'''| (s is C² with bounded s'''; a cycloid's jerk
            # peaks at 4π²·L/β³ = 4.57e-4 mm/deg³, so 1.9e-5 mm/deg at h = 0.5°), plus the rounding of the two
            # slave values over 2h (4·eps·20 mm/1°, 2e-14)
            bound = step**2 / 6 * 4 * math.pi**2 * 20 / 120**3 + 4 * np.finfo(float).eps * 20 / (2 * step)
            assert np.abs(central - velocity[1:-1]).max() <= bound
            assert np.abs(velocity).max() == pytest.approx(2 * 20 / 120, rel=1e-9)  # the cycloid's 2·L/β [mm/deg]
    # the axis at phase φ is its own lift at x − φ: the same cam at phase 0, 180 rows (90°) earlier
    at_zero = (await answer(client, URL, {**CAM_MACHINE, "axes": [{**CAM_MACHINE["axes"][0], "phase_deg": 0}]})).json()
    shifted = np.roll(np.array(at_zero["timing"]["cam_mm"][:-1]), 180)
    # x − φ in radians vs the grid's own angle: 1e-16 rad of rounding on a slope ≤ 19 mm/rad
    assert np.array(timing["cam_mm"][:-1]) == pytest.approx(shifted, abs=1e-12)


def png_size(body: bytes) -> tuple[int, int]:
    """The size in the IHDR chunk, read by hand."""
    assert body[:8] == b"\x89PNG\r\n\x1a\n"
    length, kind = struct.unpack(">I4s", body[8:16])
    assert (length, kind) == (13, b"IHDR")
    width, height = struct.unpack(">II", body[16:24])
    return int(width), int(height)


def svg_comments(body: bytes) -> list[str]:
    """Matplotlib keeps each text it draws as paths in a comment beside them: read them with xml.etree."""
    root = ET.fromstring(body, parser=ET.XMLParser(target=ET.TreeBuilder(insert_comments=True)))
    assert root.tag == "{http://www.w3.org/2000/svg}svg"
    assert len(root.findall(".//{http://www.w3.org/2000/svg}path")) > 20
    return [str(e.text).strip() for e in root.iter() if e.tag is ET.Comment]


async def test_charts_are_images_and_the_torque_chart_is_another_drawing(client: httpx.AsyncClient) -> None:
    pngs, svgs = {}, {}
    for chart in ("timing", "torque"):
        body = {**FOUR_KINDS_EXAMPLE, "chart": chart}
        png = (await answer(client, URL, body, format="png"))
        assert png.headers["content-type"] == "image/png"
        with Image.open(io.BytesIO(png.content)) as image:
            assert image.format == "PNG" and image.size == png_size(png.content)
            pixels = np.asarray(image.convert("RGB"), dtype=np.float64)
        assert pixels.var() > 0 and 0.002 < (pixels.mean(axis=-1) < 128).mean() < 0.5  # ink on white, not blank
        pngs[chart] = png.content
        svg = await answer(client, URL, body, format="svg")
        assert svg.headers["content-type"].startswith("image/svg+xml")
        svgs[chart] = svg_comments(svg.content)
    assert pngs["timing"] != pngs["torque"]
    # 1.5 s a turn: 40 rpm
    assert any(t.startswith("Timing diagram at 40 rpm") for t in svgs["timing"]), svgs["timing"]
    assert any(t.startswith("Camshaft torque at 40 rpm") for t in svgs["torque"]), svgs["torque"]
    assert not any(t.startswith("Camshaft torque") for t in svgs["timing"])
    assert not any(t.startswith("Timing diagram") for t in svgs["torque"])
    for label in ("(plate_cam, φ = 0°)", "(barrel_cam, φ = 90°)", "(indexer, φ = 0°)", "(motion, φ = 180°)"):
        assert any(label in t for t in svgs["timing"]), label
    # the four_kinds rule is broken: the timing chart says where it is marked
    assert any("red: a timing rule broken" in t for t in svgs["timing"])


# ----------------------------------------------------------------------------- 3. bad input: 422 at the field
def changed(change: Callable[[dict[str, Any]], None], base: dict[str, Any] = MACHINE_EXAMPLE) -> dict[str, Any]:
    body = copy.deepcopy(base)
    change(body)
    return body


def _oscillating(ratio: int) -> Callable[[dict[str, Any]], None]:
    def change(b: dict[str, Any]) -> None:
        b["axes"][1]["indexer"]["indexer"] = {"swing_angle_deg": 90, "indexing_angle_deg": 120, "dwells": 1}
        b["axes"][1]["indexer"]["ratio"] = ratio
        b["rules"] = []
    return change


def _pusher(motion_axis: dict[str, Any]) -> Callable[[dict[str, Any]], None]:
    return lambda b: b["axes"].append({"name": "pusher", "motion": copy.deepcopy(motion_axis)})


NOT_CLOSING = {"motion": {"unit": "mm", "segments": [{"span_deg": 120, "to": 40, "curve": CYCLOID},
                                                     {"span_deg": 240, "type": "dwell"}]}, "mass_kg": 2}
BAD: dict[str, tuple[Callable[[dict[str, Any]], None], str]] = {
    "rule names no axis": (lambda b: b["rules"][0]["while"].update(axis="spindle"), "rules.0.while.axis"),
    "phase 360": (lambda b: b["axes"][0].update(phase_deg=360), "axes.0.phase_deg"),
    "name twice": (lambda b: b["axes"][1].update(name="feed"), "axes.1.name"),
    "indexer input stops": (lambda b: b["axes"][1]["indexer"]["indexer"].update(input_stop_time_s=0.1),
                            "axes.1.indexer.indexer.input_stop_time_s"),
    "indexer with its own speed": (lambda b: b["axes"][1]["indexer"]["indexer"].update(speed_rpm=60),
                                   "axes.1.indexer.indexer.speed_rpm"),
    "oscillating unit, odd strokes": (_oscillating(1), "axes.1.indexer.ratio"),
    "motion not closing": (_pusher(NOT_CLOSING), "axes.2.motion.motion.segments"),
    "motion in mm with inertia": (_pusher({**MOTION_AXIS, "inertia_kgm2": 1.0}), "axes.2.motion.inertia_kgm2"),
    "two mechanisms": (lambda b: b["axes"][0].update(indexer=b["axes"][1]["indexer"]), "axes.0"),
    "cam table of no axis": (lambda b: b.update(cam_table_axis="spindle"), "cam_table_axis"),
    "flywheel both ways": (lambda b: b.update(flywheel={"speed_fluctuation": 0.05, "inertia_kgm2": 1.0}), "flywheel"),
    "stress without roller": (lambda b: b["axes"][0]["plate_cam"].update(allowed_stress_mpa=1000),
                              "axes.0.plate_cam.allowed_stress_mpa"),
}


@pytest.mark.parametrize("case", list(BAD))
async def test_bad_input_is_422_at_its_field(client: httpx.AsyncClient, case: str) -> None:
    change, where = BAD[case]
    r = await client.post(URL, json=changed(change))
    assert r.status_code == 422, r.text
    error = r.json()["errors"][0]
    assert error["loc"][0] == "body" and ".".join(map(str, error["loc"][1:])) == where, r.text
    assert error["msg"]


async def test_the_oscillating_unit_with_even_strokes_answers(client: httpx.AsyncClient) -> None:
    # the control of the odd case above: ratio 2 closes the swing out and back
    m = (await answer(client, URL, changed(_oscillating(2)))).json()
    swing = np.array(m["timing"]["table_deg"])
    # out to the 90° swing and back to 0 within the turn (at phase 305° the turn starts mid-swing); the same at 0°
    # and 360° of the master, but for the rounding of the own angle (1e-15 rad on a slope ≤ 300°/rad)
    assert swing.max() == pytest.approx(90.0, rel=1e-12) and swing.min() == pytest.approx(0.0, abs=1e-12)
    assert swing[0] == pytest.approx(swing[-1], abs=1e-9)


# ----------------------------------------------------------------------------- 4. cost bounded
@pytest.fixture
def no_work(monkeypatch: pytest.MonkeyPatch) -> list[object]:
    """Records any machine built: a refusal before any work builds none."""
    built: list[object] = []

    def build(*args: object) -> None:
        built.append(args)
        raise AssertionError("the machine was built")

    monkeypatch.setattr(machine_operations, "machine", build)
    return built


async def test_samples_over_the_limit_are_413_before_any_work(
        client: httpx.AsyncClient, settings: Settings, no_work: list[object]) -> None:
    r = await client.post(URL, json={**MACHINE_EXAMPLE, "samples": settings.max_table_samples + 1})
    assert r.status_code == 413, r.text
    assert r.json()["errors"][0]["loc"] == ["body", "samples"] and r.json()["limit"]["name"] == "machine samples"
    assert no_work == []


#: sixteen 6-stop tables around the camshaft: without a sweep, within the budget
SIXTEEN = {**MACHINE_EXAMPLE, "rules": [], "axes": [
    {**copy.deepcopy(MACHINE_EXAMPLE["axes"][1]), "name": f"table{i}", "phase_deg": 22.5 * i} for i in range(16)]}


async def test_sixteen_axes_at_32_speeds_are_413_at_the_sweep(client: httpx.AsyncClient, no_work: list[object]) -> None:
    r = await client.post(URL, json={**SIXTEEN, "speeds_rpm": [10.0 + 5 * k for k in range(32)]})
    assert r.status_code == 413, r.text
    assert r.json()["errors"][0]["loc"] == ["body", "speeds_rpm"], r.text
    assert "33 speeds × 16 axes" in r.json()["detail"]
    assert no_work == []


async def test_sixteen_axes_without_the_sweep_answer(client: httpx.AsyncClient) -> None:
    # the control of the refusal above: the sweep is what put it over the budget
    m = (await answer(client, URL, SIXTEEN)).json()
    assert [a["name"] for a in m["axes"]] == [f"table{i}" for i in range(16)]


async def test_an_axis_over_the_budget_is_413_at_its_own_field(
        client: httpx.AsyncClient, no_work: list[object]) -> None:
    # tests/service/profiles/test_dynamics.py's over-budget cam (360 Bezier segments of degree 20) as a machine's
    # axis: the 413 names the field in the machine's request, not in the dynamics request
    bezier = {"type": "bezier", "control_points": [[i * 10.0, min(1.0, max(0.0, (i - 2) / 15))] for i in range(21)]}
    many = {"follower": {"type": "knife-edge"}, "base_radius_mm": 400,
            "segments": [{"type": t, "angle_deg": 1, "lift_mm": 5, "curve": bezier}
                         for _ in range(180) for t in ("rise", "return")]}
    r = await client.post(URL, json=machine({"name": "feed", "plate_cam": {
        "profile": many, "mass_kg": 0.5, "spring_rate_n_mm": 2, "preload_n": 30}}))
    assert r.status_code == 413, r.text
    assert r.json()["errors"][0]["loc"] == ["body", "axes", 0, "plate_cam", "profile", "segments"], r.text
    assert no_work == []


def readme_machine() -> dict[str, Any]:
    """The body of the README's curl recipe for POST /v1/machines."""
    readme = (Path(__file__).resolve().parents[3] / "README.md").read_text(encoding="utf-8")
    found = re.search(r"curl -X POST \S*/v1/machines .*?-d '(.*?)'", readme, re.DOTALL)
    assert found, "the README's machine recipe"
    body: dict[str, Any] = json.loads(found.group(1))
    return body


@pytest.mark.timing
@pytest.mark.parametrize("name", [*[n for n in MACHINE_EXAMPLES if n != next(iter(MACHINE_EXAMPLES))], "README"])
def test_the_estimate_bounds_the_work_of_the_other_examples(name: str) -> None:
    """test_every_operation runs the first example (feed_and_table) in every format; here the others: a drive
    with its motor searches and a sweep, all four kinds of axis with a kinked (η < 1) torque, and the README's
    recipe (361 rows, the default curves)."""
    (operation,) = machine_operations.OPERATIONS
    assert operation.request is not None
    value = readme_machine() if name == "README" else copy.deepcopy(MACHINE_EXAMPLES[name]["value"])
    ctx = Context.create(Settings())  # cold caches: every curve built
    core = operation.convert(ctx, operation.request.model_validate(value), {})
    estimate = operation.estimate(ctx, core, JSON).seconds
    assert estimate <= Settings().max_work_s  # the example is admitted
    gc.disable()
    try:
        start = time.thread_time()
        operation.compute(ctx, core, JSON)
        seconds = time.thread_time() - start
    finally:
        gc.enable()
    assert within_estimate(seconds, estimate), f"{name}: {seconds:.4f} s, estimated {estimate:.4f} s"


# ----------------------------------------------------------------------------- 5. the rule's phase slack
def _rule_at(feed_phase: float) -> dict[str, Any]:
    return changed(lambda b: b["axes"][0].update(phase_deg=feed_phase % 360.0))


async def test_the_phase_slack_is_where_the_rule_breaks(client: httpx.AsyncClient) -> None:
    rule = (await answer(client, URL, MACHINE_EXAMPLE)).json()["rules"][0]
    assert rule["holds"] and rule["violations"] == []
    later, earlier = rule["slack_later_deg"], rule["slack_earlier_deg"]
    assert later > 0 and earlier > 0
    # the feed (the required axis, at phase 0) moved by the slack ± 0.05°: the level's crossings are refined to
    # machine precision, so 0.05° either side is well clear of the edge
    for phase, holds in ((later + 0.05, False), (later - 0.05, True), (-earlier - 0.05, False),
                         (-earlier + 0.05, True)):
        moved = (await answer(client, URL, _rule_at(phase))).json()["rules"][0]
        assert moved["holds"] is holds, (phase, moved)
        if not holds:  # broken by the 0.05° moved past the slack, where the table starts or ends indexing
            (v,) = moved["violations"]
            span = (v["to_deg"] - v["from_deg"]) % 360.0
            assert span == pytest.approx(0.05, abs=1e-9) and v["depth"] > 0
