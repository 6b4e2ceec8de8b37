"""Every answer's media type is declared in the OpenAPI document, with a schema.

A generated client decides how to read an answer from the document: openapi-python-client
reads the first media type it knows of a status (JSON before CSV, so the typed models stay);
openapi-typescript types each media type. Each way to get a CSV, DXF, X Y Z, PNG or SVG answer
is requested here, and its Content-Type must be one the operation declares for 200. Every
file also has an operation whose only answer is that file (the ``….csv``, ``contour.dxf``
twins): that is the one a generated client calls to download it.
"""

from __future__ import annotations

from typing import Any

import httpx
import pytest

from service.app import create_app
from service.indexers.specs import INDEXER_EXAMPLE
from service.cams.barrel_specs import BARREL_EXAMPLE
from service.cams.parallel_specs import PARALLEL_EXAMPLE
from service.cams.roller_gear_specs import ROLLER_GEAR_EXAMPLE
from service.motions.specs import FEED_CYCLE
from service.profiles.dynamics_specs import DYNAMICS_EXAMPLE
from service.profiles.specs import KNIFE_EDGE_PROFILE_EXAMPLE

pytestmark = pytest.mark.anyio

DOC = create_app().openapi()
MS = {"type": "named", "name": "MS"}
TABLE = {"curve": MS, "samples": 11}
INVERSE = {"curve": MS, "s": [0.1833]}
MOTION = {"indexer": INDEXER_EXAMPLE, "samples": 11}
POSITION = {"indexer": INDEXER_EXAMPLE, "output_angle_deg": [11]}
PROFILE = {"profile": KNIFE_EDGE_PROFILE_EXAMPLE, "samples": 37}
PROGRAM = {"motion": FEED_CYCLE, "samples": 13}
DYNAMICS = {**DYNAMICS_EXAMPLE, "samples": 13}
SPECTRUM = {"curve": MS, "tau": [1, 2.5]}
INDEXER_VIBRATION = {"indexer": INDEXER_EXAMPLE, "inertia_kgm2": 2.25, "stiffness_nm_rad": 2e5, "tolerance_arcsec": 10,
                     "samples": 11}
CSV_ACCEPT = {"Accept": "text/csv"}
SWEEP = {"load": {"inertia_kgm2": 2}, "stops": [6], "indexing_angle_deg": [270], "curves": [{"type": "named", "name": "MS"}],
         "speed_rpm": [30, 60]}
DESIGN = {"curve": {"type": "makino", "number": 4, "t1": 0.0625, "t3": 0.25}, "vary": {"t3": [0.2, 0.25]}}
SOLID = {**PROFILE, "solid": {"thickness_mm": 10, "bore_diameter_mm": 10}}
TOOLPATH = {"profile": KNIFE_EDGE_PROFILE_EXAMPLE, "tool_radius_mm": 5, "tolerance_mm": 0.01}
BARREL = {**BARREL_EXAMPLE, "samples": 13}
PARALLEL = {**PARALLEL_EXAMPLE, "samples": 31}
ROLLER_GEAR = {**ROLLER_GEAR_EXAMPLE, "samples": 13, "length_samples": 2}

