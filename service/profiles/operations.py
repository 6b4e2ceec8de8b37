"""/v1/profiles: plate-cam contours with checks, their files (the contour as DXF, X Y Z or CSV; the
solid as STEP or STL), base-circle sizing and the profile chart.

Every operation that takes a cam (these, the toolpath, the follower's dynamics) builds it with
:func:`cam` and counts its curves with :func:`schedule_work`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from fastapi.exceptions import RequestValidationError
from fastapi.openapi.models import Example
from pydantic import Field, ValidationError

import camcore
from camcore import export
from camcore.curves.kinds import LawCost
from camcore.errors import InvalidParameterError
from camcore.export import FORMATS, SOLID_FORMATS, SolidCam
from camcore.profile import CamSpec, ProfileResult
from camcore.results import as_dict
from camcore.work import (
    PROFILE_COLUMNS,
    WorkEstimate,
    WorkTerm,
    base_circle_work,
    encode_cost,
    fit_elements_estimate,
    fit_work,
    motion_work,
    profile_work,
)
from service.context import Context
from service.curves.library import check_limit
from service.curves.specs import NamedCurveSpec
from service.drawing import MAX_PLOT_SAMPLES, ChartQuery, chart_work
from service.errors import Location, query_error, relocate, within
from service.motions.operations import program_costs, resolve
from service.operations import JSON, PNG, SVG, Alias, Document, Format, Operation, Payload, Raw, csv, download
from service.profiles.charts import profile_chart
from service.profiles.specs import (
    BASE_CIRCLE_EXAMPLES,
    PROFILE_EXAMPLES,
    PROFILE_REQUEST_RULES,
    ROLLER_PROFILE_EXAMPLE,
    BaseCircleAnswer,
    BaseCircleRequest,
    FollowerSpec,
    ProfileAnswer,
    ProfileRequest,
    ProfileSpec,
    SegmentSpec,
    SolidSpec,
)
from service.specs import examples

TAG = "profiles"
#: columns where an infinite value is meaningful (a straight stretch of surface) and is
#: answered as null (JSON has no infinity)
UNBOUNDED_COLUMNS = ("radius_of_curvature_mm", "pitch_radius_of_curvature_mm")
TABLE = csv("profile.csv", "the table as CSV (null radius = an empty cell: a straight stretch)")
CONTOURS = tuple(download(fmt) for fmt in FORMATS.values())
SOLIDS = tuple(download(fmt) for fmt in SOLID_FORMATS.values())


# ----------------------------------------------------------------------------- any cam
def schedule_field(spec: ProfileSpec) -> Location:
    """The request field of the lift schedule: its segments, its one lift curve or its program's segments."""
    if spec.motion is not None:
        return ("profile", "motion", "segments")
    return ("profile", "segments") if spec.segments is not None else ("profile", "lift")


def schedule_work(ctx: Context, spec: ProfileSpec) -> tuple[list[LawCost | None], WorkEstimate]:
    """Each segment's law cost, and the work of building the distinct curves (a spec repeated in
    several segments is built once: the curve cache); a motion program's laws, with its solved
    parameters."""
    costs: list[LawCost | None] = []
    if spec.motion is not None:
        costs, solved = program_costs(ctx, spec.motion.core(), at=("profile", "motion"))
        # the program resolved (no rows: the profile's samples are counted apart)
        return costs, motion_work(costs, solved, 0, ("profile", "motion", "segments"), ("samples",))
    if spec.segments is None:
        assert spec.lift is not None
        law = spec.lift.core()
        cost = ctx.curves.cost(law, at=("profile", "lift"))
        return [cost], ctx.curves.build_work(law, cost, ("profile", "lift"))
    built = WorkEstimate()
    seen = set()
    for i, segment in enumerate(spec.segments):
        if segment.curve is None:
            costs.append(None)
            continue
        at = ("profile", "segments", i, "curve")
        law = segment.curve.core()
        cost = ctx.curves.cost(law, at=at)
        costs.append(cost)
        key = ctx.curves.key(law)
        if key not in seen:
            seen.add(key)
            built += ctx.curves.build_work(law, cost, at)
    return costs, built


