"""The plate cam's charts: the contour with its pressure angle, and a force-closed follower's
contact force over the turn. Drawn with service.drawing."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from service.drawing import COLORS, LOCK, figure, mark, render, shade_spans, style

if TYPE_CHECKING:  # pragma: no cover
    from camcore.profile import ProfileResult
    from camcore.profile.dynamics import DynamicsTable

_FORCE = "#1f77b4"
_SPRING = "#2ca02c"
_LOST = "#d62728"
_LIFT = "#7f7f7f"


def profile_chart(result: ProfileResult, base_radius_mm: float, follower_type: str, title: str, law: str,
                  fmt: str = "svg", dpi: int = 100, spans: Sequence[tuple[str, float, float]] = ()) -> bytes:
    """The cam contour with base circle (and pitch curve for rollers), and pressure angle over cam angle.

    ``spans``: (label, start_deg, end_deg) of the lift schedule, shaded and named on the pressure-angle axes.
    """
    with LOCK:
        fig = figure(10.0, 6.0)
        ax_c, ax_p = fig.subplots(1, 2, width_ratios=[1.0, 1.15])
        ang = np.linspace(0.0, 2 * np.pi, 361)
        ax_c.plot(base_radius_mm * np.cos(ang), base_radius_mm * np.sin(ang), color="#999999", linestyle="--",
                  linewidth=0.9, label=f"base circle r = {base_radius_mm:g} mm")
        if follower_type == "roller":
            ax_c.plot(result.pitch_x_mm, result.pitch_y_mm, color="#ff7f0e", linestyle="-.", linewidth=1.0,
                      label="pitch curve (roller centre)")
        ax_c.plot(result.x_mm, result.y_mm, color="#1f77b4", linewidth=1.8, label="cam contour")
        ax_c.plot([0], [0], "+", color="black", markersize=8)
        ax_c.set_aspect("equal", adjustable="datalim")
        ax_c.set_xlabel("x [mm]", fontsize=9)
        ax_c.set_ylabel("y [mm]", fontsize=9)
        ax_c.grid(True, color="#eeeeee", linewidth=0.6)
        ax_c.tick_params(labelsize=8)
        ax_c.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncols=1, frameon=False)
        ax_c.set_title(f"contour ({law})", fontsize=10)

        ch = result.checks
        flat = follower_type == "flat-faced" and result.contact_offset_mm is not None
        if flat:
            # the pressure angle of a flat face is 0 throughout: show where the contact runs on the face
            assert result.contact_offset_mm is not None
            ax_p.plot(result.cam_angle_deg, result.contact_offset_mm, color=COLORS["q"], linewidth=1.4)
        else:
            ax_p.plot(result.cam_angle_deg, result.pressure_angle_deg, color=COLORS["a"], linewidth=1.4)
        style(ax_p)
        shade_spans(ax_p, spans, 0.02)
        ax_p.set_xlim(0.0, 360.0)
        ax_p.set_xticks(np.arange(0, 361, 60))
        ax_p.margins(y=0.15)
        ax_p.set_xlabel("cam angle [deg]", fontsize=9)
        rho = ch.min_radius_of_curvature_mm
        note = (f"min radius of curvature {rho:.2f} mm at {ch.min_radius_of_curvature_at_deg:.1f}°"
                + ("; UNDERCUT" if ch.undercut else "") + ("" if ch.convex else "; not convex"))
        if flat:
            ax_p.set_ylabel("contact point on the face [mm]", fontsize=9)
            width = f"face width ≥ {ch.face_width_mm:.2f} mm" if ch.face_width_mm is not None else ""
            ax_p.set_title(f"contact position on the flat face (pressure angle 0°)\n{width}\n{note}", fontsize=9)
        else:
            at = ch.max_pressure_angle_at_deg
            mark(ax_p, at, ch.max_pressure_angle_signed_deg,
                  f"max |φ| = {ch.max_pressure_angle_deg:.2f}° at {at:.1f}°", COLORS["a"],
                  above=ch.max_pressure_angle_signed_deg >= 0)
            ax_p.set_ylabel("pressure angle φ [deg]", fontsize=9)
            ax_p.set_title(f"pressure angle\n{note}", fontsize=9)
        fig.suptitle(title, fontsize=11)
        return render(fig, fmt, dpi)


def contact_force_chart(table: DynamicsTable, summary: dict[str, Any], unit: str, title: str, fmt: str = "svg",
                        dpi: int = 100, spans: Sequence[tuple[str, float, float]] = ()) -> bytes:
    """The lift above, and below it the contact force over the cam angle with the zero line, the
    safety margin, the spring force (translating) and the region where the force is below the margin
    (the follower leaves the cam) shaded; the minimum marked, the jump speed and minimum preload said."""
    x = table.cam_angle_deg
    force = table.contact_force_n
    margin = float(summary["safety_margin_n"])
    with LOCK:
        fig = figure(10.0, 6.5)
        ax_s, ax_f = fig.subplots(2, 1, sharex=True, height_ratios=[1.0, 2.4])
        ax_s.plot(x, table.lift, color=_LIFT, linewidth=1.3)
        ax_s.set_ylabel("swing [deg]" if unit == "deg" else "lift [mm]", fontsize=9)
        style(ax_s)
        shade_spans(ax_s, spans, 0.04)
        ax_f.plot(x, force, color=_FORCE, linewidth=1.6, label="contact force")
        if unit == "mm":
            ax_f.plot(x, table.spring_force, color=_SPRING, linewidth=1.0, linestyle="--", label="spring force k·s + F0")
        style(ax_f)  # the zero line
        if margin > 0:
            ax_f.axhline(margin, color=_LOST, linewidth=0.9, linestyle=":", label=f"safety margin {margin:g} N")
        lost = force < margin
        if lost.any():
            ax_f.fill_between(x, force, margin, where=lost, interpolate=True, color=_LOST, alpha=0.35, linewidth=0,
                              label="contact lost (force below the margin)")
            for lo, hi in _runs(x, lost):
                ax_s.axvspan(lo, hi, color=_LOST, alpha=0.15, linewidth=0)
        at, low = float(summary["min_contact_force_at_deg"]), float(summary["min_contact_force_n"])
        mark(ax_f, at, low, f"min {low:.4g} N at {at:.1f}°", _LOST if summary["separates"] else _FORCE, above=False)
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
        return render(fig, fmt, dpi)


def _runs(x: np.ndarray, mask: np.ndarray) -> list[tuple[float, float]]:
    """The x ranges where mask holds, from the first to the last sample of each run."""
    edges = np.flatnonzero(np.diff(np.concatenate([[0], mask.astype(np.int8), [0]])))
    return [(float(x[a]), float(x[b - 1])) for a, b in zip(edges[::2], edges[1::2], strict=True)]
