"""The cell form: every POST computation as a GET a spreadsheet formula can build, answering one
field of its JSON answer as text.

``GET /v1/cell/{operation}?<field path>=<value>&…&pick=<answer path>``

- **Request fields** are query parameters named by their path in the JSON body: nested fields
  joined by dots (``indexer.stops``), list items by their index (``load.parts.0.mass_kg``). A
  value is read as JSON reads it when it is a JSON number, ``true``, ``false``, ``null`` or a
  quoted string; otherwise it is the text itself (``indexer.curve.name=MS``). An empty value is
  a field not given (a blank input cell). The spec is then validated by the operation's own
  request model, as its body would be: a rule added to a spec applies here too.
- **pick** names one field of the operation's JSON answer the same way (``motor_ok``,
  ``checks.max_pressure_angle_deg``, ``input_torque_table.input_torque_nm.10``). The answer
  is ``text/plain``: a number in its shortest round-trip form, ``TRUE``/``FALSE``, a text as
  it is, nothing for null; a list of such values (a table's column) one per line, no header.
- **errors**: ``status`` (default) answers a refused request with its real status and the
  service's JSON error; ``text`` answers it 200 with one line, ``Error <status>: <the
  sentence>``, and the real status in the ``Camcore-Error-Status`` header — for a spreadsheet,
  which shows every non-200 answer as the same bare error code (LibreOffice: Err:540, the code
  it also shows when links may not update) and never the sentence.

The request is answered by the operation's own path (:func:`service.operations.factory.
compute_answer`: convert, estimate, admission, compute) and its JSON answer written by the one
encoder before the field is picked, so a cell shows exactly what the JSON answer says.
"""

# (no ``from __future__ import annotations``: FastAPI reads the endpoint's annotations, which
# name the operations of the app being made)

import difflib
import re
from collections.abc import Mapping, Sequence
from typing import Annotated, Any, Literal

import orjson
from fastapi import APIRouter, FastAPI, Path, Query, Request
from fastapi.exceptions import RequestValidationError
from pydantic import BaseModel, ValidationError
from starlette.responses import PlainTextResponse, Response, StreamingResponse

from service.media import ERRORS, TEXT_MEDIA_TYPE
from service.operations.answers import respond
from service.operations.factory import compute_answer, located
from service.operations.formats import JSON
from service.operations.operation import Operation
from service.routing import OrjsonRoute

PATH = "/v1/cell/{operation}"
OPERATION_ID = "computeCell"
#: query parameters of the cell form itself; no request field may be named so
RESERVED = ("pick", "errors")
#: header carrying a refusal's real status when it is answered as text (errors=text)
ERROR_STATUS_HEADER = "Camcore-Error-Status"
#: a query value read as a JSON value rather than as text
_JSON_LITERAL = re.compile(r'-?(0|[1-9]\d*)(\.\d+)?([eE][+-]?\d+)?|true|false|null|".*"', re.DOTALL)
#: the longest answer path a cell may pick
MAX_PICK = 300
#: most query parameters a cell may carry (a 6-part load with a motor is ~40)
MAX_FIELDS = 200


def cell_operations(operations: Sequence[Operation]) -> tuple[Operation, ...]:
    """The operations with a cell form: every POST computation answering JSON."""
    chosen = tuple(op for op in operations if op.method == "POST" and op.request is not None and JSON in op.formats)
    for op in chosen:
        assert op.request is not None
        clash = set(RESERVED) & set(op.request.model_fields)
        assert not clash, f"{op.id}: a request field is named like a cell parameter: {clash}"
    return chosen


# ----------------------------------------------------------------------------- the request
def query_value(text: str) -> Any:
    """One query value as the request's JSON would hold it."""
    return orjson.loads(text) if _JSON_LITERAL.fullmatch(text) else text


def _query_error(name: str | None, message: str) -> RequestValidationError:
    """422 about one query parameter (``None``: the query as a whole)."""
    loc = ("query",) if name is None else ("query", name)
    return RequestValidationError([{"type": "value_error", "loc": loc, "msg": message}])


