"""Request examples in the OpenAPI document exactly as written, nulls included.

FastAPI writes the document with ``exclude_none`` (``fastapi.openapi.utils.get_openapi``),
which also drops every null *inside* an example's value. In a motion program ``"to": null``
is a value (the stroke is solved), so an example without it is another request, one the
service refuses. The examples of each route's body, and of each model reachable from it,
are put back as written (JSON-encoded, nulls kept).
"""

from __future__ import annotations

import typing
from collections.abc import Iterable
from typing import Any

from fastapi import APIRouter
from fastapi.encoders import jsonable_encoder
from fastapi.routing import APIRoute
from pydantic import BaseModel


def _models(annotation: Any, seen: dict[str, type[BaseModel]]) -> None:
    """Every pydantic model in an annotation and in the fields of those models, by class name."""
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        if annotation.__name__ in seen:
            return
        seen[annotation.__name__] = annotation
        for field in annotation.model_fields.values():
            _models(field.annotation, seen)
        return
    for arg in typing.get_args(annotation):
        _models(arg, seen)


def models_of(annotation: Any) -> dict[str, type[BaseModel]]:
    """Every pydantic model in an annotation and in the fields of those models, by class name."""
    seen: dict[str, type[BaseModel]] = {}
    _models(annotation, seen)
    return seen


def restore_examples(document: dict[str, Any], routers: Iterable[APIRouter]) -> None:
    """Put the request examples of ``routers`` back into ``document`` (in place) as written."""
    schemas = document.get("components", {}).get("schemas", {})
    models: dict[str, type[BaseModel]] = {}
    for router in routers:
        for route in router.routes:
            if not isinstance(route, APIRoute) or route.body_field is None:
                continue
            examples = getattr(route.body_field.field_info, "openapi_examples", None) or {}
            for method in route.methods or ():
                operation = document["paths"].get(route.path_format, {}).get(method.lower())
                written = operation["requestBody"]["content"]["application/json"].get("examples", {}) if operation else {}
                for name, example in examples.items():
                    if name in written and "value" in example:
                        written[name]["value"] = jsonable_encoder(example["value"])
            _models(route.body_field.field_info.annotation, models)
    for name, model in models.items():
        extra = model.model_config.get("json_schema_extra")
        if isinstance(extra, dict) and "examples" in extra and name in schemas:
            schemas[name]["examples"] = jsonable_encoder(extra["examples"])
