"""/v1/curves: the catalog, characteristic values, tables, inverse lookups, one value for a
spreadsheet cell, and the S-V-A-J chart of a catalog curve.

Tables answer JSON, or CSV (``?format=csv``, ``Accept: text/csv`` or the ``.csv`` twin). A
cached table, or a small one on a curve already built, is answered on the event loop; other
work goes through the gate; a large table is streamed.
"""

from __future__ import annotations

from collections.abc import Mapping
from contextlib import AbstractContextManager
from dataclasses import dataclass
from typing import Annotated, Any, Literal

import numpy as np
from fastapi import Path
from fastapi.exceptions import RequestValidationError
from pydantic import Field

import camcore
from camcore.curves import Law
from camcore.errors import NonMonotoneError
from camcore.results import as_dict
from camcore.work import INVERSE_COLUMNS, TABLE_COLUMNS, WorkEstimate, encode_cost, per_item_work
from service.context import Context
from service.curves.charts import svaj_chart
from service.curves.library import check_limit
from service.curves.specs import (
    CHARACTERISTICS_EXAMPLES,
    INVERSE_EXAMPLES,
    QM_CONVENTIONS,
    TABLE_EXAMPLES,
    CatalogAnswer,
    CatalogEntryAnswer,
    CharacteristicsRequest,
    CurveCharacteristicsAnswer,
    CurveTable,
    InverseRequest,
    InverseTable,
    TableRequest,
    solved_parameters,
)
from service.drawing import MAX_PLOT_SAMPLES, ChartQuery, chart_work
from service.errors import Location, relocate, within
from service.operations import JSON, PNG, SVG, TEXT, Format, Operation, Payload, Raw, Table, Text, csv
from service.responses import encode_table, encode_value
from service.specs import DeferredModel, Direction, QueryNumbers

#: rows of a table worth a thread-pool hop: below this, on a curve already built, the work
#: (0.07 ms for 101 rows of MS, ~1 ms for 1001 rows of a degree-20 Bezier) costs less than
#: the hop does under load, and with the GIL a thread would not run beside the loop anyway
QUICK_TABLE_ROWS = 1_001

CurveName = Annotated[str, Path(min_length=1, max_length=80, description="id, alias or Makino number")]
NAME = {"name": CurveName}
TAG = "curves"
CSV = csv()


def _named(name: str, direction: str = "rise") -> Law:
    """A catalog curve's law (a GET's curve is its path's name)."""
    return Law("named", {"name": name}, direction)


def _path_is_the_curve() -> AbstractContextManager[None]:
    return relocate(("curve",), ("path",))


# ----------------------------------------------------------------------------- the catalog
def catalog_entry(entry: camcore.CatalogEntry) -> dict[str, Any]:
    return {"id": entry.id, "aliases": list(entry.aliases), "name": entry.name, "family": entry.family,
            "source": entry.source, "makino_number": entry.makino_number, "parameters": entry.parameters,
            "characteristics": as_dict(entry.build().characteristics)}


def _catalog(ctx: Context, _: None, fmt: Format) -> Raw:
    return Raw({"curves": [catalog_entry(e) for e in camcore.CATALOG.values()], "conventions": QM_CONVENTIONS})


def _entry(ctx: Context, name: str, fmt: Format) -> Raw:
    with within("path"):
        return Raw(catalog_entry(camcore.lookup(name)))


# ----------------------------------------------------------------------------- characteristics
def _characteristics_work(ctx: Context, law: Law, fmt: Format) -> WorkEstimate:
    """The curve built with its characteristic values (no inverse tables), or nothing when cached."""
    return ctx.curves.build_work(law, ctx.curves.cost(law), ("curve",), values_only=True)


def _is_built(ctx: Context, law: Law, fmt: Format) -> bool:
    return ctx.curves.built(law) is not None


