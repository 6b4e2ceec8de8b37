"""``POST /v1/cams/roller-gear`` (``computeRollerGearCam``): a roller-gear cam's rib — both flanks as point
grids, the pressure angles, the checks; the columns over the turn as CSV (``?format=csv``, ``Accept: text/csv``,
the twin ``/roller-gear.csv``) and the rib as a closed binary STL (``?format=stl``, the twin ``/roller-gear.stl``).
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from fastapi import APIRouter, Body, Depends, Query, Request
from starlette.responses import Response

from camcore.cams.roller_gear import RollerGearResult, make_roller_gear_cam, rib_triangles, sample_roller_gear
from camcore.export import mesh_stl
from camcore.results import as_dict
from camcore.work import WorkEstimate, curve_work, per_item_work
from service.admission import WorkGate
from service.cams.roller_gear_specs import ROLLER_GEAR_EXAMPLES, RollerGearCamAnswer, RollerGearCamRequest
from service.curves.routes import CSV, CSV_FILE, ERRORS
from service.curves.service import CurveService
from service.deps import curve_service, work_gate
from service.responses import check_finite, encode_cost, json_response, table_response, wants_csv
from service.routing import OrjsonRoute

#: the largest pressure angle refined (both flanks, two radii together) and the rest of a 2 × 2 grid: measured
#: 2.3 ms (3.8 ms when the radii were refined one after the other); ×1.5 of 4 ms kept
PRESSURE_SEARCH_S = 1.5 * 4e-3
#: one flank point (both flanks: the contact, its derivatives, regularity): median 0.66 µs, at most 0.86 µs
#: over 9 runs of the largest grid (3601 × 41); ×1.5 of 0.7 µs
FLANK_POINT_S = 1.5 * 0.7e-6
#: one STL facet (the mesh indexed and written): median 0.26 µs, at most 0.54 µs over the same runs (the
#: 42 MB of vertices allocated afresh each time); ×1.5 of 0.4 µs
FACET_S = 1.5 * 0.4e-6
#: numbers per flank point in the JSON answer: x, y, z, pressure angle and regular of two flanks
FLANK_VALUES = 10
STL: dict[str, Any] = {"content": {"model/stl": {"schema": {"type": "string", "format": "binary"}}},
       "description": "the rib as a closed binary STL in mm (?format=stl)"}
STL_FILE: dict[str, Any] = {"content": {"model/stl": {"schema": {"type": "string", "format": "binary"}}},
            "description": "the rib as a closed binary STL in mm"}


def facets(body: RollerGearCamRequest) -> int:
    """The rib mesh's facets: two per quad between consecutive cross-section rings, and two caps."""
    ring = 2 * body.length_samples
    return 2 * (body.samples - 1) * ring + 4 * (body.length_samples - 1)


def roller_gear_work(curves: CurveService, body: RollerGearCamRequest, fmt: str) -> WorkEstimate:
    """The curve built, the pressure search, the flank grids and their encoding or the mesh."""
    curves.check_limit("roller-gear flank points (samples × length_samples)", body.samples * body.length_samples,
                       curves.settings.max_table_samples, ("samples",))
    points = body.samples * body.length_samples
    work = (curve_work(curves.law(body.curve), ("curve",))
            + per_item_work(1, PRESSURE_SEARCH_S, ("indexing_angle_deg",), "the largest pressure angle refined")
            + per_item_work(points, FLANK_POINT_S, ("samples",), f"{points} points on each flank"))
    if fmt == "stl":
        curves.check_limit("STL facets", facets(body), curves.settings.max_stl_triangles, ("samples",))
        return work + per_item_work(facets(body), FACET_S, ("samples",), f"{facets(body)} STL facets")
    values = body.samples * 4 + (0 if fmt == "csv" else points * FLANK_VALUES)
    return work + per_item_work(values, encode_cost(1, fmt == "csv"), ("samples",), f"{values} numbers encoded")


def _result(curves: CurveService, body: RollerGearCamRequest) -> RollerGearResult:
    cam = make_roller_gear_cam(body.stops, body.center_distance_mm, body.roller_pitch_radius_mm,
                               body.roller_radius_mm, body.roller_length_mm, body.indexing_angle_deg,
                               curves.curve(body.curve))
    return sample_roller_gear(cam, body.samples, body.length_samples)


def _columns(r: RollerGearResult) -> dict[str, Any]:
    return {"cam_angle_deg": r.cam_angle_deg, "turret_angle_deg": r.turret_angle_deg,
            "pressure_angle_deg": r.pressure_angle_deg, "back_pressure_angle_deg": r.back_pressure_angle_deg}


