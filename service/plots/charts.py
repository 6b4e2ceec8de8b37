"""Charts of curves, indexer motion and cam profiles, drawn with matplotlib (Agg) to SVG or PNG.

The drawing functions take arrays or camcore results and return bytes; :class:`PlotService`
turns the query parameters of the GET plot endpoints into specs, computes with the existing
services (so caches, limits and errors are the same as for the JSON endpoints) and draws.

Only the object API is used (``matplotlib.figure.Figure`` with ``FigureCanvasAgg``), never
pyplot, so no GUI backend and no global figure state is involved. Matplotlib's text layout
keeps some module-level caches, so drawing is serialised with a lock (a chart takes ~0.1 s).
matplotlib is imported on first use, which keeps the app's start-up time unchanged.
"""

from __future__ import annotations

import io
import threading
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from fastapi import Request
from fastapi.exceptions import RequestValidationError
from pydantic import BaseModel, ConfigDict, Field, ValidationError

import camcore
from camcore.work import WorkEstimate, WorkTerm
from service.curves.service import CurveService
from service.curves.specs import NamedCurveSpec
from service.errors import relocate, within
from service.indexers.service import IndexerService
from service.indexers.specs import IndexerSpec
from service.profiles.service import ProfileService
from service.profiles.specs import FollowerSpec, ProfileSpec, SegmentSpec

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from camcore.curves import Characteristics, CurveValues
    from camcore.profile import ProfileResult

ImageFormat = Literal["svg", "png"]
MEDIA_TYPES: dict[str, str] = {"svg": "image/svg+xml", "png": "image/png"}
#: the 200 answer of every plot endpoint in the OpenAPI document
IMAGE_RESPONSE: dict[str, Any] = {
    "content": {
        "image/svg+xml": {"schema": {"type": "string"}},
        "image/png": {"schema": {"type": "string", "format": "binary"}},
    },
    "description": "The chart as SVG (default) or PNG",
}
MAX_PLOT_SAMPLES = 2001
#: rendering one chart on the reference machine (camcore.work), measured with 2 001 points:
#: SVG 0.20-0.35 s, PNG at 300 dpi 0.39-0.75 s; the estimate is 0.35 s plus, for PNG,
#: 0.45 s × (dpi/300)², ×1.15
RENDER_S = 0.35
PNG_AT_300_DPI_S = 0.45

_LOCK = threading.Lock()
_COLORS = {"s": "#1f77b4", "v": "#2ca02c", "a": "#d62728", "j": "#9467bd", "q": "#8c564b"}


# ----------------------------------------------------------------------------- query models
class PlotQuery(BaseModel):
    """Parameters common to every chart."""

    model_config = ConfigDict(extra="ignore")

    format: ImageFormat = Field("svg", description="svg (default) or png")
    dpi: int = Field(100, ge=50, le=300, description="PNG resolution (the chart is 8 × 8.5 in, or 10 × 6 in)")


class CurvePlotQuery(PlotQuery):
    direction: Literal["rise", "return"] = "rise"
    samples: int = Field(401, ge=11, le=MAX_PLOT_SAMPLES, description="points per trace")


class IndexerPlotQuery(PlotQuery):
    """The fields of IndexerSpec, with the curve given by its catalog name."""

    stops: int | None = Field(None, ge=1, le=100_000, description="n, stops per output turn")
    swing_angle_deg: float | None = Field(None, gt=0, le=360, allow_inf_nan=False,
                                          description="ψ, output swing (instead of stops)")
    indexing_angle_deg: float = Field(gt=0, le=360, allow_inf_nan=False, description="θh, input angle per index")
    dwells: int = Field(1, ge=1, le=360, description="z, indexes per input turn")
    speed_rpm: float | None = Field(None, gt=0, le=1e6, allow_inf_nan=False, description="N, input speed")
    cycle_time_s: float | None = Field(None, gt=0, le=1e6, allow_inf_nan=False,
                                       description="t0, unit cycle time (instead of speed_rpm)")
    input_stop_time_s: float = Field(0.0, ge=0, le=1e6, allow_inf_nan=False)
    curve: str = Field("MS", min_length=1, max_length=80, description="catalog curve: id, alias or Makino number")
    samples: int = Field(401, ge=11, le=MAX_PLOT_SAMPLES)