def _characteristics(ctx: Context, law: Law, fmt: Format) -> Raw:
    answer = as_dict(ctx.curves.curve(law).characteristics)
    if law.kind == "makino":  # the parameters as built, those solved from a target among them
        answer["parameters"] = solved_parameters(law.parameters)
    return Raw(answer)


# ----------------------------------------------------------------------------- tables
@dataclass(frozen=True)
class Sampling:
    """A table of a law: ``samples`` evenly over [T0, T7], or at the times ``t``."""

    law: Law
    samples: int | None = None
    t: list[float] | None = None

    @property
    def rows(self) -> tuple[int, Location]:
        return (self.samples, ("samples",)) if self.t is None else (len(self.t), ("t",))  # type: ignore[return-value]


def _table_request(ctx: Context, body: TableRequest, path: Mapping[str, str]) -> Sampling:
    return Sampling(body.curve.core(), body.samples, body.t)


def _cached_table(ctx: Context, job: Sampling, fmt: Format) -> Payload | None:
    """A sampled table's encoded body from the cache (it passed every limit when it was cached)."""
    if job.samples is None or job.samples > ctx.settings.table_cache_max_rows:
        return None
    payload = ctx.curves.tables.get((ctx.curves.key(job.law), job.samples, fmt.name == "csv"))
    return None if payload is None else Payload(payload)


def _table_work(ctx: Context, job: Sampling, fmt: Format) -> WorkEstimate:
    """The curve, evaluated and encoded at each row; over the row limit: 413 first."""
    rows, field = job.rows
    cost = ctx.curves.cost(job.law)
    check_limit("table samples" if job.t is None else "number of times t", rows, ctx.settings.max_table_samples, field)
    return ctx.curves.build_work(job.law, cost, ("curve",)) + per_item_work(
        rows, cost.sample_s + encode_cost(TABLE_COLUMNS, fmt.name == "csv"), field, f"{rows} table rows")


def _quick_table(ctx: Context, job: Sampling, fmt: Format) -> bool:
    """Few rows on a curve already built: less work than a thread hop (a large table, never)."""
    rows, _ = job.rows
    if job.t is None and rows > ctx.settings.table_cache_max_rows:
        return False
    return rows <= QUICK_TABLE_ROWS and ctx.curves.built(job.law) is not None


def table_columns(ctx: Context, job: Sampling) -> dict[str, np.ndarray]:
    curve = ctx.curves.curve(job.law)
    rows, field = job.rows
    check_limit("table samples" if job.t is None else "number of times t", rows, ctx.settings.max_table_samples, field)
    times = curve.sample_times(rows) if job.t is None else np.asarray(job.t, dtype=np.float64)
    return curve.evaluate(times).columns()


def _table(ctx: Context, job: Sampling, fmt: Format) -> Table | Payload:
    """The table; a sampled one up to table_cache_max_rows encoded once and cached."""
    if job.samples is None or job.samples > ctx.settings.table_cache_max_rows:
        return Table(table_columns(ctx, job))
    csv_answer = fmt.name == "csv"
    key = (ctx.curves.key(job.law), job.samples, csv_answer)
    return Payload(ctx.curves.tables.get_or_create(key, lambda: encode_table(table_columns(ctx, job), csv_answer)))


class NamedTableQuery(DeferredModel):
    samples: int = Field(101, ge=2)
    direction: Direction = "rise"


def _named_table(ctx: Context, query: NamedTableQuery, path: Mapping[str, str]) -> Sampling:
    return Sampling(_named(path["name"], query.direction), query.samples)


# ----------------------------------------------------------------------------- inverses
@dataclass(frozen=True)
class Inversion:
    """T (and V, A) where S(T) = s, for each s: exact, or the catalog's table method."""

    law: Law
    s: list[float]
    method: str = "exact"
    table_step: float = 0.01
    table_decimals: int | None = None


