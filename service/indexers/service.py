"""The service's bridge to camcore.indexer: specs in, answers out."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Literal, TypeVar

import numpy as np

import camcore
from camcore.errors import InvalidParameterError, NonMonotoneError
from camcore.results import as_dict
from camcore.work import WorkEstimate, motion_work, per_item_work
from service.cache import LRUCache
from service.curves.service import CurveService
from service.errors import within
from service.indexers.specs import IndexerSpec, LoadSpec, MotorSpec
from service.motions.service import MotionService
from service.responses import encode_cost

T = TypeVar("T")

#: columns of the motion table and of a position answer (angles, times, ω, α, jerk…)
MOTION_COLUMNS = 8
#: one row of the motion table or one position beyond the curve's own evaluation: angle
#: and time scaling (measured 0.5 µs per row at 2e5 rows), ×1.5
ROW_S = 1.5 * 5e-7
#: one RMS integral over one law (every piece's Gauss-Legendre nodes in one evaluation, the
#: kinks bracketed on one grid): measured 0.15 ms for MS and MCV50 and 33 ms for a 10 000-point
#: curve (3.3 µs per piece); ×1.5
RMS_INTEGRAL_S = 1.5 * 1.5e-4
RMS_PER_PIECE_S = 1.5 * 3.5e-6
#: the exact peaks of the power balance (one grid of the curve, Newton on the brackets):
#: measured 0.45 ms for MS, plus the grid's law evaluations (V, A, J: three per point); ×1.5
PEAKS_S = 1.5 * 4.5e-4
#: pieces of a catalog or universal law at most (a points curve has one per point)
MOST_PIECES_OF_A_LAW = 9
#: bytes the cached sizing answers may hold (one is ~10 kB with its 181-row torque table)
SIZING_CACHE_MAX_BYTES = 8 * 1024 * 1024
#: where a timing chart is in the request
TIMING = ("indexer", "timing")


class IndexerService:
    """Indexer motion, position lookup and sizing, using the curve cache of ``curves``."""

    def __init__(self, curves: CurveService, motions: MotionService):
        self.curves = curves
        self.motions = motions
        # encoded sizing answers by request: a spreadsheet recalculating asks the same again
        self.sizings: LRUCache[bytes] = LRUCache(curves.settings.sizing_cache_size, SIZING_CACHE_MAX_BYTES)

    def cache_stats(self) -> dict[str, dict[str, int]]:
        return {"sizings": self.sizings.stats()}

    # ------------------------------------------------------------------ work estimates
    def _timing_work(self, spec: IndexerSpec, rows: int, rows_field: tuple[str, ...]) -> WorkEstimate:
        """A timing chart resolved and evaluated at ``rows`` input angles (the chart's laws
        and its solved parameters, camcore.work.motion_work)."""
        assert spec.timing is not None
        laws, solved = self.motions.laws(spec.timing, at=TIMING)
        return motion_work(laws, solved, rows, (*TIMING, "segments"), rows_field)

    def motion_work(self, spec: IndexerSpec, samples: int, csv: bool) -> WorkEstimate:
        self.curves.check_limit("table samples", samples, self.curves.settings.max_table_samples, ("samples",))
        if spec.timing is not None:
            return self._timing_work(spec, samples, ("samples",)) + per_item_work(
                samples, ROW_S + encode_cost(MOTION_COLUMNS, csv), ("samples",), f"{samples} table rows")
        law = self.curves.law(spec.curve, at=("indexer", "curve"))
        return self.curves.build_work(spec.curve, law, ("indexer", "curve")) + per_item_work(
            samples, law.sample_s + ROW_S + encode_cost(MOTION_COLUMNS, csv), ("samples",), f"{samples} table rows")

    def position_work(self, spec: IndexerSpec, angles: int, method: str, table_step: float,
                      csv: bool) -> WorkEstimate:
        self.curves.check_limit("number of output angles", angles, self.curves.settings.max_inverse_points,
                                ("output_angle_deg",))
        if spec.timing is not None:  # each position: a segment found, one inverse solved (≤ 2 law evaluations)
            return self._timing_work(spec, 3 * angles, ("output_angle_deg",)) + per_item_work(
                angles, ROW_S + encode_cost(MOTION_COLUMNS, csv), ("output_angle_deg",), f"{angles} positions")
        law = self.curves.law(spec.curve, at=("indexer", "curve"))
        return self.curves.build_work(spec.curve, law, ("indexer", "curve"), inverse=method == "exact") + per_item_work(
            angles, 2 * law.sample_s + ROW_S + encode_cost(MOTION_COLUMNS, csv), ("output_angle_deg",),
            f"{angles} positions") + self.curves.inverse_table_work(law, method, table_step)

    def sizing_work(self, spec: IndexerSpec, table_samples: int = 181, motor: bool = False) -> WorkEstimate:
        """Sizing: the curve, its characteristic values and the exact peaks (a few ms), or a
        timing chart's laws and peaks; the torque table's rows and the RMS integrals (one,
        or two with a motor), per moving segment."""
        if spec.timing is not None:
            laws = sum(1 for segment in spec.timing.segments if segment.type != "dwell")
            work = self._timing_work(spec, table_samples * laws, ("indexer", "timing"))
            pieces = MOST_PIECES_OF_A_LAW
        else:
            laws = 1
            law = self.curves.law(spec.curve, at=("indexer", "curve"))
            pieces = max(len(spec.curve.parameters().get("t", ())), MOST_PIECES_OF_A_LAW)
            grid = min(pieces * 257, 2**18 + 17 * pieces)  # camcore.curves.extrema's bracketing grid
            work = self.curves.build_work(spec.curve, law, ("indexer", "curve")) + per_item_work(
                table_samples, ROW_S, ("table_samples",), f"{table_samples} torque rows") + per_item_work(
                1, PEAKS_S + 1.5 * 3 * grid * law.sample_s, ("indexer", "curve"), "the exact torque peaks")
        integrals = laws * (2 if motor else 1)
        return work + per_item_work(integrals, RMS_INTEGRAL_S + RMS_PER_PIECE_S * pieces, ("indexer",),
                                    f"{integrals} RMS integrals")

    # ------------------------------------------------------------------ answers
    def indexer(self, spec: IndexerSpec) -> camcore.indexer.Indexer | camcore.indexer.TimedIndexer:
        """The single-curve indexer, or the indexer of a timing chart."""
        if spec.timing is not None:
            program = self.motions.program(spec.timing, at=TIMING)
            with within(*TIMING):
                camcore.indexer.check_timing(program)
            with within("indexer"):
                return camcore.indexer.TimedIndexer(program=program, speed_rpm=spec.speed_rpm,
                                                    cycle_time_s=spec.cycle_time_s,
                                                    input_stop_time_s=spec.input_stop_time_s)
        assert spec.indexing_angle_deg is not None  # the spec's rule without a timing chart
        curve = self.curves.curve(spec.curve, at=("indexer", "curve"))
        with within("indexer"):
            return camcore.indexer.Indexer(
                stops=spec.stops,
                swing_angle_deg=spec.swing_angle_deg,
                indexing_angle_deg=spec.indexing_angle_deg,
                dwells=spec.dwells,
                speed_rpm=spec.speed_rpm,
                cycle_time_s=spec.cycle_time_s,
                input_stop_time_s=spec.input_stop_time_s,
                curve=curve,
            )

    def motion(self, spec: IndexerSpec, samples: int) -> tuple[dict[str, Any], dict[str, np.ndarray]]:
        self.curves.check_limit("table samples", samples, self.curves.settings.max_table_samples, ("samples",))
        unit = self.indexer(spec)
        result = unit.motion(samples)
        move = self._origin(spec, unit)
        return as_dict(move(result.summary)), move(result.table).columns()

    def position(self, spec: IndexerSpec, output_angle_deg: list[float], method: Literal["exact", "table"], table_step: float,
                 table_decimals: int | None) -> dict[str, np.ndarray]:
        self.curves.check_limit("number of output angles", len(output_angle_deg),
                                self.curves.settings.max_inverse_points, ("output_angle_deg",))
        unit = self.indexer(spec)
        angles = np.asarray(output_angle_deg, dtype=np.float64)
        if isinstance(unit, camcore.indexer.TimedIndexer):
            if method != "exact":
                raise InvalidParameterError("a timing chart's positions are solved exactly: the table method "
                                            "reproduces the catalog's single-curve tables (use method 'exact').",
                                            field=("method",))
            with within(*TIMING, only=NonMonotoneError):  # a segment's law cannot be inverted
                return unit.position(angles).columns()
        with within("indexer", "curve", only=NonMonotoneError):  # the curve cannot be inverted
            result = unit.position(angles, method=method, table_step=table_step, table_decimals=table_decimals)
        return self._origin(spec, unit)(result).columns()

    def sizing(self, spec: IndexerSpec, load: LoadSpec, motor: MotorSpec | None = None,
               table_samples: int = 181) -> dict[str, Any]:
        core_load = self.core_load(load)
        core_motor = None
        if motor is not None:
            with within("motor"):
                core_motor = camcore.indexer.Motor(**motor.model_dump())
        unit = self.indexer(spec)
        with within("indexer"), np.errstate(all="ignore"):  # non-finite answers are refused when encoded
            result = camcore.indexer.size(unit, core_load, accuracy_arc_seconds=load.accuracy_arc_seconds,
                                          accuracy_radius_mm=load.accuracy_radius_mm,
                                          internal_friction_torque_nm=spec.internal_friction_torque_nm,
                                          motor=core_motor, table_samples=table_samples)
        return as_dict(self._origin(spec, unit)(result))

    @staticmethod
    def _origin(spec: IndexerSpec, unit: Any) -> Callable[[T], T]:
        """Moves a result's input angles to the spec's ``input_angle_origin``."""
        with within("indexer"):
            shift = camcore.indexer.origin_shift_deg(unit, spec.input_angle_origin)
        cycle = 360.0 / unit.dwells

        def move(result: T) -> T:
            return camcore.indexer.to_origin(result, shift, cycle)

        return move

    @staticmethod
    def core_load(load: LoadSpec) -> camcore.indexer.Load:
        """The load as camcore takes it (its errors located under ``load``)."""
        parts = []
        for i, part in enumerate(load.parts):
            with within("load", "parts", i):
                parts.append(camcore.indexer.LoadPart(**part.model_dump()))
        with within("load"):
            return camcore.indexer.Load(
                inertia_kgm2=load.inertia_kgm2,
                parts=parts,
                friction_coefficient=load.friction_coefficient,
                friction_radius_mm=load.friction_radius_mm,
                friction_torque_nm=load.friction_torque_nm,
                work_torque_nm=load.work_torque_nm,
                service_factor=load.service_factor,
                efficiency=load.efficiency,
                gear_ratio=load.gear_ratio,
                dwell_torque_nm=load.dwell_torque_nm,
            )

    @staticmethod
    def accuracy(arc_seconds: float, radius_mm: float) -> dict[str, float]:
        return {"arc_seconds": arc_seconds, "radius_mm": radius_mm,
                "accuracy_mm": float(camcore.indexer.accuracy_mm(arc_seconds, radius_mm))}
