"""``POST /v1/cams/barrel`` (``computeBarrelCam``): a barrel cam's developed groove, both flanks in
3-D and its checks; the columns over the cam angle as CSV (the flank grids are JSON only: they
are not columns over the cam angle); the cam as a solid, STEP or STL
(:class:`camcore.export.barrel_solid.BarrelSolid`, written by the CAD kernel's process).
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np

from camcore.cams.barrel import BarrelCam, BarrelResult, make_barrel_cam, sample_barrel
from camcore.curves.kinds import LawCost
from camcore.errors import InvalidParameterError
from camcore.export import SOLID_FORMATS
from camcore.export.barrel_solid import BarrelSolid
from camcore.profile import Segment
from camcore.profile.lift import program_periods_per_turn
from camcore.results import as_dict
from camcore.work import (
    BARREL_CHECKS_FACTOR,
    BARREL_COLUMNS,
    BARREL_FLANK_POINT_S,
    BARREL_FLANK_VALUES,
    BARREL_SAMPLE_S,
    WorkEstimate,
    checks_work,
    curve_work,
    encode_cost,
    motion_work,
    per_item_work,
)
from camcore.work.barrel import SOLID_POLES_PER_STATION, barrel_solid_facets, barrel_solid_stations, barrel_solid_work
from service.cams.barrel_specs import (
    BARREL_EXAMPLES,
    BARREL_SOLID_EXAMPLES,
    BarrelCamAnswer,
    BarrelCamRequest,
    BarrelSolidRequest,
    BarrelSolidSpec,
)
from service.context import Context
from service.curves.library import check_limit
from service.errors import Location, within
from service.motions.operations import program_costs, resolve
from service.operations import JSON, Document, Format, Operation, Payload, Table, csv, download
from service.responses import check_finite

#: columns whose NaN means "straight" (null in JSON, an empty CSV cell)
UNBOUNDED_COLUMNS = ("pitch_radius_of_curvature_mm", "upper_radius_of_curvature_mm", "lower_radius_of_curvature_mm")


def _check_size(ctx: Context, body: BarrelCamRequest) -> None:
    """413 when the flank grids (samples × length_samples) exceed the table limit."""
    check_limit("barrel cam samples × length_samples", body.samples * body.length_samples,
                ctx.settings.max_table_samples, ("samples",))


def _work(ctx: Context, body: BarrelCamRequest, fmt: Format) -> WorkEstimate:
    """The curves built, the checks, the samples and their encoding; a solid: the curves, its
    surfaces and the CAD kernel's work (422 first when the body has no ``solid``)."""
    if fmt.name in SOLID_FORMATS:
        return barrel_solid_estimate(ctx, body, _solid(body, fmt), fmt.name)
    _check_size(ctx, body)
    return barrel_work(ctx, body, body.samples, body.length_samples, fmt.name)


def _solid(body: BarrelCamRequest, fmt: Format) -> BarrelSolidSpec:
    if body.solid is None:
        raise InvalidParameterError(f"format {fmt.name} is a solid: give solid {{tolerance_mm, bore_diameter_mm}}.",
                                    field=("solid",))
    return body.solid


def _moves(body: BarrelCamRequest) -> list[tuple[float, float]]:
    """Each segment's cam angle [rad] and stroke along the axis [mm] over one turn (a swing: the
    arm's arc; a motion program's move: the pitch radius, its stroke may be solved)."""
    if body.motion is not None:  # a period of 360°/k repeats k times a turn (at most 1000: 422 before the list)
        with within("motion"):
            repeats = program_periods_per_turn(body.motion.period_deg)  # as the cam's MotionLift counts them
        return [(math.radians(s.span_deg), 0.0 if s.type == "dwell" else body.pitch_radius_mm)
                for s in body.motion.segments] * repeats
    arm = body.arm_length_mm or 0.0
    return [(math.radians(s.angle_deg), s.lift_mm if s.lift_mm is not None else arm * math.radians(s.swing_deg or 0.0))
            for s in body.segments or ()]


