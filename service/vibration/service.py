"""The service's bridge to camcore.dynamics: specs in, columns and answers out, with their work."""

from __future__ import annotations

from typing import Any

import numpy as np
from fastapi import Request

import camcore
from camcore.dynamics import indexer_vibration, residual_amplitude, residual_vibration
from camcore.results import as_dict
from camcore.work import WorkEstimate, curve_work, per_item_work, vibration_work
from service.curves.service import CurveService
from service.curves.specs import CurveSpec
from service.errors import within
from service.indexers.service import ROW_S, IndexerService
from service.indexers.specs import LoadSpec
from service.responses import encode_cost
from service.vibration.specs import IndexerVibrationRequest, TauRange

#: columns of a spectrum (tau, residual_amplitude, peak_deviation) and of the indexer's table
SPECTRUM_COLUMNS = 3
TABLE_COLUMNS = 2
#: smooth cells of a closed-form curve's acceleration, at most: one per piece (camcore's catalog
#: and Makino's curves have ≤ 7), each a polynomial of degree 16 to rounding (measured)
CLOSED_FORM_CELLS = 8
#: the kinds in closed form: built in a few ms, before the limits are checked (check_spec)
CLOSED_FORM_KINDS = ("named", "makino", "universal", "polynomial")
#: a Bezier curve of degree d: 2·d + 8 cells (measured at most 35 over 300 random curves of
#: degree ≤ 20; a near-vertical tangent needs more, which the deadline stops)
BEZIER_CELLS_PER_DEGREE = 2
#: the indexer's table: one row is X from the Chebyshev series of its subcell (33 terms,
#: Clenshaw, one column gathered at a time), measured 0.15 µs per row at 2e5 rows, ×1.5
VIBRATION_ROW_S = 1.5 * 2e-7


def estimated_cells(spec: CurveSpec) -> int:
    """The smooth cells of a spec's acceleration, before the curve is built."""
    if spec.type == "points":
        return max(1, len(spec.t) - 1)
    if spec.type == "bezier":
        return BEZIER_CELLS_PER_DEGREE * (len(spec.control_points) - 1) + CLOSED_FORM_CELLS
    return CLOSED_FORM_CELLS


def tau_values(tau: list[float] | None, tau_range: TauRange | None) -> np.ndarray:
    """The τ values of a request: the list, or the range's evenly spaced values."""
    if tau is not None:
        return np.asarray(tau, dtype=np.float64)
    assert tau_range is not None  # the request's rule
    return np.linspace(tau_range.start, tau_range.stop, tau_range.samples)


def tau_field(tau: list[float] | None) -> tuple[str, ...]:
    return ("tau",) if tau is not None else ("tau_range", "samples")


