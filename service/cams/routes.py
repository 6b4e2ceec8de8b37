"""The /v1/cams router; each cam type's module adds its operations to it."""

from __future__ import annotations

from fastapi import APIRouter

router = APIRouter(prefix="/v1/cams", tags=["cams"])
