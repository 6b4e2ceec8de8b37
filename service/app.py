"""The application factory: ``create_app(settings)`` builds a configured app."""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType
from typing import Any

import orjson
from fastapi import FastAPI
from starlette.types import ASGIApp

import camcore
from service.admission import InFlightLimit
from service.context import Context
from service.errors import install_error_handlers
from service.middleware import (
    AllowedMethods,
    AnsweredErrors,
    BodySizeLimit,
    JSONBodiesOnly,
    SecurityHeaders,
    ServerTiming,
)
from service.offline_docs import install_offline_docs
from service.openapi_examples import restore_examples
from service.openapi_layout import DESCRIPTION, TAGS, arrange
from service.operations.cells import register_cell_route
from service.operations.factory import register_routes
from service.registry import OPERATIONS
from service.routing import adapter_builds
from service.security import install_security
from service.settings import Settings
from service.specs import build_models, deferred_models

#: the OpenAPI documents made in this process, by the routes, title, version and description they come from
_DOCUMENTS: dict[tuple[Any, ...], bytes] = {}


class CamcoreAPI(FastAPI):
    """FastAPI with :class:`SecurityHeaders` and :class:`ServerTiming` outside everything,
    Starlette's own error middleware included (its 500 answers would miss the headers
    otherwise), and with the request examples of its routes as written, nulls included
    (service.openapi_examples), laid out by service.openapi_layout (tags, order, header)."""

    #: the kind of each route made from an operation (operation, twin, alias), by operation id:
    #: the document lists each tag's computations, then their files, then the older paths
    route_kinds: Mapping[str, str] = MappingProxyType({})

    def build_middleware_stack(self) -> ASGIApp:
        return SecurityHeaders(ServerTiming(AnsweredErrors(super().build_middleware_stack())))

    def openapi(self) -> dict[str, Any]:
        if self.openapi_schema is None:
            # the same routes, title and version make the same document: made once per process
            # (~0.4 s), each app holding its own copy
            documented = tuple(id(route) for route in self.router.routes if getattr(route, "include_in_schema", False))
            key = (documented, self.title, self.version, self.description)
            if key not in _DOCUMENTS:
                with adapter_builds():  # the models first, then the routes' adapters of them (service.routing)
                    for model in deferred_models():
                        build_models(model)
                    document = super().openapi()
                restore_examples(document, [self.router])
                arrange(document, self.route_kinds)
                _DOCUMENTS[key] = orjson.dumps(document)
            self.openapi_schema = orjson.loads(_DOCUMENTS[key])  # JSON data: a copy in ~10 ms (deepcopy: ~0.4 s)
        return self.openapi_schema


def create_app(settings: Settings | None = None) -> CamcoreAPI:
    settings = settings or Settings()
    app = CamcoreAPI(title="camcore", version=camcore.__version__, description=DESCRIPTION, openapi_tags=list(TAGS),
                     docs_url=None, redoc_url=None)  # served offline by install_offline_docs
    app.state.settings = settings
    app.state.context = Context.create(settings)
    install_error_handlers(app)
    routes = register_routes(app, OPERATIONS)  # every operation's routes, static paths before parameterised ones
    app.route_kinds = {route.id: route.kind for route in routes}
    register_cell_route(app, OPERATIONS)  # and each POST computation's cell form
    install_offline_docs(app)  # before security: it publishes the asset paths left open
    app.add_middleware(BodySizeLimit, max_body_bytes=settings.max_body_bytes)
    app.add_middleware(JSONBodiesOnly, routes=app.router.routes)  # 415 before any body is read
    app.add_middleware(AllowedMethods, routes=app.router.routes)
    app.add_middleware(InFlightLimit, max_in_flight=settings.max_in_flight)  # 503 once the body is in
    # last: outermost (CORS, then the key, then the in-flight limit, methods, media type and body limit)
    install_security(app, settings)
    return app
