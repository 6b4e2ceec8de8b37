"""What every domain's operations share in the OpenAPI document: the error answers, and how
a media type is described (text, or bytes for a generated client)."""

from __future__ import annotations

from typing import Any

from service.errors import ErrorAnswer

#: the ``responses=`` map of a route: status → OpenAPI response object
Responses = dict[int | str, dict[str, Any]]

#: the error answers every operation may give (service.errors: one body shape for all)
ERRORS: Responses = {
    400: {"model": ErrorAnswer, "description": "Malformed body"},
    404: {"model": ErrorAnswer, "description": "Unknown curve name (close matches listed)"},
    413: {"model": ErrorAnswer, "description": "Over a configured limit or the work budget (named in the answer)"},
    422: {"model": ErrorAnswer, "description": "Invalid request (field and reason given)"},
    503: {"model": ErrorAnswer, "description": "Busy, or the computation ran past its deadline: retry after "
          "the seconds in Retry-After"},
}

JSON_MEDIA_TYPE = "application/json"
CSV_MEDIA_TYPE = "text/csv; charset=utf-8"
TEXT_MEDIA_TYPE = "text/plain; charset=utf-8"


def media_content(media_type: str) -> dict[str, Any]:
    """One media type of a ``content`` map: a string, text for ``text/*``, else binary (so a
    generated client hands back bytes)."""
    bare = media_type.split(";")[0]
    schema = {"type": "string"} if bare.startswith("text/") or bare == "image/svg+xml" else \
        {"type": "string", "format": "binary"}
    return {bare: {"schema": schema}}
