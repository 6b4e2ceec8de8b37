"""``POST /v1/machines`` (``computeMachine``): several axes on one camshaft.

Each axis is built as its own operation builds it (the same caches, limits and errors, located under
``axes.<i>.<mechanism>``): a plate cam by :func:`service.profiles.operations.cam`, a barrel cam by
:func:`service.cams.barrel.barrel_cam`, an indexer by :func:`service.indexers.operations.indexer`, a
motion program by :func:`service.motions.operations.resolve`; camcore.machine does the rest.
``?format=csv`` the timing table; ``?format=png|svg`` the timing diagram or (``chart: torque``) the
camshaft torque; ``?format=cam-table`` one axis's servo cam table (``cam_table_axis``, default the first).
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from camcore.cams.barrel import barrel_checks
from camcore.errors import InvalidParameterError, NonFiniteResultError
from camcore.export import MOTION_FORMATS, CamTable
from camcore.machine import (
    Condition,
    Drive,
    DrivenLoad,
    Flywheel,
    IndexerAxis,
    LiftLoadAxis,
    Machine,
    MachineAxis,
    PlateCamAxis,
    Rule,
)
from camcore.profile.lift import MotionLift
from camcore.results import as_dict
from camcore.work import WorkEstimate, WorkTerm, encode_cost, machine_work, motion_work, per_item_work
from service.cams.barrel import barrel_cam, barrel_work
from service.context import Context
from service.curves.library import check_limit
from service.drawing import chart_work
from service.errors import relocate, within
from service.indexers.operations import indexer, indexer_work
from service.machines.charts import timing_chart, torque_chart
from service.machines.specs import (
    MACHINE_EXAMPLES,
    AxisSpec,
    ConditionSpec,
    MachineAnswer,
    MachineRequest,
)
from service.motions.operations import program_costs, resolve
from service.operations import (
    JSON,
    PNG_DRAWING,
    SVG_DRAWING,
    Document,
    Format,
    Operation,
    Payload,
    Table,
    csv,
    download,
)
from service.profiles.dynamics import follower_work
from service.profiles.operations import cam
from service.responses import check_finite

CAM_TABLE = MOTION_FORMATS["cam-table"]
FORMATS = (JSON, csv("machine-timing.csv", "the timing table: master angle and every axis's position"),
           PNG_DRAWING, SVG_DRAWING, download(CAM_TABLE))


# ----------------------------------------------------------------------------- the axes
def _axis(ctx: Context, i: int, spec: AxisSpec) -> MachineAxis:
    """One axis, built as its own operation builds its mechanism; errors located at the axis."""
    mechanism = spec.mechanism
    with relocate((), ("axes", i, mechanism)):
        if spec.plate_cam is not None:
            p = spec.plate_cam
            with within("profile", only=InvalidParameterError):
                return PlateCamAxis(spec.name, spec.phase_deg, cam(ctx, p.profile), p.follower_load(),
                                    safety_margin_n=p.safety_margin_n, roller=None if p.roller is None else p.roller.core(),
                                    allowed_stress_mpa=p.allowed_stress_mpa)
        if spec.barrel_cam is not None:
            b = spec.barrel_cam
            with relocate((), ("cam",)):
                the_cam = barrel_cam(ctx, b.cam)
            unit = "deg" if b.cam.follower == "oscillating" else "mm"
            mass, force = b.mass_and_force(unit)
            return LiftLoadAxis(spec.name, spec.phase_deg, the_cam.lift, unit, DrivenLoad(mass, 0.0, force, b.efficiency),
                                "barrel_cam", {"barrel": as_dict(barrel_checks(the_cam))})
        if spec.indexer is not None:
            x = spec.indexer
            with within("load"):
                load = x.load.core()
            unit_at = indexer(ctx, x.indexer, speed_rpm=60.0)  # any speed: the axis sets its own from the camshaft
            # IndexerAxis names its fields as the axis spec holds them (ratio, indexer.input_stop_time_s)
            return IndexerAxis(spec.name, spec.phase_deg, unit_at, load, ratio=x.ratio,
                               internal_friction_torque_nm=x.indexer.internal_friction_torque_nm,
                               rated_output_torque_nm=x.rated_output_torque_nm,
                               input_angle_origin=x.indexer.input_angle_origin)
        assert spec.motion is not None
        m = spec.motion
        program = resolve(ctx, m.motion.core())
        with within("motion"):
            lift = MotionLift(program)
        mass, force = m.mass_and_force(program.unit)
        return LiftLoadAxis(spec.name, spec.phase_deg, lift, program.unit, DrivenLoad(mass, 0.0, force, m.efficiency),
                            "motion", {"characteristics": as_dict(program.characteristics)})


def _condition(c: ConditionSpec) -> Condition:
    return Condition(c.axis, c.moving, c.at_most, c.at_least)


def machine(ctx: Context, body: MachineRequest) -> Machine:
    """The camcore machine of the request."""
    axes = [_axis(ctx, i, spec) for i, spec in enumerate(body.axes)]
    rules = [Rule(_condition(r.while_), _condition(r.require)) for r in body.rules]
    flywheel = None if body.flywheel is None else Flywheel(body.flywheel.speed_fluctuation, body.flywheel.inertia_kgm2)
    drive = None
    if body.drive is not None:
        with within("drive"):
            drive = Drive(body.drive.motor.core(), body.drive.gear_ratio, body.drive.efficiency, body.drive.slip)
    return Machine(axes, rules, flywheel, drive)


# ----------------------------------------------------------------------------- the work
def _axis_build_work(ctx: Context, i: int, spec: AxisSpec) -> WorkEstimate:
    """Building the axis and its own checks, as its own operation's estimate counts them; each term at the
    axis's field (its operation's fields are the axis spec's: a 413 names axes.<i>.<mechanism>.…)."""
    at: tuple[str | int, ...] = ("axes", i, spec.mechanism)
    with relocate((), at):
        if spec.plate_cam is not None:
            work = follower_work(ctx, spec.plate_cam.profile, 2)
        elif spec.barrel_cam is not None:
            with relocate((), ("cam",)):
                work = barrel_work(ctx, spec.barrel_cam.cam, 2, 2, "json")
            at = (*at, "cam")
        elif spec.indexer is not None:
            work = indexer_work(ctx, spec.indexer.indexer, 2, False)
        else:
            assert spec.motion is not None
            costs, solved = program_costs(ctx, spec.motion.motion.core())
            work = motion_work(costs, solved, 0, ("motion", "segments"), ())
    return WorkEstimate(tuple(dataclasses.replace(term, field=(*at, *term.field)) for term in work.terms))