def _inverse_request(ctx: Context, body: InverseRequest, path: Mapping[str, str]) -> Inversion:
    return Inversion(body.curve.core(), body.s, body.method, body.table_step, body.table_decimals)


def inverse_table_work(sample_s: float, method: str, table_step: float) -> WorkEstimate:
    """The catalog's table method samples a table at ``table_step`` first; exact: nothing."""
    if method != "table":
        return WorkEstimate()
    rows = int(1.0 / table_step) + 1
    return per_item_work(rows, sample_s, ("table_step",), f"an inverse table of {rows} rows")


def _inverse_work(ctx: Context, job: Inversion, fmt: Format) -> WorkEstimate:
    """The curve (with its inverse's start tables), each lookup encoded, the table method's table."""
    values = len(job.s)
    check_limit("number of s values", values, ctx.settings.max_inverse_points, ("s",))
    cost = ctx.curves.cost(job.law)
    work = ctx.curves.build_work(job.law, cost, ("curve",), inverse=job.method == "exact") + per_item_work(
        values, 2 * cost.sample_s + encode_cost(INVERSE_COLUMNS, fmt.name == "csv"), ("s",),
        f"{values} inverse lookups")
    return work + inverse_table_work(cost.sample_s, job.method, job.table_step)


def is_quick_inverse(ctx: Context, law: Law, values: int, method: str) -> bool:
    """Exact, for few values, on a built curve whose inverse has its start table (the catalog's
    table method builds a table each time)."""
    if method != "exact" or values > QUICK_TABLE_ROWS:
        return False
    curve = ctx.curves.built(law)
    return curve is not None and curve.inverse_ready


def inverse_columns(ctx: Context, job: Inversion) -> dict[str, np.ndarray]:
    check_limit("number of s values", len(job.s), ctx.settings.max_inverse_points, ("s",))
    curve = ctx.curves.curve(job.law)
    s = np.asarray(job.s, dtype=np.float64)
    if job.method == "table":
        span = curve.t_end - curve.t_start
        check_limit("inverse table rows", int(span / job.table_step) + 1, ctx.settings.max_table_samples,
                    ("table_step",))
        with within("curve", only=NonMonotoneError):  # the curve cannot be inverted
            vals = curve.inverse_table(s, job.table_step, job.table_decimals)
        return {"s": s, "t": vals.t, "v": vals.v, "a": vals.a}
    grows = not curve.inverse_ready
    with within("curve", only=NonMonotoneError):
        t, v, a = curve.inverse_with_rates(s)
    if grows:  # the curve now holds its inverse's start tables: count them in the cache's bytes
        ctx.curves.remeasure(job.law)
    return {"s": s, "t": t, "v": v, "a": a}


def _inverse(ctx: Context, job: Inversion, fmt: Format) -> Table:
    return Table(inverse_columns(ctx, job))


def _quick_inverse(ctx: Context, job: Inversion, fmt: Format) -> bool:
    return is_quick_inverse(ctx, job.law, len(job.s), job.method)


class NamedInverseQuery(DeferredModel):
    s: QueryNumbers = Field(min_length=1, description="S values: repeat ?s= or separate by commas")
    method: Literal["exact", "table"] = "exact"
    table_step: float = Field(0.01, ge=1e-4, le=0.5)
    table_decimals: int | None = Field(None, ge=0, le=15)
    direction: Direction = "rise"


def _named_inverse(ctx: Context, query: NamedInverseQuery, path: Mapping[str, str]) -> Inversion:
    return Inversion(_named(path["name"], query.direction), query.s, query.method, query.table_step,
                     query.table_decimals)


# ----------------------------------------------------------------------------- one value
class ValueQuery(DeferredModel):
    t: float | None = Field(None, allow_inf_nan=False, description="time T; answers quantity at T")
    s: float | None = Field(None, allow_inf_nan=False, description="displacement S; answers T of the exact inverse")
    quantity: Literal["t", "s", "v", "a", "j", "q"] | None = Field(
        None, description="with t: s (default), v, a, j or q; with s: t")
    direction: Direction = "rise"


