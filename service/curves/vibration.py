"""Residual vibration of a curve: ``POST /v1/curves/vibration`` (its spectrum over τ) and
``GET /v1/curves/vibration/plot`` (the spectra of catalog curves on one chart).

Model (camcore.dynamics): a single-degree-of-freedom follower driven through the curve, τ =
th·fn the motion time over the natural period; the answers are fractions of the stroke.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Annotated, Any, Literal

import numpy as np
from fastapi.openapi.models import Example
from pydantic import BeforeValidator, Field, model_validator

import camcore
from camcore.curves import Law
from camcore.dynamics import TAU_MAX, TAU_MIN, ResidualVibration, residual_amplitude, residual_vibration
from camcore.work import (
    SPECTRUM_COLUMNS,
    SPECTRUM_RENDER_S,
    WorkEstimate,
    encode_cost,
    estimated_cells,
    per_item_work,
    vibration_work,
)
from service.context import Context
from service.curves.charts import spectrum_chart
from service.curves.library import check_limit
from service.curves.specs import MS_SPEC, CurveSpec
from service.drawing import MAX_PLOT_SAMPLES, ChartQuery, chart_work
from service.errors import Location, relocate, within
from service.models import answer_model
from service.operations import JSON, PNG, SVG, Format, Operation, Payload, Table, csv
from service.specs import JSON_INTEGER, Spec, exactly_one, examples, rule

#: τ = th·fn within camcore's range (camcore.dynamics.vibration.TAU_MIN, TAU_MAX say why)
Tau = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=TAU_MIN, le=TAU_MAX)]
#: ζ: underdamped only; at ζ ≥ 1 nothing vibrates and the envelope is undefined (ωd = 0)
DampingRatio = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0, lt=1)]
#: the kinds in closed form: built in a few ms, before the limits are checked (check_law)
CLOSED_FORM_KINDS = ("named", "makino", "universal", "polynomial")
#: at most this many curves on one chart (they must stay apart in the legend and the colours)
MAX_CURVES = 8


class TauRange(Spec):
    """``samples`` values of τ evenly from ``start`` to ``stop`` (both included; either order)."""

    model_config = examples({"start": 0.5, "stop": 10, "samples": 96})
    start: Tau
    stop: Tau
    samples: Annotated[int, Field(ge=2), JSON_INTEGER] = Field(description="at least 2")


class VibrationRequest(Spec):
    model_config = examples(
        {"curve": MS_SPEC, "damping_ratio": 0, "tau_range": {"start": 0.5, "stop": 10, "samples": 96}},
        rules=[rule("give either tau (a list of values) or tau_range: one of them, not both", exactly_one("tau", "tau_range"))])
    curve: CurveSpec
    damping_ratio: DampingRatio = Field(0.0, description="ζ, 0 ≤ ζ < 1 (underdamped; ζ ≥ 1 is refused)")
    # minItems states the validator's rule in the schema (the validator gives the sentence)
    tau: Annotated[list[Tau], Field(json_schema_extra={"minItems": 1})] | None = Field(
        None, description=f"τ = th·fn (motion time over natural period) values, each {TAU_MIN:g} … {TAU_MAX:g}")
    tau_range: TauRange | None = Field(None, description="evenly spaced τ values instead of tau")

    @model_validator(mode="after")
    def _check(self) -> VibrationRequest:
        if (self.tau is None) == (self.tau_range is None):
            raise ValueError("give either tau (a list of values) or tau_range: one of them, not both")
        if self.tau is not None and len(self.tau) == 0:
            raise ValueError("tau must list at least one value")
        return self


VIBRATION_EXAMPLES: dict[str, Example] = {
    "MS": {"summary": "MS, undamped, τ from 0.5 to 10",
           "description": "the residual-vibration spectrum of the modified sine",
           "value": {"curve": MS_SPEC, "damping_ratio": 0, "tau_range": {"start": 0.5, "stop": 10, "samples": 96}}},
    "cycloid": {"summary": "cycloid at τ = 1, 2, 3",
                "description": "undamped: 0.5 at τ = 1, nothing at every integer τ ≥ 2",
                "value": {"curve": {"type": "named", "name": "cycloid"}, "tau": [1, 2, 3]}},
}
VibrationTableAnswer = answer_model(ResidualVibration, "ResidualVibrationTable",
                                    "Columns over τ: residual amplitude and peak deviation as fractions of the stroke.")


# ----------------------------------------------------------------------------- the spectrum
def check_law(ctx: Context, law: Law, at: Location) -> None:
    """A closed-form curve is built now, through the cache (a few ms): Makino's curves check their
    parameters only when built, and a spec that breaks its own rules is a 422 before any size
    limit is a 413."""
    if law.kind in CLOSED_FORM_KINDS:
        ctx.curves.curve(law, at)


def check_tau_count(ctx: Context, count: int, field: Location) -> None:
    """413 when a spectrum asks for more τ values than the setting allows."""
    check_limit("number of τ values", count, ctx.settings.max_vibration_tau_values, field)


@dataclass(frozen=True)
class Spectrum:
    """A law's response at τ values: a list, or ``(start, stop, samples)`` made into one only once
    its count has passed the limit; from ``field`` of the request."""

    law: Law
    tau: list[float] | tuple[float, float, int]
    field: Location
    damping_ratio: float = 0.0
    at: Location = ("curve",)

    @property
    def count(self) -> int:
        return len(self.tau) if isinstance(self.tau, list) else self.tau[2]

    def values(self) -> np.ndarray:
        if isinstance(self.tau, list):
            return np.asarray(self.tau, dtype=np.float64)
        return np.linspace(*self.tau)


def _spectrum_request(ctx: Context, body: VibrationRequest, path: Mapping[str, str]) -> Spectrum:
    if body.tau is not None:
        return Spectrum(body.curve.core(), body.tau, ("tau",), body.damping_ratio)
    assert body.tau_range is not None  # the request's rule
    r = body.tau_range
    return Spectrum(body.curve.core(), (r.start, r.stop, r.samples), ("tau_range", "samples"), body.damping_ratio)


def spectrum_work(ctx: Context, job: Spectrum, csv_answer: bool | None, peak: bool = True) -> WorkEstimate:
    """A spectrum: the τ count first (413), the curve, the response at each τ (the residual
    amplitude alone unless ``peak``), the columns encoded (``csv_answer`` None: not encoded)."""
    check_law(ctx, job.law, job.at)
    check_tau_count(ctx, job.count, job.field)
    cost = ctx.curves.cost(job.law, job.at)
    # the curve, unless it is cached, then its response
    work = ctx.curves.build_work(job.law, cost, job.at) + vibration_work(
        cost, estimated_cells(job.law.kind, job.law.parameters), job.values().tolist(), job.field, peak)
    if csv_answer is None:
        return work
    return work + per_item_work(job.count, encode_cost(SPECTRUM_COLUMNS, csv_answer), job.field,
                                f"{job.count} rows encoded")


def spectrum(ctx: Context, job: Spectrum) -> dict[str, np.ndarray]:
    check_tau_count(ctx, job.count, job.field)
    # camcore names the argument an error is about (curve, tau, damping_ratio): the request's fields
    return residual_vibration(ctx.curves.curve(job.law, job.at), job.values(), job.damping_ratio).columns()


# ----------------------------------------------------------------------------- the chart
_LABELS = {"residual_amplitude": "residual amplitude / stroke h", "peak_deviation": "peak deviation during the motion / h"}


def _names(value: object) -> object:
    """Names given as ?curves=MS&curves=TR or ?curves=MS,TR."""
    if isinstance(value, str):
        value = [value]
    if isinstance(value, list):
        return [part.strip() for raw in value for part in str(raw).split(",") if part.strip()]
    return value


class SpectrumPlotQuery(ChartQuery):
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


@dataclass(frozen=True)
class SpectrumPlot:
    """A chart's query, its curves' spectra and their legend labels."""

    query: SpectrumPlotQuery
    traces: tuple[Spectrum, ...]
    labels: tuple[str, ...]


def _plot_request(ctx: Context, q: SpectrumPlotQuery, path: Mapping[str, str]) -> SpectrumPlot:
    tau = (q.tau_start, q.tau_stop, q.samples)
    traces, labels = [], []
    for i, name in enumerate(q.curves):
        with within("curves", i, keep_field=False):
            entry = camcore.lookup(name)
        traces.append(Spectrum(Law("named", {"name": entry.id}), tau, ("samples",), q.damping_ratio,
                               ("curves", i)))
        labels.append(entry.id if entry.name.lower() == entry.id.lower() else f"{entry.id} — {entry.name}")
    return SpectrumPlot(q, tuple(traces), tuple(labels))


def _plot_work(ctx: Context, job: SpectrumPlot, fmt: Format) -> WorkEstimate:
    """Every curve's spectrum and the drawing."""
    work = chart_work(fmt.name, job.query.dpi, SPECTRUM_RENDER_S)
    for trace in job.traces:
        work += spectrum_work(ctx, trace, None, peak=job.query.quantity == "peak_deviation")
    return work


