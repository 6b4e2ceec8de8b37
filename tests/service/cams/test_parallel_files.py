"""The parallel cam's files, each read back by a second program and checked against the exact contour.

* ``?format=dxf``: ezdxf finds a closed polyline on a layer per plate, its vertices the JSON answer's
  contour points (exact points of the contour), and the header's extents their box; LibreOffice Draw
  (marker ``libreoffice``) converts it to SVG, whose paths, mapped back by the scale and shift Draw
  chose, lie on those points within Draw's own resolution (1/100 mm on its page).
* ``.step`` / ``.stl``: the kernel's STEP reader finds one solid per plate; the STL is closed.
* ``POST /v1/cams/parallel/toolpath``: pygcode (an independent G-code reader and machine) runs the
  program; every point of the cutting moves, lines and arcs as the machine interpolates them, lies at
  the tool radius from the exact contour (camcore.cams.parallel's pieces, densely) within the
  tolerance, and none nearer.
"""

from __future__ import annotations

import io
import math
import re
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import ezdxf
import httpx
import numpy as np
import pytest
from pygcode import Line, Machine

from camcore.cams.parallel import CHORD_SHARE, make_parallel_cam, plate_contour
from service.cams.parallel_specs import PARALLEL_EXAMPLE, PARALLEL_SOLID_EXAMPLE
from tests.libreoffice import convert
from tests.polylines import distance_to_ring
from tests.readers import count_solids, step_shape
from tests.stl_mesh import directed_edges, read_stl

pytestmark = pytest.mark.anyio
PATH = "/v1/cams/parallel"
RR = float(PARALLEL_EXAMPLE["roller_radius_mm"])  # type: ignore[arg-type]
#: the G-code's coordinates are written to 1e-6 mm: half a unit, and as much again for an arc's centre
WRITTEN_MM = 1e-6


async def _dxf_and_points(client: httpx.AsyncClient) -> tuple[bytes, list[np.ndarray]]:
    dxf = await client.post(PATH + "?format=dxf", json=PARALLEL_EXAMPLE)
    assert dxf.status_code == 200 and dxf.headers["content-type"] == "application/dxf", dxf.text[:300]
    plates = (await client.post(PATH, json=PARALLEL_EXAMPLE)).json()["plates"]
    return dxf.content, [np.column_stack([p["x_mm"], p["y_mm"]]) for p in plates]


async def test_dxf_has_a_closed_polyline_of_the_exact_points_on_a_layer_per_plate(client: httpx.AsyncClient) -> None:
    content, plates = await _dxf_and_points(client)
    doc = ezdxf.read(io.StringIO(content.decode()))
    assert doc.header["$INSUNITS"] == 4 and doc.header["$MEASUREMENT"] == 1  # millimetres
    entities = list(doc.modelspace())
    assert [e.dxf.layer for e in entities] == ["PLATE_0", "PLATE_1", "PLATE_2"]
    for entity, points in zip(entities, plates, strict=True):
        assert entity.dxftype() == "LWPOLYLINE" and entity.closed
        # the very numbers of the JSON answer (both are shortest round-trip floats): the contour's exact
        # points, within 1e-4·Rr of the contour between them (tests/camcore/cams/test_parallel_contour.py)
        assert np.array_equal(np.array([(x, y) for x, y, *_ in entity.get_points()]), points)
    every = np.vstack(plates)
    assert tuple(doc.header["$EXTMIN"]) == (every[:, 0].min(), every[:, 1].min(), 0.0)
    assert tuple(doc.header["$EXTMAX"]) == (every[:, 0].max(), every[:, 1].max(), 0.0)


def _svg_paths(svg: Path) -> dict[str, np.ndarray]:
    """Draw's paths of the drawing (not its templates), by stroke colour: the points [1/100 mm]."""
    paths = {}
    root = ET.parse(svg).getroot()
    for group in root.iter("{http://www.w3.org/2000/svg}g"):
        if group.get("class") != "Graphic":
            continue
        for path in group.iter("{http://www.w3.org/2000/svg}path"):
            numbers = [float(v) for v in re.findall(r"-?\d+(?:\.\d+)?", path.get("d", ""))]
            paths[path.get("stroke", "")] = np.array(numbers).reshape(-1, 2)
    return paths