def _work(ctx: Context, body: MachineRequest, fmt: Format) -> WorkEstimate:
    """Every axis built and checked, then the machine's own work per axis and speed (camcore.work.machines),
    the rules, the rows and their encoding or the chart; 413 first for more rows than max_table_samples."""
    check_limit("machine samples", body.samples, ctx.settings.max_table_samples, ("samples",))
    work = WorkEstimate()
    for i, spec in enumerate(body.axes):
        work += _axis_build_work(ctx, i, spec)
    kinds = [spec.mechanism for spec in body.axes]
    motor_searches = 0 if body.drive is None else 2
    work += machine_work(kinds, 1 + len(body.speeds_rpm), len(body.rules), motor_searches, body.samples)
    columns = 1 + 3 * len(body.axes) + 2
    if fmt.name in ("png", "svg"):
        return work + chart_work(fmt.name, 100)
    if fmt.name == CAM_TABLE.name:
        return work + WorkEstimate((WorkTerm(("samples",), f"writing {body.samples} rows as a cam table",
                                             CAM_TABLE.cost(body.samples)),))
    return work + per_item_work(body.samples * columns, encode_cost(1, fmt.name == "csv"), ("samples",),
                                f"{body.samples} rows × {columns} columns encoded")


# ----------------------------------------------------------------------------- the answer
def _cam_table(m: Machine, body: MachineRequest) -> Payload:
    axis = m.by_name[body.cam_table_axis] if body.cam_table_axis is not None else m.axes[0]
    x_deg = np.linspace(0.0, 360.0, body.samples)
    s, v, a = axis.derivatives_per_deg(axis.own(np.radians(x_deg)))
    return Payload(CAM_TABLE.write(CamTable(x_deg, s, v, a, axis.unit)))


def _compute(ctx: Context, body: MachineRequest, fmt: Format) -> Document | Table | Payload:
    check_limit("machine samples", body.samples, ctx.settings.max_table_samples, ("samples",))
    m = machine(ctx, body)
    if fmt.name == CAM_TABLE.name:
        return _cam_table(m, body)
    rpm = body.master.rpm
    x_deg = np.linspace(0.0, 360.0, body.samples)
    timing = m.timing(x_deg)
    if fmt.name == "csv":
        return Table(timing)
    with np.errstate(all="ignore"):
        result = m.compute(rpm, body.speeds_rpm)
    torque = m.torque_columns(x_deg, rpm, result.summary)
    if fmt.name in ("png", "svg"):
        if body.chart == "torque":
            return Payload(torque_chart(torque, as_dict(result.summary), fmt.name))
        return Payload(timing_chart(m, timing, result.rules, rpm, fmt.name))
    value: dict[str, Any] = {"timing": timing, "torque": torque, **as_dict(result)}
    check_finite({name: col for name, col in torque.items()})
    _check_numbers(value["summary"], "summary")
    return Document(value)


def _check_numbers(value: Any, where: str) -> None:
    if isinstance(value, dict):
        for key, item in value.items():
            _check_numbers(item, f"{where}.{key}")
    elif isinstance(value, list):
        for i, item in enumerate(value):
            _check_numbers(item, f"{where}[{i}]")
    elif isinstance(value, float) and not math.isfinite(value):
        raise NonFiniteResultError(f"the computation of '{where}' produced a non-finite number for these inputs; "
                                   "check that they describe a realistic machine.")


def _cam_table_examples() -> dict[str, Any]:
    """The examples, each writing its last axis's cam table."""
    out: dict[str, Any] = {}
    for name, example in MACHINE_EXAMPLES.items():
        value: dict[str, Any] = dict(example.get("value") or {})
        out[name] = {**example, "value": {**value, "cam_table_axis": value["axes"][-1]["name"]}}
    return out


OPERATIONS = (
    Operation("computeMachine", "/v1/machines", "machines", "Machine: several axes on one camshaft",
              "The timing diagram (every axis's position and normalised position over the master angle), each axis's "
              "torque on the camshaft and the total (peak, RMS, mean), the energy fluctuation and the flywheel, the "
              "motor check, each axis's own checks, the speed limits (each axis's first failure speed and the "
              "machine's top speed), the timing rules (where broken, phase slack) and a speed sweep; "
              "``?format=csv``: the timing table; ``?format=png|svg``: the timing diagram (``chart: torque``: the "
              "camshaft torque); ``?format=cam-table``: one axis's servo cam table (``cam_table_axis``, default the "
              "first axis).",
              MachineRequest, _compute, estimate=_work, answer=MachineAnswer, formats=FORMATS,
              examples=MACHINE_EXAMPLES, format_examples={CAM_TABLE.name: _cam_table_examples()}),
)