def cam(ctx: Context, spec: ProfileSpec, base_radius_mm: float | None = None) -> CamSpec:
    """The cam of a profile spec, its curves from the curve cache."""
    follower = spec.follower.core()
    radius = spec.base_radius_mm if base_radius_mm is None else base_radius_mm
    options: dict[str, Any] = {"rotation": spec.rotation, "rotation_ratio": spec.rotation_ratio}
    if spec.segments is not None:
        segments = []
        for i, s in enumerate(spec.segments):
            law = None if s.curve is None else ctx.curves.curve(s.curve.core(), at=("profile", "segments", i, "curve"))
            with within("profile", "segments", i):
                segments.append(camcore.profile.Segment(type=s.type, angle_deg=s.angle_deg, lift_mm=s.lift_mm or 0.0,
                                                        swing_deg=s.swing_deg, curve=law))
        options["segments"] = segments
    elif spec.motion is not None:
        options["motion"] = resolve(ctx, spec.motion.core(), at=("profile", "motion"))
    else:
        assert spec.lift is not None
        options["lift_curve"] = ctx.curves.curve(spec.lift.core(), at=("profile", "lift"))
    with within("profile"):
        return camcore.profile.make_cam(follower, radius, **options)


def samples_of(ctx: Context, samples: int | None, cam_angle_deg: list[float] | None) -> tuple[int, Location]:
    """How many cam angles, and which request field gives them (413 over the limit)."""
    n = len(cam_angle_deg) if cam_angle_deg is not None else int(samples or 361)
    field: Location = ("cam_angle_deg",) if cam_angle_deg is not None else ("samples",)
    check_limit("profile samples", n, ctx.settings.max_table_samples, field)
    return n, field


def profile_answer_work(ctx: Context, spec: ProfileSpec, samples: int | None, cam_angle_deg: list[float] | None,
                        answer: str) -> WorkEstimate:
    """A profile and its answer (``answer``: json, csv or a contour format of camcore.export.FORMATS)."""
    n, field = samples_of(ctx, samples, cam_angle_deg)
    costs, work = schedule_work(ctx, spec)
    work += profile_work(costs, n, schedule_field(spec), field)
    if answer in FORMATS:
        return work + WorkEstimate((WorkTerm(field, f"writing {n} points as {answer}", FORMATS[answer].cost(n)),))
    return work + WorkEstimate((WorkTerm(field, f"encoding {n} rows", encode_cost(n * PROFILE_COLUMNS,
                                                                                     answer == "csv")),))


def profile(ctx: Context, spec: ProfileSpec, samples: int | None, cam_angle_deg: list[float] | None) -> ProfileResult:
    """The profile at the cam angles; its checks over the turn kept by the cam's spec."""
    n, _field = samples_of(ctx, samples, cam_angle_deg)
    the_cam = cam(ctx, spec)
    with within("profile"):
        checks = ctx.profile_checks.get_or_create(spec.cache_key(), lambda: camcore.profile.profile_checks(the_cam))
        if cam_angle_deg is not None:
            return camcore.profile.compute_profile(the_cam, np.asarray(cam_angle_deg, dtype=np.float64), checks)
        return camcore.profile.sample_profile(the_cam, n, checks)


def columns(result: ProfileResult) -> dict[str, Any]:
    """The profile's columns, the radius columns NaN (null) where the surface is straight."""
    cols: dict[str, Any] = dict(result.columns())
    cols["pitch_radius_of_curvature_mm"] = result.pitch_radius_of_curvature_mm
    for name in UNBOUNDED_COLUMNS:
        col = np.asarray(cols[name], dtype=np.float64)
        # ±inf (straight surface) and nan become null in JSON; orjson writes NaN as null
        cols[name] = np.where(np.isfinite(col), col, np.nan)
    return cols


# ----------------------------------------------------------------------------- fitted contours
def strokes_mm(spec: ProfileSpec) -> list[float]:
    """The stroke of each moving segment in mm (a swing as the arc of the arm, or of the
    pivot distance for a flat face); a lift curve counts as 8 strokes of the base radius, a
    motion program's move as one (its strokes may be solved, so unknown before it runs)."""
    if spec.motion is not None:
        return [spec.base_radius_mm for s in spec.motion.segments if s.type != "dwell"]
    if spec.segments is None:
        return [spec.base_radius_mm] * 8
    arm = spec.follower.arm_length_mm or spec.follower.pivot_distance_mm or 1.0
    return [s.lift_mm if s.lift_mm is not None else arm * math.radians(s.swing_deg or 0.0)
            for s in spec.segments if s.type != "dwell"]