def barrel_solid_estimate(ctx: Context, body: BarrelCamRequest, solid: BarrelSolidSpec, answer: str) -> WorkEstimate:
    """The curves built, the solid's surfaces and the kernel's solid and file (an STL: at half
    the tolerance, and its facets)."""
    _, field, built = barrel_build_work(ctx, body)
    tolerance = solid.tolerance_mm / (2 if answer == "stl" else 1)
    moves = _moves(body)
    length = body.roller_length_mm or body.roller_radius_mm
    outer = body.pitch_radius_mm + 0.5 * length
    poles = SOLID_POLES_PER_STATION * barrel_solid_stations(moves, outer, tolerance)
    facets = 0 if answer != "stl" else barrel_solid_facets(
        body.pitch_radius_mm, body.roller_radius_mm, body.groove_depth_mm or length, [s for _, s in moves], tolerance)
    return built + barrel_solid_work(len(moves), poles, facets, field, ("solid", "tolerance_mm"))


def _warmup(ctx: Context, fmt: Format) -> None:
    # the CAD kernel's process starts on the first solid after it was retired, outside the budget (as computeProfile's)
    if fmt.name in SOLID_FORMATS:
        ctx.cad.warm()


def barrel_build_work(ctx: Context, body: BarrelCamRequest) -> tuple[list[LawCost | None], Location, WorkEstimate]:
    """Each segment's law cost, the request field of the segments, and the work of building the
    cam's curves (a motion program resolved)."""
    costs: list[LawCost | None] = []
    built = WorkEstimate()
    field: Location
    if body.motion is not None:
        costs, solved = program_costs(ctx, body.motion.core())
        built = motion_work(costs, solved, 0, ("motion", "segments"), ("samples",))
        field = ("motion", "segments")
    else:
        assert body.segments is not None
        field = ("segments",)
        seen: set[bytes] = set()
        for i, segment in enumerate(body.segments):
            if segment.curve is None:
                costs.append(None)
                continue
            law = segment.curve.core()
            cost = ctx.curves.cost(law, at=("segments", i, "curve"))
            costs.append(cost)
            if ctx.curves.key(law) not in seen:
                seen.add(ctx.curves.key(law))
                built += curve_work(cost, ("segments", i, "curve"))
    return costs, field, built


def barrel_work(ctx: Context, body: BarrelCamRequest, samples: int, length_samples: int, answer: str) -> WorkEstimate:
    """The curves built, the checks, ``samples`` × ``length_samples`` points and their encoding as ``answer``."""
    costs, field, built = barrel_build_work(ctx, body)
    checks = checks_work(costs, field).seconds * BARREL_CHECKS_FACTOR
    n, points = samples, samples * length_samples
    csv_answer = answer == "csv"
    values = n * BARREL_COLUMNS + (0 if csv_answer else points * BARREL_FLANK_VALUES)
    return (built + per_item_work(1, checks, field, "the barrel cam's checks")
            + per_item_work(n, BARREL_SAMPLE_S, ("samples",), f"{n} cam angles")
            + per_item_work(points, BARREL_FLANK_POINT_S, ("length_samples",), f"{points} flank points")
            + per_item_work(values, encode_cost(1, csv_answer), ("samples",), f"{values} numbers encoded"))


def barrel(ctx: Context, body: BarrelCamRequest) -> BarrelResult:
    """The barrel cam sampled."""
    _check_size(ctx, body)
    return sample_barrel(barrel_cam(ctx, body), body.samples, body.length_samples)


def barrel_cam(ctx: Context, body: BarrelCamRequest) -> BarrelCam:
    """The barrel cam (its curves from the curve cache, its program resolved as every program)."""
    segments = None
    program = None
    if body.segments is not None:
        segments = []
        for i, s in enumerate(body.segments):
            law = None if s.curve is None else ctx.curves.curve(s.curve.core(), at=("segments", i, "curve"))
            with within("segments", i):
                segments.append(Segment(type=s.type, angle_deg=s.angle_deg, lift_mm=s.lift_mm or 0.0,
                                        swing_deg=s.swing_deg, curve=law))
    else:
        assert body.motion is not None
        program = resolve(ctx, body.motion.core())
    return make_barrel_cam(body.pitch_radius_mm, body.roller_radius_mm, roller_length_mm=body.roller_length_mm,
                          groove_depth_mm=body.groove_depth_mm, segments=segments, motion=program,
                          roller=body.roller, follower=body.follower, arm_length_mm=body.arm_length_mm,
                          initial_arm_angle_deg=body.initial_arm_angle_deg)


