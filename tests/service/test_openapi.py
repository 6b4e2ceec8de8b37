"""The committed OpenAPI document and the operation ids (docs/api.md, "Operation ids")."""

from __future__ import annotations

import json
import re
from pathlib import Path

from scripts.export_openapi import TARGET, render
from service.app import create_app


def test_committed_openapi_matches_the_app() -> None:
    committed = Path(TARGET).read_text(encoding="utf-8")
    assert committed == render(), "openapi/openapi.json drifted: run python -m scripts.export_openapi"


def test_every_operation_id_is_explicit_camel_case_and_unique() -> None:
    spec = create_app().openapi()
    ids = [op["operationId"] for path in spec["paths"].values() for op in path.values()]
    assert ids, "no operations"
    assert len(ids) == len(set(ids)), f"duplicate operation ids: {ids}"
    for op_id in ids:
        # FastAPI's generated ids look like read_item_items__id__get: underscores and the method
        assert re.fullmatch(r"[a-z]+(?:[A-Z][a-z0-9]*)+", op_id), op_id


def test_committed_document_is_valid_json_with_the_contract_paths() -> None:
    doc = json.loads(Path(TARGET).read_text(encoding="utf-8"))
    for path in ("/v1/curves", "/v1/curves/{name}", "/v1/curves/characteristics", "/v1/curves/table",
                 "/v1/curves/{name}/table", "/v1/curves/inverse", "/v1/curves/{name}/inverse", "/health"):
        assert path in doc["paths"], path