def segment_count(spec: ProfileSpec) -> int:
    """The lift schedule's segment count (a lift curve: 8)."""
    if spec.motion is not None:
        return len(spec.motion.segments)
    return len(spec.segments) if spec.segments is not None else 8


# ----------------------------------------------------------------------------- computeProfile
def _solid(body: ProfileRequest, fmt: Format) -> SolidSpec:
    if body.solid is None:
        raise InvalidParameterError(f"format {fmt.name} is a solid: give solid {{thickness_mm, bore_diameter_mm}}.",
                                    field=("solid",))
    return body.solid


def _work(ctx: Context, body: ProfileRequest, fmt: Format) -> WorkEstimate:
    """The profile and its answer; a solid: the contour's fit (at half the tolerance for an STL)
    and the CAD kernel's work (422 first when the body has no ``solid``)."""
    if fmt.name not in SOLID_FORMATS:
        return profile_answer_work(ctx, body.profile, body.samples, body.cam_angle_deg, fmt.name)
    solid = _solid(body, fmt)
    costs, work = schedule_work(ctx, body.profile)
    tolerance = solid.tolerance_mm / (2 if fmt.name == "stl" else 1)
    elements = fit_elements_estimate(strokes_mm(body.profile), segment_count(body.profile), tolerance)
    work += fit_work(costs, elements, 1, schedule_field(body.profile), ("solid", "tolerance_mm"))
    return work + WorkEstimate((WorkTerm(("solid", "tolerance_mm"), f"the {fmt.name} solid of about {elements} edges",
                                         SOLID_FORMATS[fmt.name].cost(elements)),))


def _warmup(ctx: Context, fmt: Format) -> None:
    # the CAD kernel's process starts (~1.5 s, the kernel's load) on the first solid after it was
    # retired, outside the request's budget and deadline: it is start-up, and starting it with the
    # worker would hold its memory in every worker that makes no solid (service/cad_pool.py)
    if fmt.name in SOLID_FORMATS:
        ctx.cad.warm()


def _compute(ctx: Context, body: ProfileRequest, fmt: Format) -> Document | Payload:
    spec = body.profile
    if fmt.name in SOLID_FORMATS:
        solid = _solid(body, fmt)
        item = SolidCam(cam(ctx, spec), solid.thickness_mm, solid.bore_diameter_mm, solid.tolerance_mm,
                        ctx.settings.max_toolpath_elements, ctx.settings.max_stl_triangles)
        return Payload(ctx.cad.write(fmt.name, item))  # in the CAD kernel's process
    result = profile(ctx, spec, body.samples, body.cam_angle_deg)
    if fmt.name in FORMATS:
        contour = export.Contour(result.x_mm, result.y_mm, result.cam_angle_deg, spec.base_radius_mm)
        return Payload(FORMATS[fmt.name].write(contour))
    table = columns(result)
    return Document({**table, "checks": as_dict(result.checks)}, table=table, allow_null=UNBOUNDED_COLUMNS)


SOLID_EXAMPLE: dict[str, object] = {"thickness_mm": 12, "bore_diameter_mm": 20, "tolerance_mm": 0.01}


class SolidRequest(ProfileRequest):
    """A profile request whose ``solid`` is required (the solid operations)."""

    # its own examples, and the rules it inherits with ProfileRequest's validator
    model_config = examples({"profile": ROLLER_PROFILE_EXAMPLE, "solid": SOLID_EXAMPLE}, rules=PROFILE_REQUEST_RULES)
    solid: SolidSpec = Field(description="thickness, bore and tolerance of the solid")


SOLID_EXAMPLES: dict[str, Example] = {"roller": {"summary": "the roller-follower cam, 12 mm thick with a 20 mm bore, within 0.01 mm",
                             "value": {"profile": ROLLER_PROFILE_EXAMPLE, "solid": SOLID_EXAMPLE}}}


# ----------------------------------------------------------------------------- base circle
def _base_circle_work(ctx: Context, body: BaseCircleRequest, fmt: Format) -> WorkEstimate:
    """One solve per limit (a flat-faced follower always solves the curvature, for convexity, and
    has no pressure angle)."""
    flat = body.profile.follower.type == "flat-faced"
    limits = int(body.max_pressure_angle_deg is not None and not flat) + int(
        body.min_radius_of_curvature_mm is not None or flat)
    costs, work = schedule_work(ctx, body.profile)
    return work + base_circle_work(costs, limits, schedule_field(body.profile))


