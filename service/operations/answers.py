"""What an operation's computation gives, and how it becomes the HTTP answer in a format.

A computation returns one of these; :func:`respond` writes it in the request's format with
the one encoder (service.responses): numbers as plain JSON numbers, NaN and infinity refused
(but in the columns an answer allows to be null), large answers streamed.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from starlette.responses import PlainTextResponse, Response

from service.operations.formats import Format
from service.responses import check_finite, csv_response, json_response, table_response


@dataclass(frozen=True)
class Table:
    """Columns: a JSON object of columns, or the CSV table. ``allow_null``: columns whose NaN
    means "none" (null in JSON, an empty cell)."""

    columns: Mapping[str, Any]
    allow_null: tuple[str, ...] = ()


@dataclass(frozen=True)
class Document:
    """A JSON document; its CSV form is ``table`` (the columns it holds). The table's columns
    (but ``allow_null``) are checked finite before either is written, and so are the document's
    own numbers (its top-level floats) before it is."""

    value: Mapping[str, Any]
    table: Mapping[str, Any] | None = None
    allow_null: tuple[str, ...] = ()


@dataclass(frozen=True)
class Payload:
    """Bytes already written in the format (a file, a chart, a cached encoded answer)."""

    content: bytes


@dataclass(frozen=True)
class Text:
    """One bare value as text/plain."""

    content: bytes


@dataclass(frozen=True)
class Raw:
    """Plain JSON data with no columns to check (the catalog, a health report)."""

    value: Any = field(default=None)


Answer = Table | Document | Payload | Text | Raw


def respond(answer: Answer, fmt: Format) -> Response:
    """The HTTP answer of a computation's result in ``fmt``."""
    csv = fmt.name == "csv"
    if isinstance(answer, Payload):
        return Response(answer.content, media_type=fmt.media_type, headers=fmt.answer_headers())
    if isinstance(answer, Text):
        return PlainTextResponse(answer.content)
    if isinstance(answer, Table):
        return table_response(answer.columns, csv, fmt.file_name or "table.csv", answer.allow_null)
    if isinstance(answer, Raw):
        return json_response(answer.value)
    if csv:
        assert answer.table is not None, "a document answered as CSV names its table"
        check_finite({k: v for k, v in answer.table.items() if k not in answer.allow_null})
        return csv_response(answer.table, fmt.file_name or "table.csv")
    if answer.table is not None:
        check_finite({k: v for k, v in answer.table.items() if k not in answer.allow_null})
    check_finite({k: v for k, v in answer.value.items() if isinstance(v, float)})
    return json_response(dict(answer.value))
