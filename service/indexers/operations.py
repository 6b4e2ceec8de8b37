"""/v1/indexers: motion over the input angle, position lookup, torque and power sizing, the
indexing accuracy, and the chart of one index.

Every operation that takes an indexer builds it with :func:`indexer` (its curve from the curve
cache, or its timing chart resolved as every motion program is) and moves its input angles to
the spec's ``input_angle_origin`` with :func:`origin`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, TypeVar

import numpy as np
from pydantic import Field, ValidationError

import camcore
from camcore.errors import InvalidParameterError, NonMonotoneError
from camcore.indexer import Indexer, TimedIndexer
from camcore.results import as_dict
from camcore.work import (
    INDEXER_ROW_S,
    MOST_PIECES_OF_A_LAW,
    MOTION_COLUMNS,
    WorkEstimate,
    encode_cost,
    peaks_s,
    per_item_work,
    rms_s,
)
from service.context import Context
from service.curves.library import check_limit
from service.curves.operations import inverse_table_work
from service.curves.specs import NamedCurveSpec
from service.drawing import MAX_PLOT_SAMPLES, ChartQuery, chart_work
from service.errors import Location, query_error, relocate, within
from service.indexers.charts import indexer_chart
from service.indexers.specs import (
    MOTION_EXAMPLES,
    POSITION_EXAMPLES,
    SIZING_EXAMPLES,
    SMALLEST,
    AccuracyAnswer,
    IndexerShape,
    IndexerSpec,
    MotionAnswer,
    MotionRequest,
    PositionAnswer,
    PositionRequest,
    SizingAnswer,
    SizingRequest,
)
from service.motions.operations import program_work, resolve
from service.operations import JSON, PNG, SVG, Document, Format, Operation, Payload, Raw, Table, csv
from service.responses import JSONBody, check_finite
from service.specs import BIG, DeferredModel

T = TypeVar("T")

TAG = "indexers"
#: where a timing chart is in the request
TIMING = ("indexer", "timing")
CURVE = ("indexer", "curve")


# ----------------------------------------------------------------------------- any indexer
def indexer(ctx: Context, spec: IndexerShape, speed_rpm: float | None = None) -> Indexer | TimedIndexer:
    """The single-curve indexer, or the indexer of a timing chart; at ``speed_rpm`` when given (an indexer
    without its own speed: a machine's), else at the spec's speed or cycle time."""
    own_speed = getattr(spec, "speed_rpm", None) if speed_rpm is None else speed_rpm
    cycle_time = getattr(spec, "cycle_time_s", None) if speed_rpm is None else None
    if spec.timing is not None:
        program = resolve(ctx, spec.timing.core(), at=TIMING)
        with within(*TIMING):
            camcore.indexer.check_timing(program)
        with within("indexer"):
            return TimedIndexer(program=program, speed_rpm=own_speed, cycle_time_s=cycle_time,
                                input_stop_time_s=spec.input_stop_time_s)
    assert spec.indexing_angle_deg is not None  # the spec's rule without a timing chart
    curve = ctx.curves.curve(spec.curve.core(), at=CURVE)
    with within("indexer"):
        return Indexer(stops=spec.stops, swing_angle_deg=spec.swing_angle_deg, indexing_angle_deg=spec.indexing_angle_deg,
                       dwells=spec.dwells, speed_rpm=own_speed, cycle_time_s=cycle_time,
                       input_stop_time_s=spec.input_stop_time_s, curve=curve)


def origin(spec: IndexerSpec, unit: Any) -> Callable[[T], T]:
    """Moves a result's input angles to the spec's ``input_angle_origin``."""
    with within("indexer"):
        shift = camcore.indexer.origin_shift_deg(unit, spec.input_angle_origin)
    cycle = 360.0 / unit.dwells

    def move(result: T) -> T:
        return camcore.indexer.to_origin(result, shift, cycle)

    return move


def timing_work(ctx: Context, spec: IndexerShape, rows: int, rows_field: Location) -> WorkEstimate:
    """A timing chart resolved and evaluated at ``rows`` input angles."""
    assert spec.timing is not None
    return program_work(ctx, spec.timing.core(), rows, rows_field, at=TIMING)


# ----------------------------------------------------------------------------- motion
def _motion_work(ctx: Context, body: MotionRequest, fmt: Format) -> WorkEstimate:
    check_limit("table samples", body.samples, ctx.settings.max_table_samples, ("samples",))
    spec, samples = body.indexer, body.samples
    row = INDEXER_ROW_S + encode_cost(MOTION_COLUMNS, fmt.name == "csv")
    if spec.timing is not None:
        return timing_work(ctx, spec, samples, ("samples",)) + per_item_work(
            samples, row, ("samples",), f"{samples} table rows")
    law = spec.curve.core()
    cost = ctx.curves.cost(law, at=CURVE)
    return ctx.curves.build_work(law, cost, CURVE) + per_item_work(
        samples, cost.sample_s + row, ("samples",), f"{samples} table rows")


def motion(ctx: Context, spec: IndexerSpec, samples: int) -> tuple[dict[str, Any], dict[str, np.ndarray]]:
    """The summary and the table over one index."""
    check_limit("table samples", samples, ctx.settings.max_table_samples, ("samples",))
    unit = indexer(ctx, spec)
    result = unit.motion(samples)
    move = origin(spec, unit)
    return as_dict(move(result.summary)), move(result.table).columns()


def _motion(ctx: Context, body: MotionRequest, fmt: Format) -> Document:
    summary, table = motion(ctx, body.indexer, body.samples)
    return Document({"summary": summary, "table": table}, table=table)


# ----------------------------------------------------------------------------- positions
def _position_work(ctx: Context, body: PositionRequest, fmt: Format) -> WorkEstimate:
    angles = len(body.output_angle_deg)
    check_limit("number of output angles", angles, ctx.settings.max_inverse_points, ("output_angle_deg",))
    spec = body.indexer
    row = INDEXER_ROW_S + encode_cost(MOTION_COLUMNS, fmt.name == "csv")
    if spec.timing is not None:  # each position: a segment found, one inverse solved (≤ 2 law evaluations)
        return timing_work(ctx, spec, 3 * angles, ("output_angle_deg",)) + per_item_work(
            angles, row, ("output_angle_deg",), f"{angles} positions")
    law = spec.curve.core()
    cost = ctx.curves.cost(law, at=CURVE)
    return ctx.curves.build_work(law, cost, CURVE, inverse=body.method == "exact") + per_item_work(
        angles, 2 * cost.sample_s + row, ("output_angle_deg",), f"{angles} positions") + inverse_table_work(
        cost.sample_s, body.method, body.table_step)


def _position(ctx: Context, body: PositionRequest, fmt: Format) -> Table:
    check_limit("number of output angles", len(body.output_angle_deg), ctx.settings.max_inverse_points,
                ("output_angle_deg",))
    unit = indexer(ctx, body.indexer)
    angles = np.asarray(body.output_angle_deg, dtype=np.float64)
    if isinstance(unit, TimedIndexer):
        if body.method != "exact":
            raise InvalidParameterError("a timing chart's positions are solved exactly: the table method "
                                        "reproduces the catalog's single-curve tables (use method 'exact').",
                                        field=("method",))
        with within(*TIMING, only=NonMonotoneError):  # a segment's law cannot be inverted
            return Table(unit.position(angles).columns())
    with within(*CURVE, only=NonMonotoneError):  # the curve cannot be inverted
        result = unit.position(angles, method=body.method, table_step=body.table_step,
                               table_decimals=body.table_decimals)
    return Table(origin(body.indexer, unit)(result).columns())


# ----------------------------------------------------------------------------- sizing
def _sizing_kept(ctx: Context, body: SizingRequest, fmt: Format) -> Payload | None:
    """The same request again (a spreadsheet recalculating): its answer, on the event loop."""
    payload = ctx.sizings.get(body.cache_key())
    return None if payload is None else Payload(payload)


def _sizing_work(ctx: Context, body: SizingRequest, fmt: Format) -> WorkEstimate:
    """The curve, its characteristic values and the exact peaks (a few ms), or a timing chart's
    laws and peaks; the torque table's rows and the RMS integrals (one, or two with a motor), per
    moving segment."""
    return indexer_work(ctx, body.indexer, body.table_samples, body.motor is not None)


def indexer_work(ctx: Context, spec: IndexerShape, table_samples: int, motor: bool) -> WorkEstimate:
    """An indexer built and sized: its curve or chart, the exact peaks, ``table_samples`` torque rows per moving
    segment and the RMS integrals (two with a motor)."""
    if spec.timing is not None:
        laws = sum(1 for segment in spec.timing.segments if segment.type != "dwell")
        work = timing_work(ctx, spec, table_samples * laws, TIMING)
        pieces = MOST_PIECES_OF_A_LAW
    else:
        laws = 1
        law = spec.curve.core()
        cost = ctx.curves.cost(law, at=CURVE)
        pieces = max(len(law.parameters.get("t", ())), MOST_PIECES_OF_A_LAW)
        work = ctx.curves.build_work(law, cost, CURVE) + per_item_work(
            table_samples, INDEXER_ROW_S, ("table_samples",), f"{table_samples} torque rows") + \
            per_item_work(1, peaks_s(pieces, cost.sample_s), CURVE, "the exact torque peaks")
    integrals = laws * (2 if motor else 1)
    return work + per_item_work(integrals, rms_s(pieces), ("indexer",), f"{integrals} RMS integrals")


def sizing(ctx: Context, body: SizingRequest) -> dict[str, Any]:
    """The sizing figures (non-finite ones are refused when encoded)."""
    with within("load"):
        load = body.load.core()
    motor = None
    if body.motor is not None:
        with within("motor"):
            motor = body.motor.core()
    unit = indexer(ctx, body.indexer)
    with within("indexer"), np.errstate(all="ignore"):
        result = camcore.indexer.size(unit, load, accuracy_arc_seconds=body.load.accuracy_arc_seconds,
                                      accuracy_radius_mm=body.load.accuracy_radius_mm,
                                      internal_friction_torque_nm=body.indexer.internal_friction_torque_nm,
                                      motor=motor, table_samples=body.table_samples)
    return as_dict(origin(body.indexer, unit)(result))


def _sizing(ctx: Context, body: SizingRequest, fmt: Format) -> Payload:
    """The answer encoded once and kept for the same request."""
    result = sizing(ctx, body)
    check_finite({k: v for k, v in result.items() if isinstance(v, float)})
    encoded = bytes(JSONBody(result).body)
    return Payload(ctx.sizings.get_or_create(body.cache_key(), lambda: encoded))


# ----------------------------------------------------------------------------- accuracy
class AccuracyQuery(DeferredModel):
    arc_seconds: float = Field(ge=0, le=1e6, allow_inf_nan=False)
    radius_mm: float = Field(ge=0, le=1e7, allow_inf_nan=False)


def _accuracy(ctx: Context, q: AccuracyQuery, fmt: Format) -> Raw:
    return Raw({"arc_seconds": q.arc_seconds, "radius_mm": q.radius_mm,
                "accuracy_mm": float(camcore.indexer.accuracy_mm(q.arc_seconds, q.radius_mm))})


# ----------------------------------------------------------------------------- the chart
class IndexerPlotQuery(ChartQuery):
    """The fields of IndexerSpec, with the curve given by its catalog name."""

    stops: int | None = Field(None, ge=1, le=100_000, description="n, stops per output turn")
    # IndexerSpec's bounds (SMALLEST, BIG), which this query is checked against again: the document says what is kept
    swing_angle_deg: float | None = Field(None, ge=SMALLEST, le=360, allow_inf_nan=False,
                                          description="ψ, output swing (instead of stops)")
    indexing_angle_deg: float = Field(ge=SMALLEST, le=360, allow_inf_nan=False, description="θh, input angle per index")
    dwells: int = Field(1, ge=1, le=360, description="z, indexes per input turn")
    speed_rpm: float | None = Field(None, ge=SMALLEST, le=BIG, allow_inf_nan=False, description="N, input speed")
    cycle_time_s: float | None = Field(None, ge=SMALLEST, le=BIG, allow_inf_nan=False,
                                       description="t0, unit cycle time (instead of speed_rpm)")
    input_stop_time_s: float = Field(0.0, ge=0, le=1e6, allow_inf_nan=False)
    curve: str = Field("MS", min_length=1, max_length=80, description="catalog curve: id, alias or Makino number")
    samples: int = Field(401, ge=11, le=MAX_PLOT_SAMPLES)


def _plot_spec(q: IndexerPlotQuery) -> IndexerSpec:
    with within("curve", keep_field=False):
        camcore.lookup(q.curve)
    fields = q.model_dump(exclude={"dpi", "samples", "curve"})
    try:
        return IndexerSpec(**fields, curve=NamedCurveSpec(name=q.curve))
    except ValidationError as exc:
        raise query_error(exc) from None


def _plot(ctx: Context, q: IndexerPlotQuery, fmt: Format) -> Payload:
    spec = _plot_spec(q)
    with relocate(("indexer",), ()):  # the indexer's fields are the query's
        summary, table = motion(ctx, spec, q.samples)
    name = camcore.lookup(q.curve).id
    unit = f"{spec.stops} stops" if spec.stops is not None else f"swing {spec.swing_angle_deg:g}°"
    speed = f"{summary['speed_rpm']:g} rpm"
    title = f"Indexer: {unit}, θh = {spec.indexing_angle_deg:g}°, {speed}, curve {name}"
    return Payload(indexer_chart(table, summary, title, fmt.name, q.dpi))


OPERATIONS = (
    Operation("getIndexerMotion", "/v1/indexers/motion", TAG, "Indexer output motion over one index",
              "Summary (times, exact peaks) and the output motion over one index (CSV: the table).",
              MotionRequest, _motion, estimate=_motion_work, answer=MotionAnswer, formats=(JSON, csv("motion.csv")),
              examples=MOTION_EXAMPLES),
    Operation("getIndexerPosition", "/v1/indexers/position", TAG, "Indexer position lookup",
              "For each output angle: input angle, time, ω and α (exact, or the catalog's table method).",
              PositionRequest, _position, estimate=_position_work, answer=PositionAnswer,
              formats=(JSON, csv("position.csv")), examples=POSITION_EXAMPLES),
    Operation("sizeIndexer", "/v1/indexers/sizing", TAG, "Indexer torque and power sizing",
              "Inertia, friction and work torque, output and input torque, input power.",
              SizingRequest, _sizing, estimate=_sizing_work, cached=_sizing_kept, answer=SizingAnswer,
              examples=SIZING_EXAMPLES),
    Operation("convertIndexingAccuracy", "/v1/indexers/accuracy", TAG, "Indexing accuracy in millimetres",
              "Arc-seconds at a radius → millimetres: x = 2π·r·θ/(360·3600) (guide, 计算分度精度).",
              AccuracyQuery, _accuracy, method="GET", answer=AccuracyAnswer,
              examples={"guide": {"value": {"arc_seconds": 30, "radius_mm": 200}}}),
    Operation("plotIndexerMotion", "/v1/indexers/plot", TAG, "Indexer motion chart",
              "Output angle, ω, α and jerk over the input angle of one index (fields of IndexerSpec).",
              IndexerPlotQuery, _plot, estimate=lambda ctx, q, fmt: chart_work(fmt.name, q.dpi), formats=(SVG, PNG),
              method="GET", examples={"guide": {"value": {"stops": 6, "indexing_angle_deg": 270, "speed_rpm": 60,
                                                          "samples": 101}}}),
)
