"""``GET /health``: liveness and version, with the caches' hit and miss counts."""

from __future__ import annotations

from typing import Literal

import camcore
from service.context import Context
from service.operations import Format, Operation, Raw
from service.specs import DeferredModel


class HealthAnswer(DeferredModel):
    status: Literal["ok"]
    version: str
    caches: dict[str, dict[str, int]]


def _health(ctx: Context, _: None, fmt: Format) -> Raw:
    return Raw({"status": "ok", "version": camcore.__version__, "caches": ctx.cache_stats()})


OPERATIONS = (
    Operation("getHealth", "/health", "service", "Service health and version",
              "Liveness and version, with the caches' hit and miss counts (HEAD: the same without its body, for "
              "load balancers and probes).",
              None, _health, method="GET", answer=HealthAnswer, head=True, examples={"probe": {"value": {}}}),
)
