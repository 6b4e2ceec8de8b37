"""Specs and answers of ``POST /v1/machines`` (docs/api.md: machines)."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from fastapi.openapi.models import Example
from pydantic import Field, model_validator

from camcore.machine import (
    AxisLimit,
    AxisReport,
    MachineSummary,
    RuleResult,
)
from service.cams.barrel_specs import BarrelCamRequest
from service.indexers.specs import INDEXER_SHAPE_EXAMPLE, LOAD_EXAMPLE, MOTOR_EXAMPLE, IndexerShape, LoadSpec, MotorSpec
from service.models import answer_model
from service.motions.specs import MotionSpec
from service.profiles.dynamics_specs import FOLLOWER_LOAD_RULES, ForceClosedFollower
from service.profiles.specs import ROLLER_PROFILE_EXAMPLE
from service.specs import (
    BIG,
    JSON_INTEGER,
    CycleTimeS,
    DeferredModel,
    FieldRuleError,
    Finite,
    Spec,
    SpeedRpm,
    absent,
    exactly_one,
    examples,
    given,
    rule,
)

Positive = Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, le=BIG)]
NonNegative = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0, le=BIG)]
Efficiency = Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, le=1)]
#: axis names: column names in the timing and torque tables, so letters, digits and _ only
AxisName = Annotated[str, Field(pattern=r"^[A-Za-z][A-Za-z0-9_]{0,31}$",
                                description="the axis's name: a letter, then letters, digits or _ (at most 32)")]
MECHANISMS = ("plate_cam", "barrel_cam", "indexer", "motion")
#: most axes, rules and swept speeds of one machine (each axis is a whole operation's work)
MAX_AXES = 16
MAX_RULES = 32
MAX_SPEEDS = 32

DRIVEN_RULE = ("a driven load in mm (a translating follower, a motion in mm) is mass_kg and force_n; in deg (an "
               "oscillating follower, a motion in deg) inertia_kgm2 and torque_nm")
STOPLESS_RULE = ("an indexer geared to the camshaft turns with it: its input cannot stand still (input_stop_time_s "
                 "must be 0)")
ALLOWED_STRESS_RULE = "allowed_stress_mpa needs the roller's width and materials (roller)"


def _driven_rules(in_deg: dict[str, Any]) -> list[dict[str, Any]]:
    """The load's fields by the lift's unit, as JSON Schema (``in_deg``: the condition of a lift in deg)."""
    return [rule(DRIVEN_RULE, {"if": in_deg, "then": {"allOf": [given("inertia_kgm2"), absent("mass_kg", "force_n")]},
                               "else": {"allOf": [given("mass_kg"), absent("inertia_kgm2", "torque_nm")]}})]


class DrivenLoadFields(Spec):
    """What a positively driven lift moves: its mass and a constant force (mm), or its inertia and a torque (deg)."""

    mass_kg: NonNegative | None = Field(None, description="mm: the moving mass")
    force_n: Finite | None = Field(None, description="mm: a constant force against the positive motion; default 0")
    inertia_kgm2: NonNegative | None = Field(None, description="deg: the inertia about the swing's axis")
    torque_nm: Finite | None = Field(None, description="deg: a constant torque against the positive swing; default 0")
    efficiency: Efficiency = Field(1.0, description="η of the mechanism between camshaft and load: T/η while the "
                                                    "camshaft drives, T·η while the load drives it back")

    def check_units(self, unit: str, where: tuple[str | int, ...]) -> None:
        """mass and force for mm, inertia and torque for deg (422 at the field)."""
        own, other = (("inertia_kgm2", "torque_nm"), ("mass_kg", "force_n")) if unit == "deg" else (
            ("mass_kg", "force_n"), ("inertia_kgm2", "torque_nm"))
        wrong = [name for name in other if getattr(self, name) is not None]
        if wrong:
            raise FieldRuleError(f"{DRIVEN_RULE} ({wrong[0]} given for {unit})", *where, wrong[0])
        if getattr(self, own[0]) is None:
            raise FieldRuleError(f"{DRIVEN_RULE} (missing {own[0]})", *where, own[0])

    def mass_and_force(self, unit: str) -> tuple[float, float]:
        if unit == "deg":
            return float(self.inertia_kgm2 or 0.0), float(self.torque_nm or 0.0)
        return float(self.mass_kg or 0.0), float(self.force_n or 0.0)


class PlateCamAxisSpec(ForceClosedFollower):
    """A plate cam with a force-closed follower (the fields of computeFollowerDynamics without the speed and
    the rows) and, with the roller's materials, the Hertz stress allowed."""

    model_config = examples({"profile": ROLLER_PROFILE_EXAMPLE, "mass_kg": 0.5, "spring_rate_n_mm": 2,
                             "preload_n": 30, "safety_margin_n": 5},
                            rules=[*FOLLOWER_LOAD_RULES, rule(ALLOWED_STRESS_RULE, {"if": given("allowed_stress_mpa"),
                                                                                    "then": given("roller")})])
    allowed_stress_mpa: Positive | None = Field(
        None, description="with roller: the Hertz pressure allowed; the speed at which it is reached is a speed limit")

    @model_validator(mode="after")
    def _allowed(self) -> PlateCamAxisSpec:
        if self.allowed_stress_mpa is not None and self.roller is None:
            raise FieldRuleError(ALLOWED_STRESS_RULE, "allowed_stress_mpa")
        return self


