"""``POST /v1/cams/parallel`` (``computeParallelIndexingCam``): a parallel indexing cam's plates, contacts and
checks; the columns over the turn as CSV on ``Accept: text/csv`` / ``?format=csv`` and from the twin
``POST /v1/cams/parallel.csv`` (the plates are JSON only: each has its own rows).
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

import numpy as np
from fastapi import APIRouter, Body, Depends, Query, Request
from starlette.responses import Response

from camcore.cams.parallel import ParallelResult, make_parallel_cam, sample_parallel
from camcore.results import as_dict
from camcore.work import WorkEstimate, curve_work, per_item_work
from service.admission import WorkGate
from service.cams.parallel_specs import PARALLEL_EXAMPLES, ParallelCamAnswer, ParallelCamRequest
from service.curves.routes import CSV, CSV_FILE, ERRORS
from service.curves.service import CurveService
from service.deps import curve_service, work_gate
from service.responses import json_response, table_response, wants_csv
from service.routing import OrjsonRoute

#: one plate × roller × sampled cam angle: its path's 8 points, the bands' union, the contour's vertices put on
#: their rollers and the contacts; measured 0.084-0.14 ms (4 or 8 rollers, 2 or 3 plates, 121-361 samples); ×1.5
PLATE_ROLLER_SAMPLE_S = 1.5 * 0.15e-3
#: columns whose NaN means "no such contact" (null in JSON, an empty CSV cell)
NULLABLE = ("drive_pressure_angle_deg", "hold_pressure_angle_deg")


def parallel_work(curves: CurveService, body: ParallelCamRequest) -> WorkEstimate:
    """The curve built and the plates drawn."""
    m = body.rollers_per_plate or body.stops
    items = body.plates * m * body.samples
    return (curve_work(curves.law(body.curve), ("curve",))
            + per_item_work(items, PLATE_ROLLER_SAMPLE_S, ("samples",),
                            f"{body.plates} plates × {m} rollers × {body.samples} cam angles"))


def _result(curves: CurveService, body: ParallelCamRequest) -> ParallelResult:
    cam = make_parallel_cam(body.stops, body.center_distance_mm, body.roller_pitch_radius_mm, body.roller_radius_mm,
                            body.indexing_angle_deg, curves.curve(body.curve), plates=body.plates,
                            rollers_per_plate=body.rollers_per_plate)
    return sample_parallel(cam, body.samples)


def _columns(r: ParallelResult) -> dict[str, Any]:
    return {"cam_angle_deg": r.cam_angle_deg, "turret_angle_deg": r.turret_angle_deg,
            "held_forward": r.held_forward, "held_back": r.held_back,
            "drive_pressure_angle_deg": r.drive_pressure_angle_deg, "hold_pressure_angle_deg": r.hold_pressure_angle_deg}


def answer(curves: CurveService, body: ParallelCamRequest) -> dict[str, Any]:
    """The JSON answer: the columns over the turn, the plates, the checks."""
    r = _result(curves, body)
    # NaN (no such contact) goes out as null
    return {**_columns(r), "plates": [as_dict(p) for p in r.plates], "checks": as_dict(r.checks)}


def columns(curves: CurveService, body: ParallelCamRequest) -> dict[str, Any]:
    """The columns over the turn (CSV; true/false as 1/0)."""
    return {name: (v.astype(np.float64) if v.dtype == bool else v) for name, v in _columns(_result(curves, body)).items()}


Curves = Annotated[CurveService, Depends(curve_service)]
Gate = Annotated[WorkGate, Depends(work_gate)]
ParallelBody = Annotated[ParallelCamRequest, Body(openapi_examples=PARALLEL_EXAMPLES)]


async def compute_parallel_cam(body: ParallelBody, request: Request, curves: Curves, gate: Gate,
                               format: Annotated[Literal["json", "csv"] | None,
                                                 Query(description="csv: the columns over the turn")] = None
                               ) -> Response:
    """A parallel indexing cam: each plate's contour (what its rollers leave), which roller touches it where and
    when, every contact over the turn, pressure angles and radii of curvature, and the checks (held both ways at
    every cam angle, largest pressure angle, undercut, room for the turret's shaft)."""
    return await _answer(request, gate, curves, body, format == "csv" or (format is None and wants_csv(request)))


async def compute_parallel_cam_csv(body: ParallelBody, request: Request, curves: Curves, gate: Gate) -> Response:
    """The columns of ``computeParallelIndexingCam`` over the turn as CSV."""
    return await _answer(request, gate, curves, body, True)


async def _answer(request: Request, gate: WorkGate, curves: CurveService, body: ParallelCamRequest,
                  csv: bool) -> Response:
    work = parallel_work(curves, body)
    if csv:
        table = await gate.run(request, work, columns, curves, body)
        return table_response(table, True, filename="parallel-cam.csv", allow_null=NULLABLE)
    return json_response(await gate.run(request, work, answer, curves, body))


def register(router: APIRouter) -> None:
    """Add ``computeParallelIndexingCam`` and its CSV twin to the /v1/cams router."""
    router.add_api_route("/parallel", compute_parallel_cam, methods=["POST"], operation_id="computeParallelIndexingCam",
                         response_model=ParallelCamAnswer, responses={**ERRORS, 200: CSV},
                         route_class_override=OrjsonRoute, summary="Compute Parallel Indexing Cam")
    router.add_api_route("/parallel.csv", compute_parallel_cam_csv, methods=["POST"],
                         operation_id="computeParallelCamCsv", response_class=Response,
                         responses={**ERRORS, 200: CSV_FILE}, route_class_override=OrjsonRoute,
                         summary="Compute Parallel Cam Csv")
