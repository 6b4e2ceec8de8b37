"""POST /v1/profiles/toolpath: the cutter-centre path of a plate cam as lines and arcs.

``computeToolpath`` answers JSON (the elements, the measured deviation) or, with the body's
``format`` (or ``?format=``), a file of :data:`camcore.export.TOOLPATH_FORMATS` (G-code, DXF).
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal

from fastapi.openapi.models import Example
from pydantic import Field, model_validator

from camcore.export import TOOLPATH_FORMATS, ToolpathFile
from camcore.toolpath import Toolpath, compute_toolpath
from camcore.work import ELEMENT_VALUES, WorkEstimate, WorkTerm, encode_cost, fit_elements_estimate, fit_work
from service.context import Context
from service.operations import JSON, Alias, Format, Operation, Payload, Raw, download
from service.profiles.operations import cam, schedule_field, schedule_work, segment_count, strokes_mm
from service.profiles.specs import ROLLER_PROFILE_EXAMPLE, ProfileSpec
from service.specs import (
    BIG,
    DefaultsInDescriptions,
    DeferredModel,
    FieldRuleError,
    Spec,
    examples,
    one_of_values,
    rule,
)

#: a roller follower (the condition of a groove)
ROLLER = {"properties": {"follower": {"required": ["type"], "properties": {"type": {"const": "roller"}}}},
          "required": ["follower"]}


#: the fields a plate's cutter path shares (the plate cam's and the parallel cam's plates)
PathTolerance = Annotated[float, Field(
    strict=True, allow_inf_nan=False, ge=1e-4, le=10,
    description="largest deviation of the lines and arcs from the exact cutter-centre path, measured both ways [mm]")]
FeedRate = Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, le=BIG,
                                  description="cutting feed of the G-code [mm/min]")]
SafeHeight = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=-BIG, le=BIG,
                                    description="height of the G-code's rapid moves [mm]")]
CutHeight = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=-BIG, le=BIG,
                                   description="cutting depth of the G-code, below safe_z_mm [mm]")]
ToolpathFormat = Annotated[Literal[("json", *TOOLPATH_FORMATS)], Field(  # type: ignore[valid-type]  # from the registry
    description="json: the elements; " + "; ".join(f"{f.name}: {f.description}" for f in TOOLPATH_FORMATS.values()))]


def check_heights(safe_z_mm: float, cut_z_mm: float) -> None:
    """The G-code's cut below its rapid moves (422 at cut_z_mm)."""
    if cut_z_mm >= safe_z_mm:
        raise FieldRuleError("cut_z_mm must be below safe_z_mm (the rapid moves run above the cut)", "cut_z_mm")


class ToolpathRequest(Spec):
    """A cam, a tool and a tolerance: the path its centre runs, fitted with lines and arcs."""

    model_config = examples(
        {"profile": ROLLER_PROFILE_EXAMPLE, "tool_radius_mm": 6, "tolerance_mm": 0.01},
        rules=[rule("a groove is the track of a roller: give a roller follower",
                    {"if": one_of_values("side", "groove"), "then": {"properties": {"profile": ROLLER}}})])
    profile: ProfileSpec
    tool_radius_mm: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, le=BIG)] = Field(
        description="radius of the cutter [mm]")
    tolerance_mm: PathTolerance = 0.01
    side: Literal["outside", "inside", "groove"] = Field(
        "outside", description="outside: the tool outside the cam surface (a plate cam); inside: inside a roller "
                               "track's outer wall (or inside the surface of a knife-edge or flat-faced cam: a "
                               "pocket); groove: both walls of a roller's track, one path each")
    allow_gouge: bool = Field(False, description="follow the exact offset where the tool is larger than a concave "
                                                 "radius it must follow (the tool cuts into the wall) instead of "
                                                 "refusing (422)")
    feed_mm_min: FeedRate = 300.0
    safe_z_mm: SafeHeight = 5.0
    cut_z_mm: CutHeight = 0.0
    lead_in_mm: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0, le=BIG)] | None = Field(
        None, description="length of the straight lead-in along the normal [mm]; omitted: the tool radius (in a "
                          "roller's track: to its centre line, roller radius − tool radius)")
    format: ToolpathFormat = "json"

    @model_validator(mode="after")
    def _check(self) -> ToolpathRequest:
        if self.side == "groove" and self.profile.follower.type != "roller":
            raise FieldRuleError("a groove is the track of a roller: give a roller follower", "side")
        check_heights(self.safe_z_mm, self.cut_z_mm)
        return self


