"""``POST /v1/indexers/design`` (``designIndexer``): the indexer and motor that fit, ranked
(camcore.indexer.design does the work)."""

from __future__ import annotations

from typing import Annotated, Any, Literal

import numpy as np
from fastapi.openapi.models import Example
from pydantic import Field, model_validator

from camcore.errors import InvalidParameterError
from camcore.indexer.design import CRITERIA, IndexerDesign, NamedMotor, design_indexer
from camcore.results import as_dict
from camcore.work import INDEXER_ROW_S, MOST_PIECES_OF_A_LAW, WorkEstimate, peaks_s, per_item_work, rms_s
from service.context import Context
from service.curves.library import check_limit
from service.curves.specs import CurveSpec, NamedCurveSpec
from service.errors import within
from service.indexers.specs import LOAD_EXAMPLE, MOTOR_EXAMPLE, LoadSpec, MotorSpec, NonNegative, Positive
from service.models import answer_model
from service.operations import JSON, Document, Format, Operation, csv
from service.responses import check_finite
from service.specs import JSON_INTEGER, FieldRuleError, Spec, exactly_one, examples, one_of_values, rule

#: the candidate angles when none are given: every 30° from 90° to 330° (the catalog's usual θh)
DEFAULT_ANGLES = [90.0, 120.0, 150.0, 180.0, 210.0, 240.0, 270.0, 300.0, 330.0]
#: the candidate curves when none are given: the indexer catalog's dwell-rise-dwell curves
DEFAULT_CURVES = ("MS", "MCV50", "TR", "cycloid")
MAX_MOTORS = 20
MOTOR_RANKING_RULE = "ranking by motor needs motors to choose from"


def _default_curves() -> list[CurveSpec]:
    return [NamedCurveSpec(name=name) for name in DEFAULT_CURVES]


class NamedMotorSpec(MotorSpec):
    """A motor to choose from: its name and data."""

    model_config = examples({"name": "servo 400 W", **MOTOR_EXAMPLE})
    name: Annotated[str, Field(min_length=1, max_length=64)]


DESIGN_EXAMPLE: dict[str, Any] = {
    "stops": 6, "load": LOAD_EXAMPLE, "cycle_time_s": 1.0, "min_dwell_s": 0.4,
    "motors": [{"name": "servo 200 W", **MOTOR_EXAMPLE, "rated_torque_nm": 0.64, "peak_torque_nm": 1.91},
               {"name": "servo 400 W", **MOTOR_EXAMPLE, "rated_torque_nm": 1.27, "peak_torque_nm": 3.82},
               {"name": "servo 750 W", **MOTOR_EXAMPLE, "rated_torque_nm": 2.39, "peak_torque_nm": 7.16}]}


class IndexerDesignRequest(Spec):
    """Stops, the load, the machine's cycle (one index and one dwell per input turn) and the dwell the process
    needs; the candidates: indexing angles, curves and (optionally) motors. Every candidate is sized; the feasible
    ones are ranked."""

    model_config = examples(DESIGN_EXAMPLE, rules=[
        rule("give exactly one of speed_rpm (N) and cycle_time_s (t0)", exactly_one("speed_rpm", "cycle_time_s")),
        rule(MOTOR_RANKING_RULE, {"if": one_of_values("criterion", "motor"),
                                  "then": {"required": ["motors"], "properties": {"motors": {"minItems": 1}}}})])
    stops: Annotated[int, Field(ge=1, le=100_000), JSON_INTEGER] = Field(description="n, stops per output turn")
    load: LoadSpec
    speed_rpm: Positive | None = Field(None, description="N, the input speed (one index per input turn)")
    cycle_time_s: Positive | None = Field(None, description="t0 = 60/N: one index and one dwell (instead of speed_rpm)")
    min_dwell_s: NonNegative = Field(0.0, description="the dwell the process needs; θh ≤ 360·(1 − min_dwell_s/t0)")
    indexing_angles_deg: list[Annotated[float, Field(strict=True, allow_inf_nan=False, ge=1e-6, le=360)]] = Field(
        default_factory=lambda: list(DEFAULT_ANGLES), min_length=1, max_length=360,
        description="candidate θh; default every 30° from 90° to 330°")
    curves: list[CurveSpec] = Field(default_factory=lambda: _default_curves(), min_length=1, max_length=50,
                                    description="candidate curves; default MS, MCV50, TR and cycloid")
    motors: list[NamedMotorSpec] = Field(default_factory=list, max_length=MAX_MOTORS,
                                         description="candidate motors (names unique); none: no motor check")
    internal_friction_torque_nm: NonNegative = Field(0.0, description="the unit's own friction on the input shaft")
    rated_output_torque_nm: Positive | None = Field(None, description="the unit's rated output torque (the maker's)")
    max_input_torque_nm: Positive | None = Field(None, description="the peak input torque allowed")
    criterion: Literal[CRITERIA] | None = Field(  # type: ignore[valid-type]  # the core's tuple of names
        None, description="input_torque (the smallest peak), rms_input_torque, or motor (the smallest motor by rated "
                          "torque that carries it, then its RMS use); default motor with motors, else input_torque")

    @model_validator(mode="after")
    def _check(self) -> IndexerDesignRequest:
        if (self.speed_rpm is None) == (self.cycle_time_s is None):
            raise ValueError("give exactly one of speed_rpm (N) and cycle_time_s (t0)")
        names = [m.name for m in self.motors]
        for i, name in enumerate(names):
            if name in names[:i]:
                raise FieldRuleError(f"motor names must be unique: {name!r} is given twice", "motors", i, "name")
        if self.criterion == "motor" and not self.motors:
            raise FieldRuleError(MOTOR_RANKING_RULE, "criterion")
        return self

    @property
    def combinations(self) -> int:
        return len(self.indexing_angles_deg) * len(self.curves) * max(1, len(self.motors))

    @property
    def rpm(self) -> float:
        return float(self.speed_rpm) if self.speed_rpm is not None else 60.0 / float(self.cycle_time_s)  # type: ignore[arg-type]


