"""The one table mapping core exceptions to HTTP status codes, and the handlers.

Every error answer has the same shape: ``{"detail": "<a sentence>", "errors": [...]}``
where ``errors`` lists ``{"loc": [...], "msg": "..."}`` for validation problems.
"""

from __future__ import annotations

import logging
from typing import Any

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from starlette.exceptions import HTTPException as StarletteHTTPException

from camcore.errors import (
    CamError,
    InvalidParameterError,
    LimitExceededError,
    NonFiniteResultError,
    NonMonotoneError,
    StrokeRangeError,
    UnknownCurveError,
)

from .responses import JSONBody

logger = logging.getLogger("camcore.service")

#: exception type → HTTP status; the most specific matching class wins (MRO order)
DEFAULT_STATUS_CODES: dict[type[Exception], int] = {
    UnknownCurveError: 404,
    LimitExceededError: 413,
    StrokeRangeError: 422,
    NonMonotoneError: 422,
    NonFiniteResultError: 422,
    InvalidParameterError: 422,
    CamError: 422,
}




def status_for(exc: Exception) -> int:
    for cls in type(exc).__mro__:
        if cls in DEFAULT_STATUS_CODES:
            return DEFAULT_STATUS_CODES[cls]
    return 500


def _clean_message(msg: str) -> str:
    for prefix in ("Value error, ", "Assertion failed, "):
        if msg.startswith(prefix):
            return msg[len(prefix):]
    return msg


def _loc_text(loc: tuple[Any, ...] | list[Any]) -> str:
    parts = [str(p) for p in loc if p not in ("body",)]
    return ".".join(parts) if parts else "body"


def error_body(detail: str, errors: list[dict[str, Any]] | None = None, **extra: Any) -> dict[str, Any]:
    body: dict[str, Any] = {"detail": detail, "errors": errors or []}
    body.update(extra)
    return body


async def cam_error_handler(request: Request, exc: Exception) -> JSONBody:
    status = status_for(exc)
    extra: dict[str, Any] = {}
    if isinstance(exc, UnknownCurveError):
        extra["suggestions"] = exc.suggestions
    if isinstance(exc, LimitExceededError):
        # a fuzzer may ask for more than 64 bits hold; the sentence still carries the number
        requested = exc.requested if abs(exc.requested) < 2**63 else None
        extra["limit"] = {"name": exc.what, "requested": requested, "limit": exc.limit}
    return JSONBody(error_body(str(exc), **extra), status_code=status)


async def validation_error_handler(request: Request, exc: Exception) -> JSONBody:
    assert isinstance(exc, RequestValidationError)
    errors = []
    malformed = False
    for err in exc.errors():
        loc_tuple = tuple(err.get("loc", ()))
        if err.get("type") == "json_invalid" or (
            err.get("type") in ("model_attributes_type", "dict_type") and loc_tuple == ("body",)
        ):
            malformed = True
        loc = list(err.get("loc", ()))
        msg = _clean_message(str(err.get("msg", "invalid value")))
        errors.append({"loc": loc, "msg": msg})
    if malformed:
        first = errors[0]["msg"] if errors else "the body is not valid JSON"
        return JSONBody(
            error_body(f"The request body is not a valid JSON object: {first}.", errors), status_code=400
        )
    summary = "; ".join(f"{_loc_text(e['loc'])}: {e['msg']}" for e in errors[:5])
    if len(errors) > 5:
        summary += f"; and {len(errors) - 5} more"
    return JSONBody(error_body(f"Invalid request — {summary}", errors), status_code=422)


async def http_error_handler(request: Request, exc: Exception) -> JSONBody:
    assert isinstance(exc, StarletteHTTPException)
    detail = exc.detail if isinstance(exc.detail, str) else "request failed"
    return JSONBody(error_body(detail), status_code=exc.status_code, headers=getattr(exc, "headers", None))


async def unexpected_error_handler(request: Request, exc: Exception) -> JSONBody:
    logger.exception("unexpected error on %s %s", request.method, request.url.path)
    return JSONBody(error_body("Internal error; it has been logged."), status_code=500)


def install_error_handlers(app: FastAPI) -> None:
    app.add_exception_handler(CamError, cam_error_handler)
    app.add_exception_handler(RequestValidationError, validation_error_handler)
    app.add_exception_handler(StarletteHTTPException, http_error_handler)
    app.add_exception_handler(Exception, unexpected_error_handler)
