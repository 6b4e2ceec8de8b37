"""The committed OpenAPI document, the operation ids (docs/api.md, "Operation ids") and how the document
reads (tags, summaries, order, header: issue 33)."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

from scripts.export_openapi import TARGET, render
from service.app import create_app
from service.openapi_layout import TAGS
from service.operations.factory import routes_of
from service.registry import OPERATIONS
from service.specs import model_rules


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


#: the operations of the document before it was made from the registry, (method, path) by id
BEFORE = {
    "getHealth": ("get", "/health"), "computeBarrelCam": ("post", "/v1/cams/barrel"),
    "computeBarrelCamCsv": ("post", "/v1/cams/barrel.csv"), "computeParallelIndexingCam": ("post", "/v1/cams/parallel"),
    "computeParallelCamCsv": ("post", "/v1/cams/parallel.csv"), "computeRollerGearCam": ("post", "/v1/cams/roller-gear"),
    "computeRollerGearCamCsv": ("post", "/v1/cams/roller-gear.csv"),
    "computeRollerGearCamStl": ("post", "/v1/cams/roller-gear.stl"), "listCurves": ("get", "/v1/curves"),
    "getCurveCharacteristics": ("post", "/v1/curves/characteristics"),
    "sweepCurveCharacteristics": ("post", "/v1/curves/characteristics/sweep"),
    "invertCurve": ("post", "/v1/curves/inverse"), "invertCurveCsv": ("post", "/v1/curves/inverse.csv"),
    "sampleCurve": ("post", "/v1/curves/table"), "sampleCurveCsv": ("post", "/v1/curves/table.csv"),
    "computeResidualVibration": ("post", "/v1/curves/vibration"),
    "computeResidualVibrationCsv": ("post", "/v1/curves/vibration.csv"),
    "plotResidualVibration": ("get", "/v1/curves/vibration/plot"), "getCurve": ("get", "/v1/curves/{name}"),
    "invertNamedCurve": ("get", "/v1/curves/{name}/inverse"),
    "invertNamedCurveCsv": ("get", "/v1/curves/{name}/inverse.csv"), "plotCurve": ("get", "/v1/curves/{name}/plot"),
    "sampleNamedCurve": ("get", "/v1/curves/{name}/table"),
    "sampleNamedCurveCsv": ("get", "/v1/curves/{name}/table.csv"), "getCurveValue": ("get", "/v1/curves/{name}/value"),
    "convertIndexingAccuracy": ("get", "/v1/indexers/accuracy"), "getIndexerMotion": ("post", "/v1/indexers/motion"),
    "getIndexerMotionCsv": ("post", "/v1/indexers/motion.csv"), "plotIndexerMotion": ("get", "/v1/indexers/plot"),
    "getIndexerPosition": ("post", "/v1/indexers/position"),
    "getIndexerPositionCsv": ("post", "/v1/indexers/position.csv"), "sizeIndexer": ("post", "/v1/indexers/sizing"),
    "sweepIndexerSizing": ("post", "/v1/indexers/sizing/sweep"),
    "computeIndexerVibration": ("post", "/v1/indexers/vibration"),
    "computeIndexerVibrationCsv": ("post", "/v1/indexers/vibration.csv"), "computeMotion": ("post", "/v1/motions"),
    "exportMotionCamTable": ("post", "/v1/motions/cam-table.csv"), "computeMotionCsv": ("post", "/v1/motions/table.csv"),
    "computeProfile": ("post", "/v1/profiles"), "sizeBaseCircle": ("post", "/v1/profiles/base-circle"),
    "exportProfileContourCsv": ("post", "/v1/profiles/contour.csv"),
    "exportProfileDxf": ("post", "/v1/profiles/contour.dxf"), "exportProfileXyz": ("post", "/v1/profiles/contour.xyz"),
    "computeFollowerDynamics": ("post", "/v1/profiles/dynamics"),
    "plotFollowerDynamics": ("get", "/v1/profiles/dynamics/plot"),
    "computeFollowerDynamicsCsv": ("post", "/v1/profiles/dynamics/table.csv"),
    "plotProfile": ("get", "/v1/profiles/plot"), "exportProfileStep": ("post", "/v1/profiles/solid.step"),
    "exportProfileStl": ("post", "/v1/profiles/solid.stl"), "computeProfileCsv": ("post", "/v1/profiles/table.csv"),
    "computeToolpath": ("post", "/v1/profiles/toolpath"), "exportToolpathDxf": ("post", "/v1/profiles/toolpath.dxf"),
    "exportToolpathGcode": ("post", "/v1/profiles/toolpath.nc"),
}
#: ids that the rule ({id}{Format} at {path}.{format}) renamed where the path stayed
RENAMED_AT_THE_SAME_PATH = {"exportToolpathDxf": "computeToolpathDxf",
                            "computeParallelCamCsv": "computeParallelIndexingCamCsv"}


def test_every_operation_of_before_still_answers_and_its_id_is_kept_or_listed() -> None:
    doc = create_app().openapi()
    ids = {op["operationId"] for ops in doc["paths"].values() for op in ops.values()}
    changelog = (Path(TARGET).parents[1] / "CHANGELOG.md").read_text(encoding="utf-8")
    assert len(BEFORE) == 53
    for old_id, (method, path) in BEFORE.items():
        assert method in doc["paths"].get(path, {}), (old_id, path)  # the path answers as before
        at_path = doc["paths"][path][method]["operationId"]
        if old_id in RENAMED_AT_THE_SAME_PATH:
            assert at_path == RENAMED_AT_THE_SAME_PATH[old_id] and f"`{old_id}`" in changelog, old_id
        else:
            assert old_id in ids, old_id  # the id is kept (at its path, or at the regular twin's)
    for old_id, new_id in RENAMED_AT_THE_SAME_PATH.items():
        assert f"`{new_id}`" in changelog, (old_id, new_id)


def test_the_operation_table_of_the_docs_is_the_registry() -> None:
    from scripts.operation_table import main

    assert main(["--check"]) == 0, "docs/api.md lists other operations than the registry: python -m scripts.operation_table"


# ----------------------------------------------------------------------------- how the document reads
def _operations(doc: dict[str, Any]) -> list[dict[str, Any]]:
    return [op for item in doc["paths"].values() for op in item.values()]


def test_every_operation_is_named_in_the_readme_and_in_the_header() -> None:
    # issue 33: a newcomer finds every operation in the README and at the top of /docs
    doc = create_app().openapi()
    readme = (Path(TARGET).parents[1] / "README.md").read_text(encoding="utf-8")
    ids = [op["operationId"] for op in _operations(doc) if not op.get("deprecated")]
    assert len(ids) > 60
    assert not [op_id for op_id in ids if f"`{op_id}`" not in readme], "README.md: python -m scripts.operation_table"
    assert not [op_id for op_id in ids if f"`{op_id}`" not in doc["info"]["description"]]


def test_the_header_names_every_part_of_the_service() -> None:
    header = create_app().openapi()["info"]["description"].split("**Operations**")[0].lower()
    for part in ("curves", "motion programs", "indexers", "plate cams", "toolpath", "solid", "dynamics", "vibration",
                 "barrel", "parallel", "roller-gear"):
        assert part in header, part


def test_every_tag_is_described_and_in_order() -> None:
    doc = create_app().openapi()
    used = {op["tags"][0] for op in _operations(doc)}
    described = [tag["name"] for tag in doc["tags"] if tag.get("description")]
    assert set(described) == used == {tag["name"] for tag in doc["tags"]}
    assert described == [tag["name"] for tag in TAGS if tag["name"] in used]  # the order the document shows them


def test_every_route_has_a_summary_of_its_own_and_twins_follow_the_rule() -> None:
    doc = create_app().openapi()
    by_id = {op["operationId"]: op for op in _operations(doc)}
    for op in by_id.values():
        # FastAPI's summary from a function name: "Export Profile ContourCsv"
        from_name = " ".join(re.findall(r"[A-Z]?[a-z0-9]+|[A-Z]+(?![a-z])", op["operationId"])).title()
        assert op["summary"] and op["summary"].lower() != from_name.lower(), op["operationId"]
    current = [op["summary"] for op in by_id.values() if not op.get("deprecated")]
    assert len(current) == len(set(current)), "two operations read the same"
    for operation in OPERATIONS:
        for route in routes_of(operation):
            if route.kind != "operation":
                expected = f"{operation.summary} as {route.formats[0].label}"
                assert by_id[route.id]["summary"] == expected + (" (older path)" if route.deprecated else "")
    assert by_id["computeProfileContourCsv"]["summary"] == "Plate cam profile as contour CSV"


def test_each_tag_lists_its_computations_then_their_files_then_the_older_paths() -> None:
    app = create_app()
    rank = {"operation": 0, "twin": 1, "alias": 2}
    seen: dict[str, list[int]] = {}
    for op in _operations(app.openapi()):
        seen.setdefault(op["tags"][0], []).append(rank[app.route_kinds.get(op["operationId"], "operation")])
    assert seen["profiles"][0] == 0 and 1 in seen["profiles"] and seen["profiles"][-1] == 2
    assert all(ranks == sorted(ranks) for ranks in seen.values()), seen


#: request models whose rules stay at the top of their schema (service.specs.examples, nested=False)
RULES_AT_THE_TOP = {"MotionSegmentSpec"}


def test_request_schemas_read_as_objects_and_list_their_rules() -> None:
    # Swagger UI names a schema's type from its own allOf/anyOf/oneOf: "object | (any & any …)"
    schemas = create_app().openapi()["components"]["schemas"]
    combined = {name for name, schema in schemas.items() if {"allOf", "anyOf", "oneOf"} & set(schema)}
    assert combined == RULES_AT_THE_TOP
    with_rules = {name: model_rules(schema) for name, schema in schemas.items() if model_rules(schema)}
    assert len(with_rules) >= 20
    for name, rules in with_rules.items():
        for member in rules:
            assert f"- {member['description']}" in schemas[name]["description"], (name, member["description"])
