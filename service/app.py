"""The application factory: ``create_app(settings)`` builds a configured app."""

from __future__ import annotations

from typing import Any

from fastapi import APIRouter, FastAPI
from starlette.types import ASGIApp

import camcore
from service.admission import InFlightLimit, WorkGate
from service.cams import routes as cams
from service.curves import routes as curves
from service.curves import sweep as curve_sweep
from service.curves.service import CurveService
from service.errors import install_error_handlers
from service.health import router as health_router
from service.indexers import routes as indexers
from service.indexers.service import IndexerService
from service.middleware import AllowedMethods, BodySizeLimit, JSONBodiesOnly, SecurityHeaders, ServerTiming
from service.motions import routes as motions
from service.motions.service import MotionService
from service.offline_docs import install_offline_docs
from service.openapi_examples import restore_examples
from service.plots import routes as plots
from service.profiles import dynamics_routes as dynamics
from service.profiles import routes as profiles
from service.profiles.service import ProfileService
from service.security import install_security
from service.settings import Settings
from service.vibration import routes as vibration

DESCRIPTION = """Cam motion curves (Makino's universal cam curve, the INDEXMAN catalog curves,
polynomial laws, Bezier and measured-point curves), characteristic values, exact inverse
lookups, indexer sizing, plate-cam profiles and motion programs (machine cycles matched at every
join). Tables are column-oriented JSON, or CSV
on `Accept: text/csv` (POST) or `?format=csv` (GET)."""


class CamcoreAPI(FastAPI):
    """FastAPI with :class:`SecurityHeaders` and :class:`ServerTiming` outside everything,
    Starlette's own error middleware included (its 500 answers would miss the headers
    otherwise), and with the request examples of its routers as written, nulls included
    (service.openapi_examples)."""

    example_routers: tuple[APIRouter, ...] = ()

    def build_middleware_stack(self) -> ASGIApp:
        return SecurityHeaders(ServerTiming(super().build_middleware_stack()))

    def openapi(self) -> dict[str, Any]:
        if self.openapi_schema is None:
            restore_examples(super().openapi(), self.example_routers)
        return super().openapi()


def create_app(settings: Settings | None = None) -> FastAPI:
    settings = settings or Settings()
    app = CamcoreAPI(title="camcore", version=camcore.__version__, description=DESCRIPTION,
                     docs_url=None, redoc_url=None)  # served offline by install_offline_docs
    app.state.settings = settings
    app.state.work_gate = WorkGate(settings)
    app.state.curve_service = CurveService(settings)
    app.state.motion_service = MotionService(app.state.curve_service)
    app.state.indexer_service = IndexerService(app.state.curve_service, app.state.motion_service)
    app.state.profile_service = ProfileService(app.state.curve_service, app.state.motion_service)
    install_error_handlers(app)
    # vibration before plots: its GET /v1/curves/vibration/plot would match /v1/curves/{name}/plot
    app.example_routers = (health_router, curves.router, curve_sweep.router, indexers.router, profiles.router, motions.router,
                           vibration.router, plots.router, dynamics.router, cams.router)
    for router in app.example_routers:
        app.include_router(router)
    install_offline_docs(app)  # before security: it publishes the asset paths left open
    app.add_middleware(BodySizeLimit, max_body_bytes=settings.max_body_bytes)
    app.add_middleware(JSONBodiesOnly, routes=app.router.routes)  # 415 before any body is read
    app.add_middleware(AllowedMethods, routes=app.router.routes)
    app.add_middleware(InFlightLimit, max_in_flight=settings.max_in_flight)  # 503 before any body is read
    # last: outermost (CORS, then the key, then the in-flight limit, methods, media type and body limit)
    install_security(app, settings)
    return app
