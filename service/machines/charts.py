"""The machine's charts: the timing diagram and the camshaft torque. Drawn with service.drawing."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from camcore.machine import Machine, RuleResult
from camcore.machine.rules import FULL, master_spans
from service.drawing import LOCK, figure, mark, render, style

#: the band of one axis in the timing diagram: its normalised position drawn in 0…TRACE of it
TRACE = 0.8


def timing_chart(machine: Machine, timing: dict[str, Any], rules: Sequence[RuleResult], speed_rpm: float,
                 fmt: str, dpi: int = 100) -> bytes:
    """Every axis's normalised position stacked over the master angle (the first axis on top), its dwells
    shaded, and the master angles where a rule is broken marked across all axes in red."""
    x = np.asarray(timing["x_deg"])
    axes = machine.axes
    n = len(axes)
    with LOCK:
        fig = figure(10.0, 1.0 + 0.9 * n)
        ax = fig.subplots()
        for k, axis in enumerate(axes):
            base = n - 1 - k
            for a, b in master_spans([(math.degrees(lo), math.degrees(hi)) for lo, hi in axis.dwells()], axis.phase_deg):
                ax.fill_between([a, b], base, base + TRACE, color="#e6eef7", linewidth=0, zorder=0)
            ax.plot(x, base + TRACE * np.asarray(timing[f"{axis.name}_normalised"]), color=f"C{k % 10}",
                    linewidth=1.5)
            ax.text(-4.0, base + TRACE / 2, f"{axis.name}\n({axis.kind}, φ = {axis.phase_deg:g}°)", ha="right",
                    va="center", fontsize=8)
        broken = False
        for rule in rules:
            for v in rule.violations:
                stretches = [(v.from_deg, v.to_deg)] if v.to_deg >= v.from_deg else [(v.from_deg, FULL),
                                                                                   (0.0, v.to_deg)]
                for a, b in stretches:
                    ax.axvspan(a, b, color="#d62728", alpha=0.18, linewidth=0, zorder=1)
                broken = True
        ax.set_xlim(0.0, 360.0)
        ax.set_ylim(-0.1, n - 0.1)
        ax.set_yticks([])
        ax.set_xticks(np.arange(0, 361, 30))
        ax.grid(True, axis="x", color="#dddddd", linewidth=0.6)
        ax.tick_params(labelsize=8)
        ax.set_xlabel(f"master angle [deg]   (shaded: dwells{'; red: a timing rule broken' if broken else ''})",
                      fontsize=9)
        fig.suptitle(f"Timing diagram at {speed_rpm:g} rpm (positions normalised 0…1)", fontsize=11)
        return render(fig, fmt, dpi)


def torque_chart(torque: dict[str, Any], summary: dict[str, Any], fmt: str, dpi: int = 100) -> bytes:
    """Each axis's camshaft torque (thin), the total (thick) with its peak and mean, and with a drive and a
    flywheel the camshaft torque the motor carries then (dashed; the rest the flywheel gives and takes back)."""
    x = np.asarray(torque["x_deg"])
    with LOCK:
        fig = figure(10.0, 6.0)
        ax = fig.subplots()
        names = [name for name in torque if name.endswith("_nm") and name not in
                 ("total_nm", "motor_nm", "carried_by_motor_nm", "motor_with_flywheel_nm")]
        for k, name in enumerate(names):
            ax.plot(x, torque[name], color=f"C{(k + 1) % 10}", linewidth=1.0, label=name[:-3])
        ax.plot(x, torque["total_nm"], color="black", linewidth=2.0, label="total")
        ax.axhline(summary["mean_total_nm"], color="#555555", linestyle=":", linewidth=1.0, label="mean")
        style(ax)
        mark(ax, summary["peak_total_at_deg"], float(np.interp(summary["peak_total_at_deg"], x, torque["total_nm"])),
             f"peak {summary['peak_total_nm']:.4g} N·m", "black", above=True)
        ax.set_xlim(0.0, 360.0)
        ax.set_xlabel("master angle [deg]", fontsize=9)
        ax.set_ylabel("torque on the camshaft [N·m]", fontsize=9)
        ax.legend(fontsize=8, loc="best")
        fw = summary.get("system_inertia_kgm2")
        note = "" if not fw else f";  ΔE = {summary['energy_fluctuation_j']:.4g} J, I = {fw:.4g} kg·m²"
        if "carried_by_motor_nm" in torque:
            ax.plot(x, torque["carried_by_motor_nm"], color="#d62728", linestyle="--", linewidth=1.2,
                    label="carried by the motor, with the flywheel")
        fig.suptitle(f"Camshaft torque at {summary['speed_rpm']:g} rpm{note}", fontsize=11)
        return render(fig, fmt, dpi)