@pytest.mark.libreoffice
async def test_libreoffice_draws_each_plate_on_its_points(client: httpx.AsyncClient, tmp_path: Path) -> None:
    content, plates = await _dxf_and_points(client)
    source = tmp_path / "plates.dxf"
    source.write_bytes(content)
    svg = convert(source, "svg", tmp_path / "out", profile=tmp_path / "profile")
    paths = _svg_paths(svg)
    # the layers' colours (1 red, 2 yellow, 3 green): one path each, as many points as the polyline
    drawn = [paths["rgb(255,0,0)"], paths["rgb(255,255,0)"], paths["rgb(0,255,0)"]]
    assert [len(d) for d in drawn] == [len(p) for p in plates]
    # Draw puts the drawing on its page scaled and shifted, y downwards, in 1/100 mm of the page:
    # u = a + s·x, v = b − s·y (s in page units a drawing mm); s, a, b by least squares over every point
    xy, uv = np.vstack(plates), np.vstack(drawn)
    rows = np.vstack([np.column_stack([xy[:, 0], np.ones(len(xy)), np.zeros(len(xy))]),
                      np.column_stack([-xy[:, 1], np.zeros(len(xy)), np.ones(len(xy))])])
    (s, a, b), *_ = np.linalg.lstsq(rows, np.concatenate([uv[:, 0], uv[:, 1]]), rcond=None)
    assert 10 < s < 1000  # Draw fits the drawing on an A4 page: ~0.67 here, s = 67
    back = np.column_stack([(uv[:, 0] - a) / s, (b - uv[:, 1]) / s])
    # Draw writes its coordinates as whole 1/100 mm of its page: each point off by half of one each way,
    # so by 0.71/s mm of the drawing (~0.011 mm here, Draw's resolution); 5 % for the fit's own
    resolution = 0.5 * math.sqrt(2) / s
    assert np.hypot(*(back - xy).T).max() <= 1.05 * resolution, (np.hypot(*(back - xy).T).max(), resolution)
    # and so Draw's plates lie on the exact contours within that and the polyline's 1e-4·Rr
    for plate, points, path in zip(range(3), plates, drawn, strict=True):
        mapped = np.column_stack([(path[:, 0] - a) / s, (b - path[:, 1]) / s])
        assert distance_to_ring(mapped, points).max() <= 1.05 * resolution + CHORD_SHARE * RR, plate


async def test_step_and_stl_hold_the_plates(client: httpx.AsyncClient) -> None:
    body = {**PARALLEL_EXAMPLE, "solid": {**PARALLEL_SOLID_EXAMPLE, "spacing_mm": 14}}
    step = await client.post(PATH + ".step", json=body)
    assert step.status_code == 200 and step.headers["content-type"] == "model/step", step.text[:300]
    assert count_solids(step_shape(step.content)) == 3
    stl = await client.post(PATH + "?format=stl", json={**body, "solid": {**body["solid"], "tolerance_mm": 0.05}})
    assert stl.status_code == 200 and stl.headers["content-type"] == "model/stl"
    facets = read_stl(stl.content)
    edges = directed_edges(facets)
    assert all(n == 1 for n in edges.values()) and all(edges[(q, p)] == 1 for p, q in edges)
    assert facets[:, :, 2].max() == pytest.approx(2 * 14 + 12, abs=1e-5)


@pytest.mark.parametrize("change, loc, words", [
    ({"solid": None}, ["body", "solid"], "give solid"),
    ({"solid": {**PARALLEL_SOLID_EXAMPLE, "bore_diameter_mm": 90}}, ["body", "solid", "bore_diameter_mm"],
     "smaller than the plates at their narrowest"),
    ({"solid": {**PARALLEL_SOLID_EXAMPLE, "spacing_mm": 11}}, ["body", "solid", "spacing_mm"],
     "spacing_mm must be at least thickness_mm"),
])
async def test_solid_refusals_name_the_field(client: httpx.AsyncClient, change: dict[str, Any], loc: list[str],
                                             words: str) -> None:
    r = await client.post(PATH + "?format=step", json={**PARALLEL_EXAMPLE, **change})
    assert r.status_code == 422, r.text
    assert r.json()["errors"][0]["loc"] == loc and words in r.text