DESIGN_EXAMPLES: dict[str, Example] = {
    "motors": {"summary": "6 stops, the guide's load, a 1 s cycle with 0.4 s of dwell, three motors",
               "description": "the smallest motor that carries it, with the angle and curve that let it",
               "value": DESIGN_EXAMPLE},
    "torque": {"summary": "the same without motors: the smallest peak input torque",
               "value": {k: v for k, v in DESIGN_EXAMPLE.items() if k != "motors"}},
}

IndexerDesignAnswer = answer_model(IndexerDesign, "IndexerDesignAnswer")


def _work(ctx: Context, body: IndexerDesignRequest, fmt: Format) -> WorkEstimate:
    """413 over the combination limit; each curve built, each candidate sized (peaks, one RMS integral, two with
    a motor)."""
    check_limit("design candidates", body.combinations, ctx.settings.max_sweep_combinations, ("indexing_angles_deg",))
    work = WorkEstimate()
    per_curve = body.combinations // len(body.curves)
    integrals = 2 if body.motors else 1
    for i, spec in enumerate(body.curves):
        law = spec.core()
        cost = ctx.curves.cost(law, at=("curves", i))
        work += ctx.curves.build_work(law, cost, ("curves", i))
        pieces = max(len(law.parameters.get("t", ())), MOST_PIECES_OF_A_LAW)
        each = peaks_s(pieces, cost.sample_s) + integrals * rms_s(pieces) + 2 * INDEXER_ROW_S
        work += per_item_work(per_curve, each, ("indexing_angles_deg",), f"{per_curve} candidates along curves[{i}]")
    return work


def design(ctx: Context, body: IndexerDesignRequest) -> IndexerDesign:
    """The ranked candidates; 422 naming the requirement when none is feasible."""
    curves = [(str(getattr(spec, "name", None) or getattr(spec, "number", None) or spec.type),
               ctx.curves.curve(spec.core(), at=("curves", i))) for i, spec in enumerate(body.curves)]
    with within("load"):
        load = body.load.core()
    motors = []
    for i, m in enumerate(body.motors):
        with within("motors", i):
            motors.append(NamedMotor(m.name, m.core()))
    with np.errstate(all="ignore"):  # as sizeIndexer: a non-finite figure is refused below
        result = design_indexer(body.stops, load, body.rpm, body.indexing_angles_deg, curves,
                                min_dwell_s=body.min_dwell_s, motors=motors,
                                internal_friction_torque_nm=body.internal_friction_torque_nm,
                                rated_output_torque_nm=body.rated_output_torque_nm,
                                max_input_torque_nm=body.max_input_torque_nm, criterion=body.criterion)
    for row in result.candidates:
        check_finite({name: value for name, value in vars(row).items() if isinstance(value, float)})
    if result.best is None:
        closest = min(result.candidates, key=lambda c: (len(c.missed), c.input_torque_nm))
        where = f"θh = {closest.indexing_angle_deg:g}°, {closest.curve}" + (
            f", motor {closest.motor}" if closest.motor else "")
        raise InvalidParameterError(f"no candidate meets every requirement; the closest ({where}): {closest.reason}.",
                                    field=(closest.missed[0],))
    return result


def _column(values: list[Any]) -> np.ndarray:
    """A CSV column: numbers (null: an empty cell), or text (true/false for a verdict, empty for null)."""
    if all(isinstance(v, int | float) and not isinstance(v, bool) or v is None for v in values):
        return np.array([np.nan if v is None else v for v in values], dtype=np.float64)
    return np.array(["" if v is None else str(v).lower() if isinstance(v, bool) else str(v) for v in values])


def _compute(ctx: Context, body: IndexerDesignRequest, fmt: Format) -> Document:
    """The ranked candidates; CSV: one row per candidate."""
    result = as_dict(design(ctx, body))
    rows = result["candidates"]
    table = {name: _column([row[name] for row in rows]) for name in rows[0]}
    return Document(result, table=table, allow_null=tuple(name for name, col in table.items()
                                                          if col.dtype.kind == "f"))


OPERATIONS = (
    Operation("designIndexer", "/v1/indexers/design", "indexers", "Indexer design: the candidates ranked",
              "Every candidate indexing angle × curve × motor sized for the stops, load and cycle; those that leave the "
              "dwell needed, stay within the rated output and allowed input torque, and whose motor carries them, "
              "ranked by the criterion (the smallest motor, peak or RMS input torque); ``best`` is the first. "
              "``?format=csv``: the candidates as a table. None feasible: 422 naming the requirement.",
              IndexerDesignRequest, _compute, estimate=_work, answer=IndexerDesignAnswer,
              formats=(JSON, csv("indexer-design.csv", "the ranked candidates as CSV")), examples=DESIGN_EXAMPLES),
)
