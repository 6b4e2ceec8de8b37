"""POST /v1/curves/characteristics/sweep: characteristic values over a grid of one or two
parameters of a makino or universal spec — Makino's design chart (1977, fig. 3, appendix 3-2).

Each combination is the base spec with the varied values put in; a combination the spec's
rules refuse (T1 > T3, a target out of reach...) is a row with its error sentence, not a
failure of the request.
"""

from __future__ import annotations

import itertools
from typing import Annotated, Any, Literal

import numpy as np
from fastapi.openapi.models import Example
from pydantic import BaseModel, ConfigDict, Field, ValidationError, create_model, model_validator

from camcore.curves import Curve, build_curve
from camcore.curves.batch import VALUES, characteristic_values
from camcore.curves.targets import TARGETS
from camcore.errors import CamError
from camcore.work import CHARACTERISTICS_SWEEP_ROW_S, DESIGN_CHART_S, WorkEstimate, per_item_work
from service.context import Context
from service.curves.charts import design_chart
from service.curves.library import check_limit
from service.curves.specs import MAKINO_PARAMETERS, MAKINO_TARGETS, MakinoCurveSpec, UniversalCurveSpec
from service.operations import JSON, PNG_DRAWING, SVG_DRAWING, Format, Operation, Payload, Table, csv
from service.specs import Finite, Spec, examples, rule

#: what a universal spec may vary: a break point T0..T7 (``t3`` is T3), or an end condition
UNIVERSAL_VARIABLES = (*(f"t{i}" for i in range(8)), "m", "v0", "v7", "s0", "s7")
MAKINO_VARIABLES = (*MAKINO_PARAMETERS, *MAKINO_TARGETS)
Variable = Literal[tuple(dict.fromkeys((*MAKINO_VARIABLES, *UNIVERSAL_VARIABLES)))]  # type: ignore[valid-type]

APPENDIX_3_2_EXAMPLE: dict[str, Any] = {
    "curve": {"type": "makino", "number": 4, "t1": 0.015625, "t3": 0.03125},
    "vary": {"t3": [i / 32 for i in range(1, 5)], "t1": [j / 64 for j in range(1, 9)]}}


def _kind_rule(kind: str, names: tuple[str, ...]) -> dict[str, Any]:
    return rule(f"a {kind} spec varies {', '.join(names)}",
                {"if": {"properties": {"curve": {"properties": {"type": {"const": kind}}}}},
                 "then": {"properties": {"vary": {"propertyNames": {"enum": list(names)}}}}})


class CharacteristicsSweepRequest(Spec):
    """A makino or universal spec and one or two of its parameters, each over a list of values:
    every combination (the first parameter varies slowest), the spec's value of a varied
    parameter replaced."""

    model_config = examples(APPENDIX_3_2_EXAMPLE, rules=[_kind_rule("makino", MAKINO_VARIABLES),
                                                         _kind_rule("universal", UNIVERSAL_VARIABLES)])
    curve: Annotated[MakinoCurveSpec | UniversalCurveSpec, Field(discriminator="type")]
    vary: dict[Variable, Annotated[list[Finite], Field(min_length=1)]] = Field(  # type: ignore[valid-type]  # the names above
        min_length=1, max_length=2, description="one or two parameters → their values; makino: z, t4, t1, t3, vm, "
        "t1_over_t3, v_ratio; universal: t0..t7 (a break point), m, v0, v7, s0, s7",
        examples=[APPENDIX_3_2_EXAMPLE["vary"]])

    @model_validator(mode="after")
    def _check(self) -> CharacteristicsSweepRequest:
        names = MAKINO_VARIABLES if self.curve.type == "makino" else UNIVERSAL_VARIABLES
        wrong = [name for name in self.vary if name not in names]
        if wrong:
            raise ValueError(f"a {self.curve.type} spec varies {', '.join(names)}, not {', '.join(wrong)}")
        return self

    @property
    def combinations(self) -> int:
        return int(np.prod([len(values) for values in self.vary.values()]))


SWEEP_EXAMPLES: dict[str, Example] = {
    "appendix 3-2": {"summary": "Makino's curve 4 over T3 = I/32, T1 = J/64 (appendix 3-2)",
                     "description": "32 combinations; those with T1 > T3 are rows with their error",
                     "value": APPENDIX_3_2_EXAMPLE},
    "target": {"summary": "curve 4 designed from Vm, over Vm",
               "value": {"curve": {"type": "makino", "number": 4, "vm": 1.2}, "vary": {"vm": [1.1, 1.2, 1.3, 1.4]}}},
}

_NUMBERS = list[float | None]
_VALUE_COLUMNS: dict[str, Any] = {name: (_NUMBERS, Field(description=f"{name} of each row (characteristics)"))
                                  for name in VALUES}
CharacteristicsSweepAnswer = create_model(
    "CharacteristicsSweepAnswer",
    __doc__="One row per combination, column by column: the varied parameters (a makino spec also its "
            "parameters solved from a target), the characteristic values (null where the row has an error), "
            "and the error sentence (null where there is none).",
    __config__=ConfigDict(extra="allow", defer_build=True),  # DeferredModel's, beside extra
    **_VALUE_COLUMNS,
    error=(list[str | None], Field(description="why the combination has no curve; null: it has one")),
)
CharacteristicsSweepAnswer.__module__ = __name__