def request_body(fields: Sequence[tuple[str, str]]) -> dict[str, Any]:
    """The JSON body the query parameters stand for (``load.parts.0.mass_kg=50`` →
    ``{"load": {"parts": [{"mass_kg": 50}]}}``); blank values left out."""
    if len(fields) > MAX_FIELDS:
        raise _query_error(None, f"at most {MAX_FIELDS} fields in one cell, {len(fields)} given")
    root: dict[str, Any] = {}
    for name, text in fields:
        if text == "":
            continue
        parts = name.split(".")
        if any(part == "" for part in parts):
            raise _query_error(name, "a field path is names joined by single dots")
        node = root
        for depth, part in enumerate(parts[:-1]):
            child = node.setdefault(part, {})
            if not isinstance(child, dict):
                raise _query_error(name, f"{'.'.join(parts[:depth + 1])} is given as a value and as an object")
            node = child
        if parts[-1] in node:
            raise _query_error(name, "given twice" if not isinstance(node[parts[-1]], dict)
                               else f"{name} is given as a value and as an object")
        node[parts[-1]] = query_value(text)
    return _lists(root, "")


def _lists(node: Any, where: str) -> Any:
    """Objects whose keys are all indices become lists: 0, 1, … without a gap."""
    if not isinstance(node, dict):
        return node
    items = {key: _lists(value, f"{where}{key}.") for key, value in node.items()}
    indices = [key for key in items if key.isdigit()]
    if not indices:
        return items
    if len(indices) != len(items):
        raise _query_error(where[:-1] or None, "a list's items are named by their index alone (0, 1, …)")
    if sorted(int(key) for key in indices) != list(range(len(indices))):
        raise _query_error(where[:-1], f"list items are numbered 0, 1, … without a gap; given {sorted(indices, key=int)}")
    return [items[str(i)] for i in range(len(indices))]


#: the errors of a text field given a value that reads as a number (a curve named "48")
_TEXT_WANTED = ("string_type", "literal_error", "enum")


def validate(model: type[BaseModel], body: dict[str, Any]) -> BaseModel:
    """The spec, validated by its own model as its JSON body would be. A value read as a
    number, true, false or null where the model wants text (Makino's curve "48") is given back
    as the text it was written as, and the body validated again."""
    try:
        return model.model_validate(body)
    except ValidationError as exc:
        first = exc
    retyped = False
    for error in first.errors():
        if error["type"] in _TEXT_WANTED and not isinstance(error.get("input"), str | dict | list):
            retyped |= _as_text(body, tuple(error["loc"]), error["input"])
    if not retyped:
        raise _validation_error(first) from None
    try:
        return model.model_validate(body)
    except ValidationError as exc:
        raise _validation_error(exc) from None


def _as_text(node: Any, loc: tuple[str | int, ...], value: Any) -> bool:
    """Replace the value at the body path that ``loc`` follows (the model's location may add a
    union member's tag between the body's names) by its JSON text; whether one was found."""
    if not loc:
        return False
    head, rest = loc[0], loc[1:]
    child_key = head if isinstance(node, dict) and head in node else \
        head if isinstance(node, list) and isinstance(head, int) and head < len(node) else None
    if child_key is None:
        return _as_text(node, rest, value)  # a union's tag: not in the body
    child = node[child_key]
    if not rest:
        if child is value or child == value and type(child) is type(value):
            node[child_key] = orjson.dumps(value).decode()
            return True
        return False
    return _as_text(child, rest, value)


def _validation_error(exc: ValidationError) -> RequestValidationError:
    """The spec's own validation errors, located at the query parameter a user wrote."""
    errors = [{"type": err.get("type", "value_error"),
               "loc": ("query", ".".join(str(part) for part in err.get("loc", ())) or "query"),
               "msg": err.get("msg", "")} for err in exc.errors()]
    return RequestValidationError(errors)