class ProfilePlotQuery(PlotQuery):
    """A simple lift schedule: rise, dwell, return, and a dwell to 360° at the base circle."""

    follower: Literal["knife-edge", "roller", "flat-faced"] = "roller"
    motion: Literal["translating", "oscillating"] = "translating"
    base_radius_mm: float = Field(40.0, gt=0, le=1e5, allow_inf_nan=False)
    roller_radius_mm: float = Field(10.0, ge=0, le=1e5, allow_inf_nan=False,
                                    description="roller follower only (ignored otherwise)")
    offset_mm: float = Field(0.0, ge=-1e5, le=1e5, allow_inf_nan=False)
    arm_length_mm: float | None = Field(None, gt=0, le=1e5, allow_inf_nan=False, description="oscillating")
    pivot_distance_mm: float | None = Field(None, gt=0, le=1e5, allow_inf_nan=False, description="oscillating")
    rise_deg: float = Field(120.0, gt=0, le=360, allow_inf_nan=False)
    dwell_deg: float = Field(60.0, ge=0, le=360, allow_inf_nan=False, description="dwell at full lift")
    return_deg: float = Field(120.0, gt=0, le=360, allow_inf_nan=False)
    lift_mm: float | None = Field(20.0, ge=0, le=1e5, allow_inf_nan=False, description="translating")
    swing_deg: float | None = Field(None, ge=0, le=180, allow_inf_nan=False, description="oscillating")
    curve: str = Field("cycloid", min_length=1, max_length=80, description="catalog curve of rise and return")
    rotation: Literal["ccw", "cw"] = "ccw"
    samples: int = Field(721, ge=11, le=MAX_PLOT_SAMPLES)


def _query_error(exc: ValidationError) -> RequestValidationError:
    """A spec built from query parameters failed: answer 422 like any invalid query."""
    errors = [{"type": e.get("type", "value_error"), "loc": ("query", *e.get("loc", ())), "msg": e.get("msg", ""),
               "input": None} for e in exc.errors()]
    return RequestValidationError(errors)


