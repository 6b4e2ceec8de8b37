"""/v1/profiles/dynamics: a force-closed follower's contact force, jump speed and stress, and its
chart (GET ``/v1/profiles/dynamics/plot``, the profile chart's cam with the follower's load).

The cam is built as every profile's (service.profiles.operations.cam): same caches, limits and
errors as POST /v1/profiles.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from pydantic import Field, ValidationError

from camcore.errors import GeometryError, NonFiniteResultError
from camcore.profile.dynamics import FollowerDynamics, follower_dynamics
from camcore.results import as_dict
from camcore.work import DYNAMICS_COLUMNS, WorkEstimate, WorkTerm, dynamics_work, encode_cost
from service.context import Context
from service.curves.library import check_limit
from service.drawing import chart_work
from service.errors import query_error, relocate, within
from service.operations import JSON, PNG, SVG, Alias, Document, Format, Operation, Payload, csv
from service.profiles.charts import contact_force_chart
from service.profiles.dynamics_specs import DYNAMICS_EXAMPLES, DynamicsAnswer, DynamicsRequest
from service.profiles.operations import ProfilePlotQuery, cam, plot_profile_spec, schedule_field, schedule_work, spans
from service.profiles.specs import ProfileSpec
from service.specs import BIG, SLOWEST_RPM


def _work(ctx: Context, body: DynamicsRequest, fmt: Format | None) -> WorkEstimate:
    """The curves to build, the extremes over the turn, the rows and their encoding (none for a
    chart); 413 first for more rows than max_table_samples."""
    check_limit("dynamics samples", body.samples, ctx.settings.max_table_samples, ("samples",))
    work = follower_work(ctx, body.profile, body.samples)
    if fmt is None:
        return work
    return work + WorkEstimate((WorkTerm(("samples",), f"encoding {body.samples} rows",
                                         encode_cost(body.samples * DYNAMICS_COLUMNS, fmt.name == "csv")),))


def follower_work(ctx: Context, profile: ProfileSpec, samples: int) -> WorkEstimate:
    """The cam's curves, the follower's extremes over the turn and ``samples`` rows."""
    costs, work = schedule_work(ctx, profile)
    return work + dynamics_work(costs, samples, schedule_field(profile), ("samples",))


def dynamics(ctx: Context, body: DynamicsRequest) -> FollowerDynamics:
    check_limit("dynamics samples", body.samples, ctx.settings.max_table_samples, ("samples",))
    the_cam = cam(ctx, body.profile)
    roller = None if body.roller is None else body.roller.core()
    # what the cam turns out to be (an impact in its lift, a roller that undercuts it) is about the profile
    with within("profile", only=GeometryError):
        return follower_dynamics(the_cam, body.follower_load(), body.speed_rpm, body.samples,
                                 safety_margin_n=body.safety_margin_n, roller=roller)


def _compute(ctx: Context, body: DynamicsRequest, fmt: Format) -> Document:
    """The columns, the unit and the summary (refused when not finite)."""
    result = dynamics(ctx, body)
    summary = as_dict(result.summary)
    for name, value in summary.items():
        if isinstance(value, float) and not math.isfinite(value):
            raise NonFiniteResultError(f"the computation of 'summary.{name}' produced a non-finite number for "
                                       "these inputs; check that they describe a realistic cam and follower.")
    table = result.table.columns()
    return Document({**table, "unit": result.unit, "summary": summary}, table=table)


# ----------------------------------------------------------------------------- the chart
Load = float | None
_LOAD_FIELDS = ("mass_kg", "spring_rate_n_mm", "preload_n", "external_force_n", "damping_n_s_mm", "inertia_kgm2",
                "spring_rate_nm_rad", "preload_nm", "external_torque_nm", "damping_nm_s_rad")


class DynamicsPlotQuery(ProfilePlotQuery):
    """The profile chart's cam, and the follower's load (the fields of computeFollowerDynamics)."""

    speed_rpm: float = Field(ge=SLOWEST_RPM, le=BIG, allow_inf_nan=False, description="N, the camshaft's speed")
    mass_kg: Load = Field(None, gt=0, le=1e6, allow_inf_nan=False, description="translating")
    spring_rate_n_mm: Load = Field(None, gt=0, le=1e6, allow_inf_nan=False, description="translating")
    preload_n: Load = Field(None, ge=-1e6, le=1e6, allow_inf_nan=False, description="translating; default 0")
    external_force_n: Load = Field(None, ge=-1e6, le=1e6, allow_inf_nan=False, description="translating; default 0")
    damping_n_s_mm: Load = Field(None, ge=0, le=1e6, allow_inf_nan=False, description="translating; default 0")
    inertia_kgm2: Load = Field(None, gt=0, le=1e6, allow_inf_nan=False, description="oscillating")
    spring_rate_nm_rad: Load = Field(None, gt=0, le=1e6, allow_inf_nan=False, description="oscillating")
    preload_nm: Load = Field(None, ge=-1e6, le=1e6, allow_inf_nan=False, description="oscillating; default 0")
    external_torque_nm: Load = Field(None, ge=-1e6, le=1e6, allow_inf_nan=False, description="oscillating; default 0")
    damping_nm_s_rad: Load = Field(None, ge=0, le=1e6, allow_inf_nan=False, description="oscillating; default 0")
    safety_margin_n: float = Field(0.0, ge=0, le=1e6, allow_inf_nan=False,
                                   description="the contact force to keep: drawn, and shaded where it is not met")


@dataclass(frozen=True)
class DynamicsPlot:
    """A chart's query and the POST body it stands for."""

    query: DynamicsPlotQuery
    body: DynamicsRequest


