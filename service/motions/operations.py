"""/v1/motions: a machine cycle of one follower, matched at every join; and every motion program
in a request (a cam's lift, an indexer's timing chart) resolved the same way.

``computeMotion`` answers JSON, the table as CSV, or a servo drive's cam table
(:data:`camcore.export.MOTION_FORMATS`: the program at a fixed master step over one period,
both ends included; ``x_deg`` has no fixed step and is refused there).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from camcore.curves import Curve, Law
from camcore.curves.kinds import LawCost
from camcore.errors import InvalidParameterError, NonFiniteResultError
from camcore.export import MOTION_FORMATS, CamTable
from camcore.motion import MotionSpec as CoreMotionSpec
from camcore.motion import law_role, resolve_motion
from camcore.motion.program import MotionProgram
from camcore.results import as_dict
from camcore.work import (
    MOTION_TABLE_COLUMNS,
    MOTION_TIME_COLUMNS,
    WorkEstimate,
    WorkTerm,
    encode_cost,
    law_cost,
    motion_work,
)
from service.context import Context
from service.curves.library import check_limit
from service.errors import Location, within
from service.motions.specs import MOTION_EXAMPLES, MotionProgramAnswer, MotionProgramRequest
from service.operations import JSON, Alias, Document, Format, Operation, Payload, csv, download

FORMATS = (JSON, csv("motion.csv", "the table alone, for spreadsheets"),
           *(download(fmt) for fmt in MOTION_FORMATS.values()))


# ----------------------------------------------------------------------------- any program
def program_costs(ctx: Context, program: CoreMotionSpec, at: Location = ("motion",)
                  ) -> tuple[list[LawCost | None], int]:
    """Each segment's law cost (None where nothing is built: a dwell, a fixed law built before)
    and how many parameters are solved; 413 first for too many segments or a law over its size
    limit. ``at``: where the program is in the request."""
    check_limit("motion segments", len(program.segments), ctx.settings.max_motion_segments, (*at, "segments"))
    costs: list[LawCost | None] = []
    seen: set[bytes] = set()
    cycloid = b"cycloid"
    solved = 0
    for i, segment in enumerate(program.segments):
        if segment.law is None:  # a dwell, or the default cycloid (built once)
            costs.append(None if segment.type == "dwell" or cycloid in seen else law_cost("named", {}))
            seen.add(cycloid)
            continue
        cost = ctx.curves.cost(segment.law, at=(*at, "segments", i, "curve"))
        role = law_role(segment.law)
        fixed = role == "fixed"
        solved += role == "solved"
        key = ctx.curves.key(segment.law)
        costs.append(None if fixed and key in seen else cost)
        if fixed:
            seen.add(key)
    return costs, solved


def program_work(ctx: Context, program: CoreMotionSpec, rows: int, rows_field: Location,
                 at: Location = ("motion",)) -> WorkEstimate:
    """A program resolved and evaluated at ``rows`` master angles (camcore.work.motion_work)."""
    costs, solved = program_costs(ctx, program, at)
    return motion_work(costs, solved, rows, (*at, "segments"), rows_field)


def resolve(ctx: Context, program: CoreMotionSpec, at: Location = ("motion",)) -> MotionProgram:
    """The resolved program; fixed laws come from the curve cache. ``at``: where the program is
    in the request."""
    check_limit("motion segments", len(program.segments), ctx.settings.max_motion_segments, (*at, "segments"))
    where = {id(seg.law): i for i, seg in enumerate(program.segments) if seg.law is not None}

    def build(law: Law) -> Curve:
        if id(law) not in where:  # camcore's default law of a segment that gives none
            return ctx.curves.curve(Law("named", {"name": str(law.parameters["name"])}))
        return ctx.curves.curve(law, at=(*at, "segments", where[id(law)], "curve"))

    with within(*at), np.errstate(all="ignore"):  # non-finite results are refused below
        return resolve_motion(program, build=build, limits=ctx.curves.size_limits())


# ----------------------------------------------------------------------------- computeMotion
def _rows(ctx: Context, body: MotionProgramRequest) -> tuple[int, Location]:
    """How many master angles, and which request field gives them (413 over the limit)."""
    rows = len(body.x_deg) if body.x_deg is not None else int(body.samples or 361)
    field: Location = ("x_deg",) if body.x_deg is not None else ("samples",)
    check_limit("motion samples", rows, ctx.settings.max_table_samples, field)
    return rows, field


def _work(ctx: Context, body: MotionProgramRequest, fmt: Format) -> WorkEstimate:
    """A program and its table: 413 first for too many segments, rows or a law over its size
    limit; then the laws to build (a fixed law repeated is built once), the solved parameters
    and the rows, encoded (or written as a cam table)."""
    if fmt.name in MOTION_FORMATS and body.x_deg is not None:
        raise InvalidParameterError("a cam table has a fixed master step: give samples (the step is "
                                    "period_deg / (samples − 1)), not x_deg.", field=("x_deg",))
    costs, solved = program_costs(ctx, body.motion.core())
    rows, field = _rows(ctx, body)
    speed = body.speed_rpm is not None and fmt.name not in MOTION_FORMATS
    columns = MOTION_TABLE_COLUMNS + (MOTION_TIME_COLUMNS if speed else 0)
    work = motion_work(costs, solved, rows, ("motion", "segments"), field)
    work += WorkEstimate((WorkTerm(field, f"encoding {rows} rows", encode_cost(rows * columns, fmt is not JSON)),))
    if fmt.name in MOTION_FORMATS:
        file = MOTION_FORMATS[fmt.name]
        work += WorkEstimate((WorkTerm(("samples",), f"writing {rows} rows as {fmt.name}", file.cost(rows)),))
    return work


def _check_finite_report(value: Any, where: str = "") -> None:
    """Refuse a report holding NaN or infinity (JSON has no such numbers)."""
    if isinstance(value, dict):
        for key, item in value.items():
            _check_finite_report(item, f"{where}.{key}" if where else str(key))
    elif isinstance(value, list):
        for i, item in enumerate(value):
            _check_finite_report(item, f"{where}[{i}]")
    elif isinstance(value, float) and not math.isfinite(value):
        raise NonFiniteResultError(f"the computation of '{where}' produced a non-finite number for these inputs; "
                                   "check that the program describes a realistic machine cycle.")


def _compute(ctx: Context, body: MotionProgramRequest, fmt: Format) -> Document | Payload:
    """The columns and the report (unit, period, segments, joins, characteristics); or the cam table."""
    rows, _field = _rows(ctx, body)
    program = resolve(ctx, body.motion.core())
    if fmt.name in MOTION_FORMATS:
        x = program.sample_angles(rows)
        s, v, a = program.derivatives(x, 2)
        return Payload(MOTION_FORMATS[fmt.name].write(CamTable(x, s, v, a, program.unit)))
    x = program.sample_angles(rows) if body.x_deg is None else np.asarray(body.x_deg, dtype=np.float64)
    with np.errstate(all="ignore"):
        columns = program.table(x, body.speed_rpm).columns()
        report = {"unit": program.unit, "period_deg": program.period_deg,
                  "segments": [as_dict(s) for s in program.segments],
                  "joins": [as_dict(j) for j in program.joins],
                  "characteristics": as_dict(program.characteristics)}
    _check_finite_report(report)
    return Document({**columns, **report}, table=columns)


def _examples_with_samples() -> Mapping[str, Any]:
    """The examples a cam table takes (a fixed step: no x_deg)."""
    return {name: example for name, example in MOTION_EXAMPLES.items() if "x_deg" not in (example.get("value") or {})}


OPERATIONS = (
    Operation("computeMotion", "/v1/motions", "motions", "Motion program (machine cycle)",
              "Columns x_deg, s, v, a, j (and per second with speed_rpm), the resolved segments, the joins with "
              "their continuity, and the characteristic values over the cycle; ``?format=csv``: the table; "
              "``?format=cam-table``: the servo drive's cam table.",
              MotionProgramRequest, _compute, estimate=_work, answer=MotionProgramAnswer, formats=FORMATS,
              examples=MOTION_EXAMPLES, format_examples={"cam-table": _examples_with_samples()},
              aliases=(Alias("computeMotionTableCsv", "/v1/motions/table.csv", "csv"),
                       Alias("exportMotionCamTable", "/v1/motions/cam-table.csv", "cam-table"))),
)