# (method, path template, url, body, headers, media type answered)
CASES: list[tuple[str, str, str, dict[str, Any] | None, dict[str, str], str]] = [
    ("GET", "/v1/curves/{name}/table", "/v1/curves/MS/table?samples=11", None, {}, "application/json"),
    ("GET", "/v1/curves/{name}/table", "/v1/curves/MS/table?samples=11&format=csv", None, {}, "text/csv"),
    ("GET", "/v1/curves/{name}/table.csv", "/v1/curves/MS/table.csv?samples=11", None, {}, "text/csv"),
    ("POST", "/v1/curves/table", "/v1/curves/table", TABLE, {}, "application/json"),
    ("POST", "/v1/curves/table", "/v1/curves/table", TABLE, CSV_ACCEPT, "text/csv"),
    ("POST", "/v1/curves/table.csv", "/v1/curves/table.csv", TABLE, {}, "text/csv"),
    ("GET", "/v1/curves/{name}/inverse", "/v1/curves/MS/inverse?s=0.1833&format=csv", None, {}, "text/csv"),
    ("GET", "/v1/curves/{name}/inverse.csv", "/v1/curves/MS/inverse.csv?s=0.1833", None, {}, "text/csv"),
    ("POST", "/v1/curves/inverse", "/v1/curves/inverse", INVERSE, CSV_ACCEPT, "text/csv"),
    ("POST", "/v1/curves/inverse.csv", "/v1/curves/inverse.csv", INVERSE, {}, "text/csv"),
    ("POST", "/v1/indexers/motion", "/v1/indexers/motion", MOTION, CSV_ACCEPT, "text/csv"),
    ("POST", "/v1/indexers/motion.csv", "/v1/indexers/motion.csv", MOTION, {}, "text/csv"),
    ("POST", "/v1/indexers/position", "/v1/indexers/position", POSITION, CSV_ACCEPT, "text/csv"),
    ("POST", "/v1/indexers/position.csv", "/v1/indexers/position.csv", POSITION, {}, "text/csv"),
    ("POST", "/v1/curves/characteristics/sweep", "/v1/curves/characteristics/sweep", DESIGN, {}, "application/json"),
    ("POST", "/v1/curves/characteristics/sweep", "/v1/curves/characteristics/sweep", DESIGN, CSV_ACCEPT, "text/csv"),
    ("POST", "/v1/curves/characteristics/sweep", "/v1/curves/characteristics/sweep?format=csv", DESIGN, {},
     "text/csv"),
    ("POST", "/v1/curves/characteristics/sweep", "/v1/curves/characteristics/sweep?format=png", DESIGN, {},
     "image/png"),
    ("POST", "/v1/curves/characteristics/sweep", "/v1/curves/characteristics/sweep?format=svg", DESIGN, {},
     "image/svg+xml"),
    ("POST", "/v1/indexers/sizing/sweep", "/v1/indexers/sizing/sweep", SWEEP, {}, "application/json"),
    ("POST", "/v1/indexers/sizing/sweep", "/v1/indexers/sizing/sweep", SWEEP, CSV_ACCEPT, "text/csv"),
    ("POST", "/v1/indexers/sizing/sweep", "/v1/indexers/sizing/sweep?format=png", SWEEP, {}, "image/png"),
    ("POST", "/v1/indexers/sizing/sweep", "/v1/indexers/sizing/sweep?format=svg", SWEEP, {}, "image/svg+xml"),
    ("POST", "/v1/motions", "/v1/motions", PROGRAM, {}, "application/json"),
    ("POST", "/v1/motions", "/v1/motions?format=csv", PROGRAM, {}, "text/csv"),
    ("POST", "/v1/motions", "/v1/motions", PROGRAM, CSV_ACCEPT, "text/csv"),
    ("POST", "/v1/motions/table.csv", "/v1/motions/table.csv", PROGRAM, {}, "text/csv"),
    ("POST", "/v1/profiles", "/v1/profiles", PROFILE, {}, "application/json"),
    ("POST", "/v1/profiles", "/v1/profiles?format=csv", PROFILE, {}, "text/csv"),
    ("POST", "/v1/profiles", "/v1/profiles?format=contour-csv", PROFILE, {}, "text/csv"),
    ("POST", "/v1/profiles", "/v1/profiles?format=dxf", PROFILE, {}, "application/dxf"),
    ("POST", "/v1/profiles", "/v1/profiles?format=xyz", PROFILE, {}, "text/plain"),
    ("POST", "/v1/profiles/table.csv", "/v1/profiles/table.csv", PROFILE, {}, "text/csv"),
    ("POST", "/v1/profiles/contour.csv", "/v1/profiles/contour.csv", PROFILE, {}, "text/csv"),
    ("POST", "/v1/profiles/contour.dxf", "/v1/profiles/contour.dxf", PROFILE, {}, "application/dxf"),
    ("POST", "/v1/profiles/contour.xyz", "/v1/profiles/contour.xyz", PROFILE, {}, "text/plain"),
    ("POST", "/v1/profiles/dynamics", "/v1/profiles/dynamics", DYNAMICS, {}, "application/json"),
    ("POST", "/v1/profiles/dynamics", "/v1/profiles/dynamics?format=csv", DYNAMICS, {}, "text/csv"),
    ("POST", "/v1/profiles/dynamics", "/v1/profiles/dynamics", DYNAMICS, CSV_ACCEPT, "text/csv"),
    ("POST", "/v1/profiles/dynamics/table.csv", "/v1/profiles/dynamics/table.csv", DYNAMICS, {}, "text/csv"),
    ("GET", "/v1/profiles/dynamics/plot", "/v1/profiles/dynamics/plot?speed_rpm=600&mass_kg=0.5&spring_rate_n_mm=2"
     "&samples=101&format=png", None, {}, "image/png"),
    ("POST", "/v1/profiles", "/v1/profiles?format=step", SOLID, {}, "model/step"),
    ("POST", "/v1/profiles", "/v1/profiles?format=stl", SOLID, {}, "model/stl"),
    ("POST", "/v1/profiles/solid.step", "/v1/profiles/solid.step", SOLID, {}, "model/step"),
    ("POST", "/v1/profiles/solid.stl", "/v1/profiles/solid.stl", SOLID, {}, "model/stl"),
    ("POST", "/v1/profiles/toolpath", "/v1/profiles/toolpath", TOOLPATH, {}, "application/json"),
    ("POST", "/v1/profiles/toolpath", "/v1/profiles/toolpath", {**TOOLPATH, "format": "gcode"}, {}, "text/x-gcode"),
    ("POST", "/v1/profiles/toolpath", "/v1/profiles/toolpath", {**TOOLPATH, "format": "dxf"}, {}, "application/dxf"),
    ("POST", "/v1/profiles/toolpath.nc", "/v1/profiles/toolpath.nc", TOOLPATH, {}, "text/x-gcode"),
    ("POST", "/v1/profiles/toolpath.dxf", "/v1/profiles/toolpath.dxf", TOOLPATH, {}, "application/dxf"),
    ("POST", "/v1/motions", "/v1/motions?format=cam-table", PROGRAM, {}, "text/csv"),
    ("POST", "/v1/motions/cam-table.csv", "/v1/motions/cam-table.csv", PROGRAM, {}, "text/csv"),
    ("GET", "/v1/curves/{name}/plot", "/v1/curves/MS/plot?samples=101", None, {}, "image/svg+xml"),
    ("GET", "/v1/curves/{name}/plot", "/v1/curves/MS/plot?samples=101&format=png", None, {}, "image/png"),
    ("GET", "/v1/indexers/plot", "/v1/indexers/plot?stops=6&indexing_angle_deg=270&speed_rpm=60&samples=101&format=png",
     None, {}, "image/png"),
    ("GET", "/v1/profiles/plot", "/v1/profiles/plot?samples=101", None, {}, "image/svg+xml"),
    ("POST", "/v1/curves/vibration", "/v1/curves/vibration", SPECTRUM, {}, "application/json"),
    ("POST", "/v1/curves/vibration", "/v1/curves/vibration?format=csv", SPECTRUM, {}, "text/csv"),
    ("POST", "/v1/curves/vibration", "/v1/curves/vibration", SPECTRUM, CSV_ACCEPT, "text/csv"),
    ("POST", "/v1/curves/vibration.csv", "/v1/curves/vibration.csv", SPECTRUM, {}, "text/csv"),
    ("POST", "/v1/indexers/vibration", "/v1/indexers/vibration", INDEXER_VIBRATION, CSV_ACCEPT, "text/csv"),
    ("POST", "/v1/indexers/vibration.csv", "/v1/indexers/vibration.csv", INDEXER_VIBRATION, {}, "text/csv"),
    ("GET", "/v1/curves/vibration/plot", "/v1/curves/vibration/plot?samples=101&curves=MS,cycloid", None, {},
     "image/svg+xml"),
    ("POST", "/v1/cams/barrel", "/v1/cams/barrel", BARREL, {}, "application/json"),
    ("POST", "/v1/cams/barrel", "/v1/cams/barrel?format=csv", BARREL, {}, "text/csv"),
    ("POST", "/v1/cams/barrel", "/v1/cams/barrel", BARREL, CSV_ACCEPT, "text/csv"),
    ("POST", "/v1/cams/barrel.csv", "/v1/cams/barrel.csv", BARREL, {}, "text/csv"),
    ("POST", "/v1/cams/parallel", "/v1/cams/parallel", PARALLEL, {}, "application/json"),
    ("POST", "/v1/cams/parallel", "/v1/cams/parallel?format=csv", PARALLEL, {}, "text/csv"),
    ("POST", "/v1/cams/parallel", "/v1/cams/parallel", PARALLEL, CSV_ACCEPT, "text/csv"),
    ("POST", "/v1/cams/parallel.csv", "/v1/cams/parallel.csv", PARALLEL, {}, "text/csv"),
    ("POST", "/v1/cams/roller-gear", "/v1/cams/roller-gear", ROLLER_GEAR, {}, "application/json"),
    ("POST", "/v1/cams/roller-gear", "/v1/cams/roller-gear?format=csv", ROLLER_GEAR, {}, "text/csv"),
    ("POST", "/v1/cams/roller-gear", "/v1/cams/roller-gear", ROLLER_GEAR, CSV_ACCEPT, "text/csv"),
    ("POST", "/v1/cams/roller-gear", "/v1/cams/roller-gear?format=stl", ROLLER_GEAR, {}, "model/stl"),
    ("POST", "/v1/cams/roller-gear.csv", "/v1/cams/roller-gear.csv", ROLLER_GEAR, {}, "text/csv"),
    ("POST", "/v1/cams/roller-gear.stl", "/v1/cams/roller-gear.stl", ROLLER_GEAR, {}, "model/stl"),
]
if "/v1/curves/{name}/value" in DOC["paths"]:  # the spreadsheet cell (API contract: one bare number)
    CASES.append(("GET", "/v1/curves/{name}/value", "/v1/curves/MS/value?t=0.3&quantity=s", None, {}, "text/plain"))