class BarrelAxisSpec(DrivenLoadFields):
    """A barrel cam (the fields of computeBarrelCam; its samples are not used) and what its follower drives."""

    model_config = examples({"cam": {
        "pitch_radius_mm": 50, "roller_radius_mm": 10, "roller_length_mm": 12,
        "segments": [{"type": "rise", "angle_deg": 120, "lift_mm": 30}, {"type": "dwell", "angle_deg": 60},
                     {"type": "return", "angle_deg": 120, "lift_mm": 30}, {"type": "dwell", "angle_deg": 60}]},
        "mass_kg": 3, "force_n": 20}, rules=_driven_rules({"required": ["cam"], "properties": {"cam": {
            "required": ["follower"], "properties": {"follower": {"const": "oscillating"}}}}}))
    cam: BarrelCamRequest

    @model_validator(mode="after")
    def _units(self) -> BarrelAxisSpec:
        self.check_units("deg" if self.cam.follower == "oscillating" else "mm", ())
        return self


class IndexerAxisSpec(Spec):
    """An indexer on the camshaft: its input turns ``ratio`` times per camshaft turn (its speed is the camshaft's
    × ratio), driving its load."""

    model_config = examples({"indexer": INDEXER_SHAPE_EXAMPLE, "load": LOAD_EXAMPLE, "ratio": 1},
                            rules=[rule(STOPLESS_RULE, {"properties": {"indexer": {"properties": {
                                "input_stop_time_s": {"maximum": 0}}}}})])
    indexer: IndexerShape
    load: LoadSpec
    ratio: Annotated[int, Field(ge=1, le=100), JSON_INTEGER] = Field(
        1, description="input turns per camshaft turn (whole: the indexer's cycle repeats every camshaft turn)")
    rated_output_torque_nm: Positive | None = Field(
        None, description="the unit's rated output torque (the maker's): the speed at which the design output torque "
                          "reaches it is a speed limit")

    @model_validator(mode="after")
    def _turning(self) -> IndexerAxisSpec:
        if self.indexer.input_stop_time_s:
            raise FieldRuleError(STOPLESS_RULE, "indexer", "input_stop_time_s")
        return self


class MotionAxisSpec(DrivenLoadFields):
    """A motion program (a servo-free slave on the camshaft, or a linkage's output) driving a load."""

    model_config = examples({"motion": {"unit": "mm", "segments": [
        {"span_deg": 120, "to": 40, "curve": {"type": "named", "name": "cycloid"}}, {"span_deg": 60, "type": "dwell"},
        {"span_deg": 120, "to": 0, "curve": {"type": "named", "name": "cycloid"}}, {"span_deg": 60, "type": "dwell"}]},
        "mass_kg": 2, "force_n": 0, "efficiency": 0.95}, rules=_driven_rules({"required": ["motion"], "properties": {
            "motion": {"required": ["unit"], "properties": {"unit": {"const": "deg"}}}}}))
    motion: MotionSpec

    @model_validator(mode="after")
    def _units(self) -> MotionAxisSpec:
        self.check_units(self.motion.unit, ())
        return self


