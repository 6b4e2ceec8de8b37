"""Dependencies shared by the routes: the service objects living on the app."""

from __future__ import annotations

from fastapi import Request

from service.admission import WorkGate
from service.curves.service import CurveService
from service.indexers.service import IndexerService
from service.motions.service import MotionService
from service.profiles.service import ProfileService


async def curve_service(request: Request) -> CurveService:
    service: CurveService = request.app.state.curve_service
    return service


async def indexer_service(request: Request) -> IndexerService:
    service: IndexerService = request.app.state.indexer_service
    return service


async def motion_service(request: Request) -> MotionService:
    service: MotionService = request.app.state.motion_service
    return service


async def profile_service(request: Request) -> ProfileService:
    service: ProfileService = request.app.state.profile_service
    return service


async def work_gate(request: Request) -> WorkGate:
    gate: WorkGate = request.app.state.work_gate
    return gate
