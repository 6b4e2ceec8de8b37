"""/v1/indexers: motion over the input angle, position lookup, torque and power sizing."""

from __future__ import annotations

from typing import Annotated, Literal

from fastapi import APIRouter, Body, Depends, Query, Request
from starlette.responses import Response

from service.admission import WorkGate
from service.curves.routes import CSV, CSV_FILE, ERRORS
from service.deps import indexer_service, work_gate
from service.indexers.service import IndexerService
from service.indexers.specs import (
    MOTION_EXAMPLES,
    POSITION_EXAMPLES,
    SIZING_EXAMPLES,
    AccuracyAnswer,
    MotionAnswer,
    MotionRequest,
    PositionAnswer,
    PositionRequest,
    SizingAnswer,
    SizingRequest,
)
from service.indexers.sweep import SWEEP_EXAMPLES, SizingSweepAnswer, SizingSweepRequest, sweep, sweep_work
from service.plots.charts import IMAGE_RESPONSE, MEDIA_TYPES
from service.plots.sweep_chart import sweep_chart
from service.responses import JSONBody, check_finite, encoded_response, json_response, table_response, wants_csv
from service.routing import OrjsonRoute

router = APIRouter(prefix="/v1/indexers", tags=["indexers"], route_class=OrjsonRoute)
Service = Annotated[IndexerService, Depends(indexer_service)]
Gate = Annotated[WorkGate, Depends(work_gate)]


@router.post("/motion", operation_id="getIndexerMotion", response_model=MotionAnswer, responses={**ERRORS, 200: CSV})
async def indexer_motion(body: Annotated[MotionRequest, Body(openapi_examples=MOTION_EXAMPLES)], request: Request,
                         service: Service, gate: Gate) -> Response:
    """Summary (times, exact peaks) and the output motion over one index (CSV: the table)."""
    return await _motion(request, gate, service, body, wants_csv(request))


@router.post("/motion.csv", operation_id="getIndexerMotionCsv", response_class=Response,
             responses={**ERRORS, 200: CSV_FILE})
async def indexer_motion_csv(body: Annotated[MotionRequest, Body(openapi_examples=MOTION_EXAMPLES)],
                             request: Request, service: Service, gate: Gate) -> Response:
    """The motion table of ``getIndexerMotion`` as CSV."""
    return await _motion(request, gate, service, body, True)


async def _motion(request: Request, gate: WorkGate, service: IndexerService, body: MotionRequest,
                  csv: bool) -> Response:
    work = service.motion_work(body.indexer, body.samples, csv)
    summary, table = await gate.run(request, work, service.motion, body.indexer, body.samples)
    if csv:
        return table_response(table, True, filename="motion.csv")
    check_finite(table)
    return json_response({"summary": summary, "table": table})


@router.post("/position", operation_id="getIndexerPosition", response_model=PositionAnswer,
             responses={**ERRORS, 200: CSV})
async def indexer_position(body: Annotated[PositionRequest, Body(openapi_examples=POSITION_EXAMPLES)],
                           request: Request, service: Service, gate: Gate) -> Response:
    """For each output angle: input angle, time, ω and α (exact, or the catalog's table method)."""
    return await _position(request, gate, service, body, wants_csv(request))


@router.post("/position.csv", operation_id="getIndexerPositionCsv", response_class=Response,
             responses={**ERRORS, 200: CSV_FILE})
async def indexer_position_csv(body: Annotated[PositionRequest, Body(openapi_examples=POSITION_EXAMPLES)],
                               request: Request, service: Service, gate: Gate) -> Response:
    """The answer of ``getIndexerPosition`` as CSV."""
    return await _position(request, gate, service, body, True)


async def _position(request: Request, gate: WorkGate, service: IndexerService, body: PositionRequest,
                    csv: bool) -> Response:
    work = service.position_work(body.indexer, len(body.output_angle_deg), body.method, body.table_step, csv)
    columns = await gate.run(request, work, service.position, body.indexer, body.output_angle_deg, body.method,
                             body.table_step, body.table_decimals)
    return table_response(columns, csv, filename="position.csv")


@router.post("/sizing", operation_id="sizeIndexer", response_model=SizingAnswer, responses=ERRORS)
async def indexer_sizing(body: Annotated[SizingRequest, Body(openapi_examples=SIZING_EXAMPLES)],
                         request: Request, service: Service, gate: Gate) -> Response:
    """Inertia, friction and work torque, output and input torque, input power."""
    key = body.model_dump_json()
    payload = service.sizings.get(key)  # the same request again: its answer, on the event loop
    if payload is None:
        work = service.sizing_work(body.indexer, body.table_samples, body.motor is not None)
        result = await gate.run(request, work, service.sizing, body.indexer, body.load, body.motor,
                                body.table_samples)
        check_finite({k: v for k, v in result.items() if isinstance(v, float)})
        encoded = bytes(JSONBody(result).body)
        payload = service.sizings.get_or_create(key, lambda: encoded)
    return encoded_response(payload, False)


@router.post("/sizing/sweep", operation_id="sweepIndexerSizing", response_model=SizingSweepAnswer,
             responses={**ERRORS, 200: {"content": {**CSV["content"], **IMAGE_RESPONSE["content"]}}})
async def indexer_sizing_sweep(body: Annotated[SizingSweepRequest, Body(openapi_examples=SWEEP_EXAMPLES)],
                               request: Request, service: Service, gate: Gate,
                               format: Annotated[Literal["png", "svg"] | None, Query(
                                   description="a chart of input torque over speed per curve instead of the table")]
                               = None) -> Response:
    """Every combination of stops × indexing angles × curves × speeds sized at once (CSV on request,
    or ``?format=png|svg``: input torque over speed per curve, a panel per stops and angle)."""
    work = sweep_work(service.curves, body, chart=format is not None)
    if format is not None:  # drawn in the gate's thread, like the computation
        chart = await gate.run(request, work, lambda: sweep_chart(sweep(service, body), format))
        return Response(chart, media_type=MEDIA_TYPES[format])
    columns = await gate.run(request, work, sweep, service, body)
    return table_response(columns, wants_csv(request), filename="sizing-sweep.csv")


@router.get("/accuracy", operation_id="convertIndexingAccuracy", response_model=AccuracyAnswer, responses=ERRORS)
def indexing_accuracy(
    service: Service,
    arc_seconds: Annotated[float, Query(ge=0, le=1e6, allow_inf_nan=False)],
    radius_mm: Annotated[float, Query(ge=0, le=1e7, allow_inf_nan=False)],
) -> Response:
    """Arc-seconds at a radius → millimetres: x = 2π·r·θ/(360·3600) (guide, 计算分度精度)."""
    return JSONBody(service.accuracy(arc_seconds, radius_mm))
