"""Manufacturing outputs over HTTP: POST /v1/profiles/toolpath, ?format=step|stl on
/v1/profiles, ?format=cam-table on /v1/motions, and the file operations of each format."""

from __future__ import annotations

import io
import math

import ezdxf
import httpx
import numpy as np
import pytest

from camcore.export import MOTION_FORMATS, SOLID_FORMATS, TOOLPATH_FORMATS
from camcore.export.solid import MIN_THICKNESS_MM
from service.app import create_app
from service.motions.specs import FEED_CYCLE, MAKINO_CYCLE
from service.profiles.specs import ROLLER_PROFILE_EXAMPLE
from service.settings import Settings
from tests.camcore.export.test_solid import read_step, read_stl
from tests.toolpath_reference import cutting_polylines, parse_gcode

pytestmark = pytest.mark.anyio

TOOLPATH = {"profile": ROLLER_PROFILE_EXAMPLE, "tool_radius_mm": 6, "tolerance_mm": 0.01}
#: a roller cam whose surface is concave after the rise: smallest concave radius ~51 mm at ~254°
CONCAVE = {"follower": {"type": "roller", "roller_radius_mm": 5}, "base_radius_mm": 20,
           "segments": [{"type": "rise", "angle_deg": 90, "lift_mm": 20}, {"type": "dwell", "angle_deg": 90},
                        {"type": "return", "angle_deg": 90, "lift_mm": 20}, {"type": "dwell", "angle_deg": 90}]}
SOLID = {"profile": ROLLER_PROFILE_EXAMPLE, "solid": {"thickness_mm": 12, "bore_diameter_mm": 20}}


async def test_toolpath_json_is_a_closed_chain_within_the_tolerance(client: httpx.AsyncClient) -> None:
    r = await client.post("/v1/profiles/toolpath", json={**TOOLPATH, "side": "groove", "tool_radius_mm": 8})
    assert r.status_code == 200, r.text
    body = r.json()
    assert [p["wall"] for p in body["paths"]] == ["surface", "outer-wall"]
    assert body["segments_count"] == sum(len(p["elements"]) for p in body["paths"])
    assert 0 < body["max_deviation_mm"] <= 0.01
    for path in body["paths"]:
        els = path["elements"]
        for a, b in zip(els, els[1:] + els[:1]):  # each element starts where the one before ends
            assert (a["x1_mm"], a["y1_mm"]) == (b["x0_mm"], b["y0_mm"])
        for e in els:
            if e["type"] == "arc":  # both ends on the circle (the radius is the start's)
                r_end = math.hypot(e["x1_mm"] - e["cx_mm"], e["y1_mm"] - e["cy_mm"])
                assert r_end == pytest.approx(e["radius_mm"], abs=1e-9)


async def test_toolpath_files_from_the_body_format_and_their_own_operations(client: httpx.AsyncClient) -> None:
    for name, fmt in TOOLPATH_FORMATS.items():
        r = await client.post("/v1/profiles/toolpath", json={**TOOLPATH, "format": name})
        assert r.status_code == 200, r.text
        assert r.headers["content-type"] == fmt.media_type
        assert r.headers["content-disposition"] == f'attachment; filename="{fmt.file_name}"'
        extension = fmt.file_name.rsplit(".", 1)[1]
        own = await client.post(f"/v1/profiles/toolpath.{extension}", json=TOOLPATH)
        assert own.status_code == 200 and own.headers["content-type"] == fmt.media_type
        if fmt.is_text:
            assert own.content == r.content
    gcode = (await client.post("/v1/profiles/toolpath.nc", json={**TOOLPATH, "feed_mm_min": 250})).text
    json_paths = (await client.post("/v1/profiles/toolpath", json=TOOLPATH)).json()["paths"]
    (cut,) = cutting_polylines(parse_gcode(gcode), 0.05)
    # the program runs the JSON's elements: the same ends, in the same order (to the 1e-6 mm it writes)
    ends = np.array([(e["x1_mm"], e["y1_mm"]) for e in json_paths[0]["elements"]])
    assert all(np.hypot(*(cut - end).T).min() <= 1e-6 * math.sqrt(2) for end in ends)
    assert "F250" in gcode and "G17 G21 G90" in gcode
    dxf = (await client.post("/v1/profiles/toolpath.dxf", json=TOOLPATH)).content
    doc = ezdxf.read(io.StringIO(dxf.decode()))
    assert len(doc.modelspace().query("LINE ARC[layer=='TOOLPATH_SURFACE']")) == len(json_paths[0]["elements"])


