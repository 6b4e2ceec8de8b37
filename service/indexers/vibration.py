"""``POST /v1/indexers/vibration``: an indexer's load on an elastic drive train — its natural
frequency, τ, residual amplitude, settling time and its error over the index and the dwell
(camcore.dynamics.indexer_vibration; the curve's spectrum is /v1/curves/vibration)."""

from __future__ import annotations

import math
from typing import Annotated

from fastapi.openapi.models import Example
from pydantic import Field, model_validator

import camcore
from camcore.dynamics import IndexerVibration, VibrationTable, indexer_vibration
from camcore.indexer import Load
from camcore.results import as_dict
from camcore.work import (
    INDEXER_ROW_S,
    INDEXER_TABLE_COLUMNS,
    VIBRATION_ROW_S,
    WorkEstimate,
    curve_work,
    encode_cost,
    estimated_cells,
    per_item_work,
    vibration_work,
)
from service.context import Context
from service.curves.library import check_limit
from service.curves.vibration import DampingRatio, check_law
from service.errors import within
from service.indexers.operations import indexer
from service.indexers.specs import INDEXER_EXAMPLE, LOAD_EXAMPLE, IndexerSpec, LoadSpec
from service.models import answer_model
from service.operations import JSON, Document, Format, Operation, csv
from service.specs import JSON_INTEGER, Spec, exactly_one, examples, given, rule

#: a positive physical quantity: far beyond any indexer (the τ range bounds the ratio k/I)
PositiveQuantity = Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, le=1e12)]
#: one index along one curve: a timing chart (several moves over an input turn) is not modelled
SINGLE_CURVE = ("the residual vibration takes an indexer with one curve (stops or swing_angle_deg, indexing_angle_deg, "
                "curve), not a timing chart")
CURVE = ("indexer", "curve")


class IndexerVibrationRequest(Spec):
    model_config = examples(
        {"indexer": INDEXER_EXAMPLE, "inertia_kgm2": 2.25, "stiffness_nm_rad": 2e5, "damping_ratio": 0.05,
         "tolerance_arcsec": 10},
        rules=[rule("give the load's inertia as inertia_kgm2 or as load: one of them, not both",
                    exactly_one("inertia_kgm2", "load")),
               rule(SINGLE_CURVE, {"not": {"required": ["indexer"], "properties": {"indexer": given("timing")}}})])
    indexer: IndexerSpec
    inertia_kgm2: PositiveQuantity | None = Field(None, description="I, the load inertia on the output")
    load: LoadSpec | None = Field(None, description="the load (instead of inertia_kgm2): only its inertia is used")
    stiffness_nm_rad: PositiveQuantity = Field(description="k, torsional stiffness from the output shaft to the load")
    damping_ratio: DampingRatio = Field(0.0, description="ζ, 0 ≤ ζ < 1 (underdamped; ζ ≥ 1 is refused)")
    tolerance_arcsec: PositiveQuantity = Field(description="ε, the error allowed at the dwell")
    samples: Annotated[int, Field(ge=2), JSON_INTEGER] = Field(
        501, description="rows of the table over the index and the dwell, both ends included")

    @model_validator(mode="after")
    def _check(self) -> IndexerVibrationRequest:
        if (self.inertia_kgm2 is None) == (self.load is None):
            raise ValueError("give the load's inertia as inertia_kgm2 or as load: one of them, not both")
        if self.indexer.timing is not None:
            raise ValueError(SINGLE_CURVE)
        return self


INDEXER_VIBRATION_EXAMPLES: dict[str, Example] = {
    "guide": {"summary": "the guide's indexer and disc on a 2e5 N·m/rad drive",
              "description": "6 stops, θh = 270°, 60 rpm, MS; I = 2.25 kg·m²: fn = 47.45 Hz, τ = 35.6",
              "value": {"indexer": INDEXER_EXAMPLE, "inertia_kgm2": 2.25, "stiffness_nm_rad": 2e5,
                        "damping_ratio": 0.05, "tolerance_arcsec": 10}},
    "load": {"summary": "the same with the load given by its parts, a softer drive",
             "value": {"indexer": INDEXER_EXAMPLE, "load": LOAD_EXAMPLE, "stiffness_nm_rad": 2e4,
                       "damping_ratio": 0.02, "tolerance_arcsec": 10, "samples": 201}},
}

