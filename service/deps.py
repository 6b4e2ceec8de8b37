"""Dependencies shared by the routes: the service objects living on the app."""

from __future__ import annotations

from fastapi import Request

from .core import CurveService


def curve_service(request: Request) -> CurveService:
    service: CurveService = request.app.state.curve_service
    return service