async def test_a_gouging_tool_is_refused_naming_the_field_and_the_angle(client: httpx.AsyncClient) -> None:
    body = {"profile": CONCAVE, "tool_radius_mm": 60, "tolerance_mm": 0.01}
    r = await client.post("/v1/profiles/toolpath", json=body)
    assert r.status_code == 422, r.text
    error = r.json()
    assert error["errors"][0]["loc"] == ["body", "tool_radius_mm"]
    assert "larger than the concave radius of curvature" in error["detail"] and "at cam angle 253.9°" in error["detail"]
    r = await client.post("/v1/profiles/toolpath", json={**body, "allow_gouge": True})
    assert r.status_code == 200 and r.json()["paths"][0]["gouges"] is True
    r = await client.post("/v1/profiles/toolpath", json={**TOOLPATH, "side": "groove", "profile": {
        **ROLLER_PROFILE_EXAMPLE, "follower": {"type": "knife-edge"}}})
    assert r.status_code == 422 and "a groove is the track of a roller" in r.text


async def test_toolpath_limits_are_413() -> None:
    app = create_app(Settings(max_toolpath_elements=40))
    async with httpx.AsyncClient(transport=httpx.ASGITransport(app=app), base_url="http://t") as client:
        r = await client.post("/v1/profiles/toolpath", json={**TOOLPATH, "tolerance_mm": 0.0001})
        assert r.status_code == 413, r.text
        assert r.json()["errors"][0]["loc"] == ["body", "tolerance_mm"]
    app = create_app(Settings(max_work_s=0.01))
    async with httpx.AsyncClient(transport=httpx.ASGITransport(app=app), base_url="http://t") as client:
        r = await client.post("/v1/profiles/toolpath", json=TOOLPATH)
        assert r.status_code == 413 and "estimated work" in r.text


async def test_step_and_stl_downloads(client: httpx.AsyncClient) -> None:
    for name, fmt in SOLID_FORMATS.items():
        r = await client.post(f"/v1/profiles?format={name}", json=SOLID)
        assert r.status_code == 200, r.text
        assert r.headers["content-type"] == fmt.media_type
        assert r.headers["content-disposition"] == f'attachment; filename="{fmt.file_name}"'
        own = await client.post(f"/v1/profiles/solid.{name}", json=SOLID)
        assert own.status_code == 200 and own.headers["content-type"] == fmt.media_type
    step = (await client.post("/v1/profiles?format=step", json=SOLID)).content
    solids, volume, box = read_step(step)
    stl = read_stl((await client.post("/v1/profiles/solid.stl", json=SOLID)).content)
    # the same solid both ways: the STL's volume (divergence theorem) within the STL's own
    # tolerance (0.01 mm × ~360 mm perimeter × 12 mm) of the STEP's
    v0, v1, v2 = stl[:, 0], stl[:, 1], stl[:, 2]
    assert solids == 1 and abs(np.einsum("ij,ij->i", v0, np.cross(v1, v2)).sum() / 6 - volume) < 0.01 * 360 * 12
    assert box[2] == pytest.approx(0.0, abs=1e-6) and box[5] == pytest.approx(12.0, abs=1e-6)