def declared(method: str, path: str) -> dict[str, Any]:
    return DOC["paths"][path][method.lower()]["responses"]["200"]["content"]


@pytest.mark.parametrize(("method", "path", "url", "body", "headers", "media"), CASES,
                         ids=[f"{c[0]} {c[2][:60]}" for c in CASES])
async def test_answer_media_type_is_declared(client: httpx.AsyncClient, method: str, path: str, url: str,
                                             body: dict[str, Any] | None, headers: dict[str, str],
                                             media: str) -> None:
    r = await client.request(method, url, json=body, headers=headers)
    assert r.status_code == 200, r.text
    answered = r.headers["content-type"].split(";")[0].strip()
    assert answered == media
    content = declared(method, path)
    assert answered in content, f"{method} {path} answers {answered} but declares {list(content)}"
    assert content[answered].get("schema"), f"{method} {path}: {answered} has no schema"


def test_every_operation_with_a_non_json_answer_is_exercised() -> None:
    exercised = {(m, p) for m, p, *_ in CASES}
    non_json = {(method.upper(), path) for path, ops in DOC["paths"].items() for method, op in ops.items()
                if set(op["responses"].get("200", {}).get("content", {})) - {"application/json"}}
    assert non_json <= exercised, f"add a case above for {sorted(non_json - exercised)}"


