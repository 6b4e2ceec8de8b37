"""ASGI middleware: HTTP semantics the routes do not state themselves.

- :class:`SecurityHeaders`: ``X-Content-Type-Options: nosniff`` on every answer;
- :class:`AllowedMethods`: a 405's ``Allow`` lists every method the path accepts;
- :class:`JSONBodiesOnly`: a body in another media type than JSON is refused with 415;
- :class:`BodySizeLimit`: a body over the configured size is refused with 413 naming the limit;
- :class:`AnsweredErrors`: an error answered whole (a 500) ends there, its connection kept.

Their answers carry the service's error body, ``{"detail": ..., "errors": []}``.
"""

from __future__ import annotations

import email.message
import logging
import time
from collections.abc import Iterator, Sequence
from typing import Any

import orjson
from fastapi.routing import RouteContext, iter_route_contexts
from starlette.routing import BaseRoute, Match
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from service.wire import SECURITY_HEADERS

#: the same logger as the error handlers (service.errors)
logger = logging.getLogger("camcore.service")
#: the media type the POST bodies are read as (FastAPI also reads any ``application/*+json``)
JSON_MEDIA_TYPE = "application/json"


async def send_error(send: Send, status: int, detail: str, **extra: Any) -> None:
    payload = orjson.dumps({"detail": detail, "errors": [], **extra})
    await send({"type": "http.response.start", "status": status,
                "headers": [(b"content-type", b"application/json"),
                            (b"content-length", str(len(payload)).encode())]})
    await send({"type": "http.response.body", "body": payload})


class SecurityHeaders:
    """Adds :data:`SECURITY_HEADERS` to every HTTP answer (it wraps the whole app, error
    answers included: see ``service.app.CamcoreAPI``)."""

    def __init__(self, app: ASGIApp):
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return

        async def send_with_headers(message: Message) -> None:
            if message["type"] == "http.response.start":
                message = {**message, "headers": [*message.get("headers", []), *SECURITY_HEADERS]}
            await send(message)

        await self.app(scope, receive, send_with_headers)


class ServerTiming:
    """Adds ``Server-Timing: app;dur=<ms>`` to every HTTP answer: the time from the request
    reaching the app to its answer starting (for a streamed answer, before its body). A
    client or a load test can then tell the server's wait from its own and the network's."""

    def __init__(self, app: ASGIApp):
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        started = time.perf_counter()

        async def send_with_timing(message: Message) -> None:
            if message["type"] == "http.response.start":
                duration_ms = (time.perf_counter() - started) * 1000
                timing = (b"server-timing", b"app;dur=%.1f" % duration_ms)
                message = {**message, "headers": [*message.get("headers", []), timing]}
            await send(message)

        await self.app(scope, receive, send_with_timing)


#: the scope key where service.errors' handler leaves the error it answered with a 500 (and logged)
ANSWERED_ERROR = "camcore.answered_error"


class AnsweredErrors:
    """An error whose answer was sent whole ends here.

    Starlette's ServerErrorMiddleware answers an unexpected error with a 500 (service.errors'
    handler, which logs it) and then raises it again, for the server; uvicorn's protocol takes any
    exception after an answer has started for a broken answer and closes the transport, so the
    500 itself and the next request on that keep-alive connection met a reset (issue 34). Raised
    before its answer is complete, an error still reaches the server, which must close the
    connection: the client could not tell where the answer ends. An error after a complete answer
    that the handler did not answer (a background task's) is logged here.
    """

    def __init__(self, app: ASGIApp):
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        complete = False

        async def watch(message: Message) -> None:
            nonlocal complete
            await send(message)
            if message["type"] == "http.response.body" and not message.get("more_body", False):
                complete = True

        try:
            await self.app(scope, receive, watch)
        except Exception as exc:
            if not complete:
                raise
            if scope.get(ANSWERED_ERROR) is not exc:
                logger.exception("error after the answer to %s %s", scope.get("method"), scope.get("path"))


def _matching_routes(routes: Sequence[BaseRoute], scope: Scope) -> Iterator[tuple[Match, RouteContext]]:
    """Every route (also inside included routers) matching the request: FULL for path and
    method, PARTIAL for the path only."""
    for route in iter_route_contexts(routes):
        match, _ = route.matches(scope)
        if match != Match.NONE:
            yield match, route


