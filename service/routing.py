"""Request bodies parsed with orjson: the route class every router uses.

FastAPI parses a JSON body with the standard library's ``json``; for the large numeric
bodies this service takes (2e5 S values for an inverse, 1e4 measured points) that parse
took most of the request (80 ms of 120 for 2e5 floats; orjson: ~15 ms). What orjson
refuses or reads differently (NaN and Infinity literals; integers beyond 64 bits, which it
turns into floats) is parsed by the standard library as before, so every answer stays the same:
validation still names such a field with a 422 or a 413, and a malformed body is still
the standard library's JSON decode error (400).

Bodies over :data:`LARGE_BODY_BYTES` are parsed and validated in a worker thread, at most
:data:`LARGE_BODY_SLOTS` at a time per worker process: a 4 MB body takes ~50 ms of parsing
and validation, which on the event loop every other request waited through. The thread
hands FastAPI the validated model (which it takes as it is) or the validation errors it
would have found itself (the same 422).

A request answered before from its operation's own cache is answered with its kept reply
before FastAPI solves the endpoint's parameters (:mod:`service.replies`).

FastAPI asks of every parameter and every encoded value whether it is a pydantic v1 model (to
refuse one), importing ``pydantic.v1`` to ask: 67 ms of a cold start on the slower VM, for a
question whose answer is no while nothing has imported ``pydantic.v1`` (no class can derive from
its BaseModel before). :func:`_ask_pydantic_v1_only_once_imported` makes FastAPI ask only then.

The service's models defer their build to first use (:class:`service.specs.DeferredModel`), and so
do FastAPI's adapters of a route's parameters made from them. FastAPI builds its adapters with
pydantic's warning about the parameter's alias ignored (the alias is FastAPI's, in the Field it
wraps the type with); a deferred adapter is built later, by the first validation, outside that
filter. So a route builds its parameters' adapters itself before its first request, and the OpenAPI
document is made, under the same filter (:func:`adapter_builds`).
"""

from __future__ import annotations

import asyncio
import functools
import json
import sys
import warnings
import weakref
from collections.abc import Callable, Coroutine, Iterator, Sequence
from contextlib import contextmanager
from typing import Any

import anyio
import orjson
from fastapi import Request, Response
from fastapi.exceptions import RequestValidationError
from fastapi.routing import APIRoute
from fastapi.utils import create_model_field
from pydantic import TypeAdapter, ValidationError
from pydantic.warnings import UnsupportedFieldAttributeWarning
from starlette.requests import ClientDisconnect

from service.replies import keep, request_key
from service.specs import build_models

#: bodies larger than this are parsed and validated in a worker thread [bytes]
LARGE_BODY_BYTES = 256 * 1024
#: large bodies parsed at once per worker process (each holds its body, parsed, several times over)
LARGE_BODY_SLOTS = 2

#: every digit to "0": a run of 19 digits is then a plain substring search (C speed; a
#: regular expression scans a 4 MB body in 200 ms)
_DIGITS_TO_ZERO = bytes.maketrans(b"123456789", b"000000000")
#: the shortest integer literal that may not fit orjson's 64-bit integers: -2^63 - 1 has 19 digits
_LONG_INTEGER_DIGITS = 19
_LONG_RUN = b"0" * _LONG_INTEGER_DIGITS


def _has_long_integer(body: bytes) -> bool:
    """Whether the body has an integer literal of 19 digits or more (-2^63 - 1 has 19),
    as opposed to a float's digits (0.00010500052500262501, 1e-000000000000000000001)."""
    masked = body.translate(_DIGITS_TO_ZERO)
    start = masked.find(_LONG_RUN)
    while start >= 0:
        end = start + _LONG_INTEGER_DIGITS
        while end < len(masked) and masked[end] == 0x30:
            end += 1
        before, after = body[start - 1:start], body[end:end + 1]
        in_float = before in (b".", b"e", b"E", b"+") or after in (b".", b"e", b"E") \
            or (before == b"-" and body[start - 2:start - 1] in (b"e", b"E"))
        if not in_float:
            return True
        start = masked.find(_LONG_RUN, end)
    return False


def loads(body: bytes) -> Any:
    """json.loads(body), faster: orjson, unless the body has an integer of 19 digits or
    more (orjson would read it as a float) or orjson refuses it (NaN, Infinity)."""
    if not _has_long_integer(body):
        try:
            return orjson.loads(body)
        except orjson.JSONDecodeError:
            pass
    return json.loads(body)


def _ask_pydantic_v1_only_once_imported() -> None:
    """FastAPI's pydantic v1 checks answer False without importing ``pydantic.v1`` while it is not
    imported (module notes); once it is, they ask as before."""
    import fastapi.encoders
    from fastapi._compat import shared

    for module, name in ((shared, "is_pydantic_v1_model_class"), (shared, "is_pydantic_v1_model_instance"),
                         (fastapi.encoders, "is_pydantic_v1_model_instance")):
        asks = getattr(module, name, None)
        if asks is None or getattr(asks, "only_once_imported", False):
            continue

        def guarded(obj: Any, asks: Callable[[Any], bool] = asks) -> bool:
            return "pydantic.v1" in sys.modules and asks(obj)

        guarded.only_once_imported = True  # type: ignore[attr-defined]
        setattr(module, name, guarded)


_ask_pydantic_v1_only_once_imported()

_SLOTS: weakref.WeakKeyDictionary[asyncio.AbstractEventLoop, anyio.CapacityLimiter] = weakref.WeakKeyDictionary()


