"""``POST /v1/cams/barrel`` (``computeBarrelCam``): a barrel cam's developed groove, both flanks in
3-D and its checks; the columns as CSV on ``Accept: text/csv`` / ``?format=csv`` and from the twin
``POST /v1/cams/barrel.csv`` (the flank grids are JSON only: they are not columns over the cam angle).
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

import numpy as np
from fastapi import APIRouter, Body, Depends, Query, Request
from starlette.responses import Response

from camcore.cams.barrel import BarrelResult, make_barrel_cam, sample_barrel
from camcore.curves.kinds import LawCost
from camcore.profile import Segment
from camcore.results import as_dict
from camcore.work import WorkEstimate, checks_work, curve_work, motion_work, per_item_work
from service.admission import WorkGate
from service.cams.barrel_specs import BARREL_EXAMPLES, BarrelCamAnswer, BarrelCamRequest
from service.curves.routes import CSV, CSV_FILE, ERRORS
from service.curves.service import CurveService
from service.deps import work_gate
from service.errors import within
from service.motions.service import MotionService
from service.responses import check_finite, encode_cost, json_response, table_response, wants_csv
from service.routing import OrjsonRoute

#: the barrel checks run 25 extreme searches (pressure angle at three radii, the pitch curve's
#: curvature both ways, and both ways at 10 radii across the roller) where a plate cam's run 3;
#: measured (with the local-grid refinement of issue 21) 40-60 ms for the 4-segment request
#: examples, up to 12 times the plate checks' estimate of the same segments; ×1.5
BARREL_CHECKS_FACTOR = 18.0
#: one sampled angle (lift, state, columns) measured 1.3 µs, one flank point 0.07 µs; ×1.5
BARREL_SAMPLE_S = 1.5 * 1.3e-6
FLANK_POINT_S = 1.5 * 1e-7
#: columns over the cam angle, and numbers per flank point (x, y, z of two flanks)
TABLE_COLUMNS = 10
FLANK_VALUES = 6
#: columns whose NaN means "straight" (null in JSON, an empty CSV cell)
UNBOUNDED_COLUMNS = ("pitch_radius_of_curvature_mm", "upper_radius_of_curvature_mm", "lower_radius_of_curvature_mm")


class BarrelCamService:
    """Barrel cams from request specs, with the curve cache of ``curves`` and the programs of ``motions``."""

    def __init__(self, curves: CurveService, motions: MotionService):
        self.curves = curves
        self.motions = motions

    def check_size(self, body: BarrelCamRequest) -> None:
        """413 when the flank grids (samples × length_samples) exceed the table limit."""
        self.curves.check_limit("barrel cam samples × length_samples", body.samples * body.length_samples,
                                self.curves.settings.max_table_samples, ("samples",))

    def work(self, body: BarrelCamRequest, csv: bool) -> WorkEstimate:
        """The curves built, the checks, the samples and their encoding."""
        self.check_size(body)
        laws: list[LawCost | None] = []
        built = WorkEstimate()
        if body.motion is not None:
            laws, solved = self.motions.laws(body.motion)
            built = motion_work(laws, solved, 0, ("motion", "segments"), ("samples",))
            field: tuple[str, ...] = ("motion", "segments")
        else:
            assert body.segments is not None
            field = ("segments",)
            seen: set[str] = set()
            for i, segment in enumerate(body.segments):
                if segment.curve is None:
                    laws.append(None)
                    continue
                law = self.curves.law(segment.curve, at=("segments", i, "curve"))
                laws.append(law)
                if segment.curve.cache_key() not in seen:
                    seen.add(segment.curve.cache_key())
                    built += curve_work(law, ("segments", i, "curve"))
        checks = checks_work(laws, field).seconds * BARREL_CHECKS_FACTOR
        n, points = body.samples, body.samples * body.length_samples
        values = n * TABLE_COLUMNS + (0 if csv else points * FLANK_VALUES)
        return (built + per_item_work(1, checks, field, "the barrel cam's checks")
                + per_item_work(n, BARREL_SAMPLE_S, ("samples",), f"{n} cam angles")
                + per_item_work(points, FLANK_POINT_S, ("length_samples",), f"{points} flank points")
                + per_item_work(values, encode_cost(1, csv), ("samples",), f"{values} numbers encoded"))

    def result(self, body: BarrelCamRequest) -> BarrelResult:
        self.check_size(body)
        segments = None
        program = None
        if body.segments is not None:
            segments = []
            for i, s in enumerate(body.segments):
                law = None if s.curve is None else self.curves.curve(s.curve, at=("segments", i, "curve"))
                with within("segments", i):
                    segments.append(Segment(type=s.type, angle_deg=s.angle_deg, lift_mm=s.lift_mm or 0.0,
                                            swing_deg=s.swing_deg, curve=law))
        else:
            assert body.motion is not None
            program = self.motions.program(body.motion)
        cam = make_barrel_cam(body.pitch_radius_mm, body.roller_radius_mm, roller_length_mm=body.roller_length_mm,
                              groove_depth_mm=body.groove_depth_mm, segments=segments, motion=program,
                              roller=body.roller, follower=body.follower, arm_length_mm=body.arm_length_mm,
                              initial_arm_angle_deg=body.initial_arm_angle_deg)
        return sample_barrel(cam, body.samples, body.length_samples)

    def columns(self, body: BarrelCamRequest) -> dict[str, Any]:
        """The columns over the cam angle (CSV)."""
        r = self.result(body)
        return {"cam_angle_deg": r.cam_angle_deg, _lift_name(body): r.lift, "u_mm": r.u_mm, "y_mm": r.y_mm,
                "pressure_angle_deg": r.pressure_angle_deg, "pressure_angle_inner_deg": r.pressure_angle_inner_deg,
                "pressure_angle_outer_deg": r.pressure_angle_outer_deg,
                "pitch_radius_of_curvature_mm": r.pitch_radius_of_curvature_mm,
                "upper_radius_of_curvature_mm": r.upper.radius_of_curvature_mm,
                "lower_radius_of_curvature_mm": r.lower.radius_of_curvature_mm}

    def answer(self, body: BarrelCamRequest) -> dict[str, Any]:
        """The JSON answer: columns, flanks (grids), checks."""
        r = self.result(body)
        flanks = {}
        for name, flank in (("upper", r.upper), ("lower", r.lower)):
            check_finite({f"{name} flank": np.stack([flank.x_mm, flank.y_mm, flank.z_mm])})
            flanks[name] = {"x_mm": flank.x_mm, "y_mm": flank.y_mm, "z_mm": flank.z_mm,
                            "radius_of_curvature_mm": flank.radius_of_curvature_mm}
        columns = {"cam_angle_deg": r.cam_angle_deg, _lift_name(body): r.lift, "u_mm": r.u_mm, "y_mm": r.y_mm,
                   "pressure_angle_deg": r.pressure_angle_deg, "pressure_angle_inner_deg": r.pressure_angle_inner_deg,
                   "pressure_angle_outer_deg": r.pressure_angle_outer_deg,
                   "pitch_radius_of_curvature_mm": r.pitch_radius_of_curvature_mm,
                   "roller_position_mm": r.roller_position_mm}
        check_finite({k: v for k, v in columns.items() if k not in UNBOUNDED_COLUMNS})
        return {**columns, "flanks": flanks, "checks": as_dict(r.checks)}


def _lift_name(body: BarrelCamRequest) -> str:
    return "swing_deg" if body.follower == "oscillating" else "lift_mm"


def barrel_service(request: Request) -> BarrelCamService:
    """The app's BarrelCamService, built on first use from the services already on ``app.state``."""
    state = request.app.state
    service: BarrelCamService | None = getattr(state, "barrel_cam_service", None)
    if service is None:
        service = BarrelCamService(state.curve_service, state.motion_service)
        state.barrel_cam_service = service
    return service