class AxisSpec(Spec):
    """One axis: its name, its phase on the master, and one mechanism."""

    model_config = examples({"name": "feed", "phase_deg": 0, "plate_cam": PlateCamAxisSpec.model_config[
        "json_schema_extra"]["examples"][0]},  # type: ignore[index]
        rules=[rule("give exactly one mechanism: plate_cam, barrel_cam, indexer or motion", exactly_one(*MECHANISMS))])
    name: AxisName
    phase_deg: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0, lt=360)] = Field(
        0.0, description="φ: the master angle at which the axis is at its own 0; position(x) = own((x − φ) mod 360)")
    plate_cam: PlateCamAxisSpec | None = None
    barrel_cam: BarrelAxisSpec | None = None
    indexer: IndexerAxisSpec | None = None
    motion: MotionAxisSpec | None = None

    @model_validator(mode="after")
    def _one(self) -> AxisSpec:
        given_ = [name for name in MECHANISMS if getattr(self, name) is not None]
        if len(given_) != 1:
            raise ValueError("give exactly one mechanism: plate_cam, barrel_cam, indexer or motion"
                             + (f" (given: {', '.join(given_)})" if given_ else ""))
        return self

    @property
    def mechanism(self) -> str:
        return next(name for name in MECHANISMS if getattr(self, name) is not None)


class ConditionSpec(Spec):
    """What an axis satisfies: moving (true) or standing still (false), or its position at most / at least a
    value in its unit (mm, or deg: an indexer's output angle, a swing)."""

    model_config = examples({"axis": "table", "moving": True}, {"axis": "feed", "at_most": 2.0},
                            rules=[rule("give exactly one of moving, at_most and at_least",
                                        exactly_one("moving", "at_most", "at_least"))])
    axis: AxisName
    moving: bool | None = None
    at_most: Finite | None = None
    at_least: Finite | None = None

    @model_validator(mode="after")
    def _one(self) -> ConditionSpec:
        if sum(getattr(self, n) is not None for n in ("moving", "at_most", "at_least")) != 1:
            raise ValueError("give exactly one of moving, at_most and at_least")
        return self


class RuleSpec(Spec):
    """While ``while`` holds, ``require`` must hold (e.g. while the table indexes, the gripper is up)."""

    model_config = examples({"while": {"axis": "table", "moving": True}, "require": {"axis": "feed", "at_most": 2.0}})
    while_: ConditionSpec = Field(alias="while")
    require: ConditionSpec


class MasterSpec(Spec):
    """The camshaft's speed: one cycle is one turn."""

    model_config = examples({"speed_rpm": 120}, rules=[rule("give exactly one of speed_rpm and cycle_time_s",
                                                            exactly_one("speed_rpm", "cycle_time_s"))])
    speed_rpm: SpeedRpm | None = Field(None, description="N [rpm]")
    cycle_time_s: CycleTimeS | None = Field(None, description="one turn, 60/N [s]")

    @model_validator(mode="after")
    def _one(self) -> MasterSpec:
        if (self.speed_rpm is None) == (self.cycle_time_s is None):
            raise ValueError("give exactly one of speed_rpm and cycle_time_s")
        return self

    @property
    def rpm(self) -> float:
        return float(self.speed_rpm) if self.speed_rpm is not None else 60.0 / float(self.cycle_time_s)  # type: ignore[arg-type]


