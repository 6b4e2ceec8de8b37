"""Fast JSON (orjson) and CSV answers, and content negotiation.

Numbers leave the service as plain JSON numbers: numpy arrays are encoded by orjson
directly (no Python floats in between), and a NaN or infinity is refused before it
could be encoded. Large answers are streamed: written in chunks of :data:`CHUNK_ROWS`
rows as the client reads them, so an answer never exists whole in memory (200 000 rows
of CSV were ~23 MB of text plus ~60 MB of row objects while being joined); the chunks
join to exactly the bytes the one-piece encoders write.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from typing import Any

import numpy as np
import orjson
from starlette.responses import Response, StreamingResponse

from camcore.errors import NonFiniteResultError

_OPTIONS = orjson.OPT_SERIALIZE_NUMPY | orjson.OPT_NON_STR_KEYS

#: rows (array elements) per streamed chunk: ~0.2 MB of JSON or ~0.7 MB of CSV of 6 columns
CHUNK_ROWS = 32768
#: answers with more array elements than this are streamed; smaller ones are encoded whole
STREAM_VALUES = 4 * CHUNK_ROWS
#: encoding cost per number on the reference machine (camcore.work), measured 0.025 µs
#: (JSON) and 0.2 µs (CSV), ×1.5
ENCODE_S_PER_VALUE = {"json": 1.5 * 2.5e-8, "csv": 1.5 * 2e-7}

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


def _csv_cells(col: Any) -> list[bytes]:
    """One column's cells: orjson's shortest round-trip text of each float, NaN as empty; a
    column of text (a name per row) as it is, quoted where CSV needs it (RFC 4180)."""
    if np.asarray(col).dtype.kind in "US":
        return [_csv_text(str(cell)) for cell in np.asarray(col).reshape(-1)]
    arr = np.ascontiguousarray(np.asarray(col, dtype=np.float64).reshape(-1))
    text = orjson.dumps(arr, option=orjson.OPT_SERIALIZE_NUMPY)[1:-1]
    return [b"" if c == b"null" else c for c in text.split(b",")] if text else []


def _csv_text(cell: str) -> bytes:
    if any(c in cell for c in ',"\r\n'):
        cell = '"' + cell.replace('"', '""') + '"'
    return cell.encode()


def iter_csv(columns: Mapping[str, Any]) -> Iterator[bytes]:
    """The CSV of :func:`encode_csv` in chunks of :data:`CHUNK_ROWS` rows."""
    names = list(columns)
    yield ",".join(names).encode() + b"\n"
    arrays = [np.asarray(columns[name]).reshape(-1) for name in names]
    rows = min((a.size for a in arrays), default=0)
    for start in range(0, rows, CHUNK_ROWS):
        cells = [_csv_cells(a[start:start + CHUNK_ROWS]) for a in arrays]
        yield b"\n".join(b",".join(row) for row in zip(*cells)) + b"\n"


def encode_csv(columns: Mapping[str, Any]) -> bytes:
    """Header row, one column per quantity, '.' decimal mark, shortest round-trip floats.

    A NaN (allowed only in columns where it means "unbounded") is an empty cell.
    """
    return b"".join(iter_csv(columns))


def iter_json(value: Any) -> Iterator[bytes]:
    """``orjson.dumps(value)`` in pieces: large numpy arrays anywhere in nested dicts are
    written :data:`CHUNK_ROWS` elements at a time."""
    if isinstance(value, dict):
        yield b"{"
        for i, (key, item) in enumerate(value.items()):
            yield (b"," if i else b"") + orjson.dumps(key if isinstance(key, str) else str(key)) + b":"
            yield from iter_json(item)
        yield b"}"
    elif isinstance(value, np.ndarray) and value.ndim == 1 and value.size > CHUNK_ROWS:
        yield b"["
        for start in range(0, value.size, CHUNK_ROWS):
            part = orjson.dumps(np.ascontiguousarray(value[start:start + CHUNK_ROWS]), option=_OPTIONS)
            yield (b"," if start else b"") + part[1:-1]
        yield b"]"
    else:
        yield orjson.dumps(value, option=_OPTIONS)


def _array_values(value: Any) -> int:
    """Elements of the numpy arrays in a nested answer."""
    if isinstance(value, dict):
        return sum(_array_values(v) for v in value.values())
    return int(value.size) if isinstance(value, np.ndarray) else 0


def json_response(value: Any, status_code: int = 200) -> Response:
    """A JSON answer: streamed when its arrays hold more than :data:`STREAM_VALUES` numbers."""
    if _array_values(value) > STREAM_VALUES:
        return StreamingResponse(iter_json(value), status_code=status_code, media_type="application/json")
    return JSONBody(value, status_code=status_code)


def csv_response(columns: Mapping[str, Any], filename: str = "table.csv") -> Response:
    """A CSV answer (inline, with a file name): streamed when it is large."""
    headers = {"Content-Disposition": f'inline; filename="{filename}"'}
    if _array_values(dict(columns)) > STREAM_VALUES:
        return StreamingResponse(iter_csv(columns), media_type=CSVBody.media_type, headers=headers)
    return CSVBody(encode_csv(columns), headers=headers)


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


def table_response(columns: Mapping[str, Any], csv: bool, filename: str = "table.csv",
                   allow_null: tuple[str, ...] = ()) -> Response:
    """A table answer, CSV or a JSON object of columns, streamed when it is large;
    columns named in ``allow_null`` may hold NaN (null, or an empty cell)."""
    check_finite({k: v for k, v in columns.items() if k not in allow_null})
    return csv_response(columns, filename) if csv else json_response(dict(columns))


def encode_cost(values: int, csv: bool) -> float:
    """Seconds to encode ``values`` numbers as CSV or JSON (reference machine, camcore.work)."""
    return values * ENCODE_S_PER_VALUE["csv" if csv else "json"]
