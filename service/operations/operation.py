"""One operation of the service, declared once: what it takes, how it becomes camcore's terms,
what it costs, what it computes and in which formats it answers.

:mod:`service.operations.factory` makes every HTTP route of an operation from this: its
JSON route, ``?format=`` and Accept negotiation, a file twin per further format, deprecated
aliases, the answer's schema; and the one way every request is answered
(:func:`service.operations.factory.answer`): the spec converted once, the estimate checked
against the budget and admitted, the computation run, the answer written.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from contextlib import AbstractContextManager
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

from fastapi.openapi.models import Example
from pydantic import BaseModel

from camcore.work import WorkEstimate
from service.operations.answers import Answer
from service.operations.formats import JSON, Format

if TYPE_CHECKING:  # pragma: no cover
    from service.context import Context

#: ``convert(ctx, request, path_values) -> core``: the request in camcore's terms, made once
Convert = Callable[["Context", Any, Mapping[str, str]], Any]
#: ``estimate(ctx, core, fmt) -> WorkEstimate``: the work before it is done (413 over the budget)
Estimate = Callable[["Context", Any, Format], WorkEstimate]
#: ``compute(ctx, core, fmt) -> Answer``: the work (in a worker thread unless it is quick)
Compute = Callable[["Context", Any, Format], Answer]


def _as_is(ctx: Context, request: Any, path: Mapping[str, str]) -> Any:
    return request


def _nothing(ctx: Context, core: Any, fmt: Format) -> WorkEstimate:
    return WorkEstimate()


@dataclass(frozen=True)
class Alias:
    """A path and id that answered before the service was regular: they keep answering one
    format of the operation, marked deprecated in the document."""

    id: str
    path: str
    format: str


@dataclass(frozen=True)
class Operation:
    """One operation.

    Attributes
    ----------
    id : str
        The stable camelCase operation id (generated clients' method name).
    path : str
        Its path; path parameters in braces (``/v1/curves/{name}/table``).
    tag, summary, description : str
        Where and how the document shows it.
    request : type or None
        The body (POST) or the query's model (GET); None: no body and no query.
    compute : callable
        ``compute(ctx, core, fmt) -> Answer``.
    convert : callable
        ``convert(ctx, request, path_values) -> core`` (default: the request itself).
    estimate : callable
        ``estimate(ctx, core, fmt) -> WorkEstimate`` (default: no work).
    answer : pydantic model or None
        The JSON answer's schema.
    formats : tuple of Format
        The first is the default; each other one has ``?format=``, a twin and maybe Accept.
    method : {"POST", "GET"}
    examples : mapping
        Request examples: of the body (POST; Swagger UI pre-fills the first), or of the path and
        query parameters (GET: each value a mapping of parameter to value).
    path_parameters : mapping
        Each path parameter's annotation (``Annotated[str, Path(...)]``).
    quick : callable or None
        ``quick(ctx, core, fmt) -> bool``: answered on the event loop (the work is less than a
        thread hop costs); its estimate is still checked against the budget.
    cached : callable or None
        ``cached(ctx, core, fmt) -> Answer | None``: an answer kept from before, given at once.
    warmup : callable or None
        ``warmup(ctx, fmt)``: made ready in a thread before the work is admitted, outside its budget
        (the CAD kernel's first load: the worker's start-up, not the request's work).
    located : callable or None
        A context manager around the whole answer that says where its errors are (a GET's
        curve is its path's name).
    body_format : str or None
        A body field that chooses the format as ``?format=`` does.
    format_requests, format_examples : mapping
        By format name: the twin's body when that format needs more than the operation's
        (a solid's dimensions), and its examples.
    aliases : tuple of Alias
    head : bool
        Also answer HEAD (not in the document): the same answer without its body.
    """

    id: str
    path: str
    tag: str
    summary: str
    description: str
    request: type[BaseModel] | None
    compute: Compute
    convert: Convert = _as_is
    estimate: Estimate = _nothing
    answer: type[BaseModel] | None = None
    formats: tuple[Format, ...] = (JSON,)
    method: Literal["POST", "GET"] = "POST"
    examples: Mapping[str, Example] = field(default_factory=dict)
    path_parameters: Mapping[str, Any] = field(default_factory=dict)
    quick: Callable[[Context, Any, Format], bool] | None = None
    cached: Callable[[Context, Any, Format], Answer | None] | None = None
    warmup: Callable[[Context, Format], None] | None = None
    located: Callable[[], AbstractContextManager[None]] | None = None
    body_format: str | None = None
    format_requests: Mapping[str, type[BaseModel]] = field(default_factory=dict)
    format_examples: Mapping[str, Mapping[str, Example]] = field(default_factory=dict)
    aliases: tuple[Alias, ...] = ()
    head: bool = False

    def format(self, name: str) -> Format:
        """The format of that name (KeyError: not one of the operation's)."""
        for fmt in self.formats:
            if fmt.name == name:
                return fmt
        raise KeyError(name)

    def work(self, ctx: Context, spec: Any, fmt: str | None = None,
             path_values: Mapping[str, str] | None = None) -> WorkEstimate:
        """The estimate of a request (a validated spec) in a format (default: the first), as it
        is admitted: converted, then estimated."""
        chosen = self.formats[0] if fmt is None else self.format(fmt)
        return self.estimate(ctx, self.convert(ctx, spec, path_values or {}), chosen)

    def twin_id(self, fmt: Format) -> str:
        """The id of the file twin answering ``fmt``: ``computeProfile`` + ``Dxf``."""
        return f"{self.id}{fmt.camel()}"

    def twin_path(self, fmt: Format) -> str:
        """The path of the file twin answering ``fmt``: ``/v1/profiles`` + ``.dxf``."""
        return f"{self.path}.{fmt.name}"
