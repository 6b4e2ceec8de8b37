"""The service's bridge to camcore.profile and camcore.export."""

from __future__ import annotations

from typing import Any

import numpy as np

import camcore
from camcore import export
from camcore.curves.kinds import LawCost
from camcore.results import as_dict
from camcore.work import WorkEstimate, WorkTerm, base_circle_work, motion_work, profile_work
from service.cache import LRUCache
from service.curves.service import CurveService
from service.errors import within
from service.motions.service import MotionService
from service.profiles.specs import ProfileSpec
from service.responses import encode_cost

#: columns of a profile table (cam angle, lift, contact and pitch points, angles, radii…)
PROFILE_COLUMNS = 14

#: columns where an infinite value is meaningful (a straight stretch of surface) and is
#: answered as null (JSON has no infinity)
UNBOUNDED_COLUMNS = ("radius_of_curvature_mm", "pitch_radius_of_curvature_mm")


class ProfileService:
    """Plate-cam profiles, checks, base-circle sizing and contour export."""

    def __init__(self, curves: CurveService, motions: MotionService):
        self.curves = curves
        self.motions = motions
        # the checks over the whole turn depend on the cam alone, not on the samples or format
        self.checks_cache: LRUCache[camcore.profile.ProfileChecks] = LRUCache(
            curves.settings.profile_checks_cache_size)

    # ------------------------------------------------------------------ work estimates
    def laws(self, spec: ProfileSpec) -> tuple[list[LawCost | None], WorkEstimate]:
        """Each segment's law cost, and the work of building the distinct curves (a spec
        repeated in several segments is built once: the curve cache); a motion program's
        laws, with its solved parameters."""
        if spec.motion is not None:
            program_laws, solved = self.motions.laws(spec.motion, at=("profile", "motion"))
            # the program resolved (no rows: the profile's samples are counted by profile_work)
            return program_laws, motion_work(program_laws, solved, 0, ("profile", "motion", "segments"), ("samples",))
        if spec.segments is None:
            assert spec.lift is not None
            law = self.curves.law(spec.lift, at=("profile", "lift"))
            return [law], self.curves.build_work(spec.lift, law, ("profile", "lift"))
        laws: list[LawCost | None] = []
        built = WorkEstimate()
        seen = set()
        for i, segment in enumerate(spec.segments):
            if segment.curve is None:
                laws.append(None)
                continue
            at = ("profile", "segments", i, "curve")
            law = self.curves.law(segment.curve, at=at)
            laws.append(law)
            if segment.curve.cache_key() not in seen:
                seen.add(segment.curve.cache_key())
                built += self.curves.build_work(segment.curve, law, at)
        return laws, built

    def profile_work(self, spec: ProfileSpec, samples: int | None, cam_angle_deg: list[float] | None,
                     answer: str) -> WorkEstimate:
        """A profile and its answer (``answer``: json, csv or a contour format of camcore.export.FORMATS)."""
        n, field = self._sample_count(samples, cam_angle_deg)
        laws, work = self.laws(spec)
        work += profile_work(laws, n, self._schedule_field(spec), field)
        if answer in export.FORMATS:
            seconds = export.FORMATS[answer].cost(n)
            return work + WorkEstimate((WorkTerm(field, f"writing {n} points as {answer}", seconds),))
        return work + WorkEstimate((WorkTerm(field, f"encoding {n} rows", encode_cost(n * PROFILE_COLUMNS,
                                                                                         answer == "csv")),))

    def base_circle_work(self, spec: ProfileSpec, max_pressure_angle_deg: float | None,
                         min_radius_of_curvature_mm: float | None) -> WorkEstimate:
        """Base-circle sizing: one solve per limit (a flat-faced follower always solves the
        curvature, for convexity, and has no pressure angle)."""
        flat = spec.follower.type == "flat-faced"
        limits = int(max_pressure_angle_deg is not None and not flat) + int(min_radius_of_curvature_mm is not None
                                                                            or flat)
        laws, work = self.laws(spec)
        return work + base_circle_work(laws, limits, self._schedule_field(spec))

    @staticmethod
    def _schedule_field(spec: ProfileSpec) -> tuple[str, ...]:
        """The request field of the lift schedule: its segments, its one lift curve or its program's segments."""
        if spec.motion is not None:
            return ("profile", "motion", "segments")
        return ("profile", "segments") if spec.segments is not None else ("profile", "lift")

    def _sample_count(self, samples: int | None, cam_angle_deg: list[float] | None) -> tuple[int, tuple[str, ...]]:
        """How many cam angles, and which request field gives them (413 over the limit)."""
        n = len(cam_angle_deg) if cam_angle_deg is not None else int(samples or 361)
        field = ("cam_angle_deg",) if cam_angle_deg is not None else ("samples",)
        self.curves.check_limit("profile samples", n, self.curves.settings.max_table_samples, field)
        return n, field

    # ------------------------------------------------------------------ answers
    def cam(self, spec: ProfileSpec, base_radius_mm: float | None = None) -> camcore.profile.CamSpec:
        f = spec.follower
        follower = camcore.profile.Follower(type=f.type, motion=f.motion, offset_mm=f.offset_mm,
                                 roller_radius_mm=f.roller_radius_mm, arm_length_mm=f.arm_length_mm,
                                 pivot_distance_mm=f.pivot_distance_mm)
        radius = spec.base_radius_mm if base_radius_mm is None else base_radius_mm
        if spec.segments is not None:
            segments = []
            for i, s in enumerate(spec.segments):
                law = None if s.curve is None else self.curves.curve(s.curve, at=("profile", "segments", i, "curve"))
                with within("profile", "segments", i):
                    segments.append(camcore.profile.Segment(type=s.type, angle_deg=s.angle_deg, lift_mm=s.lift_mm or 0.0,
                                                 swing_deg=s.swing_deg, curve=law))
            with within("profile"):
                return camcore.profile.make_cam(follower, radius, segments=segments, rotation=spec.rotation,
                                     rotation_ratio=spec.rotation_ratio)
        if spec.motion is not None:
            program = self.motions.program(spec.motion, at=("profile", "motion"))
            with within("profile"):
                return camcore.profile.make_cam(follower, radius, motion=program, rotation=spec.rotation,
                                                rotation_ratio=spec.rotation_ratio)
        assert spec.lift is not None
        lift = self.curves.curve(spec.lift, at=("profile", "lift"))
        with within("profile"):
            return camcore.profile.make_cam(follower, radius, lift_curve=lift, rotation=spec.rotation,
                                 rotation_ratio=spec.rotation_ratio)

    def profile(self, spec: ProfileSpec, samples: int | None, cam_angle_deg: list[float] | None) -> camcore.profile.ProfileResult:
        n, _field = self._sample_count(samples, cam_angle_deg)
        cam = self.cam(spec)
        with within("profile"):
            checks = self.checks_cache.get_or_create(spec.model_dump_json(),
                                                     lambda: camcore.profile.profile_checks(cam))
            if cam_angle_deg is not None:
                return camcore.profile.compute_profile(cam, np.asarray(cam_angle_deg, dtype=np.float64), checks)
            return camcore.profile.sample_profile(cam, n, checks)

    def table(self, spec: ProfileSpec, samples: int | None, cam_angle_deg: list[float] | None
              ) -> tuple[dict[str, Any], dict[str, Any]]:
        """The profile's columns (radius columns: NaN where unbounded) and its checks."""
        result = self.profile(spec, samples, cam_angle_deg)
        return self.columns(result), self.checks(result)

    def contour_file(self, spec: ProfileSpec, samples: int | None, cam_angle_deg: list[float] | None,
                     fmt: str) -> bytes:
        """The contour of the profile as a file in one of :data:`camcore.export.FORMATS`."""
        return self.export(self.profile(spec, samples, cam_angle_deg), fmt, spec.base_radius_mm)

    def cache_stats(self) -> dict[str, dict[str, int]]:
        return {"profile_checks": self.checks_cache.stats()}

    @staticmethod
    def columns(result: camcore.profile.ProfileResult) -> dict[str, Any]:
        cols: dict[str, Any] = dict(result.columns())
        cols["pitch_radius_of_curvature_mm"] = result.pitch_radius_of_curvature_mm
        for name in UNBOUNDED_COLUMNS:
            col = np.asarray(cols[name], dtype=np.float64)
            # ±inf (straight surface) and nan become null in JSON; orjson writes NaN as null
            cols[name] = np.where(np.isfinite(col), col, np.nan)
        return cols

    @staticmethod
    def checks(result: camcore.profile.ProfileResult) -> dict[str, Any]:
        return as_dict(result.checks)

    def base_circle(self, spec: ProfileSpec, max_pressure_angle_deg: float | None,
                    min_radius_of_curvature_mm: float | None) -> dict[str, Any]:
        cam = self.cam(spec)
        result = camcore.profile.size_base_circle(cam, max_pressure_angle_deg, min_radius_of_curvature_mm)
        return as_dict(result)

    @staticmethod
    def export(result: camcore.profile.ProfileResult, fmt: str, base_radius_mm: float) -> bytes:
        """The file of a contour download in one of :data:`camcore.export.FORMATS`."""
        contour = export.Contour(result.x_mm, result.y_mm, result.cam_angle_deg, base_radius_mm)
        return export.FORMATS[fmt].write(contour)