def _base_circle(ctx: Context, body: BaseCircleRequest, fmt: Format) -> Raw:
    result = camcore.profile.size_base_circle(cam(ctx, body.profile), body.max_pressure_angle_deg,
                                              body.min_radius_of_curvature_mm)
    return Raw(as_dict(result))


# ----------------------------------------------------------------------------- the chart
class ProfilePlotQuery(ChartQuery):
    """A simple lift schedule: rise, dwell, return, and a dwell to 360° at the base circle."""

    follower: Literal["knife-edge", "roller", "flat-faced"] = "roller"
    motion: Literal["translating", "oscillating"] = "translating"
    base_radius_mm: float = Field(40.0, gt=0, le=1e5, allow_inf_nan=False)
    roller_radius_mm: float = Field(10.0, ge=0, le=1e5, allow_inf_nan=False,
                                    description="roller follower only (ignored otherwise)")
    offset_mm: float = Field(0.0, ge=-1e5, le=1e5, allow_inf_nan=False)
    arm_length_mm: float | None = Field(None, gt=0, le=1e5, allow_inf_nan=False, description="oscillating")
    pivot_distance_mm: float | None = Field(None, gt=0, le=1e5, allow_inf_nan=False, description="oscillating")
    rise_deg: float = Field(120.0, gt=0, le=360, allow_inf_nan=False)
    dwell_deg: float = Field(60.0, ge=0, le=360, allow_inf_nan=False, description="dwell at full lift")
    return_deg: float = Field(120.0, gt=0, le=360, allow_inf_nan=False)
    lift_mm: float | None = Field(20.0, ge=0, le=1e5, allow_inf_nan=False, description="translating")
    swing_deg: float | None = Field(None, ge=0, le=180, allow_inf_nan=False, description="oscillating")
    curve: str = Field("cycloid", min_length=1, max_length=80, description="catalog curve of rise and return")
    rotation: Literal["ccw", "cw"] = "ccw"
    samples: int = Field(721, ge=11, le=MAX_PLOT_SAMPLES)


def plot_profile_spec(q: ProfilePlotQuery) -> ProfileSpec:
    """The profile spec a chart's query stands for (its rules: 422 at the query's fields)."""
    rest = 360.0 - q.rise_deg - q.dwell_deg - q.return_deg
    if rest < -1e-9:
        raise RequestValidationError([{
            "type": "value_error", "loc": ("query", "return_deg"), "input": None,
            "msg": f"rise_deg + dwell_deg + return_deg must not exceed 360°, but they add to "
                   f"{q.rise_deg + q.dwell_deg + q.return_deg:g}°"}])
    oscillating = q.motion == "oscillating"
    amount: dict[str, float | None] = (
        {"swing_deg": q.swing_deg if q.swing_deg is not None else 20.0} if oscillating
        else {"lift_mm": q.lift_mm if q.lift_mm is not None else 0.0})
    with within("curve", keep_field=False):
        camcore.lookup(q.curve)
    law = NamedCurveSpec(name=q.curve)
    try:
        segments = [SegmentSpec(type="rise", angle_deg=q.rise_deg, curve=law, **amount)]
        if q.dwell_deg > 0:
            segments.append(SegmentSpec(type="dwell", angle_deg=q.dwell_deg))
        segments.append(SegmentSpec(type="return", angle_deg=q.return_deg, curve=law, **amount))
        if rest > 1e-9:
            segments.append(SegmentSpec(type="dwell", angle_deg=rest))
        else:  # absorb rounding so the angles add to exactly 360°
            last = segments[-1]
            segments[-1] = last.model_copy(update={"angle_deg": last.angle_deg + rest})
        follower = FollowerSpec(
            type=q.follower, motion=q.motion, offset_mm=q.offset_mm,
            roller_radius_mm=q.roller_radius_mm if q.follower == "roller" else 0.0,
            arm_length_mm=q.arm_length_mm, pivot_distance_mm=q.pivot_distance_mm)
        return ProfileSpec(follower=follower, base_radius_mm=q.base_radius_mm, rotation=q.rotation, segments=segments)
    except ValidationError as exc:
        raise query_error(exc) from None


