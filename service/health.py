"""Liveness, version and cache statistics."""

from __future__ import annotations

from typing import Annotated, Literal

from fastapi import APIRouter, Depends
from pydantic import BaseModel
from starlette.responses import Response

import camcore
from service.curves.service import CurveService
from service.indexers.service import IndexerService
from service.profiles.service import ProfileService

from .deps import curve_service, indexer_service, profile_service
from .responses import JSONBody
from .routing import OrjsonRoute


class HealthAnswer(BaseModel):
    status: Literal["ok"]
    version: str
    caches: dict[str, dict[str, int]]


router = APIRouter(tags=["service"], route_class=OrjsonRoute)


@router.get("/health", operation_id="getHealth", response_model=HealthAnswer)
async def health(service: Annotated[CurveService, Depends(curve_service)],
                 profiles: Annotated[ProfileService, Depends(profile_service)],
                 indexers: Annotated[IndexerService, Depends(indexer_service)]) -> Response:
    """Liveness and version, with the caches' hit and miss counts."""
    caches = {**service.cache_stats(), **profiles.cache_stats(), **indexers.cache_stats()}
    return JSONBody({"status": "ok", "version": camcore.__version__, "caches": caches})


@router.head("/health", include_in_schema=False)
async def health_head(service: Annotated[CurveService, Depends(curve_service)],
                      profiles: Annotated[ProfileService, Depends(profile_service)],
                      indexers: Annotated[IndexerService, Depends(indexer_service)]) -> Response:
    """The same answer without its body, for load balancers and probes that send HEAD."""
    return await health(service, profiles, indexers)