def _plot(ctx: Context, job: SpectrumPlot, fmt: Format) -> Payload:
    q = job.query
    traces: list[tuple[str, Any]] = []
    for trace, label in zip(job.traces, job.labels, strict=True):
        check_tau_count(ctx, trace.count, trace.field)
        with relocate(("curve",), trace.at, keep_rest=False):  # the query's curve
            curve = ctx.curves.curve(trace.law, ("curve",))
            if q.quantity == "peak_deviation":
                values = residual_vibration(curve, trace.values(), q.damping_ratio).columns()["peak_deviation"]
            else:
                values = residual_amplitude(curve, trace.values().tolist(), q.damping_ratio)
        traces.append((label, values))
    damping = "undamped" if q.damping_ratio == 0 else f"ζ = {q.damping_ratio:g}"
    what = "Residual vibration" if q.quantity == "residual_amplitude" else "Peak deviation during the motion"
    tau = np.linspace(q.tau_start, q.tau_stop, q.samples)
    return Payload(spectrum_chart(tau, traces, f"{what} over τ = th·fn ({damping})", _LABELS[q.quantity], fmt.name,
                                  q.dpi))


OPERATIONS = (
    Operation("computeResidualVibration", "/v1/curves/vibration", "curves", "Residual vibration of a curve",
              "Residual amplitude and peak deviation (fractions of the stroke) of a follower on the curve, over τ.",
              VibrationRequest, lambda ctx, job, fmt: Table(spectrum(ctx, job)), convert=_spectrum_request,
              estimate=lambda ctx, job, fmt: spectrum_work(ctx, job, fmt.name == "csv"),
              answer=VibrationTableAnswer, formats=(JSON, csv("vibration.csv")), examples=VIBRATION_EXAMPLES),
    Operation("plotResidualVibration", "/v1/curves/vibration/plot", "curves", "Residual vibration chart of catalog curves",
              "The residual-vibration spectra of catalog curves on one chart (log amplitude over τ).",
              SpectrumPlotQuery, _plot, convert=_plot_request, estimate=_plot_work, formats=(SVG, PNG), method="GET",
              examples={"two curves": {"value": {"curves": "MS,cycloid", "samples": 101}}}),
)