# ----------------------------------------------------------------------------- the answer
def pick(answer: Any, path: str) -> Any:
    """The answer's field at ``path`` (dots between names, indices into lists); a name after
    a list of objects takes that field of each (a column of rows)."""
    node = answer
    walked: list[str] = []
    for part in path.split("."):
        if isinstance(node, dict):
            if part not in node:
                there = ".".join(walked) or "the answer"
                close = difflib.get_close_matches(part, list(node), n=3)
                hint = f"; did you mean {', '.join(close)}?" if close else f"; its fields: {', '.join(node)}"
                raise _query_error("pick", f"{there} has no field '{part}'{hint}")
            node = node[part]
        elif isinstance(node, list) and part.isdigit():
            if int(part) >= len(node):
                raise _query_error("pick", f"{'.'.join(walked)} has {len(node)} items (0 to {len(node) - 1}); "
                                           f"{part} is past its end")
            node = node[int(part)]
        elif isinstance(node, list) and node and all(isinstance(row, dict) and part in row for row in node):
            node = [row[part] for row in node]
        else:
            raise _query_error("pick", f"{'.'.join(walked)} is {_kind(node)}: '{part}' names nothing in it")
        walked.append(part)
    return node


def _kind(value: Any) -> str:
    if isinstance(value, list):
        return f"a list of {len(value)} items (pick one by its index)"
    return "a number" if isinstance(value, int | float) and not isinstance(value, bool) else "a single value"


def cell_text(value: Any, path: str) -> str:
    """One picked value as a cell's text, or a column's values one per line."""
    if isinstance(value, list):
        if any(isinstance(item, dict | list) for item in value):
            raise _query_error("pick", f"{path} is a list of objects or lists; pick one item by its index, "
                                       f"or one field of every item ({path}.<field>)")
        return "".join(_scalar_text(item) + "\n" for item in value)
    if isinstance(value, dict):
        raise _query_error("pick", f"{path} is an object; pick one of its fields: "
                                   + ", ".join(f"{path}.{key}" for key in value))
    return _scalar_text(value)


