"""The indexers' charts: the output's motion over one index, and a sizing sweep's input torque
over speed. Drawn with service.drawing."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from camcore.errors import InvalidParameterError
from service.drawing import COLORS, LOCK, figure, mark, render, stacked_traces, style


def indexer_chart(table: dict[str, np.ndarray], summary: dict[str, Any], title: str, fmt: str = "svg",
                  dpi: int = 100) -> bytes:
    """Output angle, ω, α and jerk over the input angle of one index, peaks marked."""
    with LOCK:
        fig = figure(8.0, 8.5)
        axes = fig.subplots(4, 1, sharex=True)
        x = table["input_angle_deg"]
        rows = [("s", "output angle [deg]", table["output_angle_deg"]), ("v", "ω [rad/s]", table["omega_rad_s"]),
                ("a", "α [rad/s²]", table["alpha_rad_s2"]), ("j", "jerk [rad/s³]", table["jerk_rad_s3"])]
        stacked_traces(axes, x, rows)
        ax_o, ax_w, ax_a, ax_j = axes
        s = summary
        mark(ax_o, float(x[-1]), float(table["output_angle_deg"][-1]), f"h = {s['displacement_deg']:.4g}°",
              COLORS["s"], above=False)
        w_at = s["omega_input_angle_deg"]
        mark(ax_w, w_at, float(np.interp(w_at, x, table["omega_rad_s"])), f"ωmax = {s['omega_rad_s']:.4g} rad/s",
              COLORS["v"], above=True)
        mark(ax_a, s["alpha_pos_input_angle_deg"], s["alpha_pos_rad_s2"], f"α+ = {s['alpha_pos_rad_s2']:.4g} rad/s²",
              COLORS["a"], above=True)
        mark(ax_a, s["alpha_neg_input_angle_deg"], s["alpha_neg_rad_s2"], f"α− = {s['alpha_neg_rad_s2']:.4g} rad/s²",
              COLORS["a"], above=False)
        if s["jerk_pos_rad_s3"] > 0:
            mark(ax_j, s["jerk_pos_input_angle_deg"], s["jerk_pos_rad_s3"],
                  f"jerk+ = {s['jerk_pos_rad_s3']:.4g} rad/s³", COLORS["j"], above=True)
        if s["jerk_neg_rad_s3"] < 0:
            mark(ax_j, s["jerk_neg_input_angle_deg"], s["jerk_neg_rad_s3"],
                  f"jerk− = {s['jerk_neg_rad_s3']:.4g} rad/s³", COLORS["j"], above=False)
        ax_o.set_xlim(float(x[0]), float(x[-1]))
        ax_j.set_xlabel(f"input angle [deg]   (indexing time th = {s['indexing_time_s']:.4g} s)", fontsize=9)
        fig.suptitle(title, fontsize=11)
        return render(fig, fmt, dpi)


#: panels of one chart (stops × indexing angles): more would be unreadable
MAX_PANELS = 16


def check_panels(count: int) -> None:
    """A sweep's chart draws one panel per stops and indexing angle, at most :data:`MAX_PANELS`."""
    if count > MAX_PANELS:
        raise InvalidParameterError(f"the chart draws one panel per stops and indexing angle: at most {MAX_PANELS}, "
                                    f"not {count}; ask for fewer, or for the table (JSON or CSV).", field=("stops",))


def sweep_chart(columns: dict[str, Any], fmt: str, dpi: int = 100) -> bytes:
    """Input torque (service-factored peak) over input speed per curve, a panel per (n, θh)."""
    stops = np.asarray(columns["stops"])
    angles = np.asarray(columns["indexing_angle_deg"])
    speed = np.asarray(columns["speed_rpm"])
    torque = np.asarray(columns["input_torque_nm"])
    catalog = np.asarray(columns["input_torque_catalog_nm"])
    curves = list(dict.fromkeys(columns["curve"]))
    panels = list(dict.fromkeys(zip(stops.tolist(), angles.tolist())))
    check_panels(len(panels))
    cols = min(len(panels), 3)
    rows = math.ceil(len(panels) / cols)
    width, height = 4.0 * cols + 1.0, 3.2 * rows + 0.6
    with LOCK:
        # fixed margins, not the constrained layout: that measures every tick label of every panel
        # again, half the drawing's time (a 9-panel chart 0.68-0.83 s → 0.40-0.56 s)
        fig = figure(width, height, layout=None)
        fig.subplots_adjust(left=0.75 / width, right=1 - 0.25 / width, bottom=0.55 / height,
                            top=1 - 0.65 / height, wspace=0.3, hspace=0.5)
        axes = np.atleast_1d(fig.subplots(rows, cols, squeeze=False)).reshape(-1)
        names = np.asarray(columns["curve"])
        for ax, (n, theta) in zip(axes, panels):
            here = (stops == n) & (angles == theta)
            for k, curve in enumerate(curves):
                sel = here & (names == curve)
                order = np.argsort(speed[sel])
                color = f"C{k % 10}"
                ax.plot(speed[sel][order], torque[sel][order], color=color, marker="o", markersize=3,
                        linewidth=1.4, label=f"{curve}")
                ax.plot(speed[sel][order], catalog[sel][order], color=color, linestyle=":", linewidth=1.0)
            ax.set_title(f"n = {n:g}, θh = {theta:g}°", fontsize=9)
            ax.set_xlabel("input speed [rpm]", fontsize=8)
            ax.set_ylabel("input torque [N·m]", fontsize=8)
            style(ax)
        for ax in axes[len(panels):]:
            ax.set_visible(False)
        axes[0].legend(fontsize=7, title="curve (dotted: catalog form)", title_fontsize=7)
        fig.suptitle("Input torque over speed (service factor applied)", fontsize=11)
        return render(fig, fmt, dpi)