@dataclass(frozen=True)
class Value:
    law: Law
    quantity: str
    t: float | None
    s: float | None


def _value_request(ctx: Context, query: ValueQuery, path: Mapping[str, str]) -> Value:
    """The quantity a /value query asks for; t or s, not both, and a quantity that fits."""
    def invalid(field: str, msg: str) -> RequestValidationError:
        return RequestValidationError([{"type": "value_error", "loc": ("query", field), "msg": msg}])

    t, s, quantity = query.t, query.s, query.quantity
    if t is not None and s is not None:
        raise invalid("s", "give t (a time, for s, v, a, j or q) or s (a displacement, for its t), not both")
    if t is None and s is None:
        raise invalid("t", "give t (a time, e.g. ?t=0.3) or s (a displacement, e.g. ?s=0.1833)")
    if s is not None:
        if quantity not in (None, "t"):
            raise invalid("quantity", f"with s the answer is the time t of the exact inverse, not {quantity}")
        what = "t"
    elif quantity == "t":
        raise invalid("quantity", "with t the quantity is one of s, v, a, j, q (to find t, give s)")
    else:
        what = quantity or "s"
    return Value(_named(path["name"], query.direction), what, t, s)


def _value_work(ctx: Context, job: Value, fmt: Format) -> WorkEstimate:
    return ctx.curves.work(job.law)


def _quick_value(ctx: Context, job: Value, fmt: Format) -> bool:
    if job.s is not None:
        return is_quick_inverse(ctx, job.law, 1, "exact")
    return ctx.curves.built(job.law) is not None  # one row: quick once the curve is built


def _value(ctx: Context, job: Value, fmt: Format) -> Text:
    """``quantity`` (s, v, a, j, q) at the time t, as in a table; or, given s, the T of the exact inverse."""
    if job.s is not None:
        number = ctx.curves.curve(job.law).inverse(np.array([job.s]))[0]
    else:
        assert job.t is not None
        number = table_columns(ctx, Sampling(job.law, t=[job.t]))[job.quantity][0]
    return Text(encode_value(job.quantity, float(number)))


# ----------------------------------------------------------------------------- the chart
class CurvePlotQuery(ChartQuery):
    direction: Literal["rise", "return"] = "rise"
    samples: int = Field(401, ge=11, le=MAX_PLOT_SAMPLES, description="points per trace")


@dataclass(frozen=True)
class CurvePlot:
    name: str
    query: CurvePlotQuery


def _plot_request(ctx: Context, query: CurvePlotQuery, path: Mapping[str, str]) -> CurvePlot:
    return CurvePlot(path["name"], query)


def _plot_work(ctx: Context, job: CurvePlot, fmt: Format) -> WorkEstimate:
    return chart_work(fmt.name, job.query.dpi)


def _plot(ctx: Context, job: CurvePlot, fmt: Format) -> Payload:
    q = job.query
    with within("path"):
        entry = camcore.lookup(job.name)
    curve = ctx.curves.curve(Law("named", {"name": entry.id}, q.direction))
    values = curve.evaluate(curve.sample_times(q.samples))
    title = f"{entry.id} — {entry.name}" + (" (return)" if q.direction == "return" else "")
    return Payload(svaj_chart(values, curve.characteristics, title, fmt.name, q.dpi))