FLAT_PROFILE_EXAMPLE: dict[str, object] = {
    "follower": {"type": "flat-faced"}, "base_radius_mm": 40,
    "segments": [{"type": "rise", "angle_deg": 150, "lift_mm": 15}, {"type": "dwell", "angle_deg": 30},
                 {"type": "return", "angle_deg": 150, "lift_mm": 15}, {"type": "dwell", "angle_deg": 30}]}
#: request examples of computeToolpath (Swagger UI pre-fills the first)
TOOLPATH_EXAMPLES: dict[str, Example] = {
    "outside": {"summary": "plate cam, roller follower: a 6 mm tool outside the surface, within 0.01 mm",
                "value": {"profile": ROLLER_PROFILE_EXAMPLE, "tool_radius_mm": 6, "tolerance_mm": 0.01}},
    "groove": {"summary": "the same cam as a groove: both walls of the roller's track with an 8 mm tool "
                          "(\"format\": \"gcode\" for the program)",
               "value": {"profile": ROLLER_PROFILE_EXAMPLE, "tool_radius_mm": 8, "tolerance_mm": 0.005,
                         "side": "groove", "feed_mm_min": 250, "cut_z_mm": -10}},
    "flat": {"summary": "a flat-faced follower's cam within 0.001 mm (\"format\": \"dxf\" for the drawing)",
             "value": {"profile": FLAT_PROFILE_EXAMPLE, "tool_radius_mm": 10, "tolerance_mm": 0.001}},
}


class ElementAnswer(DeferredModel):
    """One line or arc of a path, in the cam's frame."""

    type: Literal["line", "arc"]
    x0_mm: float = Field(description="start x")
    y0_mm: float = Field(description="start y")
    x1_mm: float = Field(description="end x")
    y1_mm: float = Field(description="end y")
    cx_mm: float | None = Field(description="arc centre x (null for a line)")
    cy_mm: float | None = Field(description="arc centre y (null for a line)")
    radius_mm: float | None = Field(description="arc radius (null for a line)")
    direction: Literal["cw", "ccw"] | None = Field(description="arc sense seen from +z: cw = G2, ccw = G3 (null for "
                                                               "a line)")


class CutterPathAnswer(DeferredModel):
    """The closed cutter-centre path of one wall, starting at cam angle 0."""

    wall: Literal["surface", "outer-wall"] = Field(description="the cam surface, or a roller track's outer wall")
    side: Literal["outside", "inside"] = Field(description="the tool outside or inside that wall")
    clockwise: bool = Field(description="the sense of travel: climb milling with M3, clockwise round an outside")
    offset_mm: float = Field(description="the path's offset from the pitch curve (a flat face: from the surface) "
                                         "along the outward normal")
    max_deviation_mm: float = Field(description="measured against the exact cutter-centre path, both ways")
    segments_count: int = Field(description="lines and arcs")
    length_mm: float = Field(description="length of the path")
    min_concave_radius_mm: float | None = Field(
        description="smallest concave radius of curvature the tool follows on this wall (null: none)")
    min_concave_radius_at_deg: float | None = Field(description="cam angle of that radius")
    gouges: bool = Field(description="the tool is larger than that radius (only with allow_gouge)")
    lead_in_mm: float = Field(description="the lead-in's default length on this wall")
    elements: list[ElementAnswer]


class ToolpathAnswer(DefaultsInDescriptions):
    """The cutter-centre paths of the walls asked for, fitted with lines and arcs."""

    tool_radius_mm: float
    tolerance_mm: float
    side: Literal["outside", "inside", "groove"]
    max_deviation_mm: float = Field(description="largest measured deviation of any path (≤ tolerance_mm)")
    segments_count: int = Field(description="lines and arcs of all paths")
    paths: list[CutterPathAnswer]


