"""Servo cam tables of /v1/motions: ``?format=cam-table`` and ``/v1/motions/cam-table.csv``.

The program sampled at ``samples`` master angles evenly over one period (a fixed step of
period / (samples − 1)), written by :data:`camcore.export.MOTION_FORMATS`: master position,
slave position, and the slave's velocity and acceleration per degree of master.
:func:`register` adds the file's own operation to the motions router.
"""

from __future__ import annotations

from typing import Annotated, Any

from fastapi import APIRouter, Body, Depends, Request
from starlette.responses import Response

from camcore.errors import InvalidParameterError
from camcore.export import MOTION_FORMATS, CamTable, FileFormat
from camcore.work import WorkEstimate, WorkTerm
from service.admission import WorkGate
from service.curves.routes import ERRORS
from service.deps import motion_service, work_gate
from service.motions.service import MotionService
from service.motions.specs import MOTION_EXAMPLES, MotionProgramRequest

Service = Annotated[MotionService, Depends(motion_service)]
Gate = Annotated[WorkGate, Depends(work_gate)]
MotionBody = Annotated[MotionProgramRequest, Body(openapi_examples={
    name: example for name, example in MOTION_EXAMPLES.items() if "x_deg" not in example["value"]})]


def cam_table(service: MotionService, body: MotionProgramRequest) -> CamTable:
    """The program at a fixed master step over one period, both ends included."""
    program = service.program(body.motion)
    assert body.samples is not None  # checked by cam_table_response
    x = program.sample_angles(body.samples)
    s, v, a = program.derivatives(x, 2)
    return CamTable(x, s, v, a, program.unit)


def cam_table_file(service: MotionService, body: MotionProgramRequest, fmt: str) -> bytes:
    """The cam table written in one of :data:`camcore.export.MOTION_FORMATS`."""
    return MOTION_FORMATS[fmt].write(cam_table(service, body))


async def cam_table_response(request: Request, gate: WorkGate, service: MotionService, body: MotionProgramRequest,
                             fmt: FileFormat[CamTable]) -> Response:
    """The cam table as a download; 422 for master angles given one by one (no fixed step)."""
    if body.x_deg is not None:
        raise InvalidParameterError("a cam table has a fixed master step: give samples (the step is "
                                    "period_deg / (samples − 1)), not x_deg.", field=("x_deg",))
    work = service.motion_work(body.motion, body.samples, None, None, True)
    rows = int(body.samples or 361)
    work += WorkEstimate((WorkTerm(("samples",), f"writing {rows} rows as {fmt.name}", fmt.cost(rows)),))
    payload = await gate.run(request, work, cam_table_file, service, body, fmt.name)
    return Response(payload, media_type=fmt.media_type,
                    headers={"Content-Disposition": f'attachment; filename="{fmt.file_name}"'})


def content(fmt: FileFormat[Any]) -> dict[str, Any]:
    """A download's OpenAPI media type: text for text/*, else bytes."""
    schema = {"type": "string"} if fmt.is_text else {"type": "string", "format": "binary"}
    return {fmt.media_type.split(";")[0]: {"schema": schema}}


def register(router: APIRouter) -> None:
    """One operation per motion-table format (``/<name>.<ext>``), whose only answer is that file."""
    for fmt in MOTION_FORMATS.values():
        _route(router, fmt)


def _route(router: APIRouter, fmt: FileFormat[CamTable]) -> None:
    extension = fmt.file_name.rsplit(".", 1)[-1]
    camel = "".join(part.capitalize() for part in fmt.name.split("-"))

    async def export_table(body: MotionBody, request: Request, service: Service, gate: Gate) -> Response:
        return await cam_table_response(request, gate, service, body, fmt)

    export_table.__doc__ = f"The program as a {fmt.description} (``computeMotion`` with ``?format={fmt.name}``)."
    router.add_api_route(f"/{fmt.name}.{extension}", export_table, methods=["POST"],
                         operation_id=f"exportMotion{camel}", response_class=Response, summary=f"Export Motion {camel}",
                         responses={**ERRORS, 200: {"content": content(fmt), "description": fmt.description}})