def over_the_turn(r: BarrelResult, body: BarrelCamRequest) -> dict[str, Any]:
    """The columns over the cam angle that the JSON and the CSV answers share."""
    lift = "swing_deg" if body.follower == "oscillating" else "lift_mm"
    return {"cam_angle_deg": r.cam_angle_deg, lift: r.lift, "u_mm": r.u_mm, "y_mm": r.y_mm,
            "pressure_angle_deg": r.pressure_angle_deg, "pressure_angle_inner_deg": r.pressure_angle_inner_deg,
            "pressure_angle_outer_deg": r.pressure_angle_outer_deg,
            "pitch_radius_of_curvature_mm": r.pitch_radius_of_curvature_mm}


def _compute(ctx: Context, body: BarrelCamRequest, fmt: Format) -> Document | Table | Payload:
    """JSON: the columns, the flanks (grids) and the checks; CSV: the columns with both flanks' radii;
    STEP, STL: the solid, from the CAD kernel's process."""
    if fmt.name in SOLID_FORMATS:
        solid = _solid(body, fmt)
        item = BarrelSolid(barrel_cam(ctx, body), solid.tolerance_mm, solid.end_margin_mm, solid.bore_diameter_mm,
                           max_triangles=ctx.settings.max_stl_triangles)
        return Payload(ctx.cad.write(fmt.name, item))
    r = barrel(ctx, body)
    if fmt.name == "csv":
        return Table({**over_the_turn(r, body), "upper_radius_of_curvature_mm": r.upper.radius_of_curvature_mm,
                      "lower_radius_of_curvature_mm": r.lower.radius_of_curvature_mm}, allow_null=UNBOUNDED_COLUMNS)
    flanks = {}
    for name, flank in (("upper", r.upper), ("lower", r.lower)):
        check_finite({f"{name} flank": np.stack([flank.x_mm, flank.y_mm, flank.z_mm])})
        flanks[name] = {"x_mm": flank.x_mm, "y_mm": flank.y_mm, "z_mm": flank.z_mm,
                        "radius_of_curvature_mm": flank.radius_of_curvature_mm}
    columns = {**over_the_turn(r, body), "roller_position_mm": r.roller_position_mm}
    return Document({**columns, "flanks": flanks, "checks": as_dict(r.checks)}, table=columns,
                    allow_null=UNBOUNDED_COLUMNS)


#: the solid downloads: camcore's registry of solid formats, each file named for a barrel cam
SOLIDS = tuple(replace(download(fmt), file_name=f"barrel_cam.{fmt.name}") for fmt in SOLID_FORMATS.values())

OPERATIONS = (
    Operation("computeBarrelCam", "/v1/cams/barrel", "cams", "Barrel cam",
              "A barrel cam: the developed groove, pressure angles across the roller, the flanks' radii of curvature, "
              "both flanks in 3-D, and the checks (largest pressure angle, smallest radii, undercut, groove "
              "dimensions); CSV: the columns over the cam angle (an empty radius cell: a straight stretch); the cam "
              "as a solid (STEP, STL: give `solid` in the body).",
              BarrelCamRequest, _compute, estimate=_work, warmup=_warmup, answer=BarrelCamAnswer,
              formats=(JSON, csv("barrel-cam.csv", "the columns over the cam angle as CSV"), *SOLIDS),
              examples=BARREL_EXAMPLES, format_requests={fmt.name: BarrelSolidRequest for fmt in SOLIDS},
              format_examples={fmt.name: BARREL_SOLID_EXAMPLES for fmt in SOLIDS}),
)
