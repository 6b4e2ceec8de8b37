"""``POST /v1/cams/parallel/toolpath`` (``computeParallelToolpath``): the cutter-centre path round one
plate of a parallel indexing cam, as lines and arcs within a tolerance; JSON, or a file of
:data:`camcore.export.TOOLPATH_FORMATS` (G-code, DXF) with the body's ``format`` or ``?format=``.

The path is the plate's exact contour (camcore.cams.parallel.trace) offset by the tool radius,
fitted as the plate cam's toolpath is (camcore.cams.parallel.fit), clockwise round the plate (climb
milling with M3), the answer and the files those of ``POST /v1/profiles/toolpath``.
"""

from __future__ import annotations

import math
from typing import Annotated

from fastapi.openapi.models import Example
from pydantic import Field, model_validator

from camcore.cams.parallel import plate_contour
from camcore.cams.parallel.fit import concave_radius, fit_plate
from camcore.export import TOOLPATH_FORMATS
from camcore.toolpath import Toolpath
from camcore.work import ELEMENT_VALUES, WorkEstimate, WorkTerm, encode_cost
from camcore.work.parallel import fit_work
from service.cams.parallel import parallel_cam, plates_work
from service.cams.parallel_specs import PARALLEL_EXAMPLE, ParallelCamRequest
from service.context import Context
from service.operations import JSON, Format, Operation, Payload, Raw, download
from service.profiles.toolpath import (
    CutHeight,
    FeedRate,
    PathTolerance,
    SafeHeight,
    ToolpathAnswer,
    ToolpathFormat,
    check_heights,
    toolpath_reply,
)
from service.specs import BIG, JSON_INTEGER, FieldRuleError, Spec, examples, rule

PLATE_RULE = "plate must be below cam.plates (plates are numbered from 0)"


class ParallelToolpathRequest(Spec):
    """A parallel cam, one of its plates, a tool and a tolerance: the path the tool's centre runs round the plate."""

    model_config = examples(
        {"cam": PARALLEL_EXAMPLE, "plate": 1, "tool_radius_mm": 6, "tolerance_mm": 0.01},
        rules=[rule(PLATE_RULE, {"if": {"properties": {"cam": {"properties": {"plates": {"const": 2}},
                                                               "required": ["plates"]}}},
                                 "then": {"properties": {"plate": {"maximum": 1}}}})])
    cam: ParallelCamRequest = Field(description="the parallel cam, as POST /v1/cams/parallel takes it (its samples "
                                                "set the traced cam angles; its solid is not used)")
    plate: Annotated[int, Field(ge=0, le=2), JSON_INTEGER] = Field(0, description="which plate, 0 … plates − 1")
    tool_radius_mm: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, le=BIG)] = Field(
        description="radius of the cutter, at most the plate's smallest concave radius (the rollers' radius at the "
                    "least) [mm]")
    tolerance_mm: PathTolerance = 0.01
    feed_mm_min: FeedRate = 300.0
    safe_z_mm: SafeHeight = 5.0
    cut_z_mm: CutHeight = 0.0
    lead_in_mm: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0, le=BIG)] | None = Field(
        None, description="length of the straight lead-in along the normal [mm]; omitted: the tool radius")
    format: ToolpathFormat = "json"

    @model_validator(mode="after")
    def _check(self) -> ParallelToolpathRequest:
        if self.plate >= self.cam.plates:
            raise FieldRuleError(f"{PLATE_RULE}: plate {self.plate} of {self.cam.plates}", "plate")
        check_heights(self.safe_z_mm, self.cut_z_mm)
        return self


#: request examples of computeParallelToolpath (Swagger UI pre-fills the first)
PARALLEL_TOOLPATH_EXAMPLES: dict[str, Example] = {
    "plate 1": {"summary": "plate 1 of the three-plate cam, a 6 mm tool, within 0.01 mm (\"format\": \"gcode\" for "
                           "the program)",
                "value": {"cam": PARALLEL_EXAMPLE, "plate": 1, "tool_radius_mm": 6, "tolerance_mm": 0.01}},
    "deep": {"summary": "plate 0 with a 5 mm tool within 0.005 mm, 10 mm deep (\"format\": \"dxf\" for the "
                        "drawing)",
             "value": {"cam": PARALLEL_EXAMPLE, "plate": 0, "tool_radius_mm": 5, "tolerance_mm": 0.005,
                       "cut_z_mm": -10}},
}


def _work(ctx: Context, body: ParallelToolpathRequest, fmt: Format) -> WorkEstimate:
    """The plate traced, its path fitted and the answer written."""
    fit, pieces, elements = fit_work(body.cam.center_distance_mm, body.cam.rollers_per_plate or body.cam.stops,
                                     body.tolerance_mm, 1, ("tolerance_mm",))
    count = elements + pieces  # and an arc round each corner
    seconds = TOOLPATH_FORMATS[fmt.name].cost(count) if fmt.name in TOOLPATH_FORMATS else \
        encode_cost(count * ELEMENT_VALUES, False)
    return plates_work(ctx, body.cam, 1, ("cam",)) + fit + WorkEstimate((
        WorkTerm(("tolerance_mm",), f"writing about {count} elements as {fmt.name}", seconds),))


def plate_toolpath(ctx: Context, body: ParallelToolpathRequest) -> Toolpath:
    """The plate's cutter path (413 over the element limit)."""
    cam = parallel_cam(ctx, body.cam)
    contour, pts = plate_contour(cam, body.plate, body.cam.samples)
    radius, at = concave_radius(contour, pts.rho, pts.cam_angle * (180 / math.pi))
    path = fit_plate(contour, body.tool_radius_mm, body.tolerance_mm, radius, at, ctx.settings.max_toolpath_elements)
    return Toolpath(float(body.tool_radius_mm), float(body.tolerance_mm), "outside", (path,))


def _compute(ctx: Context, body: ParallelToolpathRequest, fmt: Format) -> Raw | Payload:
    """The JSON answer, or the path written in one of :data:`camcore.export.TOOLPATH_FORMATS`."""
    return toolpath_reply(plate_toolpath(ctx, body), fmt, body.feed_mm_min, body.safe_z_mm, body.cut_z_mm,
                          body.lead_in_mm)


OPERATIONS = (
    Operation("computeParallelToolpath", "/v1/cams/parallel/toolpath", "cams",
              "Parallel indexing cam plate toolpath (cutter centre)",
              "The cutter-centre path round one plate of a parallel indexing cam (its exact contour offset by the tool "
              "radius) as lines and arcs within tolerance_mm, the deviation measured; JSON, or G-code or DXF with "
              "format.",
              ParallelToolpathRequest, _compute, estimate=_work, answer=ToolpathAnswer,
              formats=(JSON, *(download(fmt) for fmt in TOOLPATH_FORMATS.values())), body_format="format",
              examples=PARALLEL_TOOLPATH_EXAMPLES),
)
