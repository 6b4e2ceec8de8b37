"""``POST /v1/cams/parallel`` (``computeParallelIndexingCam``): a parallel indexing cam's plates,
contacts and checks; the columns over the turn as CSV (the plates are JSON only: each has its own
rows); the plates' contours as DXF (a layer each) and the plates as solids (STEP, STL: give
``solid``), written by the CAD kernel's process.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from camcore.cams.parallel import (
    ParallelCam,
    ParallelResult,
    make_parallel_cam,
    plate_contour,
    sample_parallel,
    trace_factor,
)
from camcore.errors import InvalidParameterError
from camcore.export import PLATE_FORMATS, SOLID_FORMATS, ParallelPlatesSolid, PlateDrawing
from camcore.results import as_dict
from camcore.work import WorkEstimate, WorkTerm, encode_cost
from camcore.work.parallel import answer_values, contour_points, solid_work, trace_work
from service.cams.parallel_specs import (
    PARALLEL_EXAMPLES,
    PARALLEL_SOLID_EXAMPLES,
    PARALLEL_STL_EXAMPLES,
    ParallelCamAnswer,
    ParallelCamRequest,
    ParallelSolidRequest,
    ParallelSolidSpec,
    ParallelSolidStlRequest,
)
from service.context import Context
from service.operations import JSON, Document, Format, Operation, Payload, Table, csv, download

#: columns whose NaN means "no such contact" (null in JSON, an empty CSV cell)
NULLABLE = ("drive_pressure_angle_deg", "hold_pressure_angle_deg")
#: the columns over the turn (over_the_turn)
TURN_COLUMNS = 6


def plates_work(ctx: Context, body: ParallelCamRequest, plates: int | None = None,
                at: tuple[str | int, ...] = ()) -> WorkEstimate:
    """The curve built and ``plates`` plates (default all) traced, at ``trace_factor`` times the samples
    (at least 720 cam angles a turn); ``at``: where the cam is in the request."""
    traced = body.samples * trace_factor(body.samples)
    return ctx.curves.work(body.curve.core(), (*at, "curve")) + trace_work(
        body.plates if plates is None else plates, body.rollers_per_plate or body.stops, traced, at)


def _solid_spec(body: ParallelCamRequest, fmt: Format) -> ParallelSolidSpec:
    if body.solid is None:
        raise InvalidParameterError(f"format {fmt.name} is the plates as solids: give solid {{thickness_mm, "
                                    "bore_diameter_mm}.", field=("solid",))
    return body.solid


def _work(ctx: Context, body: ParallelCamRequest, fmt: Format) -> WorkEstimate:
    """The plates traced and the answer encoded (the contours' points and the contacts in JSON), or
    written as DXF; a solid: the contours fitted (at half the tolerance for an STL) and the CAD kernel's
    work (422 first when the body has no ``solid``)."""
    traced = body.samples * trace_factor(body.samples)
    if fmt.name in SOLID_FORMATS:
        solid = _solid_spec(body, fmt)
        return plates_work(ctx, body) + solid_work(body.center_distance_mm, body.rollers_per_plate or body.stops,
                                                   body.plates, solid.tolerance_mm, solid.bore_diameter_mm,
                                                   fmt.name == "stl", ("solid", "tolerance_mm"))
    if fmt.name in PLATE_FORMATS:
        points = contour_points(body.plates, traced)
        return plates_work(ctx, body) + WorkEstimate((WorkTerm(
            ("samples",), f"writing about {points} points as {fmt.name}", PLATE_FORMATS[fmt.name].cost(points)),))
    values = answer_values(body.plates, body.samples, traced) if fmt.name == "json" else 0
    encoding = encode_cost(TURN_COLUMNS * body.samples + values, fmt.name == "csv")
    return plates_work(ctx, body) + WorkEstimate((WorkTerm(("samples",), "encoding the answer", encoding),))


def parallel_cam(ctx: Context, body: ParallelCamRequest) -> ParallelCam:
    """The cam of a request, its index law from the curve cache."""
    return make_parallel_cam(body.stops, body.center_distance_mm, body.roller_pitch_radius_mm, body.roller_radius_mm,
                             body.indexing_angle_deg, ctx.curves.curve(body.curve.core()), plates=body.plates,
                             rollers_per_plate=body.rollers_per_plate)


def parallel(ctx: Context, body: ParallelCamRequest) -> ParallelResult:
    return sample_parallel(parallel_cam(ctx, body), body.samples)


def _warmup(ctx: Context, fmt: Format) -> None:
    # the CAD kernel's process starts outside the request's budget (service/profiles/operations.py says why)
    if fmt.name in SOLID_FORMATS:
        ctx.cad.warm()


def over_the_turn(r: ParallelResult) -> dict[str, Any]:
    return {"cam_angle_deg": r.cam_angle_deg, "turret_angle_deg": r.turret_angle_deg,
            "held_forward": r.held_forward, "held_back": r.held_back,
            "drive_pressure_angle_deg": r.drive_pressure_angle_deg, "hold_pressure_angle_deg": r.hold_pressure_angle_deg}


def _compute(ctx: Context, body: ParallelCamRequest, fmt: Format) -> Document | Table | Payload:
    """JSON: the columns over the turn, the plates, the checks (NaN, no such contact, as null);
    CSV: the columns (true/false as 1/0); DXF: the plates' contours; STEP, STL: the plates as solids."""
    if fmt.name in SOLID_FORMATS or fmt.name in PLATE_FORMATS:
        cam = parallel_cam(ctx, body)
        traced = [plate_contour(cam, p, body.samples) for p in range(cam.plates)]
        if fmt.name in PLATE_FORMATS:
            drawing = PlateDrawing(tuple(pts.x for _, pts in traced), tuple(pts.y for _, pts in traced))
            return Payload(PLATE_FORMATS[fmt.name].write(drawing))
        solid = _solid_spec(body, fmt)
        item = ParallelPlatesSolid(tuple(contour for contour, _ in traced), solid.thickness_mm, solid.bore_diameter_mm,
                                   solid.spacing_mm, solid.tolerance_mm, ctx.settings.max_toolpath_elements,
                                   ctx.settings.max_stl_triangles)
        return Payload(ctx.cad.write(fmt.name, item))  # in the CAD kernel's process
    r = parallel(ctx, body)
    columns = over_the_turn(r)
    if fmt.name == "csv":
        return Table({name: (v.astype(np.float64) if v.dtype == bool else v) for name, v in columns.items()},
                     allow_null=NULLABLE)
    return Document({**columns, "plates": [as_dict(p) for p in r.plates], "checks": as_dict(r.checks)},
                    table=columns, allow_null=NULLABLE)


SOLIDS = tuple(download(fmt) for fmt in SOLID_FORMATS.values())

OPERATIONS = (
    Operation("computeParallelIndexingCam", "/v1/cams/parallel", "cams", "Parallel indexing cam",
              "A parallel indexing cam: each plate's exact contour (the envelope of its rollers), which roller touches "
              "it where and when, every contact over the turn, pressure angles and radii of curvature, and the checks "
              "(held both ways at every cam angle, largest pressure angle, undercut, room for the turret's shaft); CSV: "
              "the columns over the turn; DXF: the plates' contours, a layer each; STEP, STL: the plates as solids "
              "(give `solid` in the body).",
              ParallelCamRequest, _compute, estimate=_work, warmup=_warmup, answer=ParallelCamAnswer,
              formats=(JSON, csv("parallel-cam.csv", "the columns over the turn as CSV"),
                       *(download(fmt) for fmt in PLATE_FORMATS.values()), *SOLIDS),
              examples=PARALLEL_EXAMPLES, format_requests={"step": ParallelSolidRequest, "stl": ParallelSolidStlRequest},
              format_examples={"step": PARALLEL_SOLID_EXAMPLES, "stl": PARALLEL_STL_EXAMPLES}),
)