async def test_a_solid_needs_its_spec(client: httpx.AsyncClient) -> None:
    r = await client.post("/v1/profiles?format=step", json={"profile": ROLLER_PROFILE_EXAMPLE})
    assert r.status_code == 422 and r.json()["errors"][0]["loc"] == ["body", "solid"]
    r = await client.post("/v1/profiles/solid.stl", json={"profile": ROLLER_PROFILE_EXAMPLE})
    assert r.status_code == 422 and r.json()["errors"][0]["loc"][:2] == ["body", "solid"]
    r = await client.post("/v1/profiles?format=step", json={**SOLID, "solid": {"thickness_mm": 5, "bore_diameter_mm": 81}})
    assert r.status_code == 422 and r.json()["errors"][0]["loc"] == ["body", "solid", "bore_diameter_mm"]


async def test_the_thinnest_solid(client: httpx.AsyncClient) -> None:
    # issue 34, point 4: 1e-7 mm, the CAD kernel's confusion tolerance, made it refuse the extrusion
    # (Standard_ConstructionError, 500); the spec's bound is camcore's MIN_THICKNESS_MM (1 µm)
    for url in ("/v1/profiles?format=step", "/v1/profiles/solid.step", "/v1/profiles/solid.stl"):
        r = await client.post(url, json={**SOLID, "solid": {"thickness_mm": 1e-7, "bore_diameter_mm": 20}})
        assert r.status_code == 422, r.text
        assert r.json()["errors"][0]["loc"] == ["body", "solid", "thickness_mm"]
        assert "greater than or equal to 0.001" in r.json()["errors"][0]["msg"]
    r = await client.post("/v1/profiles/solid.step", json={**SOLID, "solid": {"thickness_mm": MIN_THICKNESS_MM}})
    assert r.status_code == 200, r.text
    solids, _, box = read_step(r.content)
    # the kernel pads its box by its 1e-7 mm precision
    assert solids == 1 and box[2] == pytest.approx(0.0, abs=1e-6) and box[5] == pytest.approx(1e-3, abs=1e-6)


@pytest.mark.parametrize("cycle", [MAKINO_CYCLE, FEED_CYCLE], ids=["makino", "feed"])
async def test_cam_table_positions_equal_the_motion_at_the_same_masters(client: httpx.AsyncClient,
                                                                        cycle: dict[str, object]) -> None:
    body = {"motion": cycle, "samples": 73}
    r = await client.post("/v1/motions?format=cam-table", json=body)
    assert r.status_code == 200, r.text
    fmt = MOTION_FORMATS["cam-table"]
    assert r.headers["content-type"] == fmt.media_type
    assert r.headers["content-disposition"] == f'attachment; filename="{fmt.file_name}"'
    header, *rows = r.text.splitlines()
    assert header == "master_deg,slave_mm,velocity_mm_per_deg,acceleration_mm_per_deg2"
    table = np.array([[float(v) for v in row.split(",")] for row in rows])
    motion = (await client.post("/v1/motions", json=body)).json()
    # the same program at the same masters: equal to the last bit (both print repr of a float64)
    assert table[:, 0].tolist() == motion["x_deg"]
    assert table[:, 1].tolist() == motion["s"]
    assert table[:, 2].tolist() == motion["v"] and table[:, 3].tolist() == motion["a"]
    # a fixed step over one period, both ends
    assert np.allclose(np.diff(table[:, 0]), 360.0 / 72, rtol=0, atol=1e-12) and table[-1, 0] == 360.0
    own = await client.post("/v1/motions/cam-table.csv", json=body)
    assert own.status_code == 200 and own.content == r.content


async def test_a_cam_table_needs_a_fixed_step(client: httpx.AsyncClient) -> None:
    r = await client.post("/v1/motions?format=cam-table", json={"motion": FEED_CYCLE, "x_deg": [0, 10, 30]})
    assert r.status_code == 422 and r.json()["errors"][0]["loc"] == ["body", "x_deg"]
