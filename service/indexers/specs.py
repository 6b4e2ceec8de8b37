"""Specs and answers of /v1/indexers (docs/api.md: IndexerSpec, LoadSpec)."""

from __future__ import annotations

from typing import Annotated, Literal

from fastapi.openapi.models import Example
from pydantic import Field, PrivateAttr, model_validator

from camcore.indexer import (
    IndexerPosition,
    Load,
    LoadPart,
    MotionSummary,
    MotionTable,
    Motor,
    Sizing,
    check_timing_frame,
)
from camcore.indexer.checks import check_speed_alternatives, check_total_indexing_angle
from service.curves.specs import MS_SPEC, CurveSpec, NamedCurveSpec
from service.models import answer_model
from service.motions.specs import MotionSpec
from service.specs import (
    BIG,
    JSON_INTEGER,
    DeferredModel,
    Spec,
    absent,
    exactly_one,
    examples,
    given,
    not_both,
    one_of_values,
    rule,
    together,
)

#: physical lower bound of an indexer's speeds, times and angles: a subnormal speed or time would
#: make th² underflow to zero. The chart's query (service.indexers.operations) keeps the same bounds
SMALLEST = 1e-6
Positive = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=SMALLEST, le=BIG)]
NonNegative = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0, le=BIG)]

#: the guide's worked example: 6 stops, θh = 270°, MS, 60 rpm (INDEXMAN technical guide)
INDEXER_EXAMPLE: dict[str, object] = {"stops": 6, "indexing_angle_deg": 270, "speed_rpm": 60, "curve": MS_SPEC}
#: and its load: a 50 kg disc of Ø600 mm, friction μ = 0.1 at R = 200 mm, service factor 1.5
LOAD_EXAMPLE: dict[str, object] = {"parts": [{"shape": "disc", "mass_kg": 50, "diameter_mm": 600}],
                                   "friction_coefficient": 0.1, "friction_radius_mm": 200, "service_factor": 1.5}
#: a servo motor through a 10:1 reduction (95 %)
MOTOR_EXAMPLE: dict[str, object] = {"rated_torque_nm": 3.2, "peak_torque_nm": 9.6, "rotor_inertia_kgm2": 0.00034,
                                    "max_speed_rpm": 3000, "reduction_ratio": 10, "reduction_efficiency": 0.95}

#: the indexer guide's oscillating unit as a timing chart (§4-5): out 90° over 120° of input
#: (MS), dwell 60°, back over 120° (MS played backwards), dwell 60°
TIMING_INDEXER_EXAMPLE: dict[str, object] = {
    "speed_rpm": 60, "timing": {"unit": "deg", "segments": [
        {"span_deg": 120, "to": 90, "curve": MS_SPEC}, {"span_deg": 60, "type": "dwell"},
        {"span_deg": 120, "to": 0, "curve": {**MS_SPEC, "direction": "return"}}, {"span_deg": 60, "type": "dwell"}]}}
TIMING_REPLACES = "a timing chart replaces stops, swing_angle_deg, indexing_angle_deg, dwells and curve: give none of them"


#: a timing chart's own 0° is its origin
DWELL_CENTRE_RULE = "input_angle_origin dwell-centre is for a single-curve indexer: a timing chart starts at its own 0°"


#: an indexer's rules as JSON Schema but the speed's (the validators say the same)
SHAPE_RULES = [
    rule(TIMING_REPLACES, {"if": given("timing"),
                           "then": absent("stops", "swing_angle_deg", "indexing_angle_deg", "dwells", "curve")}),
    rule("give exactly one of stops (n) and swing_angle_deg (ψ, oscillating units)",
         {"if": {"not": given("timing")}, "then": exactly_one("stops", "swing_angle_deg")}),
    rule("indexing_angle_deg (θh) is needed without a timing chart",
         {"if": {"not": given("timing")}, "then": given("indexing_angle_deg")}),
    rule("a timing chart gives the output angle in deg over one input turn (period_deg 360)",
         {"if": given("timing"), "then": {"properties": {"timing": {"required": ["unit"], "properties": {
             "unit": {"const": "deg"}, "period_deg": {"const": 360}}}}}}),
    rule(DWELL_CENTRE_RULE, {"if": given("timing"), "then": {"properties": {
        "input_angle_origin": {"not": {"const": "dwell-centre"}}}}})]
