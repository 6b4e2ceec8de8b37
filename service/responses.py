"""Fast JSON (orjson) and CSV answers, and content negotiation.

Numbers leave the service as plain JSON numbers: numpy arrays are encoded by orjson
directly (no Python floats in between), and a NaN or infinity is refused before it
could be encoded.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import orjson
from fastapi import Request
from starlette.responses import Response

from camcore.errors import NonFiniteResultError

_OPTIONS = orjson.OPT_SERIALIZE_NUMPY | orjson.OPT_NON_STR_KEYS

#: the ``responses=`` map of a route: status → OpenAPI response object
Responses = dict[int | str, dict[str, Any]]


class JSONBody(Response):
    """application/json encoded with orjson (numpy arrays welcome)."""

    media_type = "application/json"

    def render(self, content: Any) -> bytes:
        return orjson.dumps(content, option=_OPTIONS)


class CSVBody(Response):
    media_type = "text/csv; charset=utf-8"


def check_finite(columns: Mapping[str, Any]) -> None:
    """Refuse to answer NaN or infinity (JSON has no such numbers)."""
    for name, col in columns.items():
        arr = np.asarray(col)
        if arr.dtype.kind == "f" and not np.isfinite(arr).all():
            raise NonFiniteResultError(
                f"the computation of '{name}' produced a non-finite number for these inputs; "
                "check that the parameters describe a realistic cam."
            )


def encode_csv(columns: Mapping[str, Any]) -> bytes:
    """Header row, one column per quantity, '.' decimal mark, shortest round-trip floats.

    A NaN (allowed only in columns where it means "unbounded") is an empty cell.
    """
    names = list(columns)
    cells = []
    for name in names:
        col = np.ascontiguousarray(np.asarray(columns[name], dtype=np.float64).reshape(-1))
        # orjson writes each float in its shortest round-trip form; reuse that text
        text = orjson.dumps(col, option=orjson.OPT_SERIALIZE_NUMPY)[1:-1]
        cells.append([b"" if c == b"null" else c for c in text.split(b",")] if text else [])
    rows = [b",".join(row) for row in zip(*cells)]
    return b"\n".join([",".join(names).encode(), *rows]) + b"\n"


def wants_csv(request: Request, format_param: str | None = None) -> bool:
    """CSV on ``?format=csv`` (GET) or ``Accept: text/csv`` (POST)."""
    if format_param is not None:
        return format_param.lower() == "csv"
    accept = request.headers.get("accept", "")
    return "text/csv" in accept.lower()


def encode_table(columns: Mapping[str, Any], csv: bool, allow_null: tuple[str, ...] = ()) -> bytes:
    """The body of a table answer: CSV text or a JSON object of columns.

    Columns named in ``allow_null`` may hold NaN, written as null (JSON) or an empty cell.
    """
    check_finite({k: v for k, v in columns.items() if k not in allow_null})
    return encode_csv(columns) if csv else orjson.dumps(dict(columns), option=_OPTIONS)


def encode_value(name: str, value: float) -> bytes:
    """One number as the whole answer (text/plain): Python's shortest round-trip form."""
    check_finite({name: np.float64(value)})
    return repr(float(value)).encode()


def encoded_response(payload: bytes, csv: bool, filename: str = "table.csv") -> Response:
    if csv:
        return CSVBody(payload, headers={"Content-Disposition": f'inline; filename="{filename}"'})
    return Response(payload, media_type="application/json")


def table_response(columns: Mapping[str, Any], csv: bool, filename: str = "table.csv",
                   allow_null: tuple[str, ...] = ()) -> Response:
    return encoded_response(encode_table(columns, csv, allow_null), csv, filename)
