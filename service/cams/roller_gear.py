"""``POST /v1/cams/roller-gear`` (``computeRollerGearCam``): a roller-gear cam's rib — both flanks as
point grids, the pressure angles, the checks; the columns over the turn as CSV and the rib as a
closed binary STL.
"""

from __future__ import annotations

from typing import Any

from camcore.cams.roller_gear import RollerGearResult, make_roller_gear_cam, rib_triangles, sample_roller_gear
from camcore.export import mesh_stl
from camcore.results import as_dict
from camcore.work import (
    RIB_COLUMNS,
    RIB_FACET_S,
    RIB_FLANK_POINT_S,
    RIB_FLANK_VALUES,
    RIB_PRESSURE_SEARCH_S,
    WorkEstimate,
    encode_cost,
    per_item_work,
    rib_facets,
)
from service.cams.roller_gear_specs import ROLLER_GEAR_EXAMPLES, RollerGearCamAnswer, RollerGearCamRequest
from service.context import Context
from service.curves.library import check_limit
from service.operations import JSON, Document, Format, Operation, Payload, Table, csv
from service.responses import check_finite

STL = Format("stl", "model/stl", "the rib as a closed binary STL in mm", file_name="roller-gear-rib.stl",
                 attachment=True)


def _work(ctx: Context, body: RollerGearCamRequest, fmt: Format) -> WorkEstimate:
    """The curve built, the pressure search, the flank grids and their encoding or the mesh."""
    points = body.samples * body.length_samples
    check_limit("roller-gear flank points (samples × length_samples)", points, ctx.settings.max_table_samples,
                ("samples",))
    work = (ctx.curves.work(body.curve.core(), ("curve",))
            + per_item_work(1, RIB_PRESSURE_SEARCH_S, ("indexing_angle_deg",), "the largest pressure angle refined")
            + per_item_work(points, RIB_FLANK_POINT_S, ("samples",), f"{points} points on each flank"))
    if fmt is STL:
        facets = rib_facets(body.samples, body.length_samples)
        check_limit("STL facets", facets, ctx.settings.max_stl_triangles, ("samples",))
        return work + per_item_work(facets, RIB_FACET_S, ("samples",), f"{facets} STL facets")
    csv_answer = fmt.name == "csv"
    values = body.samples * RIB_COLUMNS + (0 if csv_answer else points * RIB_FLANK_VALUES)
    return work + per_item_work(values, encode_cost(1, csv_answer), ("samples",), f"{values} numbers encoded")


def roller_gear(ctx: Context, body: RollerGearCamRequest) -> RollerGearResult:
    geometry = body.model_dump(include={"stops", "center_distance_mm", "roller_pitch_radius_mm", "roller_radius_mm",
                                        "roller_length_mm", "indexing_angle_deg"})
    cam = make_roller_gear_cam(**geometry, curve=ctx.curves.curve(body.curve.core()))
    return sample_roller_gear(cam, body.samples, body.length_samples)


def over_the_turn(r: RollerGearResult) -> dict[str, Any]:
    return {"cam_angle_deg": r.cam_angle_deg, "turret_angle_deg": r.turret_angle_deg,
            "pressure_angle_deg": r.pressure_angle_deg, "back_pressure_angle_deg": r.back_pressure_angle_deg}


def _compute(ctx: Context, body: RollerGearCamRequest, fmt: Format) -> Document | Table | Payload:
    """JSON: the columns over the turn, both flank grids, the checks; CSV: the columns; STL: the rib."""
    r = roller_gear(ctx, body)
    if fmt is STL:
        return Payload(mesh_stl(rib_triangles(r), header=f"camcore roller-gear rib, {body.stops} stops",
                                max_triangles=ctx.settings.max_stl_triangles, field=("samples",)))
    if fmt.name == "csv":
        return Table(over_the_turn(r))
    columns = {**over_the_turn(r), "roller_position_mm": r.roller_position_mm}
    flanks = {f.flank: {"x_mm": f.x_mm, "y_mm": f.y_mm, "z_mm": f.z_mm, "pressure_angle_deg": f.pressure_angle_deg,
                        "regular": f.regular} for f in (r.forward, r.back)}
    check_finite({**columns, **{f"{name} flank {k}": v for name, flank in flanks.items() for k, v in flank.items()}})
    return Document({**columns, "flanks": flanks, "checks": as_dict(r.checks)})


OPERATIONS = (
    Operation("computeRollerGearCam", "/v1/cams/roller-gear", "cams", "Roller-gear (globoidal) cam",
              "A roller-gear (globoidal) cam: both flanks of its rib as point grids in the cam's frame (the envelopes "
              "of the two rollers straddling the rib), the pressure angle over the index, the turret's angle, and "
              "the checks (largest pressure angle, undercut, the rib's thickness and radii); CSV: the columns over "
              "the turn; STL: the rib.",
              RollerGearCamRequest, _compute, estimate=_work, answer=RollerGearCamAnswer,
              formats=(JSON, csv("roller-gear-cam.csv", "the columns over the rib's turn as CSV"), STL),
              examples=ROLLER_GEAR_EXAMPLES),
)