SPEED_RULE = "give exactly one of speed_rpm (N) and cycle_time_s (t0 = 60/(N·z))"
#: the guide's worked example without its speed (a machine's camshaft sets it)
INDEXER_SHAPE_EXAMPLE = {k: v for k, v in INDEXER_EXAMPLE.items() if k != "speed_rpm"}


class IndexerShape(Spec):
    """A cam indexer (stops) or oscillating unit (swing angle), or an indexer whose output follows a
    timing chart over one input turn, without its speed (on a machine, the camshaft turns it).

    The total indexing angle θt = θh·z (indexing_angle_deg × dwells) is at most 360°.
    """

    model_config = examples(INDEXER_SHAPE_EXAMPLE, {k: v for k, v in TIMING_INDEXER_EXAMPLE.items()
                                                    if k != "speed_rpm"}, rules=SHAPE_RULES)
    stops: Annotated[int, Field(ge=1, le=100_000), JSON_INTEGER] | None = Field(None, description="n, stops per output turn")
    swing_angle_deg: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=SMALLEST, le=360)] | None = Field(
        None, description="ψ, output swing of an oscillating unit (instead of stops)")
    indexing_angle_deg: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=SMALLEST, le=360)] | None = Field(
        None, description="θh, input angle per index (needed without a timing chart)")
    dwells: Annotated[int, Field(ge=1, le=360), JSON_INTEGER] = Field(1, description="z, indexes per input turn")
    input_stop_time_s: NonNegative = Field(0.0, description="ts, input stands still each index")
    internal_friction_torque_nm: NonNegative = Field(
        0.0, description="the unit's own friction torque on the input shaft while it turns (the maker's data); in the "
                         "sizing's torque table, RMS and motor figures")
    curve: CurveSpec = Field(default_factory=lambda: NamedCurveSpec(name="MS"))
    input_angle_origin: Literal["index-start", "dwell-centre"] = Field(
        "index-start", description="where every input angle of the answer starts: at the start of the index, or at "
                                   "the centre of the dwell before it (the catalog's keyway reference position, "
                                   "guide §4-2): angles from the index start plus half the dwell, within one cycle")
    timing: MotionSpec | None = Field(
        None, description="a timing chart: the output angle (unit deg) over one input turn (period_deg 360), in place "
                          "of stops/swing_angle_deg, indexing_angle_deg, dwells and curve; it closes for an "
                          "oscillating unit (out and back) or advances by the output's travel per input turn. z is "
                          "then the number of dwells in the chart, and the summary's per-index values are averages")

    @model_validator(mode="after")
    def _check(self) -> IndexerShape:
        # the core's own rules (camcore raises ValueError subclasses: 422 with the same sentence)
        if self.timing is not None:
            replaced = [name for name in ("stops", "swing_angle_deg", "indexing_angle_deg", "dwells", "curve")
                        if name in self.model_fields_set and getattr(self, name) is not None]
            if replaced:
                raise ValueError(f"{TIMING_REPLACES} (given: {', '.join(replaced)})")
            if self.input_angle_origin == "dwell-centre":
                raise ValueError(DWELL_CENTRE_RULE)
            check_timing_frame(self.timing.unit, self.timing.period_deg)
            return self
        if (self.stops is None) == (self.swing_angle_deg is None):
            raise ValueError("give exactly one of stops (n) and swing_angle_deg (ψ, oscillating units).")
        if self.indexing_angle_deg is None:
            raise ValueError("indexing_angle_deg (θh) is needed without a timing chart")
        check_total_indexing_angle(self.indexing_angle_deg, self.dwells)
        return self


class IndexerSpec(IndexerShape):
    """A cam indexer (stops) or oscillating unit (swing angle) at constant input speed, or an
    indexer whose output follows a timing chart over one input turn.

    The total indexing angle θt = θh·z (indexing_angle_deg × dwells) is at most 360°.
    """

    model_config = examples(INDEXER_EXAMPLE, TIMING_INDEXER_EXAMPLE,
                            rules=[*SHAPE_RULES, rule(SPEED_RULE, exactly_one("speed_rpm", "cycle_time_s"))])
    speed_rpm: Positive | None = Field(None, description="N, input speed")
    cycle_time_s: Positive | None = Field(None, description="t0, unit cycle time (instead of speed_rpm)")

    @model_validator(mode="after")
    def _check_speed(self) -> IndexerSpec:
        check_speed_alternatives(self.speed_rpm, self.cycle_time_s)
        return self


