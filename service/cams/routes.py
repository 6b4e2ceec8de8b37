"""The /v1/cams router; each cam type's module adds its operations to it."""

from __future__ import annotations

from fastapi import APIRouter

from service.cams import barrel, parallel, roller_gear
from service.routing import OrjsonRoute

router = APIRouter(prefix="/v1/cams", tags=["cams"], route_class=OrjsonRoute)
barrel.register(router)
parallel.register(router)
roller_gear.register(router)
