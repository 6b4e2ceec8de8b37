"""The residual-vibration spectrum of several catalog curves on one chart (log amplitude over τ).

The chart a designer uses to choose a curve for a flexible follower or an indexer's load:
for each curve, the amplitude of the vibration left after the motion (or the largest
deviation during it) as a fraction of the stroke, over τ = th·fn. Drawn like the other
charts (service.plots.charts: matplotlib's object API, Agg, one drawing at a time).
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

import numpy as np
from pydantic import BeforeValidator, Field

import camcore
from camcore.dynamics import TAU_MAX, TAU_MIN
from camcore.work import WorkEstimate
from service.curves.specs import NamedCurveSpec
from service.errors import relocate, within
from service.plots.charts import _LOCK, MAX_PLOT_SAMPLES, PlotQuery, PlotService, _figure, _render
from service.vibration.service import VibrationService

#: at most this many curves on one chart (they must stay apart in the legend and the colours)
MAX_CURVES = 8
#: the log axis has no 0, and an undamped spectrum dips to 0 at its notches (the cycloid at
#: every integer τ ≥ 2): the axis starts a decade below the lowest trace's 10th percentile,
#: not below this, and the notches run to its bottom edge
FLOOR = 1e-9
_COLORS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf")
_LABELS = {"residual_amplitude": "residual amplitude / stroke h", "peak_deviation": "peak deviation during the motion / h"}


def _names(value: object) -> object:
    """Names given as ?curves=MS&curves=TR or ?curves=MS,TR."""
    if isinstance(value, str):
        value = [value]
    if isinstance(value, list):
        return [part.strip() for raw in value for part in str(raw).split(",") if part.strip()]
    return value


class SpectrumPlotQuery(PlotQuery):
    """Catalog curves, damping, the τ range and what to draw."""

    curves: Annotated[list[Annotated[str, Field(min_length=1, max_length=80)]], BeforeValidator(_names)] = Field(
        ["MS", "MT", "TR", "cycloid", "3-4-5"], min_length=1, max_length=MAX_CURVES,
        description="catalog curves (id, alias or Makino number): repeat ?curves= or separate by commas")
    damping_ratio: float = Field(0.0, ge=0, lt=1, allow_inf_nan=False, description="ζ, 0 ≤ ζ < 1")
    tau_start: float = Field(0.5, ge=TAU_MIN, le=TAU_MAX, allow_inf_nan=False, description="first τ = th·fn")
    tau_stop: float = Field(20.0, ge=TAU_MIN, le=TAU_MAX, allow_inf_nan=False, description="last τ")
    samples: int = Field(781, ge=11, le=MAX_PLOT_SAMPLES, description="τ values per curve, evenly spaced")
    quantity: Literal["residual_amplitude", "peak_deviation"] = Field(
        "residual_amplitude", description="residual_amplitude (after the motion) or peak_deviation (during it)")


def _specs(q: SpectrumPlotQuery) -> list[NamedCurveSpec]:
    specs = []
    for i, name in enumerate(q.curves):
        with within("curves", i, keep_field=False):
            specs.append(NamedCurveSpec(name=camcore.lookup(name).id))
    return specs


def spectrum_work(service: VibrationService, q: SpectrumPlotQuery) -> WorkEstimate:
    """Every curve's spectrum and the drawing."""
    tau = np.linspace(q.tau_start, q.tau_stop, q.samples).tolist()
    work = PlotService.render_work(q)
    for i, spec in enumerate(_specs(q)):
        work += service.spectrum_work(spec, tau, None, False, ("curves", i), peak=q.quantity == "peak_deviation")
    return work


def spectrum_plot(service: VibrationService, q: SpectrumPlotQuery) -> bytes:
    """The chart of the query's curves."""
    tau = np.linspace(q.tau_start, q.tau_stop, q.samples)
    traces = []
    for i, spec in enumerate(_specs(q)):
        with relocate(("curve",), ("curves", i), keep_rest=False):  # the query's curve
            if q.quantity == "peak_deviation":
                values = service.spectrum(spec, tau.tolist(), None, q.damping_ratio)["peak_deviation"]
            else:
                values = service.residual(spec, tau.tolist(), q.damping_ratio)
        entry = camcore.lookup(spec.name)
        same = entry.name.lower() == entry.id.lower()
        traces.append((entry.id if same else f"{entry.id} — {entry.name}", values))
    damping = "undamped" if q.damping_ratio == 0 else f"ζ = {q.damping_ratio:g}"
    what = "Residual vibration" if q.quantity == "residual_amplitude" else "Peak deviation during the motion"
    return spectrum_chart(tau, traces, f"{what} over τ = th·fn ({damping})", _LABELS[q.quantity], q.format, q.dpi)


def spectrum_chart(tau: np.ndarray, traces: list[tuple[str, np.ndarray]], title: str, label: str,
                   fmt: str = "svg", dpi: int = 100) -> bytes:
    """Each trace (name, amplitude over τ) on a log axis; see :data:`FLOOR` for where it starts."""
    lows = [float(np.percentile(np.maximum(values, FLOOR), 10)) for _, values in traces]
    bottom = max(FLOOR, 10.0 ** (np.floor(np.log10(min(lows))) - 1))
    top = max(float(np.max(values)) for _, values in traces)
    with _LOCK:
        fig = _figure(10.0, 6.0)
        ax: Any = fig.subplots(1, 1)
        for k, (name, values) in enumerate(traces):
            ax.plot(tau, np.maximum(values, bottom), color=_COLORS[k % len(_COLORS)], linewidth=1.2, label=name)
        ax.set_yscale("log")
        ax.set_ylim(bottom, max(10.0 ** np.ceil(np.log10(max(top, bottom))), 10 * bottom))
        ax.set_xlim(float(tau.min()), float(tau.max()))
        ax.grid(True, which="major", color="#cccccc", linewidth=0.7)
        ax.grid(True, which="minor", color="#eeeeee", linewidth=0.5)
        ax.tick_params(labelsize=8)
        ax.set_xlabel("τ = th·fn (motion time / natural period of the follower)", fontsize=9)
        ax.set_ylabel(label, fontsize=9)
        ax.legend(fontsize=8, loc="upper right", frameon=True, framealpha=0.9)
        if any(float(np.min(values)) < bottom for _, values in traces):
            ax.set_title("a notch running to the bottom edge: a τ where the curve leaves (almost) nothing",
                         fontsize=8, color="#666666")
        fig.suptitle(title, fontsize=11)
        return _render(fig, fmt, dpi)