class FlywheelSpec(Spec):
    """Size the flywheel for a speed fluctuation, or give its inertia and get the fluctuation it leaves."""

    model_config = examples({"speed_fluctuation": 0.02}, {"inertia_kgm2": 0.5},
                            rules=[rule("give exactly one of speed_fluctuation and inertia_kgm2",
                                        exactly_one("speed_fluctuation", "inertia_kgm2"))])
    speed_fluctuation: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, lt=1)] | None = Field(
        None, description="Cs = (ω_max − ω_min)/ω to keep")
    inertia_kgm2: NonNegative | None = Field(None, description="the flywheel's inertia on the camshaft [kg·m²]")

    @model_validator(mode="after")
    def _one(self) -> FlywheelSpec:
        if (self.speed_fluctuation is None) == (self.inertia_kgm2 is None):
            raise ValueError("give exactly one of speed_fluctuation and inertia_kgm2")
        return self


class DriveSpec(Spec):
    """The camshaft's motor through a gear."""

    model_config = examples({"gear_ratio": 10, "efficiency": 0.9, "motor": MOTOR_EXAMPLE})
    gear_ratio: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=1e-3, le=1e5)] = Field(
        1.0, description="motor-side turns per camshaft turn (the motor's own reduction_ratio multiplies it)")
    efficiency: Efficiency = Field(1.0, description="η of the gear (the motor's reduction_efficiency multiplies it)")
    motor: MotorSpec
    slip: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, lt=1)] = Field(
        0.05, description="the motor's speed drop at rated torque as a fraction of its speed (an induction motor's "
                          "rated slip): with a flywheel, how much of the torque fluctuation the motor still carries")


#: a feed (the roller cam of computeProfile's example) and a 6-stop table indexing in 45° of camshaft angle
#: while the feed is back within 2 mm of its base
MACHINE_EXAMPLE: dict[str, Any] = {
    "master": {"speed_rpm": 60},
    "axes": [
        {"name": "feed", "phase_deg": 0, "plate_cam": {"profile": ROLLER_PROFILE_EXAMPLE, "mass_kg": 0.8,
                                                       "spring_rate_n_mm": 3, "preload_n": 40, "safety_margin_n": 10}},
        {"name": "table", "phase_deg": 305, "indexer": {"indexer": {"stops": 6, "indexing_angle_deg": 45},
                                                        "load": LOAD_EXAMPLE, "ratio": 1}},
    ],
    "rules": [{"while": {"axis": "table", "moving": True}, "require": {"axis": "feed", "at_most": 2.0}}],
    "flywheel": {"speed_fluctuation": 0.05},
    "samples": 361,
}
#: every kind of axis: the feed, a barrel cam's slide, a table indexing twice per turn, a pusher's motion program
FOUR_KINDS_EXAMPLE: dict[str, Any] = {
    "master": {"cycle_time_s": 1.5},
    "axes": [
        MACHINE_EXAMPLE["axes"][0],
        {"name": "slide", "phase_deg": 90, "barrel_cam": BarrelAxisSpec.model_config["json_schema_extra"][
            "examples"][0]},  # type: ignore[index]
        {"name": "table", "phase_deg": 0, "indexer": {"indexer": {"stops": 8, "indexing_angle_deg": 90},
                                                      "load": LOAD_EXAMPLE, "ratio": 2,
                                                      "rated_output_torque_nm": 400}},
        {"name": "pusher", "phase_deg": 180, "motion": MotionAxisSpec.model_config["json_schema_extra"][
            "examples"][0]},  # type: ignore[index]
    ],
    "rules": [{"while": {"axis": "table", "moving": True}, "require": {"axis": "pusher", "moving": False}}],
    "flywheel": {"inertia_kgm2": 100},
    "samples": 181,
}


