"""The service's bridge to camcore.motion: specs in, columns and reports out."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from camcore.curves import Curve
from camcore.curves.kinds import LawCost
from camcore.errors import NonFiniteResultError
from camcore.motion import Law, law_role, resolve_motion
from camcore.motion.program import MotionProgram
from camcore.results import as_dict
from camcore.work import Field, WorkEstimate, WorkTerm, law_cost, motion_work
from service.curves.service import CurveService
from service.curves.specs import NamedCurveSpec
from service.errors import within
from service.motions.specs import MotionSpec
from service.responses import encode_cost

#: columns of a motion table: x_deg, s, v, a, j, and with a speed time_s, v_per_s, a_per_s2, j_per_s3
COLUMNS = 5
TIME_COLUMNS = 4


class MotionService:
    """Motion programs, with the fixed laws built through the curve cache of ``curves``."""

    def __init__(self, curves: CurveService):
        self.curves = curves

    # ------------------------------------------------------------------ work estimates
    def laws(self, spec: MotionSpec, at: Field = ("motion",)) -> tuple[list[LawCost | None], int]:
        """Each segment's law cost (None where nothing is built: a dwell, a fixed law built
        before) and how many parameters are solved; 413 first for too many segments or a law
        over its size limit. ``at``: where the program is in the request."""
        self.curves.check_limit("motion segments", len(spec.segments), self.curves.settings.max_motion_segments,
                                (*at, "segments"))
        laws: list[LawCost | None] = []
        seen: set[str] = set()
        solved = 0
        for i, segment in enumerate(spec.segments):
            if segment.curve is None:  # a dwell, or the default cycloid (built once)
                laws.append(None if segment.type == "dwell" or "cycloid" in seen else law_cost("named", {}))
                seen.add("cycloid")
                continue
            law = self.curves.law(segment.curve, at=(*at, "segments", i, "curve"))
            role = law_role(Law(segment.curve.type, segment.curve.parameters(), segment.curve.direction))
            fixed = role == "fixed"
            solved += role == "solved"
            key = segment.curve.cache_key()
            laws.append(None if fixed and key in seen else law)
            if fixed:
                seen.add(key)
        return laws, solved

    def motion_work(self, spec: MotionSpec, samples: int | None, x_deg: list[float] | None, speed_rpm: float | None,
                    csv: bool) -> WorkEstimate:
        """A program and its table: 413 first for too many segments, rows or a law over its
        size limit; then the laws to build (a fixed law repeated is built once), the solved
        parameters and the rows, encoded."""
        laws, solved = self.laws(spec)
        rows, field = self._rows(samples, x_deg)
        columns = COLUMNS + (TIME_COLUMNS if speed_rpm is not None else 0)
        work = motion_work(laws, solved, rows, ("motion", "segments"), field)
        return work + WorkEstimate((WorkTerm(field, f"encoding {rows} rows", encode_cost(rows * columns, csv)),))

    def _rows(self, samples: int | None, x_deg: list[float] | None) -> tuple[int, tuple[str, ...]]:
        """How many master angles, and which request field gives them (413 over the limit)."""
        rows = len(x_deg) if x_deg is not None else int(samples or 361)
        field = ("x_deg",) if x_deg is not None else ("samples",)
        self.curves.check_limit("motion samples", rows, self.curves.settings.max_table_samples, field)
        return rows, field

    # ------------------------------------------------------------------ answers
    def program(self, spec: MotionSpec, at: Field = ("motion",)) -> MotionProgram:
        """The resolved program; fixed laws come from the curve cache. ``at``: where the
        program is in the request."""
        self.curves.check_limit("motion segments", len(spec.segments), self.curves.settings.max_motion_segments,
                                (*at, "segments"))
        core = spec.core()
        specs = {id(seg.law): (i, spec.segments[i].curve) for i, seg in enumerate(core.segments) if seg.law}

        def build(law: Law) -> Curve:
            if id(law) not in specs:  # camcore's default law of a segment that gives none
                return self.curves.curve(NamedCurveSpec(name=str(law.parameters["name"])))
            i, curve_spec = specs[id(law)]
            assert curve_spec is not None  # a law of the core spec is a segment's curve
            return self.curves.curve(curve_spec, at=(*at, "segments", i, "curve"))

        with within(*at), np.errstate(all="ignore"):  # non-finite results are refused below
            return resolve_motion(core, build=build, limits=self.curves.size_limits())

    def motion(self, spec: MotionSpec, samples: int | None, x_deg: list[float] | None,
               speed_rpm: float | None) -> tuple[dict[str, Any], dict[str, Any]]:
        """The columns, and the report: unit, period, segments, joins, characteristics."""
        rows, _field = self._rows(samples, x_deg)
        program = self.program(spec)
        x = program.sample_angles(rows) if x_deg is None else np.asarray(x_deg, dtype=np.float64)
        with np.errstate(all="ignore"):
            columns = program.table(x, speed_rpm).columns()
            report = {"unit": program.unit, "period_deg": program.period_deg,
                      "segments": [as_dict(s) for s in program.segments],
                      "joins": [as_dict(j) for j in program.joins],
                      "characteristics": as_dict(program.characteristics)}
        _check_finite_report(report)
        return columns, report


def _check_finite_report(value: Any, where: str = "") -> None:
    """Refuse a report holding NaN or infinity (JSON has no such numbers)."""
    if isinstance(value, dict):
        for key, item in value.items():
            _check_finite_report(item, f"{where}.{key}" if where else str(key))
    elif isinstance(value, list):
        for i, item in enumerate(value):
            _check_finite_report(item, f"{where}[{i}]")
    elif isinstance(value, float) and not math.isfinite(value):
        raise NonFiniteResultError(f"the computation of '{where}' produced a non-finite number for these inputs; "
                                   "check that the program describes a realistic machine cycle.")