def answer(curves: CurveService, body: RollerGearCamRequest) -> dict[str, Any]:
    """The JSON answer: the columns over the turn, both flank grids, the checks."""
    r = _result(curves, body)
    columns = {**_columns(r), "roller_position_mm": r.roller_position_mm}
    flanks = {f.flank: {"x_mm": f.x_mm, "y_mm": f.y_mm, "z_mm": f.z_mm, "pressure_angle_deg": f.pressure_angle_deg,
                        "regular": f.regular} for f in (r.forward, r.back)}
    check_finite({**columns, **{f"{name} flank {k}": v for name, flank in flanks.items() for k, v in flank.items()}})
    return {**columns, "flanks": flanks, "checks": as_dict(r.checks)}


def columns(curves: CurveService, body: RollerGearCamRequest) -> dict[str, Any]:
    """The columns over the turn (CSV)."""
    return _columns(_result(curves, body))


def stl(curves: CurveService, body: RollerGearCamRequest) -> bytes:
    """The rib as a binary STL."""
    r = _result(curves, body)
    return mesh_stl(rib_triangles(r), header=f"camcore roller-gear rib, {body.stops} stops",
                    max_triangles=curves.settings.max_stl_triangles, field=("samples",))


Curves = Annotated[CurveService, Depends(curve_service)]
Gate = Annotated[WorkGate, Depends(work_gate)]
RollerGearBody = Annotated[RollerGearCamRequest, Body(openapi_examples=ROLLER_GEAR_EXAMPLES)]


async def compute_roller_gear_cam(body: RollerGearBody, request: Request, curves: Curves, gate: Gate,
                                  format: Annotated[Literal["json", "csv", "stl"] | None,
                                                    Query(description="csv: the columns over the turn; stl: the rib "
                                                                      "as a closed binary STL")] = None
                                  ) -> Response:
    """A roller-gear (globoidal) cam: both flanks of its rib as point grids in the cam's frame (the envelopes of
    the two rollers straddling the rib), the pressure angle over the index, the turret's angle, and the checks
    (largest pressure angle, undercut, the rib's thickness and radii); the rib as an STL with ``?format=stl``."""
    fmt = format or ("csv" if wants_csv(request) else "json")
    return await _answer(request, gate, curves, body, fmt)


async def compute_roller_gear_cam_csv(body: RollerGearBody, request: Request, curves: Curves, gate: Gate) -> Response:
    """The columns of ``computeRollerGearCam`` over the rib's turn as CSV."""
    return await _answer(request, gate, curves, body, "csv")


async def compute_roller_gear_cam_stl(body: RollerGearBody, request: Request, curves: Curves, gate: Gate) -> Response:
    """The rib of ``computeRollerGearCam`` as a closed binary STL (mm, the cam's frame)."""
    return await _answer(request, gate, curves, body, "stl")


async def _answer(request: Request, gate: WorkGate, curves: CurveService, body: RollerGearCamRequest,
                  fmt: str) -> Response:
    work = roller_gear_work(curves, body, fmt)
    if fmt == "stl":
        payload = await gate.run(request, work, stl, curves, body)
        return Response(payload, media_type="model/stl",
                        headers={"Content-Disposition": 'attachment; filename="roller-gear-rib.stl"'})
    if fmt == "csv":
        return table_response(await gate.run(request, work, columns, curves, body), True,
                              filename="roller-gear-cam.csv")
    return json_response(await gate.run(request, work, answer, curves, body))


def register(router: APIRouter) -> None:
    """Add ``computeRollerGearCam`` and its CSV and STL twins to the /v1/cams router."""
    router.add_api_route("/roller-gear", compute_roller_gear_cam, methods=["POST"], operation_id="computeRollerGearCam",
                         response_model=RollerGearCamAnswer,
                         responses={**ERRORS, 200: {"content": {**CSV["content"], **STL["content"]},
                                                    "description": "the rib (JSON), its columns (CSV) or its STL"}},
                         route_class_override=OrjsonRoute, summary="Compute Roller Gear Cam")
    router.add_api_route("/roller-gear.csv", compute_roller_gear_cam_csv, methods=["POST"],
                         operation_id="computeRollerGearCamCsv", response_class=Response,
                         responses={**ERRORS, 200: CSV_FILE}, route_class_override=OrjsonRoute,
                         summary="Compute Roller Gear Cam Csv")
    router.add_api_route("/roller-gear.stl", compute_roller_gear_cam_stl, methods=["POST"],
                         operation_id="computeRollerGearCamStl", response_class=Response,
                         responses={**ERRORS, 200: STL_FILE}, route_class_override=OrjsonRoute,
                         summary="Compute Roller Gear Cam Stl")
