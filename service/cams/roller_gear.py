"""``POST /v1/cams/roller-gear`` (``computeRollerGearCam``): a roller-gear cam's rib — both flanks as
point grids, the pressure angles, the checks; the columns over the turn as CSV, the rib as a
closed binary STL, and the whole cam (the rib on its globoidal body) as a solid from the CAD kernel:
STEP, or STL of the kernel's mesh (``solid-stl``).
"""

from __future__ import annotations

import math
from typing import Any

from camcore.cams.roller_gear import (
    RollerGearCam,
    RollerGearResult,
    make_roller_gear_cam,
    rib_triangles,
    sample_roller_gear,
)
from camcore.export import mesh_stl
from camcore.export.roller_gear_solid import RollerGearSolid
from camcore.results import as_dict
from camcore.work import (
    RIB_COLUMNS,
    RIB_FACET_S,
    RIB_FLANK_POINT_S,
    RIB_FLANK_VALUES,
    RIB_PRESSURE_SEARCH_S,
    WorkEstimate,
    WorkTerm,
    encode_cost,
    per_item_work,
    rib_facets,
)
from camcore.work.roller_gear import (
    RIB_SOLID_BASE_S,
    RIB_SOLID_NODE_S,
    RIB_STL_FACET_S,
    rib_nodes_estimate,
    rib_solid_facets,
)
from service.cams.roller_gear_specs import (
    ROLLER_GEAR_EXAMPLES,
    SOLID_EXAMPLES,
    SOLID_STL_EXAMPLES,
    RollerGearCamAnswer,
    RollerGearCamRequest,
    RollerGearSolidSpec,
    RollerGearSolidStlRequest,
)
from service.context import Context
from service.curves.library import check_limit
from service.operations import JSON, Document, Format, Operation, Payload, Table, csv
from service.responses import check_finite

STL = Format("stl", "model/stl", "the rib as a closed binary STL in mm", file_name="roller-gear-rib.stl",
                 attachment=True)
STEP = Format("step", "model/step", "the cam as a STEP AP214 solid in mm (OpenCASCADE): the rib on its globoidal body, "
              "its flanks B-spline surfaces within solid.tolerance_mm of the exact flanks", file_name="roller-gear-cam.step",
              attachment=True)
SOLID_STL = Format("solid-stl", "model/stl", "the same solid as a binary STL in mm (OpenCASCADE's mesh): every facet "
                   "within solid.tolerance_mm of the exact flanks", file_name="roller-gear-cam.stl", attachment=True)
#: each solid format and the kernel's writer of it (camcore.export.SOLID_FORMATS)
SOLIDS = {STEP.name: "step", SOLID_STL.name: "stl"}
#: the patches may take this many times the estimate's cam angles before the solid is refused (413):
#: 300 of 304 random cams took no more than the estimated cam angles, the rest at most 23 % more, and
#: the estimate's 3.75 ms an estimated angle covers the 2.2 ms measured at most (camcore.work.roller_gear):
#: half as many again still within the estimate
NODES_SLACK = 1.5


def _solid(body: RollerGearCamRequest) -> RollerGearSolidSpec:
    return body.solid if body.solid is not None else RollerGearSolidSpec()


def _fit_tolerance(body: RollerGearCamRequest, fmt: Format) -> float:
    """The patches' tolerance: an STL's halves it (the other half for its facets)."""
    return _solid(body).tolerance_mm / (2 if fmt is SOLID_STL else 1)


def _solid_work(ctx: Context, body: RollerGearCamRequest, fmt: Format) -> WorkEstimate:
    """The curve, the patches fitted and sewn by the kernel, the file; an STL's facets (413 over the limit)."""
    nodes = rib_nodes_estimate(body.center_distance_mm, _fit_tolerance(body, fmt))
    work = ctx.curves.work(body.curve.core(), ("curve",)) + WorkEstimate((WorkTerm(
        ("solid", "tolerance_mm"), f"the cam's faces at up to {nodes} cam angles, sewn into a solid and written",
        RIB_SOLID_BASE_S + nodes * RIB_SOLID_NODE_S),))
    if fmt is SOLID_STL:
        facets = rib_solid_facets(body.stops, body.center_distance_mm, body.roller_pitch_radius_mm,
                                  body.roller_radius_mm, body.roller_length_mm, 0.5 * _solid(body).tolerance_mm)
        check_limit("STL facets", facets, ctx.settings.max_stl_triangles, ("solid", "tolerance_mm"))
        work += per_item_work(facets, RIB_STL_FACET_S, ("solid", "tolerance_mm"), f"up to {facets} STL facets")
    return work


def _warmup(ctx: Context, fmt: Format) -> None:
    # the CAD kernel's process starts outside the budget, on the first solid (service/cad_pool.py)
    if fmt.name in SOLIDS:
        ctx.cad.warm()


def _work(ctx: Context, body: RollerGearCamRequest, fmt: Format) -> WorkEstimate:
    """The curve built, the pressure search, the flank grids and their encoding or the mesh; a solid's own."""
    if fmt.name in SOLIDS:
        return _solid_work(ctx, body, fmt)
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


def roller_gear_cam(ctx: Context, body: RollerGearCamRequest) -> RollerGearCam:
    geometry = body.model_dump(include={"stops", "center_distance_mm", "roller_pitch_radius_mm", "roller_radius_mm",
                                        "roller_length_mm", "indexing_angle_deg"})
    return make_roller_gear_cam(**geometry, curve=ctx.curves.curve(body.curve.core()))


def roller_gear(ctx: Context, body: RollerGearCamRequest) -> RollerGearResult:
    return sample_roller_gear(roller_gear_cam(ctx, body), body.samples, body.length_samples)


def over_the_turn(r: RollerGearResult) -> dict[str, Any]:
    return {"cam_angle_deg": r.cam_angle_deg, "turret_angle_deg": r.turret_angle_deg,
            "pressure_angle_deg": r.pressure_angle_deg, "back_pressure_angle_deg": r.back_pressure_angle_deg}


def _compute(ctx: Context, body: RollerGearCamRequest, fmt: Format) -> Document | Table | Payload:
    """JSON: the columns over the turn, both flank grids, the checks; CSV: the columns; STL: the rib; a
    solid: the cam, written by the CAD kernel's process."""
    if fmt.name in SOLIDS:
        spec = _solid(body)
        item = RollerGearSolid(roller_gear_cam(ctx, body), spec.tolerance_mm, spec.bore_diameter_mm,
                               spec.root_clearance_mm, spec.body_length_mm,
                               math.floor(NODES_SLACK * rib_nodes_estimate(body.center_distance_mm, _fit_tolerance(body, fmt))),
                               ctx.settings.max_stl_triangles)
        return Payload(ctx.cad.write(SOLIDS[fmt.name], item))
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
              "the turn; STL: the rib; STEP (and solid-stl): the whole cam, the rib on its globoidal body, as one "
              "solid from the CAD kernel (give `solid` for its tolerance, bore, clearance and length).",
              RollerGearCamRequest, _compute, estimate=_work, warmup=_warmup, answer=RollerGearCamAnswer,
              formats=(JSON, csv("roller-gear-cam.csv", "the columns over the rib's turn as CSV"), STL, STEP, SOLID_STL),
              examples=ROLLER_GEAR_EXAMPLES,
              format_requests={SOLID_STL.name: RollerGearSolidStlRequest},
              format_examples={STEP.name: SOLID_EXAMPLES, SOLID_STL.name: SOLID_STL_EXAMPLES}),
)