def sweep_work(ctx: Context, body: CharacteristicsSweepRequest, fmt: Format) -> WorkEstimate:
    """413 over CAMCORE_MAX_SWEEP_COMBINATIONS; each combination (and a chart's drawing)."""
    first = next(iter(body.vary))
    check_limit("characteristics sweep combinations", body.combinations, ctx.settings.max_sweep_combinations,
                ("vary", first))
    work = per_item_work(body.combinations, CHARACTERISTICS_SWEEP_ROW_S, ("vary", first),
                         f"{body.combinations} curves")
    if fmt in CHARTS:
        work += per_item_work(1, DESIGN_CHART_S, ("vary",), "drawing the chart")
    return work


def _with(base: dict[str, Any], kind: str, values: dict[str, float]) -> dict[str, Any]:
    """The base spec with the varied values put in; for a makino spec a varied target drops the
    parameters it replaces (and a varied parameter the target that would replace it)."""
    spec = dict(base)
    if kind == "universal":
        spec["t"] = list(spec["t"])
        for name, value in values.items():
            if name[0] == "t" and name[1:].isdigit():
                spec["t"][int(name[1:])] = value
            else:
                spec[name] = value
        return spec
    for targets, replaced in TARGETS.values():
        if set(values) & set(targets):
            spec.update(dict.fromkeys(replaced))
        if set(values) & set(replaced):
            spec.update(dict.fromkeys(targets))
    spec.update(values)
    return spec


def _error(exc: Exception) -> str:
    if isinstance(exc, ValidationError):
        first = exc.errors()[0]
        return str(first["msg"]).removeprefix("Value error, ")
    return str(exc)


def column(name: str) -> str:
    """A varied parameter's column: its name, but the target ``vm`` is ``vm_target`` (``vm`` is the
    curve's Vm, equal to the target to rounding)."""
    return f"{name}_target" if name in VALUES else name


def sweep(ctx: Context, body: CharacteristicsSweepRequest) -> dict[str, Any]:
    """The sweep's columns: the varied parameters, solved ones, the values, the error of each row.

    Each combination is validated and built on its own; the characteristic values of all
    the built curves are found together (:func:`camcore.curves.batch.characteristic_values`).
    """
    names = list(body.vary)
    base = body.curve.model_dump()
    model: type[BaseModel] = type(body.curve)
    solved_names = [p for p in MAKINO_PARAMETERS if p not in names] if body.curve.type == "makino" else []
    columns: dict[str, list[Any]] = {name: [] for name in [*map(column, names), *solved_names, "error"]}
    built: list[Curve] = []
    for combination in itertools.product(*body.vary.values()):
        values = dict(zip(names, combination))
        for name, value in values.items():
            columns[column(name)].append(value)
        try:
            spec = model.model_validate(_with(base, body.curve.type, values))
            curve = build_curve(spec.type, spec.parameters(), spec.direction, ctx.curves.size_limits())  # type: ignore[attr-defined]
        except (ValidationError, CamError) as exc:
            for name in solved_names:
                columns[name].append(np.nan)
            columns["error"].append(_error(exc))
            continue
        built.append(curve)
        solved = spec.solved_parameters() if isinstance(spec, MakinoCurveSpec) else {}
        for name in solved_names:
            columns[name].append(solved.get(name, np.nan))
        columns["error"].append(None)
    found = characteristic_values(built)
    has_curve = np.array([error is None for error in columns["error"]], dtype=bool)
    for name in VALUES:
        column_values = np.full(has_curve.size, np.nan)
        column_values[has_curve] = found[name]
        columns[name] = column_values.tolist()
    columns["error"] = columns.pop("error")  # the last column
    # a solved parameter the curve does not have (t4 of curve 4) is not a column
    return {name: column for name, column in columns.items()
            if name not in solved_names or not all(np.isnan(x) for x in column)}


CHARTS = (PNG_DRAWING, SVG_DRAWING)
CSV = csv("characteristics-sweep.csv")


def _answer(ctx: Context, body: CharacteristicsSweepRequest, fmt: Format) -> Table | Payload:
    """The table (CSV: an empty cell where a row has no error), or the design chart."""
    columns = sweep(ctx, body)
    if fmt in CHARTS:
        return Payload(design_chart(columns, {column(k): v for k, v in body.vary.items()}, fmt.name))
    if fmt.name == "csv":
        columns["error"] = [text or "" for text in columns["error"]]
    return Table(columns, allow_null=tuple(name for name in columns if name != "error"))


OPERATIONS = (
    Operation("sweepCurveCharacteristics", "/v1/curves/characteristics/sweep", "curves", "Characteristic values over a parameter sweep",
              "Vm, Am±, Jm±, Qm± over every combination of one or two parameters of a makino or universal spec (CSV "
              "on ``?format=csv`` or ``Accept: text/csv``; the design chart on ``?format=png|svg``: two parameters, "
              "contours of Vm and Am over them, Makino's fig. 3; one, Vm and Am over it).",
              CharacteristicsSweepRequest, _answer, estimate=sweep_work, answer=CharacteristicsSweepAnswer,
              formats=(JSON, CSV, PNG_DRAWING, SVG_DRAWING), examples=SWEEP_EXAMPLES),
)