def _large_body_slots() -> anyio.CapacityLimiter:
    """This worker's limiter of large bodies (one per event loop: a limiter belongs to one)."""
    loop = asyncio.get_running_loop()
    if loop not in _SLOTS:
        _SLOTS[loop] = anyio.CapacityLimiter(LARGE_BODY_SLOTS)
    return _SLOTS[loop]


class OrjsonRequest(Request):
    async def json(self) -> Any:
        if not hasattr(self, "_json"):
            self._json = loads(await self.body())
        return self._json

    async def validate_large_body(self, annotation: Any, slots: anyio.CapacityLimiter) -> None:
        """When the body is large, parse and validate it off the event loop: ``json()``
        then returns the validated model; a body that is not JSON is left to FastAPI's
        error (parsed again, as before)."""
        body = await self.body()
        if len(body) <= LARGE_BODY_BYTES:
            return

        adapter = _body_adapter(annotation)

        def parse_and_validate() -> Any:
            try:
                value = loads(body)
            except ValueError:
                return None  # JSONDecodeError: FastAPI parses it again and answers its 400
            try:
                return adapter.validate_python(value, from_attributes=True)
            except ValidationError as exc:  # as FastAPI words it: each error's loc under "body"
                errors = [{**error, "loc": ("body", *error["loc"])} for error in exc.errors(include_url=False)]
                return RequestValidationError(errors, body=value)

        result = await anyio.to_thread.run_sync(parse_and_validate, limiter=slots)
        if isinstance(result, RequestValidationError):
            raise result
        if result is not None:
            self._json = result


@functools.cache
def _body_adapter(annotation: Any) -> TypeAdapter[Any]:
    """The validator of a whole body, made when a large one first comes (most never do), one
    per body type: a route and its aliases share it. Its model is built here, on the event loop (it
    defers its build; the worker threads would otherwise race to build it), and the adapter takes it."""
    build_models(annotation)
    return TypeAdapter(annotation)


@contextmanager
def adapter_builds() -> Iterator[None]:
    """While FastAPI's adapters of the routes' parameters are built: pydantic's warning that a
    parameter's alias has no effect in an adapter ignored, as FastAPI ignores it when it builds them."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UnsupportedFieldAttributeWarning)
        yield


def _build_adapters(fields: Sequence[Any]) -> None:
    """Build the adapters of a route's parameters that pydantic deferred (a no-op for a built one),
    after the models they take."""
    with adapter_builds():
        for field in fields:
            build_models(field.field_info.annotation)
            field._type_adapter.rebuild()


@functools.cache
def _response_field(status_code: int | str, model: Any) -> Any:
    """The field FastAPI documents a response model by, one per status code and model."""
    return create_model_field(name=f"Response_{status_code}_{model.__name__}", type_=model, mode="serialization")


class OrjsonRoute(APIRoute):
    """An APIRoute whose handler sees an :class:`OrjsonRequest` (FastAPI's documented
    "custom Request and APIRoute class" pattern).

    FastAPI makes a field (a pydantic ``TypeAdapter``, ~0.4 ms) of each further response's
    model on every route, for the OpenAPI document only; the error answer, documented for five
    status codes on ~100 routes, was ~0.2 s of start-up. Here each status code and model has
    one field, shared by the routes (:func:`_response_field`): the same document.
    """

    def __init__(self, path: str, endpoint: Callable[..., Any], *,
                 responses: dict[int | str, dict[str, Any]] | None = None, **options: Any) -> None:
        responses = responses or {}
        modelled = {code: answer["model"] for code, answer in responses.items() if answer.get("model")}
        without_models = {code: {key: value for key, value in answer.items() if key != "model"}
                          for code, answer in responses.items()}
        super().__init__(path, endpoint, responses=without_models, **options)
        self.responses = responses  # as given: the document reads the descriptions beside the models
        self.response_fields = {code: _response_field(code, model) for code, model in modelled.items()}

    def get_route_handler(self) -> Callable[[Request], Coroutine[Any, Any, Response]]:
        handler = super().get_route_handler()
        params = self.dependant.body_params
        # one body parameter, not embedded: FastAPI validates the whole body as its type
        whole = len(params) == 1 and not getattr(params[0].field_info, "embed", False)
        annotation = params[0].field_info.annotation if whole else None
        dependant = self.dependant
        unbuilt = [*dependant.path_params, *dependant.query_params, *dependant.header_params,
                   *dependant.cookie_params, *([self.body_field] if self.body_field is not None else [])]

        async def orjson_route_handler(request: Request) -> Response:
            if unbuilt:  # the route's first request
                _build_adapters(unbuilt)
                unbuilt.clear()
            orjson_request = OrjsonRequest(request.scope, request.receive)
            try:
                key = request_key(orjson_request, await orjson_request.body())
                if annotation is not None:
                    await orjson_request.validate_large_body(annotation, _large_body_slots())
            except ClientDisconnect:
                # the body never came whole: the client left, or the server answered for it
                # already (408 at the body timeout, 413, 503) and told the app it had gone.
                # Nothing is sent from here; without this, a traceback per such request
                return Response(status_code=400)
            replies = request.app.state.context.replies
            if key is not None:
                kept = replies.get(key)
                if kept is not None:  # answered before from its operation's cache: the same bytes again
                    return kept.response()
            response = await handler(orjson_request)
            if key is not None:
                keep(replies, orjson_request, key, response)
            return response

        return orjson_route_handler
