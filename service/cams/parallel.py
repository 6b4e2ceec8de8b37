"""``POST /v1/cams/parallel`` (``computeParallelIndexingCam``): a parallel indexing cam's plates,
contacts and checks; the columns over the turn as CSV (the plates are JSON only: each has its own
rows).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from camcore.cams.parallel import ParallelResult, make_parallel_cam, sample_parallel, trace_factor
from camcore.results import as_dict
from camcore.work import (
    PARALLEL_CONTACT_VALUES,
    PARALLEL_CONTACTS_PER_SAMPLE,
    PARALLEL_PLATE_S,
    PARALLEL_PLATE_SAMPLE_S,
    PARALLEL_POINT_VALUES,
    PARALLEL_POINTS_PER_SAMPLE,
    PLATE_ROLLER_SAMPLE_S,
    WorkEstimate,
    WorkTerm,
    encode_cost,
    per_item_work,
)
from service.cams.parallel_specs import PARALLEL_EXAMPLES, ParallelCamAnswer, ParallelCamRequest
from service.context import Context
from service.operations import JSON, Document, Format, Operation, Table, csv

#: columns whose NaN means "no such contact" (null in JSON, an empty CSV cell)
NULLABLE = ("drive_pressure_angle_deg", "hold_pressure_angle_deg")
#: the columns over the turn (over_the_turn)
TURN_COLUMNS = 6


def plates_work(ctx: Context, body: ParallelCamRequest) -> WorkEstimate:
    """The curve built and the plates traced (at ``trace_factor`` times the samples, at least 720
    cam angles a turn)."""
    m = body.rollers_per_plate or body.stops
    traced = body.samples * trace_factor(body.samples)
    return ctx.curves.work(body.curve.core(), ("curve",)) + WorkEstimate((
        WorkTerm(("plates",), f"tracing {body.plates} plates", body.plates * PARALLEL_PLATE_S),
        WorkTerm(("samples",), f"walking {body.plates} plates × {traced} traced cam angles",
                 body.plates * traced * PARALLEL_PLATE_SAMPLE_S))) + per_item_work(
        body.plates * m * traced, PLATE_ROLLER_SAMPLE_S, ("samples",),
        f"{body.plates} plates × {m} rollers × {traced} traced cam angles")


def _work(ctx: Context, body: ParallelCamRequest, fmt: Format) -> WorkEstimate:
    """The plates traced and the answer encoded (the contours' points and the contacts in JSON)."""
    traced = body.samples * trace_factor(body.samples)
    values = body.plates * (PARALLEL_POINT_VALUES * PARALLEL_POINTS_PER_SAMPLE * traced
                            + PARALLEL_CONTACT_VALUES * PARALLEL_CONTACTS_PER_SAMPLE * body.samples)
    encoding = encode_cost(TURN_COLUMNS * body.samples + (values if fmt.name == "json" else 0), fmt.name == "csv")
    return plates_work(ctx, body) + WorkEstimate((WorkTerm(("samples",), "encoding the answer", encoding),))


def parallel(ctx: Context, body: ParallelCamRequest) -> ParallelResult:
    cam = make_parallel_cam(body.stops, body.center_distance_mm, body.roller_pitch_radius_mm, body.roller_radius_mm,
                            body.indexing_angle_deg, ctx.curves.curve(body.curve.core()), plates=body.plates,
                            rollers_per_plate=body.rollers_per_plate)
    return sample_parallel(cam, body.samples)


def over_the_turn(r: ParallelResult) -> dict[str, Any]:
    return {"cam_angle_deg": r.cam_angle_deg, "turret_angle_deg": r.turret_angle_deg,
            "held_forward": r.held_forward, "held_back": r.held_back,
            "drive_pressure_angle_deg": r.drive_pressure_angle_deg, "hold_pressure_angle_deg": r.hold_pressure_angle_deg}


def _compute(ctx: Context, body: ParallelCamRequest, fmt: Format) -> Document | Table:
    """JSON: the columns over the turn, the plates, the checks (NaN, no such contact, as null);
    CSV: the columns (true/false as 1/0)."""
    r = parallel(ctx, body)
    columns = over_the_turn(r)
    if fmt.name == "csv":
        return Table({name: (v.astype(np.float64) if v.dtype == bool else v) for name, v in columns.items()},
                     allow_null=NULLABLE)
    return Document({**columns, "plates": [as_dict(p) for p in r.plates], "checks": as_dict(r.checks)},
                    table=columns, allow_null=NULLABLE)


OPERATIONS = (
    Operation("computeParallelIndexingCam", "/v1/cams/parallel", "cams", "Parallel indexing cam",
              "A parallel indexing cam: each plate's contour (what its rollers leave), which roller touches it where "
              "and when, every contact over the turn, pressure angles and radii of curvature, and the checks (held "
              "both ways at every cam angle, largest pressure angle, undercut, room for the turret's shaft); CSV: "
              "the columns over the turn.",
              ParallelCamRequest, _compute, estimate=_work, answer=ParallelCamAnswer,
              formats=(JSON, csv("parallel-cam.csv", "the columns over the turn as CSV")), examples=PARALLEL_EXAMPLES),
)