# ----------------------------------------------------------------------------- the service
class PlotService:
    """Specs from query parameters, numbers from the existing services, charts as bytes."""

    def __init__(self, curves: CurveService, indexers: IndexerService, profiles: ProfileService):
        self.curves = curves
        self.indexers = indexers
        self.profiles = profiles

    @staticmethod
    def render_work(q: PlotQuery) -> WorkEstimate:
        """Drawing and encoding one chart."""
        png = PNG_AT_300_DPI_S * (q.dpi / 300) ** 2 if q.format == "png" else 0.0
        return WorkEstimate((WorkTerm(("dpi",) if q.format == "png" else ("format",), "drawing the chart",
                                      1.15 * (RENDER_S + png)),))

    def profile_work(self, q: ProfilePlotQuery) -> WorkEstimate:
        spec = self.profile_spec(q)
        with relocate(("profile",), (), keep_rest=False):
            return self.profiles.profile_work(spec, q.samples, None, "json") + self.render_work(q)

    def curve_plot(self, name: str, q: CurvePlotQuery) -> bytes:
        with within("path"):
            entry = camcore.lookup(name)
        curve = self.curves.curve(NamedCurveSpec(name=entry.id, direction=q.direction))
        values = curve.evaluate(curve.sample_times(q.samples))
        title = f"{entry.id} — {entry.name}" + (" (return)" if q.direction == "return" else "")
        return svaj_chart(values, curve.characteristics, title, q.format, q.dpi)

    def indexer_spec(self, q: IndexerPlotQuery) -> IndexerSpec:
        with within("curve", keep_field=False):
            camcore.lookup(q.curve)
        fields = q.model_dump(exclude={"format", "dpi", "samples", "curve"})
        try:
            return IndexerSpec(**fields, curve=NamedCurveSpec(name=q.curve))
        except ValidationError as exc:
            raise _query_error(exc) from None

    def indexer_plot(self, q: IndexerPlotQuery) -> bytes:
        spec = self.indexer_spec(q)
        with relocate(("indexer",), ()):  # the indexer's fields are the query's
            summary, table = self.indexers.motion(spec, q.samples)
        name = camcore.lookup(q.curve).id
        unit = f"{spec.stops} stops" if spec.stops is not None else f"swing {spec.swing_angle_deg:g}°"
        speed = f"{summary['speed_rpm']:g} rpm"
        title = f"Indexer: {unit}, θh = {spec.indexing_angle_deg:g}°, {speed}, curve {name}"
        return indexer_chart(table, summary, title, q.format, q.dpi)

    def profile_spec(self, q: ProfilePlotQuery) -> ProfileSpec:
        rest = 360.0 - q.rise_deg - q.dwell_deg - q.return_deg
        if rest < -1e-9:
            raise RequestValidationError([{
                "type": "value_error", "loc": ("query", "return_deg"), "input": None,
                "msg": f"rise_deg + dwell_deg + return_deg must not exceed 360°, but they add to "
                       f"{q.rise_deg + q.dwell_deg + q.return_deg:g}°"}])
        oscillating = q.motion == "oscillating"
        amount: dict[str, float | None] = (
            {"swing_deg": q.swing_deg if q.swing_deg is not None else 20.0} if oscillating
            else {"lift_mm": q.lift_mm if q.lift_mm is not None else 0.0})
        with within("curve", keep_field=False):
            camcore.lookup(q.curve)
        law = NamedCurveSpec(name=q.curve)
        try:
            segments = [SegmentSpec(type="rise", angle_deg=q.rise_deg, curve=law, **amount)]
            if q.dwell_deg > 0:
                segments.append(SegmentSpec(type="dwell", angle_deg=q.dwell_deg))
            segments.append(SegmentSpec(type="return", angle_deg=q.return_deg, curve=law, **amount))
            if rest > 1e-9:
                segments.append(SegmentSpec(type="dwell", angle_deg=rest))
            else:  # absorb rounding so the angles add to exactly 360°
                last = segments[-1]
                segments[-1] = last.model_copy(update={"angle_deg": last.angle_deg + rest})
            follower = FollowerSpec(
                type=q.follower, motion=q.motion, offset_mm=q.offset_mm,
                roller_radius_mm=q.roller_radius_mm if q.follower == "roller" else 0.0,
                arm_length_mm=q.arm_length_mm, pivot_distance_mm=q.pivot_distance_mm)
            return ProfileSpec(follower=follower, base_radius_mm=q.base_radius_mm, rotation=q.rotation,
                               segments=segments)
        except ValidationError as exc:
            raise _query_error(exc) from None

    def profile_plot(self, q: ProfilePlotQuery) -> bytes:
        spec = self.profile_spec(q)
        with relocate(("profile",), (), keep_rest=False):  # the query is flat: point at all of it
            result = self.profiles.profile(spec, q.samples, None)
        name = camcore.lookup(q.curve).id
        f = spec.follower
        roller = f", roller r = {f.roller_radius_mm:g} mm" if f.type == "roller" else ""
        offset = f", offset e = {f.offset_mm:g} mm" if f.offset_mm else ""
        arm = (f", arm {f.arm_length_mm:g} mm, pivot at {f.pivot_distance_mm:g} mm"
               if f.motion == "oscillating" and f.arm_length_mm is not None else "")
        assert spec.segments is not None
        rise = spec.segments[0]
        stroke = f"swing {rise.swing_deg:g}°" if rise.swing_deg is not None else f"lift {rise.lift_mm:g} mm"
        title = (f"Cam profile: {f.motion} {f.type} follower{arm}, {stroke}\n"
                 f"base r = {spec.base_radius_mm:g} mm{roller}{offset}")
        spans, start = [], 0.0
        for seg in spec.segments:
            spans.append((seg.type, start, start + seg.angle_deg))
            start += seg.angle_deg
        law = f"law {name}, {'counter-clockwise' if spec.rotation == 'ccw' else 'clockwise'} rotation"
        return profile_chart(result, spec.base_radius_mm, f.type, title, law, q.format, q.dpi, spans)


def plot_service(request: Request) -> PlotService:
    """The app's PlotService, built on first use from the services already on ``app.state``."""
    state = request.app.state
    service: PlotService | None = getattr(state, "plot_service", None)
    if service is None:
        service = PlotService(state.curve_service, state.indexer_service, state.profile_service)
        state.plot_service = service
    return service


