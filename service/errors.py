"""The one table mapping core exceptions to HTTP status codes, and the handlers.

Every error answer has the same shape: ``{"detail": "<a sentence>", "errors": [...]}``
where ``errors`` lists ``{"loc": [...], "msg": "..."}``: for validation problems, and for
domain errors (unknown curve, out of stroke, over a limit, any CamError) the request field
the error is about, as far as it is known, with the same sentence as ``detail``.

Locating a domain error: camcore names the argument it is about (``CamError.field``, e.g.
``("s", 3)``); the service, which knows where it took that argument from, prefixes it
(:func:`within`, :func:`relocate`); the handler puts "body" (POST) or "query" (GET) in
front, unless the location already starts with "path". Unlocated errors point at the
request as a whole (``["body"]`` or ``["query"]``).
"""

from __future__ import annotations

import logging
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from typing import Any

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from pydantic import BaseModel, ValidationError
from starlette.exceptions import HTTPException as StarletteHTTPException

from camcore.errors import (
    CamError,
    InvalidParameterError,
    LimitExceededError,
    NonFiniteResultError,
    NonMonotoneError,
    StrokeRangeError,
    UnknownCurveError,
    WorkStoppedError,
)
from service.middleware import ANSWERED_ERROR
from service.responses import JSONBody
from service.specs import FieldRuleError
from service.wire import RETRY_AFTER_S

logger = logging.getLogger("camcore.service")

#: where in a request something is: ("profile", "segments", 2, "curve")
Location = tuple[str | int, ...]

#: exception type → HTTP status; the most specific matching class wins (MRO order)
DEFAULT_STATUS_CODES: dict[type[Exception], int] = {
    UnknownCurveError: 404,
    LimitExceededError: 413,
    WorkStoppedError: 503,
    StrokeRangeError: 422,
    NonMonotoneError: 422,
    NonFiniteResultError: 422,
    InvalidParameterError: 422,
    CamError: 422,
}


class ServiceBusyError(Exception):
    """This worker has no room for the request now (503); the client should retry later."""

    def __init__(self, detail: str, retry_after_s: int = RETRY_AFTER_S):
        super().__init__(detail)
        self.retry_after_s = retry_after_s


#: attribute holding a CamError's location in the request (below "body"/"query"), once known
_REQUEST_FIELD = "request_field"


def request_field(exc: CamError) -> tuple[str | int, ...]:
    """Where in the request a domain error lies: as located by the service, or the core's own
    field (the service passes request fields to camcore under their own names: s,
    output_angle_deg), or () for the request as a whole."""
    located = getattr(exc, _REQUEST_FIELD, None)
    return exc.field if located is None else located


@contextmanager
def within(*parts: str | int, keep_field: bool = True,
           only: type[CamError] = CamError) -> Iterator[None]:
    """A CamError (of type ``only``) raised inside is about the request field ``parts``
    (followed by the error's own field, unless ``keep_field`` is false). The innermost
    ``within`` decides."""
    try:
        yield
    except only as exc:
        if getattr(exc, _REQUEST_FIELD, None) is None:
            setattr(exc, _REQUEST_FIELD, (*parts, *exc.field) if keep_field else parts)
        raise


@contextmanager
def relocate(old: tuple[str | int, ...], new: tuple[str | int, ...], keep_rest: bool = True) -> Iterator[None]:
    """A CamError raised inside whose location starts with ``old`` is at ``new`` instead,
    followed by the rest of its location unless ``keep_rest`` is false (for a spec the route
    built from path or query parameters: its fields are those parameters)."""
    try:
        yield
    except CamError as exc:
        located = request_field(exc)
        if located[: len(old)] == old:
            setattr(exc, _REQUEST_FIELD, (*new, *located[len(old):]) if keep_rest else new)
        raise


def query_error(exc: ValidationError) -> RequestValidationError:
    """A spec built from query parameters failed: answer 422 like any invalid query."""
    errors = [{"type": e.get("type", "value_error"), "loc": ("query", *e.get("loc", ())), "msg": e.get("msg", ""),
               "input": None} for e in exc.errors()]
    return RequestValidationError(errors)


def error_loc(request: Request, exc: CamError) -> list[str | int]:
    located = request_field(exc)
    if located[:1] == ("path",):
        return list(located)
    return ["query" if request.method in ("GET", "HEAD") else "body", *located]


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


def _loc_text(loc: Sequence[Any]) -> str:
    parts = [str(p) for p in loc if p not in ("body",)]
    return ".".join(parts) if parts else "body"


def error_body(detail: str, errors: list[dict[str, Any]] | None = None, **extra: Any) -> dict[str, Any]:
    body: dict[str, Any] = {"detail": detail, "errors": errors or []}
    body.update(extra)
    return body


async def cam_error_handler(request: Request, exc: Exception) -> JSONBody:
    assert isinstance(exc, CamError)
    status = status_for(exc)
    extra: dict[str, Any] = {}
    if isinstance(exc, UnknownCurveError):
        extra["suggestions"] = exc.suggestions
    if isinstance(exc, LimitExceededError):
        # a fuzzer may ask for more than 64 bits hold; the sentence still carries the number
        requested = exc.requested if abs(exc.requested) < 2**63 else None
        extra["limit"] = {"name": exc.what, "requested": requested, "limit": exc.limit}
    errors = [{"loc": error_loc(request, exc), "msg": str(exc)}]
    headers = {"Retry-After": str(RETRY_AFTER_S)} if status == 503 else None
    return JSONBody(error_body(str(exc), errors, **extra), status_code=status, headers=headers)


async def busy_error_handler(request: Request, exc: Exception) -> JSONBody:
    assert isinstance(exc, ServiceBusyError)
    return JSONBody(error_body(str(exc)), status_code=503, headers={"Retry-After": str(exc.retry_after_s)})


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
        broken = (err.get("ctx") or {}).get("error")
        if isinstance(broken, FieldRuleError):  # a model's rule: at its field, not at the model
            loc += broken.field
        elif isinstance(broken, CamError):  # camcore's rule called by a model's validator: at the field it names
            loc += request_field(broken)
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
    request.scope[ANSWERED_ERROR] = exc  # answered and logged: it ends at AnsweredErrors, its connection kept
    return JSONBody(error_body("Internal error; it has been logged."), status_code=500)


def install_error_handlers(app: FastAPI) -> None:
    app.add_exception_handler(CamError, cam_error_handler)
    app.add_exception_handler(ServiceBusyError, busy_error_handler)
    app.add_exception_handler(RequestValidationError, validation_error_handler)
    app.add_exception_handler(StarletteHTTPException, http_error_handler)
    app.add_exception_handler(Exception, unexpected_error_handler)


class ErrorItem(BaseModel):
    loc: list[str | int]
    msg: str


class ErrorAnswer(BaseModel):
    detail: str
    errors: list[ErrorItem] = []
