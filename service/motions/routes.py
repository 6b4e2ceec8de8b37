"""/v1/motions: a machine cycle of one follower, matched at every join.

``computeMotion`` answers JSON, or the table as CSV on ``?format=csv`` / ``Accept: text/csv``;
``computeMotionCsv`` answers only the CSV, for generated clients, which read one media type
per operation.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from fastapi import APIRouter, Body, Depends, Query, Request
from starlette.responses import Response

from camcore.export import MOTION_FORMATS
from service.admission import WorkGate
from service.curves.routes import CSV, CSV_FILE, ERRORS
from service.deps import motion_service, work_gate
from service.motions import cam_table
from service.motions.service import MotionService
from service.motions.specs import MOTION_EXAMPLES, MotionProgramAnswer, MotionProgramRequest
from service.responses import check_finite, json_response, table_response, wants_csv
from service.routing import OrjsonRoute

router = APIRouter(prefix="/v1/motions", tags=["motions"], route_class=OrjsonRoute)
Service = Annotated[MotionService, Depends(motion_service)]
Gate = Annotated[WorkGate, Depends(work_gate)]
MotionBody = Annotated[MotionProgramRequest, Body(openapi_examples=MOTION_EXAMPLES)]


#: ``?format=``: JSON, the table as CSV, or a file of camcore.export.MOTION_FORMATS
MotionFormat = Literal[("json", "csv", *MOTION_FORMATS)]  # type: ignore[valid-type]  # built from the registry
FORMAT_HELP = "csv: the table alone, for spreadsheets; " + "; ".join(
    f"{fmt.name}: {fmt.description}" for fmt in MOTION_FORMATS.values())
ANSWERS: dict[str, Any] = {"content": CSV["content"], "description": "Columns as JSON, or CSV: the table, or the cam table"}


@router.post("", operation_id="computeMotion", response_model=MotionProgramAnswer, responses={**ERRORS, 200: ANSWERS})
async def compute_motion(body: MotionBody, request: Request, service: Service, gate: Gate,
                         format: Annotated[MotionFormat | None, Query(description=FORMAT_HELP)] = None,
                         ) -> Response:
    """Columns x_deg, s, v, a, j (and per second with speed_rpm), the resolved segments, the
    joins with their continuity, and the characteristic values over the cycle; ``?format=cam-table``:
    the servo drive's cam table."""
    if format in MOTION_FORMATS:
        return await cam_table.cam_table_response(request, gate, service, body, MOTION_FORMATS[format])
    csv = format == "csv" or (format is None and wants_csv(request))
    return await _motion(request, gate, service, body, csv)


@router.post("/table.csv", operation_id="computeMotionCsv", response_class=Response,
             responses={**ERRORS, 200: CSV_FILE})
async def compute_motion_csv(body: MotionBody, request: Request, service: Service, gate: Gate) -> Response:
    """The columns of ``computeMotion`` as CSV."""
    return await _motion(request, gate, service, body, True)


async def _motion(request: Request, gate: WorkGate, service: MotionService, body: MotionProgramRequest,
                  csv: bool) -> Response:
    work = service.motion_work(body.motion, body.samples, body.x_deg, body.speed_rpm, csv)
    columns, report = await gate.run(request, work, service.motion, body.motion, body.samples, body.x_deg,
                                     body.speed_rpm)
    if csv:
        return table_response(columns, True, filename="motion.csv")
    check_finite(columns)
    return json_response({**columns, **report})


cam_table.register(router)