#: the dimensions each shape needs (camcore's LoadPart checks the same; the agreement is tested)
SHAPE_NEEDS: dict[str, tuple[str, ...]] = {"disc": ("diameter_mm",), "ring": ("diameter_mm", "inner_diameter_mm"),
                                            "block": ("a_mm", "b_mm"), "point": ()}


class LoadPartSpec(Spec):
    """A part of the load; its own axis is offset_mm from the output axis.

    A disc needs diameter_mm, a ring diameter_mm and inner_diameter_mm (inner ≤ outer), a
    block a_mm and b_mm; a point needs none.
    """

    model_config = examples(
        {"shape": "disc", "mass_kg": 50, "diameter_mm": 600},
        rules=[rule(f"a {shape} part needs {', '.join(needs)}", {"if": one_of_values("shape", shape), "then": given(*needs)})
               for shape, needs in SHAPE_NEEDS.items() if needs])
    shape: Literal["disc", "ring", "block", "point"]
    mass_kg: NonNegative
    diameter_mm: NonNegative | None = None
    inner_diameter_mm: NonNegative | None = None
    a_mm: NonNegative | None = None
    b_mm: NonNegative | None = None
    offset_mm: NonNegative = 0.0
    count: Annotated[int, Field(ge=1, le=100_000), JSON_INTEGER] = 1

    _core: LoadPart | None = PrivateAttr(None)

    @model_validator(mode="after")
    def _check(self) -> LoadPartSpec:
        self.core()  # camcore's rules and sentences (a ValueError: 422)
        return self

    def core(self) -> LoadPart:
        """The part as camcore takes it; made once."""
        if self._core is None:
            self._core = LoadPart(**self.model_dump())
        return self._core


class LoadSpec(Spec):
    """What the output drives: inertia, friction, work torque, service factor, efficiency."""

    model_config = examples(
        LOAD_EXAMPLE,
        rules=[rule("friction_coefficient and friction_radius_mm go together (Tf = μ·m·g·R)",
                    together("friction_coefficient", "friction_radius_mm")),
               rule("give friction as friction_coefficient with friction_radius_mm, or friction_torque_nm, not both",
                    not_both("friction_coefficient", "friction_torque_nm")),
               rule("friction_coefficient needs parts with mass_kg (friction torque μ·m·g·R uses the parts' masses)",
                    {"if": given("friction_coefficient"),
                     "then": {"required": ["parts"], "properties": {"parts": {"minItems": 1}}}}),
               rule("accuracy_arc_seconds and accuracy_radius_mm go together",
                    together("accuracy_arc_seconds", "accuracy_radius_mm"))])
    inertia_kgm2: NonNegative = Field(0.0, description="given directly, added to the parts")
    parts: list[LoadPartSpec] = Field(default_factory=list, max_length=1000)
    friction_coefficient: NonNegative | None = Field(None, description="μ, with friction_radius_mm")
    friction_radius_mm: NonNegative | None = None
    friction_torque_nm: NonNegative | None = None
    work_torque_nm: NonNegative = 0.0
    service_factor: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=1, le=100)] = 1.5
    efficiency: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, le=1)] = 1.0
    gear_ratio: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=1e-3, le=1000)] = Field(
        1.0, description="g, output-shaft turns per dial turn: the inertia, friction and work torque above are the "
                         "dial's, reflected to the output shaft as I/g² and T/g")
    dwell_torque_nm: NonNegative = Field(0.0, description="external torque on the dial held while it stands still")
    accuracy_arc_seconds: NonNegative | None = Field(None, description="with accuracy_radius_mm: arc-seconds → mm")
    accuracy_radius_mm: NonNegative | None = None

    @model_validator(mode="after")
    def _check(self) -> LoadSpec:
        if (self.friction_coefficient is None) != (self.friction_radius_mm is None):
            raise ValueError("friction_coefficient and friction_radius_mm go together (Tf = μ·m·g·R)")
        if self.friction_coefficient is not None and self.friction_torque_nm is not None:
            raise ValueError("give friction as friction_coefficient with friction_radius_mm, or friction_torque_nm, not both")
        if (self.accuracy_arc_seconds is None) != (self.accuracy_radius_mm is None):
            raise ValueError("accuracy_arc_seconds and accuracy_radius_mm go together")
        return self

    def core(self) -> Load:
        """The load as camcore takes it (its own errors: at the load, where the caller puts it)."""
        return Load(**self.model_dump(exclude={"parts", "accuracy_arc_seconds", "accuracy_radius_mm"}),
                    parts=[part.core() for part in self.parts])


