"""POST /v1/indexers/sizing/sweep: the spec, its answer, and the bridge to camcore.indexer.sweep."""

from __future__ import annotations

from typing import Annotated, Any

import numpy as np
from fastapi.openapi.models import Example
from pydantic import Field, create_model, model_validator

from camcore.indexer import Sizing
from camcore.indexer.checks import check_speed_alternatives
from camcore.indexer.sizing import FIGURE_FIELDS
from camcore.indexer.sweep import size_sweep
from camcore.results import answer_fields
from camcore.work import (
    MOST_PIECES_OF_A_LAW,
    SIZING_SWEEP_ROW_S,
    WorkEstimate,
    per_item_work,
    sweep_chart_s,
    sweep_row_s,
)
from service.context import Context
from service.curves.library import check_limit
from service.curves.specs import MS_SPEC, CurveSpec
from service.errors import within
from service.indexers.charts import check_panels, sweep_chart
from service.indexers.specs import LOAD_EXAMPLE, LoadSpec, Positive
from service.operations import JSON, PNG_DRAWING, SVG_DRAWING, Format, Operation, Payload, Table, csv
from service.specs import JSON_INTEGER, DeferredModel, Spec, exactly_one, examples, rule

SWEEP_EXAMPLE: dict[str, object] = {
    "load": LOAD_EXAMPLE, "stops": [4, 6, 8], "indexing_angle_deg": [120, 180, 270],
    "curves": [MS_SPEC, {"type": "named", "name": "MCV50"}, {"type": "named", "name": "TR"}],
    "speed_rpm": [30, 60, 90, 120]}


class SizingSweepRequest(Spec):
    """Every combination of stops × indexing angles × curves × speeds (or cycle times), sized
    with one load; rows in that order, the last varying fastest."""

    model_config = examples(SWEEP_EXAMPLE, rules=[rule("give exactly one of speed_rpm (N) and cycle_time_s "
                                                       "(t0 = 60/(N·z))", exactly_one("speed_rpm", "cycle_time_s"))])
    load: LoadSpec
    stops: list[Annotated[int, Field(ge=1, le=100_000), JSON_INTEGER]] = Field(min_length=1)
    indexing_angle_deg: list[Annotated[float, Field(strict=True, allow_inf_nan=False, ge=1e-6, le=360)]] = Field(
        min_length=1)
    curves: list[CurveSpec] = Field(min_length=1, max_length=100)
    speed_rpm: Annotated[list[Positive], Field(json_schema_extra={"minItems": 1})] | None = None
    cycle_time_s: Annotated[list[Positive], Field(json_schema_extra={"minItems": 1})] | None = Field(
        None, description="t0 = 60/N (one index per input turn) instead of speed_rpm")

    @model_validator(mode="after")
    def _check(self) -> SizingSweepRequest:
        check_speed_alternatives(self.speed_rpm, self.cycle_time_s)
        if not (self.speed_rpm or self.cycle_time_s):
            raise ValueError("speed_rpm (or cycle_time_s) must list at least one value")
        return self

    @property
    def combinations(self) -> int:
        speeds = len(self.speed_rpm or self.cycle_time_s or ())
        return len(self.stops) * len(self.indexing_angle_deg) * len(self.curves) * speeds


SWEEP_EXAMPLES: dict[str, Example] = {
    "grid": {"summary": "3 stops × 3 angles × 3 curves × 4 speeds: 108 designs, the guide's load",
             "value": SWEEP_EXAMPLE},
}

#: the sweep's columns: the design, then every sizing figure that depends on it
_FIGURES: dict[str, Any] = {name: (list[float], Field(description=text)) for name, _, text, _ in answer_fields(Sizing)
                            if name in FIGURE_FIELDS}
SizingSweepAnswer = create_model(
    "SizingSweepAnswer", __base__=DeferredModel, __doc__="One row per combination (the sizing figures of sizeIndexer, column by column).",
    stops=(list[float], Field(description="n")), indexing_angle_deg=(list[float], Field(description="θh [deg]")),
    curve=(list[str], Field(description="the curve's catalog id, or its spec's kind")),
    cycle_time_s=(list[float] | None, Field(None, description="with cycle_time_s: t0 [s]")), **_FIGURES)
SizingSweepAnswer.__module__ = __name__


CHARTS = (PNG_DRAWING, SVG_DRAWING)


def sweep_work(ctx: Context, body: SizingSweepRequest, fmt: Format) -> WorkEstimate:
    """413 over the combination limit; the curves and the rows (and a chart's drawing)."""
    check_limit("sizing combinations", body.combinations, ctx.settings.max_sweep_combinations, ("stops",))
    work = WorkEstimate()
    designs = body.combinations // len(body.curves)  # along each curve
    for i, spec in enumerate(body.curves):
        law = spec.core()
        work += ctx.curves.work(law, ("curves", i))
        # a design costs its law's bracketing grid: a points curve has a piece per point
        pieces = max(len(law.parameters.get("t", ())), MOST_PIECES_OF_A_LAW)
        row_s = sweep_row_s(pieces)
        field = ("stops",) if row_s == SIZING_SWEEP_ROW_S else ("curves", i)
        work += per_item_work(designs, row_s, field, f"{designs} designs along curves[{i}]")
    if fmt in CHARTS:  # a panel per stops and indexing angle
        panels = len(set(body.stops)) * len(set(body.indexing_angle_deg))
        check_panels(panels)  # 422 before the budget's 413: the chart cannot be drawn at any budget
        work += per_item_work(1, sweep_chart_s(panels), ("stops",), f"drawing the chart of {panels} panels")
    return work


def sweep(ctx: Context, body: SizingSweepRequest) -> dict[str, Any]:
    """The sweep's columns."""
    built = [ctx.curves.curve(spec.core(), at=("curves", i)) for i, spec in enumerate(body.curves)]
    names = [str(getattr(spec, "name", None) or getattr(spec, "number", None) or spec.type) for spec in body.curves]
    with within("load"):
        load = body.load.core()
    with np.errstate(all="ignore"):  # non-finite answers are refused when encoded
        return size_sweep(load, body.stops, body.indexing_angle_deg, built, names, speed_rpm=body.speed_rpm,
                          cycle_time_s=body.cycle_time_s)


def _answer(ctx: Context, body: SizingSweepRequest, fmt: Format) -> Table | Payload:
    """The table, or its chart (drawn in the gate's thread, like the computation)."""
    if fmt in CHARTS:
        return Payload(sweep_chart(sweep(ctx, body), fmt.name))
    return Table(sweep(ctx, body))


OPERATIONS = (
    Operation("sweepIndexerSizing", "/v1/indexers/sizing/sweep", "indexers", "Indexer sizing over a grid of designs",
              "Every combination of stops × indexing angles × curves × speeds sized at once (CSV on request, or "
              "``?format=png|svg``: input torque over speed per curve, a panel per stops and angle).",
              SizingSweepRequest, _answer, estimate=sweep_work, answer=SizingSweepAnswer,
              formats=(JSON, csv("sizing-sweep.csv"), PNG_DRAWING, SVG_DRAWING), examples=SWEEP_EXAMPLES),
)
