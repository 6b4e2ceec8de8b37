"""/v1/motions: a machine cycle of one follower, matched at every join.

``computeMotion`` answers JSON, or the table as CSV on ``?format=csv`` / ``Accept: text/csv``;
``computeMotionCsv`` answers only the CSV, for generated clients, which read one media type
per operation.
"""

from __future__ import annotations

from typing import Annotated, Literal

from fastapi import APIRouter, Body, Depends, Query, Request
from starlette.responses import Response

from service.admission import WorkGate
from service.curves.routes import CSV, CSV_FILE, ERRORS
from service.deps import motion_service, work_gate
from service.motions.service import MotionService
from service.motions.specs import MOTION_EXAMPLES, MotionProgramAnswer, MotionProgramRequest
from service.responses import check_finite, json_response, table_response, wants_csv
from service.routing import OrjsonRoute

router = APIRouter(prefix="/v1/motions", tags=["motions"], route_class=OrjsonRoute)
Service = Annotated[MotionService, Depends(motion_service)]
Gate = Annotated[WorkGate, Depends(work_gate)]
MotionBody = Annotated[MotionProgramRequest, Body(openapi_examples=MOTION_EXAMPLES)]


@router.post("", operation_id="computeMotion", response_model=MotionProgramAnswer, responses={**ERRORS, 200: CSV})
async def compute_motion(body: MotionBody, request: Request, service: Service, gate: Gate,
                         format: Annotated[Literal["json", "csv"] | None,
                                           Query(description="csv: the table alone, for spreadsheets")] = None,
                         ) -> Response:
    """Columns x_deg, s, v, a, j (and per second with speed_rpm), the resolved segments, the
    joins with their continuity, and the characteristic values over the cycle."""
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