# ----------------------------------------------------------------------------- drawing
def _figure(width_in: float, height_in: float) -> Figure:
    from matplotlib.figure import Figure

    return Figure(figsize=(width_in, height_in), layout="constrained")


def _render(fig: Figure, fmt: str, dpi: int) -> bytes:
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig)
    buf = io.BytesIO()
    # no date or software stamp, so the same request gives the same bytes
    metadata: dict[str, Any] = {"Date": None} if fmt == "svg" else {"Software": None}
    import matplotlib

    # fixed salt: SVG element ids are then a function of the drawing (rcParams are global,
    # which is safe here because every drawing holds _LOCK)
    with matplotlib.rc_context({"svg.hashsalt": "camcore"}):
        fig.savefig(buf, format=fmt, dpi=dpi, metadata=metadata, facecolor="white")
    return buf.getvalue()


def _style(ax: Axes) -> None:
    ax.grid(True, color="#dddddd", linewidth=0.6)
    ax.axhline(0.0, color="#888888", linewidth=0.6)
    ax.tick_params(labelsize=8)


def _mark(ax: Axes, x: float, y: float, text: str, color: str, above: bool) -> None:
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


def svaj_chart(values: CurveValues, ch: Characteristics, title: str, fmt: str = "svg", dpi: int = 100) -> bytes:
    """S, V, A, J over T on four stacked axes sharing T, with Vm, Am±, Jm± marked."""
    with _LOCK:
        fig = _figure(8.0, 8.5)
        axes = fig.subplots(4, 1, sharex=True)
        t = values.t
        rows = [("s", "S (displacement)", values.s), ("v", "V (velocity)", values.v),
                ("a", "A (acceleration)", values.a), ("j", "J (jerk)", values.j)]
        for ax, (key, label, y) in zip(axes, rows, strict=True):
            ax.plot(t, y, color=_COLORS[key], linewidth=1.4)
            ax.set_ylabel(label, fontsize=9)
            _style(ax)
            ax.margins(x=0.0, y=0.18)
        ax_s, ax_v, ax_a, ax_j = axes
        v_at = float(np.interp(ch.vm.t, t, values.v))
        _mark(ax_v, ch.vm.t, v_at, f"Vm = {ch.vm.value:.4f} at T = {ch.vm.t:.4f}", _COLORS["v"], above=v_at >= 0)
        if ch.am_pos.value > 0:
            _mark(ax_a, ch.am_pos.t, ch.am_pos.value, f"Am+ = {ch.am_pos.value:.4f} at T = {ch.am_pos.t:.4f}",
                  _COLORS["a"], above=True)
        if ch.am_neg.value < 0:
            _mark(ax_a, ch.am_neg.t, ch.am_neg.value, f"Am− = {ch.am_neg.value:.4f} at T = {ch.am_neg.t:.4f}",
                  _COLORS["a"], above=False)
        if ch.jm_pos.value > 0:
            _mark(ax_j, ch.jm_pos.t, ch.jm_pos.value, f"Jm+ = {ch.jm_pos.value:.2f}", _COLORS["j"], above=True)
        if ch.jm_neg.value < 0:
            _mark(ax_j, ch.jm_neg.t, ch.jm_neg.value, f"Jm− = {ch.jm_neg.value:.2f}", _COLORS["j"], above=False)
        ax_s.set_xlim(float(t[0]), float(t[-1]))
        ax_j.set_xlabel("T (dimensionless time)", fontsize=9)
        fig.suptitle(title, fontsize=11)
        return _render(fig, fmt, dpi)