def toolpath_work(ctx: Context, body: ToolpathRequest, fmt: Format) -> WorkEstimate:
    """The curves, the checks of each wall, the fitted elements and the answer's encoding."""
    costs, work = schedule_work(ctx, body.profile)
    paths = 2 if body.side == "groove" else 1
    elements = paths * fit_elements_estimate(strokes_mm(body.profile), segment_count(body.profile), body.tolerance_mm)
    work += fit_work(costs, elements, paths, schedule_field(body.profile), ("tolerance_mm",))
    seconds = TOOLPATH_FORMATS[fmt.name].cost(elements) if fmt.name in TOOLPATH_FORMATS else \
        encode_cost(elements * ELEMENT_VALUES, False)
    return work + WorkEstimate((WorkTerm(("tolerance_mm",), f"writing about {elements} elements as {fmt.name}",
                                         seconds),))


def toolpath(ctx: Context, body: ToolpathRequest) -> Toolpath:
    """The fitted paths (413 over the element limit)."""
    return compute_toolpath(cam(ctx, body.profile), body.tool_radius_mm, body.tolerance_mm, body.side, body.allow_gouge,
                            ctx.settings.max_toolpath_elements)


def _compute(ctx: Context, body: ToolpathRequest, fmt: Format) -> Raw | Payload:
    """The JSON answer, or the paths written in one of :data:`camcore.export.TOOLPATH_FORMATS`."""
    return toolpath_reply(toolpath(ctx, body), fmt, body.feed_mm_min, body.safe_z_mm, body.cut_z_mm, body.lead_in_mm)


def toolpath_reply(tp: Toolpath, fmt: Format, feed_mm_min: float, safe_z_mm: float, cut_z_mm: float,
                   lead_in_mm: float | None) -> Raw | Payload:
    """A plate's paths as the JSON answer, or written in one of :data:`camcore.export.TOOLPATH_FORMATS`."""
    if fmt.name in TOOLPATH_FORMATS:
        return Payload(TOOLPATH_FORMATS[fmt.name].write(ToolpathFile(tp, feed_mm_min, safe_z_mm, cut_z_mm, lead_in_mm)))
    return Raw(toolpath_answer(tp))


def toolpath_answer(tp: Toolpath) -> dict[str, Any]:
    """The JSON answer: every element of every path, the deviations and counts."""
    paths = []
    for p in tp.paths:
        elements = [{"type": "arc" if e.is_arc else "line", "x0_mm": e.start[0], "y0_mm": e.start[1],
                     "x1_mm": e.end[0], "y1_mm": e.end[1],
                     "cx_mm": e.centre[0] if e.centre else None, "cy_mm": e.centre[1] if e.centre else None,
                     "radius_mm": e.radius_mm if e.centre else None,
                     "direction": ("ccw" if e.ccw else "cw") if e.centre else None} for e in p.elements]
        paths.append({"wall": p.wall, "side": p.side, "clockwise": p.clockwise, "offset_mm": p.offset_mm,
                      "max_deviation_mm": p.max_deviation_mm, "segments_count": len(p.elements),
                      "length_mm": p.length_mm,
                      "min_concave_radius_mm": p.min_concave_radius_mm if math.isfinite(p.min_concave_radius_mm)
                      else None,
                      "min_concave_radius_at_deg": p.min_concave_radius_at_deg, "gouges": p.gouges,
                      "lead_in_mm": p.lead_in_mm, "elements": elements})
    return {"tool_radius_mm": tp.tool_radius_mm, "tolerance_mm": tp.tolerance_mm, "side": tp.side,
            "max_deviation_mm": tp.max_deviation_mm, "segments_count": tp.segments_count, "paths": paths}


OPERATIONS = (
    Operation("computeToolpath", "/v1/profiles/toolpath", "profiles", "Plate cam toolpath (cutter centre)",
              "The cutter-centre path of a plate cam (its surface offset by the tool radius) as lines and arcs "
              "within tolerance_mm, the deviation measured; JSON, or G-code or DXF with format.",
              ToolpathRequest, _compute, estimate=toolpath_work, answer=ToolpathAnswer,
              formats=(JSON, *(download(fmt) for fmt in TOOLPATH_FORMATS.values())), body_format="format",
              examples=TOOLPATH_EXAMPLES, aliases=(Alias("exportToolpathGcode", "/v1/profiles/toolpath.nc", "gcode"),)),
)
