"""Every route of every operation, made from its declaration by one rule (titiler's
``TilerFactory.register_routes`` is the model).

For an operation ``X`` at ``P`` with formats ``f0`` (its default), ``f1``, …:

- ``P`` answers ``f0``, or ``fi`` on ``?format=fi`` (or the body field the operation names,
  or ``Accept`` for a format that takes it); its document lists every format's media type;
- ``P.fi`` (id ``X`` + ``Fi``, e.g. ``/v1/profiles.dxf``, ``computeProfileDxf``) answers only
  ``fi``: the operation a generated client calls for that file;
- each alias (an older path and id) answers its format, marked deprecated.

Routes are added with static paths before parameterised ones, so ``/v1/curves/vibration/plot``
is never taken for ``/v1/curves/{name}/plot`` whatever order the domains declare them in.
Every request is then answered the same way (:func:`answer`).
"""

from __future__ import annotations

import inspect
from collections.abc import Mapping, Sequence
from contextlib import AbstractContextManager, nullcontext
from dataclasses import dataclass
from typing import Annotated, Any, Literal

from fastapi import APIRouter, Body, FastAPI, Query, Request
from fastapi.openapi.models import Example
from pydantic import BaseModel
from starlette.concurrency import run_in_threadpool
from starlette.responses import Response
from starlette.routing import BaseRoute

from service.media import ERRORS, Responses, media_content
from service.operations.answers import Answer, respond
from service.operations.formats import JSON, Format
from service.operations.operation import Operation
from service.replies import KEPT_FLAG
from service.routing import OrjsonRoute


@dataclass(frozen=True)
class Route:
    """One route of an operation: the operation itself, a twin or an alias."""

    operation: Operation
    path: str
    id: str
    formats: tuple[Format, ...]  # what this route answers; one for a twin or an alias
    kind: Literal["operation", "twin", "alias"] = "operation"

    @property
    def main(self) -> bool:
        return self.kind == "operation"

    @property
    def deprecated(self) -> bool:
        return self.kind == "alias"


def routes_of(operation: Operation) -> list[Route]:
    """The operation's own route, its twins and its aliases."""
    routes = [Route(operation, operation.path, operation.id, operation.formats)]
    routes += [Route(operation, operation.twin_path(fmt), operation.twin_id(fmt), (fmt,), "twin")
               for fmt in operation.formats[1:]]
    routes += [Route(operation, alias.path, alias.id, (operation.format(alias.format),), "alias")
               for alias in operation.aliases]
    return routes


def _specificity(route: Route) -> tuple[int, int]:
    """Fewer path parameters first; among equals, the older alias paths after the regular ones."""
    return route.path.count("{"), int(route.deprecated)


#: the routes made for a tuple of operations, by its identity: made once per process (FastAPI
#: analyses each endpoint's signature and answer model, ~2 ms a route) and shared by every app
#: made from them (a route holds nothing of its app: the context is read from the request)
_MADE: dict[int, tuple[Sequence[Operation], list[BaseRoute]]] = {}


def register_routes(app: FastAPI, operations: Sequence[Operation]) -> list[Route]:
    """Add every route of ``operations`` to ``app``; the routes, in the order they were added."""
    routes = sorted((route for operation in operations for route in routes_of(operation)), key=_specificity)
    made = _MADE.get(id(operations))
    if made is None or made[0] is not operations:
        router = APIRouter()
        for route in routes:
            _add(router, route)
        made = _MADE[id(operations)] = (operations, list(router.routes))
    app.router.routes.extend(made[1])
    return routes


# ----------------------------------------------------------------------------- one request
def choose_format(route: Route, chosen: str | None, body: Any, request: Request) -> Format:
    """The format of this request: the twin's, ``?format=``, the body's format field, the
    Accept header (formats that take it), or the default."""
    operation = route.operation
    if len(route.formats) == 1:
        return route.formats[0]
    if chosen is not None:
        return operation.format(chosen)
    if operation.body_format is not None and body is not None:
        named = getattr(body, operation.body_format)
        if named != operation.formats[0].name:
            return operation.format(named)
    accept = request.headers.get("accept", "").lower()
    for fmt in operation.formats[1:]:
        if fmt.accept and fmt.bare_media_type in accept:
            return fmt
    return operation.formats[0]


async def answer(operation: Operation, fmt: Format, request: Request, spec: Any,
                 path_values: Mapping[str, str]) -> Response:
    """Answer one request: :func:`compute_answer`, written in ``fmt``, sent within the worker's
    budget of answers in flight (service.answer_budget: 503 when it is used up)."""
    answers = request.app.state.context.answers
    answers.check_room()
    with located(operation):
        result = await compute_answer(operation, fmt, request, spec, path_values)
        return answers.hold(result, respond(result, fmt))


def located(operation: Operation) -> AbstractContextManager[None]:
    """Where the operation says its errors are, around its whole answer."""
    return operation.located() if operation.located is not None else nullcontext()


