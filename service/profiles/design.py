"""``POST /v1/profiles/design`` (``designProfile``): the smallest plate cam that works — the base radius,
offset (or an arm's pivot), roller radius and spring the user frees, within their bounds (camcore.profile.design does the
work; the designed cam's profile is computeProfile's)."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

from camcore.errors import GeometryError
from camcore.profile import CamSpec
from camcore.profile.design import ProfileDesign, design_profile
from camcore.results import as_dict
from camcore.work import PROFILE_COLUMNS, WorkEstimate, WorkTerm, encode_cost, profile_work
from camcore.work.design import design_work
from service.context import Context
from service.curves.library import check_limit
from service.errors import relocate, within
from service.operations import Document, Format, Operation
from service.profiles.design_specs import DESIGN_EXAMPLES, ProfileDesignAnswer, ProfileDesignRequest
from service.profiles.operations import UNBOUNDED_COLUMNS, cam, columns, profile, schedule_field, schedule_work
from service.profiles.specs import FollowerSpec, ProfileSpec
from service.responses import check_finite


def _top_level(work: WorkEstimate) -> WorkEstimate:
    """Terms located in a profile spec (``profile.segments``) at the request's own fields (``segments``)."""
    return WorkEstimate(tuple(replace(t, field=t.field[1:] if t.field[:1] == ("profile",) else t.field)
                              for t in work.terms))


def _work(ctx: Context, body: ProfileDesignRequest, fmt: Format) -> WorkEstimate:
    """The lift's curves, the search's evaluations, the exact solves at the design found and the designed
    cam's profile with its answer (camcore.work.design)."""
    check_limit("profile samples", body.samples, ctx.settings.max_table_samples, ("samples",))
    costs, work = schedule_work(ctx, body.template)
    free = body.free.core()
    follower = body.follower
    translating = follower.motion == "translating"
    place = "offset_mm" if translating else "pivot_distance_mm"
    searched = [name for name in (place, "roller_radius_mm") if name in free and free[name][0] < free[name][1]
                and not (name == "offset_mm" and follower.type == "flat-faced")]
    limits = body.limits
    rate, preload = (("spring_rate_nm_rad", "preload_nm") if not translating else ("spring_rate_n_mm", "preload_n"))
    load = body.load() is not None
    stress = limits.allowed_stress_mpa is not None
    trades = stress and all(name in free and free[name][0] < free[name][1] for name in (rate, preload))
    pressure_limits = (0 if follower.type == "flat-faced" else
                       (2 if limits.max_return_pressure_angle_deg is not None and limits.max_pressure_angle_deg
                        is not None and limits.max_return_pressure_angle_deg != limits.max_pressure_angle_deg else
                        int(limits.max_pressure_angle_deg is not None or limits.max_return_pressure_angle_deg
                            is not None)))
    curvature = (limits.min_radius_of_curvature_mm is not None
                 or limits.min_radius_of_curvature_roller_multiple is not None or follower.type != "knife-edge")
    kind = ("flat" if follower.type == "flat-faced" else "closed_form" if translating
            else "placed_arm" if place in searched else "arm")
    field = schedule_field(body.template)
    work += design_work(costs, searched=len(searched), kind=kind, roots=curvature, pressure_limits=pressure_limits,
                        own_solves=not translating or pressure_limits == 2, curvature=curvature, stress=stress,
                        load=load, trades=trades, segments_field=field, free_field=("free",))
    work += profile_work(costs, body.samples, field, ("samples",))
    rows = WorkEstimate((WorkTerm(("samples",), f"encoding {body.samples} rows",
                                  encode_cost(body.samples * PROFILE_COLUMNS, False)),))
    return _top_level(work) + rows


def _cam(ctx: Context, body: ProfileDesignRequest) -> CamSpec:
    """The request's lift on its own follower (the template's follower replaced; not yet validated)."""
    with relocate(("profile",), ()):
        lift_cam = cam(ctx, body.template)
    return replace(lift_cam, follower=body.follower.core(),
                   base_radius_mm=body.base_radius_mm if body.base_radius_mm is not None else lift_cam.base_radius_mm)


def design(ctx: Context, body: ProfileDesignRequest) -> ProfileDesign:
    """The design; 422 naming the limit that cannot be met, or the field of a rule broken."""
    spec = _cam(ctx, body)
    if body.free.base_radius_mm is not None:
        spec = replace(spec, base_radius_mm=float(body.free.base_radius_mm[0]))
    where = "segments" if body.segments is not None else "lift" if body.lift is not None else "motion"
    with within(where, only=GeometryError):
        return design_profile(body.problem(spec))


def designed_profile(body: ProfileDesignRequest, result: ProfileDesign) -> ProfileSpec:
    """The profile spec of the designed cam (computeProfile's request for it)."""
    values = result.design
    follower = body.follower.model_copy(update={
        "offset_mm": values.offset_mm if values.offset_mm is not None else body.follower.offset_mm,
        "pivot_distance_mm": values.pivot_distance_mm if values.pivot_distance_mm is not None
        else body.follower.pivot_distance_mm,
        "roller_radius_mm": values.roller_radius_mm if values.roller_radius_mm is not None
        else body.follower.roller_radius_mm})
    return ProfileSpec(follower=FollowerSpec.model_validate(follower.model_dump()), base_radius_mm=values.base_radius_mm,
                       rotation=body.rotation, rotation_ratio=body.rotation_ratio, segments=body.segments,
                       lift=body.lift, motion=body.motion)


def _compute(ctx: Context, body: ProfileDesignRequest, fmt: Format) -> Document:
    result = design(ctx, body)
    answer: dict[str, Any] = as_dict(result)
    check_finite({k: v for k, v in answer["design"].items() if v is not None})
    for row in answer["constraints"]:
        check_finite({k: row[k] for k in ("value", "limit", "margin")})
    spec = designed_profile(body, result)
    with relocate(("profile",), ()):
        drawn = profile(ctx, spec, body.samples, None)
    table = columns(drawn)
    check_finite({k: v for k, v in table.items() if k not in UNBOUNDED_COLUMNS})
    answer["profile"] = {**table, "checks": as_dict(drawn.checks)}
    return Document(answer)

OPERATIONS = (
    Operation("designProfile", "/v1/profiles/design", "profiles", "Plate cam design: the smallest cam that works",
              "The base radius, offset (an arm's pivot distance), roller radius, spring rate and preload (those given in `free`, within their "
              "bounds) of the smallest plate cam meeting the pressure-angle, curvature, contact-stress and "
              "contact-force limits at the worst speed of the range, then the softest spring and the smallest "
              "preload; every limit at the design (value, limit, margin, active), the designed cam's profile "
              "(computeProfile's answer) and how the search went. None within the bounds: 422 naming the limit "
              "and the best value reachable.",
              ProfileDesignRequest, _compute, estimate=_work, answer=ProfileDesignAnswer, examples=DESIGN_EXAMPLES),
)
