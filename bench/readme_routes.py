"""The README's requests of the routes a designer waits on, answered in-process (``httpx.ASGITransport``)
by the service and by a bare FastAPI app that returns the same bytes: the service's time per request,
and its rate as a share of the bare app's (× bare).

The requests are the README's own ``curl -X POST … -d '…'`` blocks, read from it, so the figure times
what the README shows; each is sent over and over (as a page that reloads it: the curve caches warm,
the answer computed every time). Pairs are interleaved (bare, service, bare, service, …).
"""

from __future__ import annotations

import asyncio
import json
import re
import statistics
import time
from pathlib import Path
from typing import Any

import httpx
from fastapi import FastAPI, Response

from .timing import figure

README = Path(__file__).resolve().parent.parent / "README.md"
#: the routes timed: a plate cam's toolpath, a barrel cam, Makino's matched cycle, a base circle, a
#: follower's dynamics, a parallel indexing cam (the second round's, slowest first when issue 38 began)
ROUTES = ("/v1/profiles/toolpath", "/v1/cams/barrel", "/v1/motions", "/v1/profiles/base-circle",
          "/v1/profiles/dynamics", "/v1/cams/parallel")
_CURL = re.compile(r"curl -X POST '?http://127\.0\.0\.1:8000(/v1/[^\s']+)'?[^\n]*\n\s*-d '(.*?)'", re.DOTALL)


def readme_requests() -> dict[str, bytes]:
    """Each route's README body (the first block that posts to exactly that path)."""
    found: dict[str, bytes] = {}
    for path, body in _CURL.findall(README.read_text(encoding="utf-8")):
        if path in ROUTES and path not in found:
            found[path] = json.dumps(json.loads(body)).encode()
    missing = set(ROUTES) - set(found)
    if missing:
        raise RuntimeError(f"the README has no curl block for {sorted(missing)}")
    return found


def _bare(answers: dict[str, tuple[bytes, str]]) -> FastAPI:
    """One POST route per path answering the service's bytes as they are."""
    app = FastAPI()
    for path, (content, media_type) in answers.items():
        async def route(content: bytes = content, media_type: str = media_type) -> Response:
            return Response(content=content, media_type=media_type)
        app.post(path)(route)
    return app


async def _measure(repeats: int) -> dict[str, Any]:
    from service.app import create_app

    bodies = readme_requests()
    headers = {"Content-Type": "application/json"}
    ours = httpx.AsyncClient(transport=httpx.ASGITransport(app=create_app()), base_url="http://bench", timeout=120)
    answers = {}
    for path, body in bodies.items():
        answer = await ours.post(path, content=body, headers=headers)  # warms the caches and the CAD-free paths
        answer.raise_for_status()
        answers[path] = (answer.content, answer.headers["content-type"])
    bare = httpx.AsyncClient(transport=httpx.ASGITransport(app=_bare(answers)), base_url="http://bench", timeout=120)

    async def timed(client: httpx.AsyncClient, path: str) -> float:
        start = time.perf_counter()
        answer = await client.post(path, content=bodies[path], headers=headers)
        seconds = time.perf_counter() - start
        assert answer.content == answers[path][0], path  # the same bytes both ways
        return seconds

    ms: dict[str, list[float]] = {p: [] for p in ROUTES}
    shares: dict[str, list[float]] = {p: [] for p in ROUTES}
    try:
        for _ in range(repeats):
            for path in ROUTES:
                floor = await timed(bare, path)
                own = await timed(ours, path)
                ms[path].append(own * 1e3)
                shares[path].append(floor / own)
    finally:
        await ours.aclose()
        await bare.aclose()
    slowest = [max(ms[p][i] for p in ROUTES) for i in range(repeats)]
    routes = {p: {"ms_median": round(statistics.median(ms[p]), 2), "x_bare": round(statistics.median(shares[p]), 4),
                  "req_per_s": round(1e3 / statistics.median(ms[p]), 1)} for p in ROUTES}
    return figure(slowest, "<= 10", unit="ms", routes=routes,
                  what="the slowest of the README's requests to the routes listed, each answered in-process by the "
                       "service (ms; its median per route beside, with req/s = 1000/ms on one core and x_bare = the "
                       "bare FastAPI app's time for the same bytes ÷ the service's)")


def readme_routes_ms(repeats: int) -> dict[str, Any]:
    """The figure (see the module's docstring)."""
    return asyncio.run(_measure(repeats))
