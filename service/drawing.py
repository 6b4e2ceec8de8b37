"""Drawing charts with matplotlib (Agg) to SVG or PNG: what every domain's charts share.

Only the object API is used (``matplotlib.figure.Figure`` with ``FigureCanvasAgg``), never
pyplot, so no GUI backend and no global figure state is involved. Matplotlib's text layout
keeps some module-level caches, so every drawing holds :data:`LOCK` (a chart takes ~0.1 s).
matplotlib is imported on first use, which keeps the app's start-up time unchanged. The
same drawing always gives the same bytes: no date or software stamp, fixed SVG ids.
"""

from __future__ import annotations

import io
import threading
from typing import TYPE_CHECKING, Any, Literal

from pydantic import ConfigDict, Field

from camcore.work import RENDER_S, WorkEstimate, WorkTerm, chart_s
from service.specs import DeferredModel

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: every drawing holds it (matplotlib's text layout caches are module-level)
LOCK = threading.Lock()
#: the colours of S (or position), V, A, J and Q everywhere
COLORS = {"s": "#1f77b4", "v": "#2ca02c", "a": "#d62728", "j": "#9467bd", "q": "#8c564b"}
#: points per trace a chart may ask for
MAX_PLOT_SAMPLES = 2001


class ChartQuery(DeferredModel):
    """What every chart's query has: the PNG resolution (the format is ``?format=``)."""

    model_config = ConfigDict(extra="ignore")

    dpi: int = Field(100, ge=50, le=300, description="PNG resolution (the chart is 8 × 8.5 in, or 10 × 6 in)")


def chart_work(fmt: str, dpi: int, render_s: float = RENDER_S) -> WorkEstimate:
    """Drawing and encoding one chart (camcore.work.chart_s), at the request's field that drives it."""
    return WorkEstimate((WorkTerm(("dpi",) if fmt == "png" else ("format",), "drawing the chart",
                                  chart_s(fmt, dpi, render_s)),))


def figure(width_in: float, height_in: float, layout: Literal["constrained"] | None = "constrained") -> Figure:
    """A figure of that size [in]; laid out by matplotlib's constrained layout unless ``layout`` is None."""
    from matplotlib.figure import Figure

    return Figure(figsize=(width_in, height_in), layout=layout)


def render(fig: Figure, fmt: str, dpi: int) -> bytes:
    """The figure's bytes (hold :data:`LOCK`)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig)
    buf = io.BytesIO()
    # no date or software stamp, so the same request gives the same bytes
    metadata: dict[str, Any] = {"Date": None} if fmt == "svg" else {"Software": None}
    import matplotlib

    # fixed salt: SVG element ids are then a function of the drawing (rcParams are global,
    # which is safe here because every drawing holds LOCK)
    with matplotlib.rc_context({"svg.hashsalt": "camcore"}):
        fig.savefig(buf, format=fmt, dpi=dpi, metadata=metadata, facecolor="white")
    return buf.getvalue()


def style(ax: Axes) -> None:
    """A light grid and the zero line."""
    ax.grid(True, color="#dddddd", linewidth=0.6)
    ax.axhline(0.0, color="#888888", linewidth=0.6)
    ax.tick_params(labelsize=8)


def mark(ax: Axes, x: float, y: float, text: str, color: str, above: bool) -> None:
    """A dot at a characteristic value with its label, kept inside the axes: labels of points
    in the right part of the x range are written to the left of the dot. Call after the plot
    whose x range it uses."""
    x0, x1 = ax.dataLim.intervalx
    right = x > x0 + 0.6 * (x1 - x0)
    ax.plot([x], [y], "o", color=color, markersize=4, zorder=3)
    text = text.replace("-", "\N{MINUS SIGN}")  # as on the tick labels
    ax.annotate(text, (x, y), xytext=(-6 if right else 6, 4 if above else -4), textcoords="offset points",
                fontsize=8, color=color, ha="right" if right else "left", va="bottom" if above else "top",
                bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none", "alpha": 0.8})


def stacked_traces(axes: Any, x: Any, rows: list[tuple[str, str, Any]]) -> None:
    """One trace per axes, stacked over a shared x: (colour key, label, values) each."""
    for ax, (key, label, y) in zip(axes, rows, strict=True):
        ax.plot(x, y, color=COLORS[key], linewidth=1.4)
        ax.set_ylabel(label, fontsize=9)
        style(ax)
        ax.margins(x=0.0, y=0.18)


def shade_spans(ax: Axes, spans: Any, y: float) -> None:
    """The lift schedule's stretches (label, start, end) shaded in turn and named at height ``y``
    (a fraction of the axes)."""
    for i, (label, start, end) in enumerate(spans):
        ax.axvspan(start, end, color="#f2f2f2" if i % 2 else "#e6eef7", zorder=0, linewidth=0)
        ax.text((start + end) / 2, y, label, transform=ax.get_xaxis_transform(), ha="center", va="bottom",
                fontsize=8, color="#555555")
