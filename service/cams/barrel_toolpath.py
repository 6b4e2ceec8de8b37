"""``POST /v1/cams/barrel/toolpath`` (``computeBarrelToolpath``): a barrel cam's groove on a
four-axis mill, the cutter's axis as straight moves in A and X within a tolerance; JSON (the
passes' nodes, the deviations measured, the walls' gaps) or, with ``format`` (or
``?format=gcode``), the program (:data:`camcore.export.barrel_toolpath.BARREL_TOOLPATH_FORMATS`).
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from fastapi.openapi.models import Example
from pydantic import Field, model_validator

from camcore.cams.barrel.toolpath import BarrelToolpath, check_cutter, compute_barrel_toolpath
from camcore.errors import CamError
from camcore.export.barrel_toolpath import BARREL_TOOLPATH_FORMATS, BarrelToolpathFile
from camcore.work import WorkEstimate, WorkTerm, encode_cost
from camcore.work.barrel import NODE_VALUES, barrel_moves_estimate, barrel_toolpath_work
from service.cams.barrel import barrel_build_work, barrel_cam
from service.cams.barrel_specs import BARREL_EXAMPLE, BarrelCamRequest
from service.context import Context
from service.errors import within
from service.operations import JSON, Format, Operation, Payload, Raw, download
from service.specs import BIG, DefaultsInDescriptions, DeferredModel, FieldRuleError, Spec, examples

#: the safe Z's default height above the cam's outer radius [mm]
SAFE_CLEARANCE_MM = 5.0


def _dimensions(cam: BarrelCamRequest) -> tuple[float, float]:
    """The cam's outer radius and its groove's bottom radius [mm] (the defaults of the cam spec)."""
    length = cam.roller_length_mm or cam.roller_radius_mm
    outer = cam.pitch_radius_mm + 0.5 * length
    return outer, outer - (cam.groove_depth_mm or length)


class BarrelToolpathRequest(Spec):
    """A barrel cam, a cutter and a tolerance: the groove's passes on a four-axis mill."""

    model_config = examples({"cam": BARREL_EXAMPLE, "tool_radius_mm": 10, "tolerance_mm": 0.01})
    cam: BarrelCamRequest = Field(description="the barrel cam (its samples and length_samples are not used)")
    tool_radius_mm: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, le=BIG)] = Field(
        description="radius of the end mill [mm]: the roller's radius (one pass on the centre line), or down to half "
                    "of it (one pass on each wall, the cutter's axis offset by roller − tool radius)")
    tolerance_mm: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=1e-4, le=10)] = Field(
        0.01, description="largest deviation of the straight moves in A and X from the exact path, measured both ways "
                          "in the developed plane of the cam's outer radius [mm]")
    feed_mm_min: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, le=BIG)] = Field(
        300.0, description="the cutter axis's speed along the groove at the pitch radius (and of the plunge) "
                           "[mm/min], written as inverse-time F words (G93)")
    safe_z_mm: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, le=BIG)] | None = Field(
        None, description="the tool tip's distance from the cam axis in rapid moves, above the cam's outer radius "
                          f"[mm]; omitted: the outer radius + {SAFE_CLEARANCE_MM:g} mm")
    cut_z_mm: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, le=BIG)] | None = Field(
        None, description="the tool tip's distance from the cam axis while cutting, from the groove's bottom radius "
                          "up to below the outer radius [mm]; omitted: the groove's bottom radius (its full depth)")
    format: Literal[("json", *BARREL_TOOLPATH_FORMATS)] = Field(  # type: ignore[valid-type]  # from the registry
        "json", description="json: the passes; " + "; ".join(f"{f.name}: {f.description}"
                                                             for f in BARREL_TOOLPATH_FORMATS.values()))

    @model_validator(mode="after")
    def _check(self) -> BarrelToolpathRequest:
        try:  # camcore's rules and sentences, at the cam's fields where they are the cam's
            check_cutter(self.cam.follower, self.cam.roller, self.cam.roller_radius_mm, self.tool_radius_mm)
        except CamError as exc:
            at = ("cam", *exc.field) if exc.field in (("follower",), ("roller",)) else exc.field
            raise FieldRuleError(str(exc), *at) from None
        outer, bottom = _dimensions(self.cam)
        if self.safe_z_mm is not None and not self.safe_z_mm > outer:
            raise FieldRuleError(f"safe_z_mm must be above the cam's outer radius, {outer!r} mm (the rapid moves turn "
                                 "A over the cam)", "safe_z_mm")
        if self.cut_z_mm is not None and not bottom <= self.cut_z_mm < outer:
            raise FieldRuleError(f"cut_z_mm must lie from the groove's bottom radius, {bottom!r} mm, up to below the "
                                 f"cam's outer radius, {outer!r} mm", "cut_z_mm")
        return self

    def heights(self) -> tuple[float, float]:
        """The safe and the cutting Z, defaults filled [mm]."""
        outer, bottom = _dimensions(self.cam)
        safe = outer + SAFE_CLEARANCE_MM if self.safe_z_mm is None else self.safe_z_mm
        return safe, bottom if self.cut_z_mm is None else self.cut_z_mm


