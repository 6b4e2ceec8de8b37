"""Liveness, version and cache statistics."""

from __future__ import annotations

from typing import Annotated, Literal

from fastapi import APIRouter, Depends
from pydantic import BaseModel
from starlette.responses import Response

import camcore
from service.curves.service import CurveService

from .deps import curve_service
from .responses import JSONBody
from .routing import OrjsonRoute


class HealthAnswer(BaseModel):
    status: Literal["ok"]
    version: str
    caches: dict[str, dict[str, int]]


router = APIRouter(tags=["service"], route_class=OrjsonRoute)


@router.get("/health", operation_id="getHealth", response_model=HealthAnswer)
async def health(service: Annotated[CurveService, Depends(curve_service)]) -> Response:
    """Liveness and version, with the caches' hit and miss counts."""
    return JSONBody({"status": "ok", "version": camcore.__version__, "caches": service.cache_stats()})


@router.head("/health", include_in_schema=False)
async def health_head(service: Annotated[CurveService, Depends(curve_service)]) -> Response:
    """The same answer without its body, for load balancers and probes that send HEAD."""
    return await health(service)