IndexerVibrationTableAnswer = answer_model(VibrationTable, "IndexerVibrationTable")
_IndexerVibrationFields = answer_model(IndexerVibration, "IndexerVibrationFields")


class IndexerVibrationAnswer(_IndexerVibrationFields):  # type: ignore[valid-type, misc]  # derived (service.models)
    """Natural frequency, τ, residual amplitude and settling time of an indexer's load, and its error over
    the index and the dwell."""

    table: IndexerVibrationTableAnswer  # type: ignore[valid-type]  # derived answer model (service.models)


def load_inertia(load: LoadSpec | None) -> float:
    """The inertia of a LoadSpec (its parts and the inertia given directly), > 0."""
    assert load is not None
    inertia = Load(inertia_kgm2=load.inertia_kgm2, parts=[part.core() for part in load.parts]).total_inertia_kgm2
    if not inertia > 0:
        raise camcore.InvalidParameterError(
            f"the load's inertia must be greater than 0 (its parts and inertia_kgm2 add to {inertia!r} kg·m²).")
    return float(inertia)


def _tau_guess(body: IndexerVibrationRequest) -> float:
    """τ from the request's numbers, bounded to camcore's range (out of it: refused later, 422)."""
    try:
        inertia = body.inertia_kgm2 if body.inertia_kgm2 is not None else load_inertia(body.load)
        rpm = body.indexer.speed_rpm or 60.0 / ((body.indexer.cycle_time_s or 1.0) * body.indexer.dwells)
        th = (body.indexer.indexing_angle_deg or 360.0) / 360.0 * 60.0 / rpm
        tau = th * (body.stiffness_nm_rad / inertia) ** 0.5 / (2 * math.pi)
    except (ArithmeticError, ValueError):
        return camcore.dynamics.TAU_MIN
    return float(min(max(tau, camcore.dynamics.TAU_MIN), camcore.dynamics.TAU_MAX))


def _work(ctx: Context, body: IndexerVibrationRequest, fmt: Format) -> WorkEstimate:
    """One τ (known once the inertia is: estimated at the largest τ the range allows is too
    much, so at the τ of the request's numbers) and the table."""
    law = body.indexer.curve.core()
    check_law(ctx, law, CURVE)
    check_limit("table samples", body.samples, ctx.settings.max_table_samples, ("samples",))
    cost = ctx.curves.cost(law, CURVE)
    return (curve_work(cost, CURVE)
            + vibration_work(cost, estimated_cells(law.kind, law.parameters), [_tau_guess(body)],
                             ("stiffness_nm_rad",))
            + per_item_work(body.samples, VIBRATION_ROW_S + INDEXER_ROW_S
                            + encode_cost(INDEXER_TABLE_COLUMNS, fmt.name == "csv"), ("samples",),
                            f"{body.samples} table rows"))


def _answer(ctx: Context, body: IndexerVibrationRequest, fmt: Format) -> Document:
    """The answer's fields and its table."""
    check_limit("table samples", body.samples, ctx.settings.max_table_samples, ("samples",))
    unit = indexer(ctx, body.indexer)
    assert isinstance(unit, camcore.indexer.Indexer)  # the request's rule: no timing chart
    if body.inertia_kgm2 is not None:
        inertia = body.inertia_kgm2
    else:
        with within("load"):
            inertia = load_inertia(body.load)
    result = indexer_vibration(unit, inertia, body.stiffness_nm_rad, body.damping_ratio, body.tolerance_arcsec,
                               body.samples)
    table = result.table.columns()
    return Document({**as_dict(result), "table": table}, table=table)


OPERATIONS = (
    Operation("computeIndexerVibration", "/v1/indexers/vibration", "indexers", "Indexer load vibration on an elastic drive",
              "Natural frequency, τ, residual amplitude and settling time of the load, and its error over the index "
              "and the dwell (CSV: the table).",
              IndexerVibrationRequest, _answer, estimate=_work, answer=IndexerVibrationAnswer,
              formats=(JSON, csv("indexer-vibration.csv")), examples=INDEXER_VIBRATION_EXAMPLES),
)