async def compute_answer(operation: Operation, fmt: Format, request: Request, spec: Any,
                         path_values: Mapping[str, str]) -> Answer:
    """What one request computes (inside :func:`located`): the spec converted once, a kept
    answer given at once, else the estimate checked and admitted, the computation run (on the
    event loop when it is quick)."""
    ctx = request.app.state.context
    core = operation.convert(ctx, spec, path_values)
    if operation.cached is not None:
        kept = operation.cached(ctx, core, fmt)
        if kept is not None:
            setattr(request.state, KEPT_FLAG, True)  # this request's reply may be kept (service.replies)
            return kept
    work = operation.estimate(ctx, core, fmt)
    if operation.warmup is not None:
        await run_in_threadpool(operation.warmup, ctx, fmt)
    if operation.quick is not None and operation.quick(ctx, core, fmt):
        ctx.gate.check_budget(work)
        return operation.compute(ctx, core, fmt)
    result: Answer = await ctx.gate.run(request, work, operation.compute, ctx, core, fmt)
    return result


# ----------------------------------------------------------------------------- the routes
def _format_help(formats: tuple[Format, ...]) -> str:
    default, *others = formats
    lines = [f"- `{fmt.name}` ({fmt.bare_media_type}): {fmt.description}" for fmt in others]
    return f"omitted: {default.name}; or\n\n" + "\n".join(lines)


def _request_model(route: Route) -> type[BaseModel] | None:
    operation = route.operation
    if not route.main:
        return operation.format_requests.get(route.formats[0].name, operation.request)
    return operation.request


def _examples(route: Route) -> Mapping[str, Example]:
    operation = route.operation
    if not route.main:
        return operation.format_examples.get(route.formats[0].name, operation.examples)
    return operation.examples


def _parameters(route: Route) -> list[inspect.Parameter]:
    operation = route.operation
    keyword = inspect.Parameter.KEYWORD_ONLY
    params = [inspect.Parameter("request", keyword, annotation=Request)]
    params += [inspect.Parameter(name, keyword, annotation=annotation)
               for name, annotation in operation.path_parameters.items()]
    model = _request_model(route)
    if model is not None:
        where = Body(openapi_examples=dict(_examples(route)) or None) if operation.method == "POST" else Query()
        params.append(inspect.Parameter("spec", keyword, annotation=Annotated[model, where]))
    if route.main and len(operation.formats) > 1:
        names = tuple(fmt.name for fmt in operation.formats)
        params.append(inspect.Parameter(
            "format", keyword, default=None,
            annotation=Annotated[Literal[names], Query(description=_format_help(operation.formats))]))
    return params


def _endpoint(route: Route) -> Any:
    operation = route.operation
    path_names = tuple(operation.path_parameters)

    async def endpoint(**values: Any) -> Response:
        request: Request = values["request"]
        spec = values.get("spec")
        fmt = choose_format(route, values.get("format"), spec, request)
        return await answer(operation, fmt, request, spec, {name: values[name] for name in path_names})

    endpoint.__signature__ = inspect.Signature(_parameters(route))  # type: ignore[attr-defined]
    endpoint.__name__ = route.id
    return endpoint


def _responses(route: Route) -> Responses:
    formats = [fmt for fmt in route.formats if fmt is not JSON]
    if not formats:
        return dict(ERRORS)
    content: dict[str, Any] = {}
    for fmt in formats:
        content |= media_content(fmt.media_type)
    descriptions = [fmt.description for fmt in route.formats]
    return {**ERRORS, 200: {"content": content, "description": "; or ".join(descriptions)}}


def _summary(route: Route) -> str:
    """The operation's summary; a twin's is the operation's and its format ("Plate cam profile
    as DXF drawing"), an alias's the same and "(older path)"."""
    summary = route.operation.summary
    if route.main:
        return summary
    summary = f"{summary} as {route.formats[0].label}"
    return f"{summary} (older path)" if route.deprecated else summary


def _add(router: APIRouter, route: Route) -> None:
    operation = route.operation
    json_answer = route.formats[0] is JSON or JSON in route.formats
    summary = _summary(route)
    description = operation.description if route.main else (
        f"The answer of `{operation.id}` as {route.formats[0].description}"
        f" (`{operation.id}` with `?format={route.formats[0].name}`).")
    if route.deprecated:
        description += f"\n\nDeprecated: the same as `{operation.twin_id(route.formats[0])}` " \
                       f"(`{operation.method} {operation.twin_path(route.formats[0])}`)."
    endpoint = _endpoint(route)
    options: dict[str, Any] = {
        "methods": [operation.method], "operation_id": route.id, "summary": summary, "description": description,
        "tags": [operation.tag], "responses": _responses(route), "deprecated": route.deprecated or None,
        "route_class_override": OrjsonRoute}
    if json_answer:
        options["response_model"] = operation.answer
    else:
        options["response_class"] = Response
    router.add_api_route(route.path, endpoint, **options)
    if operation.head and route.main:
        router.add_api_route(route.path, endpoint, methods=["HEAD"], include_in_schema=False,
                             route_class_override=OrjsonRoute)
