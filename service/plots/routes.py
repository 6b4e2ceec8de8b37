"""Charts as GET endpoints (SVG or PNG), so a browser, a wiki or a document can embed them."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Depends, Query, Request
from starlette.responses import Response

from service.admission import WorkGate
from service.curves.routes import ERRORS, CurveName
from service.deps import work_gate
from service.plots.charts import (
    IMAGE_RESPONSE,
    MEDIA_TYPES,
    CurvePlotQuery,
    IndexerPlotQuery,
    PlotService,
    ProfilePlotQuery,
    plot_service,
)
from service.routing import OrjsonRoute

router = APIRouter(route_class=OrjsonRoute)
Service = Annotated[PlotService, Depends(plot_service)]
Gate = Annotated[WorkGate, Depends(work_gate)]
IMAGE = {**ERRORS, 200: IMAGE_RESPONSE}


def image(body: bytes, fmt: str) -> Response:
    # the same query always draws the same chart
    return Response(body, media_type=MEDIA_TYPES[fmt], headers={"Cache-Control": "public, max-age=3600"})


@router.get("/v1/curves/{name}/plot", operation_id="plotCurve", tags=["curves"], response_class=Response,
            responses=IMAGE)
async def plot_curve(name: CurveName, query: Annotated[CurvePlotQuery, Query()], request: Request, service: Service,
                     gate: Gate) -> Response:
    """S, V, A, J of a catalog curve over T, characteristic values marked (``?format=png`` for PNG)."""
    return image(await gate.run(request, service.render_work(query), service.curve_plot, name, query), query.format)


@router.get("/v1/indexers/plot", operation_id="plotIndexerMotion", tags=["indexers"], response_class=Response,
            responses=IMAGE)
async def plot_indexer_motion(query: Annotated[IndexerPlotQuery, Query()], request: Request, service: Service,
                              gate: Gate) -> Response:
    """Output angle, ω, α and jerk over the input angle of one index (fields of IndexerSpec)."""
    return image(await gate.run(request, service.render_work(query), service.indexer_plot, query), query.format)


@router.get("/v1/profiles/plot", operation_id="plotProfile", tags=["profiles"], response_class=Response,
            responses=IMAGE)
async def plot_profile(query: Annotated[ProfilePlotQuery, Query()], request: Request, service: Service,
                       gate: Gate) -> Response:
    """Contour, base circle, pitch curve (roller) and pressure angle of a rise–dwell–return–dwell cam."""
    return image(await gate.run(request, service.profile_work(query), service.profile_plot, query), query.format)
