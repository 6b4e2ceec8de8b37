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