# ----------------------------------------------------------------------------- the operations
_TABLE_ANSWER = "Columns t, s, v, a, j, q at evenly spaced samples or at given times."
OPERATIONS = (
    Operation("listCurves", "/v1/curves", TAG, "Catalog of named curves",
              "The catalog: every named curve with its aliases, source and characteristic values.",
              None, _catalog, method="GET", answer=CatalogAnswer, examples={"catalog": {"value": {}}}),
    Operation("getCurve", "/v1/curves/{name}", TAG, "One catalog curve",
              "One catalog entry, by id, alias or Makino number (case-insensitive).",
              None, _entry, convert=lambda ctx, _, path: path["name"], method="GET", path_parameters=NAME,
              answer=CatalogEntryAnswer, examples={"MS": {"value": {"name": "MS"}}}),
    Operation("getCurveCharacteristics", "/v1/curves/characteristics", TAG, "Characteristic values of a curve",
              "Vm, Am±, Jm±, Qm± (and raw A·V extremes) with the T where each occurs.",
              CharacteristicsRequest, _characteristics, convert=lambda ctx, body, path: body.curve.core(),
              estimate=_characteristics_work, quick=_is_built, answer=CurveCharacteristicsAnswer,
              examples=CHARACTERISTICS_EXAMPLES),
    Operation("sampleCurve", "/v1/curves/table", TAG, "Curve table (S, V, A, J, Q over T)", _TABLE_ANSWER,
              TableRequest, _table, convert=_table_request, estimate=_table_work, quick=_quick_table,
              cached=_cached_table, answer=CurveTable, formats=(JSON, CSV), examples=TABLE_EXAMPLES),
    Operation("sampleNamedCurve", "/v1/curves/{name}/table", TAG, "Catalog curve table",
              "The table of a catalog curve, for spreadsheets (``?format=csv``).",
              NamedTableQuery, _table, convert=_named_table, estimate=_table_work, quick=_quick_table,
              cached=_cached_table, answer=CurveTable, formats=(JSON, CSV), method="GET", path_parameters=NAME,
              located=_path_is_the_curve, examples={"MS": {"value": {"name": "MS", "samples": 11}}}),
    Operation("invertCurve", "/v1/curves/inverse", TAG, "Inverse lookup (T where S = s)",
              "T (and V, A) where S(T) = s: exact, or the catalog's table interpolation.",
              InverseRequest, _inverse, convert=_inverse_request, estimate=_inverse_work, quick=_quick_inverse,
              answer=InverseTable, formats=(JSON, CSV), examples=INVERSE_EXAMPLES),
    Operation("invertNamedCurve", "/v1/curves/{name}/inverse", TAG, "Inverse lookup on a catalog curve",
              "The inverse lookup of a catalog curve, for spreadsheets (``?s=0.1833&format=csv``).",
              NamedInverseQuery, _inverse, convert=_named_inverse, estimate=_inverse_work, quick=_quick_inverse,
              answer=InverseTable, formats=(JSON, CSV), method="GET", path_parameters=NAME,
              located=_path_is_the_curve, examples={"guide": {"value": {"name": "MS", "s": "0.1833,0.5"}}}),
    Operation("getCurveValue", "/v1/curves/{name}/value", TAG, "One value of a catalog curve (spreadsheet cell)",
              "One number for a spreadsheet cell (``=WEBSERVICE(...)``): S, V, A, J or Q at T, or T where S = s "
              "(exact inverse), as ``text/plain``; errors are JSON as everywhere.",
              ValueQuery, _value, convert=_value_request, estimate=_value_work, quick=_quick_value, formats=(TEXT,),
              method="GET", path_parameters=NAME, located=_path_is_the_curve,
              examples={"S at T = 0.3": {"value": {"name": "MS", "t": 0.3}},
                        "T where S = 0.1833": {"value": {"name": "MS", "s": 0.1833}}}),
    Operation("plotCurve", "/v1/curves/{name}/plot", TAG, "Catalog curve chart (S, V, A, J)",
              "S, V, A, J of a catalog curve over T, characteristic values marked (``?format=png`` for PNG).",
              CurvePlotQuery, _plot, convert=_plot_request, estimate=_plot_work, formats=(SVG, PNG), method="GET",
              path_parameters=NAME, examples={"MS": {"value": {"name": "MS", "samples": 101}}}),
)
