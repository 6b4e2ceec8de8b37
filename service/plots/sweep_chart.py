"""The chart of a sizing sweep: input torque over speed, one line per curve, one panel per
(stops, indexing angle) — the comparison a designer makes before choosing a unit."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from camcore.errors import InvalidParameterError
from service.plots.charts import _LOCK, _figure, _render, _style

#: panels of one chart (stops × indexing angles): more would be unreadable
MAX_PANELS = 16


def sweep_chart(columns: dict[str, Any], fmt: str, dpi: int = 100) -> bytes:
    """Input torque (service-factored peak) over input speed per curve, a panel per (n, θh)."""
    stops = np.asarray(columns["stops"])
    angles = np.asarray(columns["indexing_angle_deg"])
    speed = np.asarray(columns["speed_rpm"])
    torque = np.asarray(columns["input_torque_nm"])
    catalog = np.asarray(columns["input_torque_catalog_nm"])
    curves = list(dict.fromkeys(columns["curve"]))
    panels = list(dict.fromkeys(zip(stops.tolist(), angles.tolist())))
    if len(panels) > MAX_PANELS:
        raise InvalidParameterError(f"the chart draws one panel per stops and indexing angle: at most {MAX_PANELS}, "
                                    f"not {len(panels)}; ask for fewer, or for the table (JSON or CSV).",
                                    field=("stops",))
    cols = min(len(panels), 3)
    rows = math.ceil(len(panels) / cols)
    with _LOCK:
        fig = _figure(4.0 * cols + 1.0, 3.2 * rows + 0.6)
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
            _style(ax)
        for ax in axes[len(panels):]:
            ax.set_visible(False)
        axes[0].legend(fontsize=7, title="curve (dotted: catalog form)", title_fontsize=7)
        fig.suptitle("Input torque over speed (service factor applied)", fontsize=11)
        return _render(fig, fmt, dpi)