def _machine_path(program: str) -> list[np.ndarray]:
    """The cutting moves as pygcode's machine runs them, each a dense polyline (an arc interpolated about
    its centre, start plus I, J, the way G2/G3 turn), from the lead-in's end to the lead-out."""
    machine = Machine()
    moves: list[np.ndarray] = []
    cutting = False
    for raw in program.splitlines():
        if raw == "%":
            continue
        line = Line(raw)
        words = {w.letter: float(w.value) for w in line.block.words}
        start = machine.pos
        x0, y0 = start.X, start.Y
        machine.process_block(line.block)
        comment = str(line.comment or "")
        if "lead-out" in comment:
            cutting = False
        if cutting:
            x1, y1 = machine.pos.X, machine.pos.Y
            g = next(int(c.word.value) for c in line.block.gcodes if c.word.letter == "G")
            if g == 1:
                u = np.linspace(0.0, 1.0, 50)
                moves.append(np.column_stack([x0 + u * (x1 - x0), y0 + u * (y1 - y0)]))
            else:
                cx, cy = x0 + words["I"], y0 + words["J"]
                a0, a1 = math.atan2(y0 - cy, x0 - cx), math.atan2(y1 - cy, x1 - cx)
                sweep = (a1 - a0) % (2 * math.pi) if g == 3 else -((a0 - a1) % (2 * math.pi))
                r = math.hypot(x0 - cx, y0 - cy)
                a = a0 + np.linspace(0.0, 1.0, 400) * sweep
                moves.append(np.column_stack([cx + r * np.cos(a), cy + r * np.sin(a)]))
        if "lead-in" in comment:
            cutting = True
    return moves


@pytest.mark.parametrize("plate", [0, 1])
async def test_the_program_keeps_the_tool_radius_from_the_exact_plate(client: httpx.AsyncClient, plate: int) -> None:
    tool, tolerance = 5.0, 0.005
    body = {"cam": PARALLEL_EXAMPLE, "plate": plate, "tool_radius_mm": tool, "tolerance_mm": tolerance,
            "cut_z_mm": -12, "format": "gcode"}
    r = await client.post(PATH + "/toolpath", json=body)
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/x-gcode"), r.text[:300]
    moves = _machine_path(r.text)
    answer = (await client.post(PATH + "/toolpath", json={**body, "format": "json"})).json()
    assert len(moves) == answer["segments_count"] > 0
    # the exact contour, from the pieces themselves at 20 000 cam angles each (chords ≤ 1e-5 mm off)
    cam = make_parallel_cam(4, 100, 60, RR, 120, "MS", plates=3)
    contour, _points = plate_contour(cam, plate, int(PARALLEL_EXAMPLE["samples"]))  # type: ignore[call-overload]
    ring = np.vstack([np.column_stack([(e := contour.at(k, np.linspace(p.tau_start_rad, p.tau_end_rad, 20_000)[:-1])).x,
                                       e.y]) for k, p in enumerate(contour.pieces)])
    d = distance_to_ring(np.vstack(moves), ring)
    # at the tool radius within the tolerance (the fit's), the dense ring's chords and the program's 1e-6 mm
    assert np.abs(d - tool).max() <= tolerance + 1e-5 + 2 * WRITTEN_MM, np.abs(d - tool).max()
    # the path closes: the last cutting move ends where the first began
    assert math.dist(moves[-1][-1], moves[0][0]) <= 2 * WRITTEN_MM
    dxf = await client.post(PATH + "/toolpath.dxf", json={**body, "format": "json"})
    assert dxf.status_code == 200
    layer = [e for e in ezdxf.read(io.StringIO(dxf.text)).modelspace() if e.dxf.layer == "TOOLPATH_SURFACE"]
    assert len(layer) == answer["segments_count"]


async def test_toolpath_refusals_name_the_field(client: httpx.AsyncClient) -> None:
    too_big = await client.post(PATH + "/toolpath", json={"cam": PARALLEL_EXAMPLE, "plate": 1, "tool_radius_mm": 20})
    assert too_big.status_code == 422 and too_big.json()["errors"][0]["loc"] == ["body", "tool_radius_mm"]
    assert "is larger than the concave radius of curvature" in too_big.text
    no_plate = await client.post(PATH + "/toolpath", json={"cam": {**PARALLEL_EXAMPLE, "plates": 2}, "plate": 2,
                                                           "tool_radius_mm": 5})
    assert no_plate.status_code == 422 and no_plate.json()["errors"][0]["loc"] == ["body", "plate"]