#: request examples of computeBarrelToolpath (Swagger UI pre-fills the first)
BARREL_TOOLPATH_EXAMPLES: dict[str, Example] = {
    "roller-cutter": {"summary": "the translating barrel cam with a cutter of the roller's size: one pass on the "
                                 "groove's centre line, within 0.01 mm",
                      "value": {"cam": BARREL_EXAMPLE, "tool_radius_mm": 10, "tolerance_mm": 0.01}},
    "smaller-cutter": {"summary": "an 8 mm cutter in the 10 mm roller's groove: one pass on each wall (\"format\": "
                                  "\"gcode\" for the program)",
                       "value": {"cam": BARREL_EXAMPLE, "tool_radius_mm": 8, "tolerance_mm": 0.005,
                                 "feed_mm_min": 250}},
}


class RotaryPassAnswer(DeferredModel):
    """One pass of the cutter, its nodes in the order it runs them."""

    wall: Literal["groove", "lower", "upper"] = Field(
        description="groove: a cutter of the roller's size on the centre line (both walls); lower or upper: one wall "
                    "(the −z or +z side of the groove)")
    offset_mm: float = Field(description="the cutter axis's offset from the centre line along the developed normal at "
                                         "the pitch radius, + towards +z")
    direction: Literal["A rising", "A falling"] = Field(description="climb milling with M3: the wall on the tool's right")
    moves_count: int
    length_mm: float = Field(description="length of the moves in the developed plane of the pitch radius")
    max_deviation_mm: float = Field(description="measured both ways at the cam's outer radius (≤ tolerance_mm)")
    max_deviation_pitch_mm: float = Field(description="the same at the pitch radius")
    cam_angle_deg: list[float] = Field(description="the cam angle of each node")
    a_deg: list[float] = Field(description="A of each node: the cam angle, shifted by the offset (the tool's angle)")
    x_mm: list[float] = Field(description="X of each node: along the cam axis from the cam's z = 0")


class BarrelToolpathAnswer(DefaultsInDescriptions):
    """The passes of a barrel cam's groove on a four-axis mill, and what was measured of them."""

    tool_radius_mm: float
    roller_radius_mm: float
    tolerance_mm: float
    pitch_radius_mm: float
    wrap_diameter_mm: float = Field(description="the pitch diameter: the A words are the developed path drawn on it")
    outer_radius_mm: float = Field(description="the cam's outer radius, where the deviation is measured")
    groove_bottom_radius_mm: float
    safe_z_mm: float
    cut_z_mm: float
    max_deviation_mm: float = Field(description="largest of the passes' deviations at the outer radius")
    max_deviation_pitch_mm: float = Field(description="largest at the pitch radius")
    moves_count: int = Field(description="straight moves of all passes")
    wall_gap_max_mm: float = Field(
        description="a smaller cutter: the most material its passes leave on a wall, measured in 3-D against the "
                    "exact flanks across the roller's length (the offset is exact at the pitch radius; the roller's "
                    "wall turns along its length, a radial cutter's does not); 0 for a cutter of the roller's size")
    wall_gap_min_mm: float = Field(description="the same, the most the passes cut past a wall (negative)")
    wall_gap_at_deg: float | None = Field(description="cam angle of the larger of the two")
    wall_gap_at_position_mm: float | None = Field(description="position along the roller's axis (from the cam axis) "
                                                              "of the larger of the two")
    passes: list[RotaryPassAnswer]