def spans(spec: ProfileSpec) -> list[tuple[str, float, float]]:
    """The schedule's stretches (type, start, end) for a chart."""
    assert spec.segments is not None  # a chart's cam is always a rise-dwell-return schedule
    out: list[tuple[str, float, float]] = []
    start = 0.0
    for seg in spec.segments:
        out.append((seg.type, start, start + seg.angle_deg))
        start += seg.angle_deg
    return out


@dataclass(frozen=True)
class ProfilePlot:
    """A chart's query and the profile spec it stands for."""

    query: ProfilePlotQuery
    spec: ProfileSpec


def _plot_request(ctx: Context, q: ProfilePlotQuery, path: Mapping[str, str]) -> ProfilePlot:
    return ProfilePlot(q, plot_profile_spec(q))


def _plot_work(ctx: Context, job: ProfilePlot, fmt: Format) -> WorkEstimate:
    with relocate(("profile",), (), keep_rest=False):
        return profile_answer_work(ctx, job.spec, job.query.samples, None, "json") + chart_work(fmt.name, job.query.dpi)


def _plot(ctx: Context, job: ProfilePlot, fmt: Format) -> Payload:
    q, spec = job.query, job.spec
    with relocate(("profile",), (), keep_rest=False):  # the query is flat: point at all of it
        result = profile(ctx, spec, q.samples, None)
    name = camcore.lookup(q.curve).id
    f = spec.follower
    roller = f", roller r = {f.roller_radius_mm:g} mm" if f.type == "roller" else ""
    offset = f", offset e = {f.offset_mm:g} mm" if f.offset_mm else ""
    arm = (f", arm {f.arm_length_mm:g} mm, pivot at {f.pivot_distance_mm:g} mm"
           if f.motion == "oscillating" and f.arm_length_mm is not None else "")
    assert spec.segments is not None
    rise = spec.segments[0]
    stroke = f"swing {rise.swing_deg:g}°" if rise.swing_deg is not None else f"lift {rise.lift_mm:g} mm"
    title = (f"Cam profile: {f.motion} {f.type} follower{arm}, {stroke}\n"
             f"base r = {spec.base_radius_mm:g} mm{roller}{offset}")
    law = f"law {name}, {'counter-clockwise' if spec.rotation == 'ccw' else 'clockwise'} rotation"
    return Payload(profile_chart(result, spec.base_radius_mm, f.type, title, law, fmt.name, q.dpi, spans(spec)))


OPERATIONS = (
    Operation("computeProfile", "/v1/profiles", TAG, "Plate cam profile",
              "Cam surface, pitch curve, lift, pressure angle, radius of curvature, and the checks; the contour "
              "as a file (DXF, X Y Z, CSV) or the cam as a solid (STEP, STL: give `solid` in the body).",
              ProfileRequest, _compute, estimate=_work, warmup=_warmup, answer=ProfileAnswer,
              formats=(JSON, TABLE, *CONTOURS, *SOLIDS), examples=PROFILE_EXAMPLES,
              format_requests={fmt.name: SolidRequest for fmt in SOLIDS},
              format_examples={fmt.name: SOLID_EXAMPLES for fmt in SOLIDS},
              aliases=(Alias("computeProfileTableCsv", "/v1/profiles/table.csv", "csv"),
                       Alias("exportProfileDxf", "/v1/profiles/contour.dxf", "dxf"),
                       Alias("exportProfileXyz", "/v1/profiles/contour.xyz", "xyz"),
                       Alias("exportProfileContourCsv", "/v1/profiles/contour.csv", "contour-csv"),
                       Alias("exportProfileStep", "/v1/profiles/solid.step", "step"),
                       Alias("exportProfileStl", "/v1/profiles/solid.stl", "stl"))),
    Operation("sizeBaseCircle", "/v1/profiles/base-circle", TAG, "Smallest base circle of a plate cam",
              "The smallest base radius meeting a pressure-angle limit and/or a curvature limit.",
              BaseCircleRequest, _base_circle, estimate=_base_circle_work, answer=BaseCircleAnswer,
              examples=BASE_CIRCLE_EXAMPLES),
    Operation("plotProfile", "/v1/profiles/plot", TAG, "Plate cam chart",
              "Contour, base circle, pitch curve (roller) and pressure angle of a rise–dwell–return–dwell cam.",
              ProfilePlotQuery, _plot, convert=_plot_request, estimate=_plot_work, formats=(SVG, PNG), method="GET",
              examples={"roller": {"value": {"samples": 101}}}),
)