def indexer_chart(table: dict[str, np.ndarray], summary: dict[str, Any], title: str, fmt: str = "svg",
                  dpi: int = 100) -> bytes:
    """Output angle, ω, α and jerk over the input angle of one index, peaks marked."""
    with _LOCK:
        fig = _figure(8.0, 8.5)
        axes = fig.subplots(4, 1, sharex=True)
        x = table["input_angle_deg"]
        rows = [("s", "output angle [deg]", table["output_angle_deg"]), ("v", "ω [rad/s]", table["omega_rad_s"]),
                ("a", "α [rad/s²]", table["alpha_rad_s2"]), ("j", "jerk [rad/s³]", table["jerk_rad_s3"])]
        for ax, (key, label, y) in zip(axes, rows, strict=True):
            ax.plot(x, y, color=_COLORS[key], linewidth=1.4)
            ax.set_ylabel(label, fontsize=9)
            _style(ax)
            ax.margins(x=0.0, y=0.18)
        ax_o, ax_w, ax_a, ax_j = axes
        s = summary
        _mark(ax_o, float(x[-1]), float(table["output_angle_deg"][-1]), f"h = {s['displacement_deg']:.4g}°",
              _COLORS["s"], above=False)
        w_at = s["omega_input_angle_deg"]
        _mark(ax_w, w_at, float(np.interp(w_at, x, table["omega_rad_s"])), f"ωmax = {s['omega_rad_s']:.4g} rad/s",
              _COLORS["v"], above=True)
        _mark(ax_a, s["alpha_pos_input_angle_deg"], s["alpha_pos_rad_s2"], f"α+ = {s['alpha_pos_rad_s2']:.4g} rad/s²",
              _COLORS["a"], above=True)
        _mark(ax_a, s["alpha_neg_input_angle_deg"], s["alpha_neg_rad_s2"], f"α− = {s['alpha_neg_rad_s2']:.4g} rad/s²",
              _COLORS["a"], above=False)
        if s["jerk_pos_rad_s3"] > 0:
            _mark(ax_j, s["jerk_pos_input_angle_deg"], s["jerk_pos_rad_s3"],
                  f"jerk+ = {s['jerk_pos_rad_s3']:.4g} rad/s³", _COLORS["j"], above=True)
        if s["jerk_neg_rad_s3"] < 0:
            _mark(ax_j, s["jerk_neg_input_angle_deg"], s["jerk_neg_rad_s3"],
                  f"jerk− = {s['jerk_neg_rad_s3']:.4g} rad/s³", _COLORS["j"], above=False)
        ax_o.set_xlim(float(x[0]), float(x[-1]))
        ax_j.set_xlabel(f"input angle [deg]   (indexing time th = {s['indexing_time_s']:.4g} s)", fontsize=9)
        fig.suptitle(title, fontsize=11)
        return _render(fig, fmt, dpi)


def profile_chart(result: ProfileResult, base_radius_mm: float, follower_type: str, title: str, law: str,
                  fmt: str = "svg", dpi: int = 100, spans: Sequence[tuple[str, float, float]] = ()) -> bytes:
    """The cam contour with base circle (and pitch curve for rollers), and pressure angle over cam angle.

    ``spans``: (label, start_deg, end_deg) of the lift schedule, shaded and named on the pressure-angle axes.
    """
    with _LOCK:
        fig = _figure(10.0, 6.0)
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
            ax_p.plot(result.cam_angle_deg, result.contact_offset_mm, color=_COLORS["q"], linewidth=1.4)
        else:
            ax_p.plot(result.cam_angle_deg, result.pressure_angle_deg, color=_COLORS["a"], linewidth=1.4)
        _style(ax_p)
        for i, (label, start, end) in enumerate(spans):
            ax_p.axvspan(start, end, color="#f2f2f2" if i % 2 else "#e6eef7", zorder=0, linewidth=0)
            ax_p.text((start + end) / 2, 0.02, label, transform=ax_p.get_xaxis_transform(), ha="center",
                      va="bottom", fontsize=8, color="#555555")
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
            _mark(ax_p, at, ch.max_pressure_angle_signed_deg,
                  f"max |φ| = {ch.max_pressure_angle_deg:.2f}° at {at:.1f}°", _COLORS["a"],
                  above=ch.max_pressure_angle_signed_deg >= 0)
            ax_p.set_ylabel("pressure angle φ [deg]", fontsize=9)
            ax_p.set_title(f"pressure angle\n{note}", fontsize=9)
        fig.suptitle(title, fontsize=11)
        return _render(fig, fmt, dpi)


__all__ = [
    "IMAGE_RESPONSE", "MEDIA_TYPES", "CurvePlotQuery", "IndexerPlotQuery", "PlotService", "ProfilePlotQuery",
    "indexer_chart", "plot_service", "profile_chart", "svaj_chart",
]