Service = Annotated[BarrelCamService, Depends(barrel_service)]
Gate = Annotated[WorkGate, Depends(work_gate)]
BarrelBody = Annotated[BarrelCamRequest, Body(openapi_examples=BARREL_EXAMPLES)]


async def compute_barrel_cam(body: BarrelBody, request: Request, service: Service, gate: Gate,
                             format: Annotated[Literal["json", "csv"] | None,
                                               Query(description="csv: the columns over the cam angle")] = None
                             ) -> Response:
    """A barrel cam: the developed groove, pressure angles across the roller, the flanks' radii of curvature,
    both flanks in 3-D, and the checks (largest pressure angle, smallest radii, undercut, groove dimensions)."""
    return await _answer(request, gate, service, body, format == "csv" or (format is None and wants_csv(request)))


async def compute_barrel_cam_csv(body: BarrelBody, request: Request, service: Service, gate: Gate) -> Response:
    """The columns of ``computeBarrelCam`` as CSV (an empty radius cell: a straight stretch)."""
    return await _answer(request, gate, service, body, True)


async def _answer(request: Request, gate: WorkGate, service: BarrelCamService, body: BarrelCamRequest,
                  csv: bool) -> Response:
    work = service.work(body, csv)
    if csv:
        columns = await gate.run(request, work, service.columns, body)
        return table_response(columns, True, filename="barrel-cam.csv", allow_null=UNBOUNDED_COLUMNS)
    return json_response(await gate.run(request, work, service.answer, body))


def register(router: APIRouter) -> None:
    """Add ``computeBarrelCam`` and its CSV twin to the /v1/cams router."""
    router.add_api_route("/barrel", compute_barrel_cam, methods=["POST"], operation_id="computeBarrelCam",
                         response_model=BarrelCamAnswer, responses={**ERRORS, 200: CSV},
                         route_class_override=OrjsonRoute, summary="Compute Barrel Cam")
    router.add_api_route("/barrel.csv", compute_barrel_cam_csv, methods=["POST"], operation_id="computeBarrelCamCsv",
                         response_class=Response, responses={**ERRORS, 200: CSV_FILE},
                         route_class_override=OrjsonRoute, summary="Compute Barrel Cam Csv")
