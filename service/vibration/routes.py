"""Residual vibration: ``POST /v1/curves/vibration`` (a curve's spectrum over τ),
``POST /v1/indexers/vibration`` (an indexer's load on an elastic drive train) and
``GET /v1/curves/vibration/plot`` (the spectra of catalog curves on one chart).

Both answer JSON, or their table as CSV on ``Accept: text/csv`` / ``?format=csv``; their
``.csv`` twins answer only CSV, for generated clients (service.curves.routes says why).
"""

from __future__ import annotations

from typing import Annotated, Literal

from fastapi import APIRouter, Body, Depends, Query, Request
from starlette.responses import Response

from service.admission import WorkGate
from service.curves.routes import CSV, CSV_FILE, ERRORS
from service.deps import work_gate
from service.plots.charts import IMAGE_RESPONSE
from service.plots.routes import image
from service.responses import check_finite, json_response, table_response, wants_csv
from service.routing import OrjsonRoute
from service.vibration.plot import SpectrumPlotQuery, spectrum_plot, spectrum_work
from service.vibration.service import VibrationService, vibration_service
from service.vibration.specs import (
    INDEXER_VIBRATION_EXAMPLES,
    VIBRATION_EXAMPLES,
    IndexerVibrationAnswer,
    IndexerVibrationRequest,
    VibrationRequest,
    VibrationTableAnswer,
)

router = APIRouter(route_class=OrjsonRoute)
Service = Annotated[VibrationService, Depends(vibration_service)]
Gate = Annotated[WorkGate, Depends(work_gate)]
SpectrumBody = Annotated[VibrationRequest, Body(openapi_examples=VIBRATION_EXAMPLES)]
IndexerBody = Annotated[IndexerVibrationRequest, Body(openapi_examples=INDEXER_VIBRATION_EXAMPLES)]
Format = Annotated[Literal["json", "csv"] | None, Query(description="csv: the table, for spreadsheets")]


@router.post("/v1/curves/vibration", operation_id="computeResidualVibration", tags=["curves"],
             response_model=VibrationTableAnswer, responses={**ERRORS, 200: CSV})
async def residual_vibration(body: SpectrumBody, request: Request, service: Service, gate: Gate,
                             format: Format = None) -> Response:
    """Residual amplitude and peak deviation (fractions of the stroke) of a follower on the curve, over τ."""
    return await _spectrum(request, gate, service, body, format == "csv" or (format is None and wants_csv(request)))


@router.post("/v1/curves/vibration.csv", operation_id="computeResidualVibrationCsv", tags=["curves"],
             response_class=Response, responses={**ERRORS, 200: CSV_FILE})
async def residual_vibration_csv(body: SpectrumBody, request: Request, service: Service, gate: Gate) -> Response:
    """The columns of ``computeResidualVibration`` as CSV."""
    return await _spectrum(request, gate, service, body, True)


async def _spectrum(request: Request, gate: WorkGate, service: VibrationService, body: VibrationRequest,
                    csv: bool) -> Response:
    work = service.spectrum_work(body.curve, body.tau, body.tau_range, csv)
    columns = await gate.run(request, work, service.spectrum, body.curve, body.tau, body.tau_range,
                             body.damping_ratio)
    return table_response(columns, csv, filename="vibration.csv")


@router.post("/v1/indexers/vibration", operation_id="computeIndexerVibration", tags=["indexers"],
             response_model=IndexerVibrationAnswer, responses={**ERRORS, 200: CSV})
async def indexer_vibration(body: IndexerBody, request: Request, service: Service, gate: Gate,
                            format: Format = None) -> Response:
    """Natural frequency, τ, residual amplitude and settling time of the load, and its error over
    the index and the dwell (CSV: the table)."""
    return await _indexer(request, gate, service, body, format == "csv" or (format is None and wants_csv(request)))


@router.post("/v1/indexers/vibration.csv", operation_id="computeIndexerVibrationCsv", tags=["indexers"],
             response_class=Response, responses={**ERRORS, 200: CSV_FILE})
async def indexer_vibration_csv(body: IndexerBody, request: Request, service: Service, gate: Gate) -> Response:
    """The table of ``computeIndexerVibration`` as CSV."""
    return await _indexer(request, gate, service, body, True)


async def _indexer(request: Request, gate: WorkGate, service: VibrationService, body: IndexerVibrationRequest,
                   csv: bool) -> Response:
    work = service.indexer_work(body, csv)
    fields, table = await gate.run(request, work, service.indexer_answer, body)
    if csv:
        return table_response(table, True, filename="indexer-vibration.csv")
    check_finite(table)
    check_finite({k: v for k, v in fields.items() if isinstance(v, float)})
    return json_response({**fields, "table": table})


@router.get("/v1/curves/vibration/plot", operation_id="plotResidualVibration", tags=["curves"],
            response_class=Response, responses={**ERRORS, 200: IMAGE_RESPONSE})
async def plot_residual_vibration(query: Annotated[SpectrumPlotQuery, Query()], request: Request, service: Service,
                                  gate: Gate) -> Response:
    """The residual-vibration spectra of catalog curves on one chart (log amplitude over τ)."""
    body = await gate.run(request, spectrum_work(service, query), spectrum_plot, service, query)
    return image(body, query.format)
