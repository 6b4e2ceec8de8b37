"""The service's bridge to camcore.profile and camcore.export."""

from __future__ import annotations

from typing import Any

import numpy as np

import camcore
from camcore import export
from camcore.results import as_dict
from service.curves.service import CurveService
from service.errors import within
from service.profiles.specs import ProfileSpec

#: columns where an infinite value is meaningful (a straight stretch of surface) and is
#: answered as null (JSON has no infinity)
UNBOUNDED_COLUMNS = ("radius_of_curvature_mm", "pitch_radius_of_curvature_mm")


class ProfileService:
    """Plate-cam profiles, checks, base-circle sizing and contour export."""

    def __init__(self, curves: CurveService):
        self.curves = curves

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
        assert spec.lift is not None
        lift = self.curves.curve(spec.lift, at=("profile", "lift"))
        with within("profile"):
            return camcore.profile.make_cam(follower, radius, lift_curve=lift, rotation=spec.rotation,
                                 rotation_ratio=spec.rotation_ratio)

    def profile(self, spec: ProfileSpec, samples: int | None, cam_angle_deg: list[float] | None) -> camcore.profile.ProfileResult:
        n = len(cam_angle_deg) if cam_angle_deg is not None else int(samples or 361)
        self.curves.check_limit("profile samples", n, self.curves.settings.max_table_samples,
                                ("cam_angle_deg",) if cam_angle_deg is not None else ("samples",))
        cam = self.cam(spec)
        with within("profile"):
            if cam_angle_deg is not None:
                return camcore.profile.compute_profile(cam, np.asarray(cam_angle_deg, dtype=np.float64))
            return camcore.profile.sample_profile(cam, n)

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