def _plot_request(ctx: Context, q: DynamicsPlotQuery, path: Mapping[str, str]) -> DynamicsPlot:
    """The query and its body (the body's rules and sentences: 422 at the query's fields)."""
    profile = plot_profile_spec(q)
    try:
        return DynamicsPlot(q, DynamicsRequest(profile=profile, speed_rpm=q.speed_rpm, safety_margin_n=q.safety_margin_n,
                                               samples=q.samples, **{name: getattr(q, name) for name in _LOAD_FIELDS}))
    except ValidationError as exc:
        raise query_error(exc) from None


def _plot_work(ctx: Context, job: DynamicsPlot, fmt: Format) -> WorkEstimate:
    with relocate(("profile",), (), keep_rest=False):
        return _work(ctx, job.body, JSON) + chart_work(fmt.name, job.query.dpi)


def _plot(ctx: Context, job: DynamicsPlot, fmt: Format) -> Payload:
    q, body = job.query, job.body
    with relocate(("profile",), (), keep_rest=False):  # the query is flat: point at all of it
        result = dynamics(ctx, body)
    f = body.profile.follower
    assert body.profile.segments is not None  # the chart's cam is always a rise-dwell-return schedule
    rise = body.profile.segments[0]
    stroke = f"swing {rise.swing_deg:g}°" if rise.swing_deg is not None else f"lift {rise.lift_mm:g} mm"
    title = f"Follower dynamics: {f.motion} {f.type} follower, {stroke}, law {q.curve}, {q.speed_rpm:g} rpm"
    summary: dict[str, Any] = vars(result.summary)
    return Payload(contact_force_chart(result.table, summary, result.unit, title, fmt.name, q.dpi, spans(body.profile)))


OPERATIONS = (
    Operation("computeFollowerDynamics", "/v1/profiles/dynamics", "profiles", "Spring-loaded follower dynamics",
              "Contact force, normal force, camshaft torque and Hertz stress over the cam angle of a spring-loaded "
              "follower at a speed; minimum contact force, whether the follower leaves the cam, the jump speed, the "
              "smallest preload, peak and RMS torque, peak stress over the turn.",
              DynamicsRequest, _compute, estimate=_work, answer=DynamicsAnswer,
              formats=(JSON, csv("dynamics.csv", "the table alone, for spreadsheets")), examples=DYNAMICS_EXAMPLES,
              aliases=(Alias("computeFollowerDynamicsTableCsv", "/v1/profiles/dynamics/table.csv", "csv"),)),
    Operation("plotFollowerDynamics", "/v1/profiles/dynamics/plot", "profiles", "Follower contact-force chart",
              "Contact force over the cam angle of a rise–dwell–return cam (the fields of plotProfile) with the zero "
              "line, the safety margin and the region where the follower leaves the cam shaded.",
              DynamicsPlotQuery, _plot, convert=_plot_request, estimate=_plot_work, formats=(SVG, PNG), method="GET",
              examples={"roller": {"value": {"speed_rpm": 600, "mass_kg": 0.5, "spring_rate_n_mm": 2,
                                             "samples": 101}}}),
)