class MachineRequest(Spec):
    """Several axes on one camshaft: their timing, summed torque, flywheel, motor, speed limits and timing rules.

    One cycle is one turn of the camshaft (the master). Axis names are unique; rules name axes of the machine.
    """

    model_config = examples(MACHINE_EXAMPLE)
    master: MasterSpec
    axes: list[AxisSpec] = Field(min_length=1, max_length=MAX_AXES)
    rules: list[RuleSpec] = Field(default_factory=list, max_length=MAX_RULES)
    flywheel: FlywheelSpec | None = None
    drive: DriveSpec | None = None
    samples: Annotated[int, Field(ge=2), JSON_INTEGER] = Field(
        361, description="rows of the timing and torque tables: master angles 0…360° inclusive, evenly spaced")
    speeds_rpm: list[SpeedRpm] = Field(default_factory=list, max_length=MAX_SPEEDS,
                                       description="a sweep: the summary at each of these camshaft speeds")
    cam_table_axis: AxisName | None = Field(
        None, description="?format=cam-table: the axis whose servo cam table is written (over the master angle, at "
                          "its phase); default the first axis")
    chart: Literal["timing", "torque"] = Field(
        "timing", description="?format=png|svg: the timing diagram, or the camshaft torque (per axis, total, motor)")

    @model_validator(mode="after")
    def _names(self) -> MachineRequest:
        names = [a.name for a in self.axes]
        for i, name in enumerate(names):
            if name in names[:i]:
                raise FieldRuleError(f"axis names must be unique: {name!r} is given twice", "axes", i, "name")
        for i, r in enumerate(self.rules):
            for part, c in (("while", r.while_), ("require", r.require)):
                if c.axis not in names:
                    raise FieldRuleError(f"{c.axis!r} is not an axis of this machine ({', '.join(names)})",
                                         "rules", i, part, "axis")
        if self.cam_table_axis is not None and self.cam_table_axis not in names:
            raise FieldRuleError(f"{self.cam_table_axis!r} is not an axis of this machine ({', '.join(names)})",
                                 "cam_table_axis")
        return self


MACHINE_EXAMPLES: dict[str, Example] = {
    "feed_and_table": {"summary": "a roller-follower feed and a 6-stop table on one camshaft at 60 rpm",
                       "description": "the feed must be within 2 mm of its base while the table indexes; the flywheel "
                                      "is sized for Cs = 0.05",
                       "value": MACHINE_EXAMPLE},
    "with_motor": {"summary": "the same, through a 2:1 gear to a motor (its own 10:1 reduction), swept over speed",
                   "value": {**MACHINE_EXAMPLE, "drive": {"gear_ratio": 2, "efficiency": 0.9, "motor": MOTOR_EXAMPLE},
                             "speeds_rpm": [30, 60, 90], "samples": 73}},
    "four_kinds": {"summary": "a plate cam, a barrel cam, an indexer geared 2:1 and a motion program on one camshaft",
                   "description": "the pusher must stand still while the table indexes (it does not: see rules); a 100 "
                                  "kg·m² flywheel",
                   "value": FOUR_KINDS_EXAMPLE},
}

MachineSummaryAnswer = answer_model(MachineSummary, "MachineSummaryAnswer")


class SpeedLimitsAnswer(DeferredModel):
    """How fast the machine can run: each axis's first failure speed and the smallest."""

    axes: list[answer_model(AxisLimit, "AxisLimitAnswer")]  # type: ignore[valid-type]
    machine_top_speed_rpm: float | None = Field(description="the smallest limit; null: none found [rpm]")
    axis: str | None = Field(description="which axis sets it (drive: the motor)")
    reason: str | None = Field(description="and why")
    runs_within_limits: bool = Field(description="the machine's speed is at or below its top speed")


class MachineAnswer(DeferredModel):
    """The timing and torque tables over the master angle, the totals, each axis, the limits and the rules."""

    timing: dict[str, list[float]] = Field(description=(
        "x_deg, then per axis <name>_mm or <name>_deg (its position) and <name>_normalised (0…1; an indexer: the "
        "current index's progress)"))
    torque: dict[str, list[float]] = Field(description=(
        "x_deg, per axis <name>_nm (its torque on the camshaft), total_nm, and with a drive motor_nm [N·m]"))
    summary: MachineSummaryAnswer  # type: ignore[valid-type]
    axes: list[answer_model(AxisReport, "AxisReportAnswer")]  # type: ignore[valid-type]
    speed_limits: SpeedLimitsAnswer
    rules: list[answer_model(RuleResult, "RuleResultAnswer")]  # type: ignore[valid-type]
    sweep: list[MachineSummaryAnswer]  # type: ignore[valid-type]
