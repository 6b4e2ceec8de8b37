"""Charts as GET endpoints (SVG or PNG), so a browser, a wiki or a document can embed them."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Depends, Query
from starlette.responses import Response

from service.curves.routes import ERRORS, CurveName
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
IMAGE = {**ERRORS, 200: IMAGE_RESPONSE}


def image(body: bytes, fmt: str) -> Response:
    # the same query always draws the same chart
    return Response(body, media_type=MEDIA_TYPES[fmt], headers={"Cache-Control": "public, max-age=3600"})


@router.get("/v1/curves/{name}/plot", operation_id="plotCurve", tags=["curves"], response_class=Response,
            responses=IMAGE)
def plot_curve(name: CurveName, query: Annotated[CurvePlotQuery, Query()], service: Service) -> Response:
    """S, V, A, J of a catalog curve over T, characteristic values marked (``?format=png`` for PNG)."""
    return image(service.curve_plot(name, query), query.format)


@router.get("/v1/indexers/plot", operation_id="plotIndexerMotion", tags=["indexers"], response_class=Response,
            responses=IMAGE)
def plot_indexer_motion(query: Annotated[IndexerPlotQuery, Query()], service: Service) -> Response:
    """Output angle, ω, α and jerk over the input angle of one index (fields of IndexerSpec)."""
    return image(service.indexer_plot(query), query.format)


@router.get("/v1/profiles/plot", operation_id="plotProfile", tags=["profiles"], response_class=Response,
            responses=IMAGE)
def plot_profile(query: Annotated[ProfilePlotQuery, Query()], service: Service) -> Response:
    """Contour, base circle, pitch curve (roller) and pressure angle of a rise–dwell–return–dwell cam."""
    return image(service.profile_plot(query), query.format)
