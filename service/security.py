"""Access control for deployment: an API key and a CORS allow-list, both off by default.

``install_security(app, settings)`` wires two pieces of ASGI middleware:

- :class:`APIKeyMiddleware` when ``settings.api_key`` is set (``CAMCORE_API_KEY``): every
  request must carry the key in the ``X-API-Key`` header, except ``/health`` and the
  documentation (``/docs``, ``/redoc``, ``/openapi.json``); others get 401 with the
  service's error body. The comparison is constant-time (:func:`hmac.compare_digest`).
- Starlette's ``CORSMiddleware`` when ``settings.cors_origins`` is non-empty
  (``CAMCORE_CORS_ORIGINS='["https://a.example"]'``): exactly those origins, methods
  GET and POST, request headers Content-Type, Accept and X-API-Key.

Both are middleware, not route dependencies, so the OpenAPI document is the same
whatever the settings (the committed ``openapi/openapi.json`` is generated with the
defaults). Call it last in ``create_app`` so that it wraps everything else: CORS is
outermost after the security headers (a browser's preflight is answered without a key, and a
401 still carries the CORS headers the browser needs to read it), then the key check, then the
in-flight limit, allowed methods, media type and body-size limit — an unauthenticated caller
learns nothing about the limits.
"""

from __future__ import annotations

import hmac
from collections.abc import Iterable

import orjson
from fastapi import FastAPI
from starlette.middleware.cors import CORSMiddleware
from starlette.types import ASGIApp, Receive, Scope, Send

from service.settings import Settings

API_KEY_HEADER = "X-API-Key"
UNAUTHORIZED_DETAIL = "missing or wrong API key (send it in the X-API-Key header)"
CORS_METHODS = ["GET", "POST"]
CORS_HEADERS = ["Content-Type", "Accept", API_KEY_HEADER]


def open_paths(app: FastAPI) -> frozenset[str]:
    """Paths served without a key: the health check and the app's documentation pages."""
    paths = {"/health", app.docs_url, app.redoc_url, app.openapi_url, app.swagger_ui_oauth2_redirect_url}
    # the offline docs' own scripts and styles, or the pages would load blank behind a key
    paths |= set(getattr(app.state, "docs_asset_paths", ()))
    return frozenset(p for p in paths if p)


class APIKeyMiddleware:
    """Answers 401 unless the ``X-API-Key`` header equals the configured key."""

    def __init__(self, app: ASGIApp, api_key: str, open_paths: Iterable[str] = ("/health",)):
        if not api_key:
            raise ValueError("APIKeyMiddleware needs a non-empty key")
        self.app = app
        self._key = api_key.encode("utf-8")
        self._header = API_KEY_HEADER.lower().encode("latin-1")
        self._open = frozenset(open_paths)
        self._body = orjson.dumps({"detail": UNAUTHORIZED_DETAIL, "errors": []})

    def _path(self, scope: Scope) -> str:
        path: str = scope.get("path", "")
        root: str = scope.get("root_path", "")
        if root and path.startswith(root):
            path = path[len(root):] or "/"
        return path

    def _authorized(self, scope: Scope) -> bool:
        for name, value in scope.get("headers", []):
            if name == self._header:
                # constant time in the key's content; only the first header counts
                return hmac.compare_digest(value, self._key)
        return False

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] not in ("http", "websocket") or self._path(scope) in self._open or self._authorized(scope):
            await self.app(scope, receive, send)
            return
        if scope["type"] == "websocket":  # no websocket routes today; refuse them the same way
            await send({"type": "websocket.close", "code": 1008})
            return
        await send({
            "type": "http.response.start",
            "status": 401,
            "headers": [
                (b"content-type", b"application/json"),
                (b"content-length", str(len(self._body)).encode()),
                (b"www-authenticate", b'ApiKey header="X-API-Key"'),
            ],
        })
        await send({"type": "http.response.body", "body": self._body})


def install_security(app: FastAPI, settings: Settings) -> None:
    """Add the API-key check and CORS as the settings ask; with the defaults, nothing."""
    if settings.api_key:
        app.add_middleware(APIKeyMiddleware, api_key=settings.api_key, open_paths=open_paths(app))
    if settings.cors_origins:
        # added last = outermost: preflights never reach the key check
        app.add_middleware(
            CORSMiddleware,
            allow_origins=list(settings.cors_origins),
            allow_methods=CORS_METHODS,
            allow_headers=CORS_HEADERS,
            allow_credentials=False,
        )