class AllowedMethods:
    """Gives a 405 the ``Allow`` header of every route matching the path, not only the
    first: Starlette takes the first partial match, so ``OPTIONS /v1/curves/table`` said
    ``Allow: GET`` (from ``GET /v1/curves/{name}``) and left out its own POST."""

    def __init__(self, app: ASGIApp, routes: Sequence[BaseRoute]):
        self.app = app
        self.routes = routes  # the router's live list: routes added later count too

    def allowed(self, scope: Scope) -> list[str]:
        methods: set[str] = set()
        for _, route in _matching_routes(self.routes, scope):
            methods |= route.methods or set()  # a Mount has none (its app answers for itself)
        return sorted(methods)

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return

        async def send_with_allow(message: Message) -> None:
            if message["type"] == "http.response.start" and message["status"] == 405:
                allowed = self.allowed(scope)
                if allowed:
                    headers = [(k, v) for k, v in message.get("headers", []) if k.lower() != b"allow"]
                    message = {**message, "headers": [*headers, (b"allow", ", ".join(allowed).encode())]}
            await send(message)

        await self.app(scope, receive, send_with_allow)


def is_json_media_type(content_type: str) -> bool:
    """FastAPI's rule for reading a body as JSON: ``application/json`` or ``application/*+json``."""
    message = email.message.Message()
    message["content-type"] = content_type
    subtype = message.get_content_subtype()
    return message.get_content_maintype() == "application" and (subtype == "json" or subtype.endswith("+json"))


class JSONBodiesOnly:
    """Answers 415 naming ``application/json`` when a request to a route that reads a body
    declares another Content-Type (text/plain, a form, multipart...). A request without
    Content-Type is left to the route, and one to an unknown path or method to the router
    (404, 405)."""

    def __init__(self, app: ASGIApp, routes: Sequence[BaseRoute]):
        self.app = app
        self.routes = routes

    def _reads_body(self, scope: Scope) -> bool:
        return any(match == Match.FULL and getattr(route, "body_field", None) is not None
                   for match, route in _matching_routes(self.routes, scope))

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] == "http":
            content_type = next((v for k, v in scope.get("headers", []) if k == b"content-type"), None)
            if content_type and content_type.strip():  # an empty one counts as missing, as for FastAPI
                declared = content_type.decode("latin-1")
                if not is_json_media_type(declared) and self._reads_body(scope):
                    shown = declared.split(";")[0].strip()[:100] or "(empty)"
                    await send_error(send, 415, f"Content-Type {shown} is not supported: send the request "
                                                f"body as {JSON_MEDIA_TYPE}.")
                    return
        await self.app(scope, receive, send)


class BodySizeLimit:
    """Answers 413 when Content-Length, or the bytes actually received, pass the limit."""

    def __init__(self, app: ASGIApp, max_body_bytes: int):
        self.app = app
        self.max_body_bytes = max_body_bytes

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        for name, value in scope.get("headers", []):
            if name == b"content-length":
                try:
                    declared = int(value)
                except ValueError:
                    declared = 0
                if declared > self.max_body_bytes:
                    await self._refuse(send, declared)
                    return
        received = 0
        started = False
        refused = False  # the body passed the limit
        answered = False  # ... and the 413 is the answer

        async def limited_receive() -> Message:
            # Over the limit, answer 413 here and tell the app the client has gone: an
            # exception raised in receive() would reach FastAPI's body reading, which turns
            # every exception into 400 "There was an error parsing the body".
            nonlocal received, refused, answered
            if refused:
                return {"type": "http.disconnect"}
            message = await receive()
            if message["type"] == "http.request":
                received += len(message.get("body", b""))
                if received > self.max_body_bytes:
                    refused = True
                    if not started:
                        answered = True
                        await self._refuse(send, received)
                    return {"type": "http.disconnect"}
            return message

        async def tracking_send(message: Message) -> None:
            nonlocal started
            if answered:
                return
            if message["type"] == "http.response.start":
                started = True
            await send(message)

        await self.app(scope, limited_receive, tracking_send)

    async def _refuse(self, send: Send, size: int) -> None:
        await send_error(send, 413, f"request body size is {size} bytes, over the limit of {self.max_body_bytes} bytes.",
                         limit={"name": "request body size", "requested": size, "limit": self.max_body_bytes})