def test_json_answers_keep_their_models_and_come_first() -> None:
    # JSON is typed by a model (generated clients get classes), and listed first where an
    # operation also answers a file, so that a generator reading the first media type reads JSON
    for path, ops in DOC["paths"].items():
        for method, op in ops.items():
            content = op["responses"]["200"]["content"]
            if "application/json" in content:
                assert "$ref" in content["application/json"]["schema"], (method, path)
                assert next(iter(content)) == "application/json", (method, path, list(content))


def test_file_twins_answer_only_their_file() -> None:
    twins = {path: ops["post"] if "post" in ops else ops["get"] for path, ops in DOC["paths"].items()
             if path.endswith((".csv", ".dxf", ".xyz", ".step", ".stl", ".nc"))}
    # the 12 table and contour files, the 2 vibration tables, the cam table, the toolpath's G-code
    # and DXF, the two solids, the barrel and parallel cams' tables, the roller-gear cam's table and rib
    assert len(twins) == 23, sorted(twins)
    for path, op in twins.items():
        content = op["responses"]["200"]["content"]
        assert len(content) == 1, (path, list(content))
        # binary for DXF, STEP and STL (a generator hands back bytes), text for CSV, X Y Z, G-code
        media, entry = next(iter(content.items()))
        binary = media in ("application/dxf", "model/step", "model/stl")
        assert entry["schema"] == ({"type": "string", "format": "binary"} if binary
                                   else {"type": "string"}), (path, entry)


def test_committed_document_keeps_json_first() -> None:
    # the committed file sorts keys for a stable diff, but not the media types of a content map
    import json

    from scripts.export_openapi import TARGET

    committed = json.loads(TARGET.read_text(encoding="utf-8"))
    content = committed["paths"]["/v1/profiles"]["post"]["responses"]["200"]["content"]
    assert next(iter(content)) == "application/json", list(content)
