"""/v1/profiles/dynamics: a force-closed follower's contact force, jump speed and stress.

``computeFollowerDynamics`` answers JSON, or the table as CSV on ``?format=csv`` /
``Accept: text/csv``; ``computeFollowerDynamicsCsv`` answers only the CSV, for generated
clients; ``plotFollowerDynamics`` draws the contact force (GET, like the other charts).
"""

from __future__ import annotations

from typing import Annotated, Literal

from fastapi import APIRouter, Body, Depends, Query, Request
from starlette.responses import Response

from service.admission import WorkGate
from service.curves.routes import CSV, CSV_FILE, ERRORS
from service.deps import work_gate
from service.plots.charts import IMAGE_RESPONSE, PlotService, plot_service
from service.plots.dynamics_chart import DynamicsPlotQuery, dynamics_plot, dynamics_plot_work
from service.plots.routes import image
from service.profiles.dynamics_service import DynamicsService, dynamics_service
from service.profiles.dynamics_specs import DYNAMICS_EXAMPLES, DynamicsAnswer, DynamicsRequest
from service.responses import check_finite, json_response, table_response, wants_csv
from service.routing import OrjsonRoute

router = APIRouter(prefix="/v1/profiles", tags=["profiles"], route_class=OrjsonRoute)
Service = Annotated[DynamicsService, Depends(dynamics_service)]
Plots = Annotated[PlotService, Depends(plot_service)]
Gate = Annotated[WorkGate, Depends(work_gate)]
DynamicsBody = Annotated[DynamicsRequest, Body(openapi_examples=DYNAMICS_EXAMPLES)]


@router.post("/dynamics", operation_id="computeFollowerDynamics", response_model=DynamicsAnswer,
             responses={**ERRORS, 200: CSV})
async def compute_follower_dynamics(body: DynamicsBody, request: Request, service: Service, gate: Gate,
                                    format: Annotated[Literal["json", "csv"] | None,
                                                      Query(description="csv: the table alone, for spreadsheets")]
                                    = None) -> Response:
    """Contact force, normal force, camshaft torque and Hertz stress over the cam angle of a
    spring-loaded follower at a speed; minimum contact force, whether the follower leaves the cam,
    the jump speed, the smallest preload, peak and RMS torque, peak stress over the turn."""
    csv = format == "csv" or (format is None and wants_csv(request))
    return await _dynamics(request, gate, service, body, csv)


@router.post("/dynamics/table.csv", operation_id="computeFollowerDynamicsCsv", response_class=Response,
             responses={**ERRORS, 200: CSV_FILE})
async def compute_follower_dynamics_csv(body: DynamicsBody, request: Request, service: Service,
                                        gate: Gate) -> Response:
    """The columns of ``computeFollowerDynamics`` as CSV."""
    return await _dynamics(request, gate, service, body, True)


async def _dynamics(request: Request, gate: WorkGate, service: DynamicsService, body: DynamicsRequest,
                    csv: bool) -> Response:
    columns, report = await gate.run(request, service.work(body, csv), service.answer, body)
    if csv:
        return table_response(columns, True, filename="dynamics.csv")
    check_finite(columns)
    return json_response({**columns, **report})


@router.get("/dynamics/plot", operation_id="plotFollowerDynamics", response_class=Response,
            responses={**ERRORS, 200: IMAGE_RESPONSE})
async def plot_follower_dynamics(query: Annotated[DynamicsPlotQuery, Query()], request: Request, plots: Plots,
                                 service: Service, gate: Gate) -> Response:
    """Contact force over the cam angle of a rise–dwell–return cam (the fields of plotProfile) with
    the zero line, the safety margin and the region where the follower leaves the cam shaded."""
    work = dynamics_plot_work(plots, service, query)
    return image(await gate.run(request, work, dynamics_plot, plots, service, query), query.format)