class VibrationService:
    """Residual-vibration spectra and indexer vibration, with the curve cache of ``curves``."""

    def __init__(self, curves: CurveService, indexers: IndexerService):
        self.curves = curves
        self.indexers = indexers

    # ------------------------------------------------------------------ limits and work
    def check_tau_count(self, count: int, field: tuple[str, ...]) -> None:
        """413 when a spectrum asks for more τ values than the setting allows."""
        self.curves.check_limit("number of τ values", count, self.curves.settings.max_vibration_tau_values, field)

    def check_spec(self, spec: CurveSpec, at: tuple[str | int, ...]) -> None:
        """A closed-form curve is built now, through the cache (a few ms): Makino's curves check
        their parameters only when built, and a spec that breaks its own rules is a 422 before
        any size limit is a 413."""
        if spec.type in CLOSED_FORM_KINDS:
            self.curves.curve(spec, at)

    def spectrum_work(self, spec: CurveSpec, tau: list[float] | None, tau_range: TauRange | None, csv: bool,
                      at: tuple[str | int, ...] = ("curve",), peak: bool = True) -> WorkEstimate:
        """A spectrum: the τ count first (413), the curve, the response at each τ (the residual
        amplitude alone unless ``peak``), the columns encoded."""
        self.check_spec(spec, at)
        field = tau_field(tau)
        count = len(tau) if tau is not None else tau_range.samples  # type: ignore[union-attr]
        self.check_tau_count(count, field)
        law = self.curves.law(spec, at)
        values = tau_values(tau, tau_range).tolist()
        return (curve_work(law, at) + vibration_work(law, estimated_cells(spec), values, field, peak)
                + per_item_work(count, encode_cost(SPECTRUM_COLUMNS, csv), field, f"{count} rows encoded"))

    def indexer_work(self, body: IndexerVibrationRequest, csv: bool) -> WorkEstimate:
        """One τ (known once the inertia is: estimated at the largest τ the range allows is
        too much, so at the τ of the request's numbers) and the table."""
        spec = body.indexer.curve
        self.check_spec(spec, ("indexer", "curve"))
        settings = self.curves.settings
        self.curves.check_limit("table samples", body.samples, settings.max_table_samples, ("samples",))
        law = self.curves.law(spec, ("indexer", "curve"))
        tau = self._tau_guess(body)
        return (curve_work(law, ("indexer", "curve"))
                + vibration_work(law, estimated_cells(spec), [tau], ("stiffness_nm_rad",))
                + per_item_work(body.samples, VIBRATION_ROW_S + ROW_S + encode_cost(TABLE_COLUMNS, csv), ("samples",),
                                f"{body.samples} table rows"))

    @staticmethod
    def _tau_guess(body: IndexerVibrationRequest) -> float:
        """τ from the request's numbers, bounded to camcore's range (out of it: refused later, 422)."""
        try:
            inertia = body.inertia_kgm2 if body.inertia_kgm2 is not None else _load_inertia(body.load)
            rpm = body.indexer.speed_rpm or 60.0 / ((body.indexer.cycle_time_s or 1.0) * body.indexer.dwells)
            th = (body.indexer.indexing_angle_deg or 360.0) / 360.0 * 60.0 / rpm
            tau = th * (body.stiffness_nm_rad / inertia) ** 0.5 / (2 * np.pi)
        except (ArithmeticError, ValueError):
            return camcore.dynamics.TAU_MIN
        return float(min(max(tau, camcore.dynamics.TAU_MIN), camcore.dynamics.TAU_MAX))

    # ------------------------------------------------------------------ answers
    def spectrum(self, spec: CurveSpec, tau: list[float] | None, tau_range: TauRange | None,
                 damping_ratio: float) -> dict[str, np.ndarray]:
        field = tau_field(tau)
        values = tau_values(tau, tau_range)
        self.check_tau_count(values.size, field)
        # camcore names the argument an error is about (curve, tau, damping_ratio): the request's fields
        return residual_vibration(self.curves.curve(spec), values, damping_ratio).columns()

    def residual(self, spec: CurveSpec, tau: list[float], damping_ratio: float) -> np.ndarray:
        """The residual amplitude alone at each τ (a chart's trace)."""
        self.check_tau_count(len(tau), ("samples",))
        return residual_amplitude(self.curves.curve(spec), tau, damping_ratio)

    def indexer_answer(self, body: IndexerVibrationRequest) -> tuple[dict[str, Any], dict[str, np.ndarray]]:
        """The answer's fields and its table."""
        self.curves.check_limit("table samples", body.samples, self.curves.settings.max_table_samples, ("samples",))
        unit = self.indexers.indexer(body.indexer)
        assert isinstance(unit, camcore.indexer.Indexer)  # the request's rule: no timing chart
        if body.inertia_kgm2 is not None:
            inertia = body.inertia_kgm2
        else:
            with within("load"):
                inertia = _load_inertia(body.load)
        result = indexer_vibration(unit, inertia, body.stiffness_nm_rad, body.damping_ratio, body.tolerance_arcsec,
                                   body.samples)
        return as_dict(result), result.table.columns()


def _load_inertia(load: LoadSpec | None) -> float:
    """The inertia of a LoadSpec (its parts and the inertia given directly), > 0."""
    assert load is not None
    parts = [camcore.indexer.LoadPart(**part.model_dump()) for part in load.parts]
    inertia = camcore.indexer.Load(inertia_kgm2=load.inertia_kgm2, parts=parts).total_inertia_kgm2
    if not inertia > 0:
        raise camcore.InvalidParameterError(
            f"the load's inertia must be greater than 0 (its parts and inertia_kgm2 add to {inertia!r} kg·m²).")
    return float(inertia)


def vibration_service(request: Request) -> VibrationService:
    """The app's VibrationService, built on first use from the services already on ``app.state``."""
    state = request.app.state
    service: VibrationService | None = getattr(state, "vibration_service", None)
    if service is None:
        service = VibrationService(state.curve_service, state.indexer_service)
        state.vibration_service = service
    return service