def _scalar_text(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "TRUE" if value else "FALSE"
    if isinstance(value, float):
        return repr(value)
    return str(value)


async def _json_answer(response: Response) -> Any:
    if isinstance(response, StreamingResponse):
        body = b"".join([chunk.encode() if isinstance(chunk, str) else bytes(chunk)
                         async for chunk in response.body_iterator])
    else:
        body = bytes(response.body)
    return orjson.loads(body)


# ----------------------------------------------------------------------------- the route
def _operation(name: str, operations: Mapping[str, Operation]) -> Operation:
    if name not in operations:
        close = difflib.get_close_matches(name, list(operations), n=3)
        hint = f" Did you mean: {', '.join(close)}?" if close else ""
        raise _query_error("operation", f"'{name}' is no operation with a cell form.{hint}")
    return operations[name]


async def _error_as_text(request: Request, exc: Exception) -> Response:
    """A refusal as one line of text, 200, its real status in a header (errors=text)."""
    handlers = request.app.exception_handlers
    handler = next(handlers[cls] for cls in type(exc).__mro__ if cls in handlers)
    refused = await handler(request, exc)
    body = orjson.loads(bytes(refused.body))
    # each error at the parameter the user wrote (``load.parts.0.mass_kg: …``), else the sentence
    located = [f"{'.'.join(str(part) for part in error['loc'][1:])}: {error['msg']}"
               for error in body.get("errors", []) if error.get("loc", [])[1:]]
    detail = "; ".join(located) if located else body.get("detail", "refused")
    headers = {ERROR_STATUS_HEADER: str(refused.status_code)}
    if "retry-after" in refused.headers:
        headers["Retry-After"] = refused.headers["retry-after"]
    return PlainTextResponse(f"Error {refused.status_code}: {detail}", headers=headers)


def _description(operations: Sequence[Operation]) -> str:
    listed = "\n".join(f"- `{op.id}`: `{op.method} {op.path}`" for op in operations)
    return (
        "One number (or text, or a column) of any POST computation, by GET, for a spreadsheet's "
        "`WEBSERVICE()` or `IMPORTDATA()` cell.\n\n"
        "Query parameters: the operation's request fields, named by their path in its JSON body — "
        "nested fields joined by dots (`indexer.stops=6`), list items by index "
        "(`load.parts.0.mass_kg=50`); a value is read as JSON reads it when it is a number, `true`, "
        "`false`, `null` or a quoted string, else as text (`indexer.curve.name=MS`); an empty value "
        "is a field not given. `pick` names the answer's field the same way "
        "(`checks.max_pressure_angle_deg`, `input_torque_table.input_torque_nm.10`).\n\n"
        "The answer is text/plain: a number in its shortest round-trip form, `TRUE`/`FALSE`, text, "
        "or a column one value per line. Refused: the operation's own status and JSON error, or "
        f"with `errors=text` one line `Error <status>: <sentence>`, 200, the status in "
        f"`{ERROR_STATUS_HEADER}`.\n\nOperations:\n\n{listed}")


def register_cell_route(app: FastAPI, operations: Sequence[Operation]) -> None:
    """Add ``GET /v1/cell/{operation}`` for the POST computations among ``operations``."""
    chosen = cell_operations(operations)
    by_id = {op.id: op for op in chosen}
    names = tuple(by_id)

    async def compute_cell(
        request: Request,
        operation: Annotated[str, Path(description="The operation's id.", json_schema_extra={"enum": list(names)})],
        pick_path: Annotated[str | None, Query(alias="pick", json_schema_extra={"maxLength": MAX_PICK}, description=(
            "The answer's field, by its path (dots; list indices). Required; without it the "
            "refusal lists the answer's fields."))] = None,
        errors: Annotated[Literal["status", "text"], Query(
            description="How a refused request answers: its status and JSON error (`status`), or one "
                        "line of text with status 200 (`text`, for spreadsheets).")] = "status",
    ) -> Response:
        try:
            op = _operation(operation, by_id)
            if pick_path is not None and len(pick_path) > MAX_PICK:  # here, so that errors=text holds for it too
                raise _query_error("pick", f"at most {MAX_PICK} characters, {len(pick_path)} given")
            fields = [(key, value) for key, value in request.query_params.multi_items() if key not in RESERVED]
            assert op.request is not None
            spec = validate(op.request, request_body(fields))
            with located(op):
                answer = await _json_answer(respond(await compute_answer(op, JSON, request, spec, {}), JSON))
            if not pick_path:
                fields_of = ", ".join(answer) if isinstance(answer, dict) else "none"
                raise _query_error("pick", f"required: the answer's field to give; its fields: {fields_of}")
            text = cell_text(pick(answer, pick_path), pick_path)
        except Exception as exc:
            if errors == "text":
                return await _error_as_text(request, exc)
            raise
        return PlainTextResponse(text)

    fields_parameter = {
        "name": "fields", "in": "query", "required": False, "style": "form", "explode": True,
        "description": "The request's fields, one query parameter each, named by their path in the JSON body.",
        "schema": {"type": "object", "additionalProperties": {"type": "string"}}}
    router = APIRouter()
    router.add_api_route(
        PATH, compute_cell, methods=["GET"], operation_id=OPERATION_ID, tags=["spreadsheets"],
        summary="One field of any computation, for a spreadsheet cell", description=_description(chosen),
        response_class=Response, route_class_override=OrjsonRoute,  # (errors documented as JSON)
        responses={**ERRORS, 200: {"content": {TEXT_MEDIA_TYPE.split(";")[0]: {"schema": {"type": "string"}}},
                                   "description": "the picked value as text"}},
        openapi_extra={"parameters": [fields_parameter]})
    app.router.routes.extend(router.routes)