class MotionRequest(Spec):
    model_config = examples({"indexer": INDEXER_EXAMPLE, "samples": 101})
    indexer: IndexerSpec
    samples: Annotated[int, Field(ge=2), JSON_INTEGER] = 101


class PositionRequest(Spec):
    model_config = examples({"indexer": INDEXER_EXAMPLE, "output_angle_deg": [11]})
    indexer: IndexerSpec
    output_angle_deg: list[Annotated[float, Field(strict=True, allow_inf_nan=False, ge=-BIG, le=BIG)]] = Field(min_length=1)
    method: Literal["exact", "table"] = "exact"
    table_step: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=1e-4, le=0.5)] = 0.01
    table_decimals: Annotated[int, Field(ge=0, le=15), JSON_INTEGER] | None = None


class MotorSpec(Spec):
    """A motor to check against the machine cycle (peak, RMS, speed, inertia ratio)."""

    model_config = examples(MOTOR_EXAMPLE)
    rated_torque_nm: Positive = Field(description="continuous torque")
    peak_torque_nm: Positive = Field(description="peak torque")
    rotor_inertia_kgm2: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, le=BIG)]
    max_speed_rpm: Positive
    reduction_ratio: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=1e-3, le=1e5)] = Field(
        1.0, description="i, motor turns per input-shaft turn")
    reduction_efficiency: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, le=1)] = 1.0

    def core(self) -> Motor:
        """The motor as camcore takes it (its own fields: a named motor's name is not the motor's data)."""
        return Motor(**self.model_dump(include=set(MotorSpec.model_fields)))


class SizingRequest(Spec):
    model_config = examples({"indexer": INDEXER_EXAMPLE, "load": LOAD_EXAMPLE})
    indexer: IndexerSpec
    load: LoadSpec
    motor: MotorSpec | None = None
    table_samples: Annotated[int, Field(ge=2, le=10_001), JSON_INTEGER] = Field(
        181, description="rows of the input torque table over each index")


#: request examples of the POST operations (Swagger UI pre-fills the first)
MOTION_EXAMPLES: dict[str, Example] = {
    "guide": {"summary": "6 stops, θh = 270°, MS, 60 rpm",
              "description": "the guide's example: indexing time 0.75 s, ω max = Vm·60°/0.75 s = 2.457 rad/s",
              "value": {"indexer": INDEXER_EXAMPLE, "samples": 101}},
}
POSITION_EXAMPLES: dict[str, Example] = {
    "guide": {"summary": "where the output is at 11° (of 60°)",
              "description": "the guide's example: S = 0.1833, T = 0.304, input ≈ 82.1°, ω ≈ 1.87 rad/s",
              "value": {"indexer": INDEXER_EXAMPLE, "output_angle_deg": [11]}},
}
SIZING_EXAMPLES: dict[str, Example] = {
    "guide": {"summary": "50 kg disc Ø600 mm, μ = 0.1 at 200 mm, service factor 1.5",
              "description": "the guide's sizing example: I = m·D²/8 = 2.25 kg·m², "
                             "friction torque μ·m·g·R = 9.81 N·m",
              "value": {"indexer": INDEXER_EXAMPLE, "load": LOAD_EXAMPLE}},
    "motor": {"summary": "the same through a 2:1 belt to the dial, with 2 N·m internal friction and a motor check",
              "value": {"indexer": {**INDEXER_EXAMPLE, "internal_friction_torque_nm": 2},
                        "load": {**LOAD_EXAMPLE, "gear_ratio": 2, "dwell_torque_nm": 40}, "motor": MOTOR_EXAMPLE}},
}


MotionSummaryAnswer = answer_model(MotionSummary, "MotionSummaryAnswer")


MotionTableAnswer = answer_model(MotionTable, "MotionTableAnswer")


class MotionAnswer(DeferredModel):
    summary: MotionSummaryAnswer  # type: ignore[valid-type]  # derived answer model (service.models)
    table: MotionTableAnswer  # type: ignore[valid-type]  # derived answer model (service.models)


PositionAnswer = answer_model(IndexerPosition, "PositionAnswer")


SizingAnswer = answer_model(Sizing, "SizingAnswer")


class AccuracyAnswer(DeferredModel):
    arc_seconds: float
    radius_mm: float
    accuracy_mm: float
