"""The contact-force chart of a force-closed follower: GET /v1/profiles/dynamics/plot.

The query is the profile chart's (a rise–dwell–return cam, service.plots.charts.ProfilePlotQuery)
plus the follower's load and speed; the numbers come from the dynamics service (same limits,
caches and errors as POST /v1/profiles/dynamics). Drawn like the other charts: matplotlib's
object API under the charts' lock, SVG or PNG without a date stamp.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from pydantic import Field, ValidationError

from camcore.profile.dynamics import DynamicsTable
from camcore.work import WorkEstimate
from service.errors import relocate
from service.plots.charts import _LOCK, PlotService, ProfilePlotQuery, _figure, _mark, _query_error, _render, _style
from service.profiles.dynamics_service import DynamicsService
from service.profiles.dynamics_specs import DynamicsRequest

_FORCE = "#1f77b4"
_SPRING = "#2ca02c"
_LOST = "#d62728"
_LIFT = "#7f7f7f"

Load = float | None
_LOAD_FIELDS = ("mass_kg", "spring_rate_n_mm", "preload_n", "external_force_n", "damping_n_s_mm", "inertia_kgm2",
                "spring_rate_nm_rad", "preload_nm", "external_torque_nm", "damping_nm_s_rad")


class DynamicsPlotQuery(ProfilePlotQuery):
    """The profile chart's cam, and the follower's load (the fields of computeFollowerDynamics)."""

    speed_rpm: float = Field(gt=0, le=1e6, allow_inf_nan=False, description="N, the camshaft's speed")
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


def dynamics_request(plots: PlotService, q: DynamicsPlotQuery) -> DynamicsRequest:
    """The POST body the query stands for (its rules and sentences: 422 at the query's fields)."""
    profile = plots.profile_spec(q)
    try:
        return DynamicsRequest(profile=profile, speed_rpm=q.speed_rpm, safety_margin_n=q.safety_margin_n,
                               samples=q.samples, **{name: getattr(q, name) for name in _LOAD_FIELDS})
    except ValidationError as exc:
        raise _query_error(exc) from None


def dynamics_plot_work(plots: PlotService, dynamics: DynamicsService, q: DynamicsPlotQuery) -> WorkEstimate:
    body = dynamics_request(plots, q)
    with relocate(("profile",), (), keep_rest=False):
        return dynamics.work(body, csv=False) + plots.render_work(q)


def dynamics_plot(plots: PlotService, dynamics: DynamicsService, q: DynamicsPlotQuery) -> bytes:
    body = dynamics_request(plots, q)
    with relocate(("profile",), (), keep_rest=False):  # the query is flat: point at all of it
        result = dynamics.compute(body)
    f = body.profile.follower
    assert body.profile.segments is not None  # the chart's cam is always a rise-dwell-return schedule
    spans, start = [], 0.0
    for seg in body.profile.segments:
        spans.append((seg.type, start, start + seg.angle_deg))
        start += seg.angle_deg
    rise = body.profile.segments[0]
    stroke = f"swing {rise.swing_deg:g}°" if rise.swing_deg is not None else f"lift {rise.lift_mm:g} mm"
    title = (f"Follower dynamics: {f.motion} {f.type} follower, {stroke}, law {q.curve}, "
             f"{q.speed_rpm:g} rpm")
    return contact_force_chart(result.table, vars(result.summary), result.unit, title, q.format, q.dpi, spans)


def contact_force_chart(table: DynamicsTable, summary: dict[str, Any], unit: str, title: str, fmt: str = "svg",
                        dpi: int = 100, spans: Sequence[tuple[str, float, float]] = ()) -> bytes:
    """The lift above, and below it the contact force over the cam angle with the zero line, the
    safety margin, the spring force (translating) and the region where the force is below the margin
    (the follower leaves the cam) shaded; the minimum marked, the jump speed and minimum preload said."""
    x = table.cam_angle_deg
    force = table.contact_force_n
    margin = float(summary["safety_margin_n"])
    with _LOCK:
        fig = _figure(10.0, 6.5)
        ax_s, ax_f = fig.subplots(2, 1, sharex=True, height_ratios=[1.0, 2.4])
        ax_s.plot(x, table.lift, color=_LIFT, linewidth=1.3)
        ax_s.set_ylabel("swing [deg]" if unit == "deg" else "lift [mm]", fontsize=9)
        _style(ax_s)
        for i, (label, lo, hi) in enumerate(spans):
            ax_s.axvspan(lo, hi, color="#f2f2f2" if i % 2 else "#e6eef7", zorder=0, linewidth=0)
            ax_s.text((lo + hi) / 2, 0.04, label, transform=ax_s.get_xaxis_transform(), ha="center", va="bottom",
                      fontsize=8, color="#555555")
        ax_f.plot(x, force, color=_FORCE, linewidth=1.6, label="contact force")
        if unit == "mm":
            ax_f.plot(x, table.spring_force, color=_SPRING, linewidth=1.0, linestyle="--", label="spring force k·s + F0")
        _style(ax_f)  # the zero line
        if margin > 0:
            ax_f.axhline(margin, color=_LOST, linewidth=0.9, linestyle=":", label=f"safety margin {margin:g} N")
        lost = force < margin
        if lost.any():
            ax_f.fill_between(x, force, margin, where=lost, interpolate=True, color=_LOST, alpha=0.35, linewidth=0,
                              label="contact lost (force below the margin)")
            for lo, hi in _runs(x, lost):
                ax_s.axvspan(lo, hi, color=_LOST, alpha=0.15, linewidth=0)
        at, low = float(summary["min_contact_force_at_deg"]), float(summary["min_contact_force_n"])
        _mark(ax_f, at, low, f"min {low:.4g} N at {at:.1f}°", _LOST if summary["separates"] else _FORCE, above=False)
        ax_f.set_xlim(0.0, 360.0)
        ax_f.set_xticks(np.arange(0, 361, 60))
        ax_f.margins(y=0.12)
        ax_f.set_xlabel("cam angle [deg]", fontsize=9)
        ax_f.set_ylabel("force along the follower's motion [N]", fontsize=9)
        ax_f.legend(fontsize=8, loc="upper right", framealpha=0.85)
        jump = summary["jump_speed_rpm"]
        preload = summary["min_preload_n"] if unit == "mm" else summary["min_preload_nm"]
        verdict = "the follower LEAVES the cam" if summary["separates"] else "the follower stays on the cam"
        jump_text = "never" if jump is None else f"{jump:.5g} rpm"
        preload_text = f"{preload:.4g} N" if unit == "mm" else f"{preload:.4g} N·m"
        ax_f.set_title(f"{verdict}; jump speed {jump_text}; smallest preload for the margin {preload_text}",
                       fontsize=9)
        fig.suptitle(title, fontsize=11)
        return _render(fig, fmt, dpi)


def _runs(x: np.ndarray, mask: np.ndarray) -> list[tuple[float, float]]:
    """The x ranges where mask holds, from the first to the last sample of each run."""
    edges = np.flatnonzero(np.diff(np.concatenate([[0], mask.astype(np.int8), [0]])))
    return [(float(x[a]), float(x[b - 1])) for a, b in zip(edges[::2], edges[1::2], strict=True)]