def _estimate(ctx: Context, body: BarrelToolpathRequest, fmt: Format) -> WorkEstimate:
    """The cam's curves, the passes' fit (and the walls' measurement) and the answer's writing."""
    cam = body.cam
    _, field, built = barrel_build_work(ctx, cam)
    segments = len(cam.motion.segments) if cam.motion is not None else len(cam.segments or ())
    if cam.motion is not None:  # a program's strokes may be solved: one pitch radius a move
        strokes = [cam.pitch_radius_mm for s in cam.motion.segments if s.type != "dwell"]
    else:
        strokes = [s.lift_mm or 0.0 for s in cam.segments or () if s.type != "dwell"]
    passes = 1 if body.tool_radius_mm == cam.roller_radius_mm else 2
    moves = passes * barrel_moves_estimate(strokes, segments, body.tolerance_mm)
    work = built + barrel_toolpath_work(moves, passes, segments, ("cam", *field), ("tolerance_mm",))
    seconds = BARREL_TOOLPATH_FORMATS[fmt.name].cost(moves) if fmt.name in BARREL_TOOLPATH_FORMATS else \
        encode_cost(moves * NODE_VALUES, False)
    return work + WorkEstimate((WorkTerm(("tolerance_mm",), f"writing about {moves} moves as {fmt.name}", seconds),))


def barrel_toolpath(ctx: Context, body: BarrelToolpathRequest) -> BarrelToolpath:
    """The fitted passes (413 over the move limit)."""
    with within("cam"):
        cam = barrel_cam(ctx, body.cam)
    return compute_barrel_toolpath(cam, body.tool_radius_mm, body.tolerance_mm, ctx.settings.max_toolpath_elements)


def _compute(ctx: Context, body: BarrelToolpathRequest, fmt: Format) -> Raw | Payload:
    """The JSON answer, or the program of :data:`BARREL_TOOLPATH_FORMATS`."""
    tp = barrel_toolpath(ctx, body)
    safe, cut = body.heights()
    if fmt.name in BARREL_TOOLPATH_FORMATS:
        return Payload(BARREL_TOOLPATH_FORMATS[fmt.name].write(BarrelToolpathFile(tp, body.feed_mm_min, safe, cut)))
    return Raw(barrel_toolpath_answer(tp, safe, cut))


def barrel_toolpath_answer(tp: BarrelToolpath, safe_z_mm: float, cut_z_mm: float) -> dict[str, Any]:
    """The JSON answer: each pass's nodes, the deviations and the walls' gaps."""
    passes = [{"wall": p.wall, "offset_mm": p.offset_mm,
               "direction": "A rising" if p.a_deg[-1] > p.a_deg[0] else "A falling",
               "moves_count": len(p.a_deg) - 1, "length_mm": p.length_mm, "max_deviation_mm": p.max_deviation_mm,
               "max_deviation_pitch_mm": p.max_deviation_pitch_mm, "cam_angle_deg": p.cam_angle_deg.tolist(),
               "a_deg": p.a_deg.tolist(), "x_mm": p.x_mm.tolist()} for p in tp.passes]
    return {"tool_radius_mm": tp.tool_radius_mm, "roller_radius_mm": tp.roller_radius_mm,
            "tolerance_mm": tp.tolerance_mm, "pitch_radius_mm": tp.pitch_radius_mm,
            "wrap_diameter_mm": 2 * tp.pitch_radius_mm, "outer_radius_mm": tp.outer_radius_mm,
            "groove_bottom_radius_mm": tp.groove_bottom_radius_mm, "safe_z_mm": safe_z_mm, "cut_z_mm": cut_z_mm,
            "max_deviation_mm": tp.max_deviation_mm, "max_deviation_pitch_mm": tp.max_deviation_pitch_mm,
            "moves_count": tp.segments_count, "wall_gap_max_mm": tp.wall_gap_max_mm,
            "wall_gap_min_mm": tp.wall_gap_min_mm, "wall_gap_at_deg": tp.wall_gap_at_deg,
            "wall_gap_at_position_mm": tp.wall_gap_at_position_mm, "passes": passes}


OPERATIONS = (
    Operation("computeBarrelToolpath", "/v1/cams/barrel/toolpath", "cams", "Barrel cam toolpath (4-axis)",
              "The groove of a barrel cam on a four-axis mill (A about the cam axis along X, the tool radial along Z): "
              "the cutter axis's straight moves in A and X within tolerance_mm, measured at the cam's outer radius; "
              "JSON, or G-code (G93 inverse-time feed) with format.",
              BarrelToolpathRequest, _compute, estimate=_estimate, answer=BarrelToolpathAnswer,
              formats=(JSON, *(download(fmt) for fmt in BARREL_TOOLPATH_FORMATS.values())), body_format="format",
              examples=BARREL_TOOLPATH_EXAMPLES),
)
