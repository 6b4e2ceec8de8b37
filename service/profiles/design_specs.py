"""Specs and answers of POST /v1/profiles/design (docs/api.md: designProfile)."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from fastapi.openapi.models import Example
from pydantic import Field, PrivateAttr, ValidationError, create_model, model_validator

from camcore.errors import InvalidParameterError
from camcore.profile import CamSpec
from camcore.profile.design import DesignLimits, DesignProblem, FollowerLoad, ProfileDesign, check_problem
from service.curves.specs import BezierCurveSpec, PointsCurveSpec
from service.models import answer_model
from service.motions.specs import MotionSpec
from service.profiles.dynamics_specs import (
    OSCILLATING_FIELDS,
    OSCILLATING_PROFILE,
    OSCILLATING_RULE,
    TRANSLATING_FIELDS,
    TRANSLATING_RULE,
    NonNegative,
    Positive,
    RollerSpec,
)
from service.profiles.specs import (
    NOT_FLAT_FACED,
    TRANSLATING,
    FollowerSpec,
    ProfileAnswer,
    ProfileSpec,
    SegmentSpec,
)
from service.specs import (
    BIG,
    JSON_INTEGER,
    FieldRuleError,
    Finite,
    Spec,
    SpeedRpm,
    absent,
    all_of,
    exactly_one,
    examples,
    rule,
)

#: a variable's bounds: [lo, hi]
Bounds = Annotated[list[Finite], Field(min_length=2, max_length=2, description="[lo, hi]")]
PositiveBounds = Annotated[list[Positive], Field(min_length=2, max_length=2, description="[lo, hi], both > 0")]
Angle = Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, lt=90)]
#: the template follower whose cam carries the lift (a knife-edge on an arm so long that any base radius
#: assembles it): the design's own follower replaces it
TEMPLATE_ARM_MM = BIG

#: a roller cam rising 30 mm over 80° and returning over 100° (cycloids), 0.5 kg at 600 rpm
DESIGN_SEGMENTS: list[dict[str, Any]] = [
    {"type": "rise", "angle_deg": 80, "lift_mm": 30}, {"type": "dwell", "angle_deg": 100},
    {"type": "return", "angle_deg": 100, "lift_mm": 30}, {"type": "dwell", "angle_deg": 80}]
DESIGN_EXAMPLE: dict[str, Any] = {
    "segments": DESIGN_SEGMENTS, "follower": {"type": "roller", "roller_radius_mm": 10},
    "speed_rpm": 600, "mass_kg": 0.5,
    "limits": {"max_pressure_angle_deg": 30, "min_radius_of_curvature_mm": 15, "safety_margin_n": 5},
    "free": {"base_radius_mm": [10, 200], "offset_mm": [-30, 30], "roller_radius_mm": [5, 20],
             "spring_rate_n_mm": [0.5, 50], "preload_n": [0, 500]}}


class DesignLimitsSpec(Spec):
    """The limits the design must meet (each optional)."""

    model_config = examples({"max_pressure_angle_deg": 30, "min_radius_of_curvature_mm": 15, "safety_margin_n": 5})
    max_pressure_angle_deg: Angle | None = Field(
        None, description="the largest pressure angle while the cam pushes the follower out, and on the return too "
                          "unless max_return_pressure_angle_deg is given [deg]")
    max_return_pressure_angle_deg: Angle | None = Field(
        None, description="the largest pressure angle on the return (the spring drives the follower back) [deg]")
    min_radius_of_curvature_mm: NonNegative | None = Field(
        None, description="the smallest radius of curvature of the cam surface's convex parts [mm]")
    min_radius_of_curvature_roller_multiple: NonNegative | None = Field(
        None, description="roller followers: the same as a multiple of the roller radius (with "
                          "min_radius_of_curvature_mm too: the larger)")
    allowed_stress_mpa: Positive | None = Field(
        None, description="the largest Hertz pressure of the roller on the cam, at the worst speed (needs roller) [MPa]")
    safety_margin_n: NonNegative | None = Field(
        None, description="the contact force the follower must keep at every speed of the range (with a load; "
                          "default 0: it must not jump) [N]")

    def core(self) -> DesignLimits:
        return DesignLimits(**self.model_dump())


class FreeSpec(Spec):
    """The variables the design may move, each within [lo, hi] (lo ≤ hi); the others keep the request's value."""

    model_config = examples({"base_radius_mm": [10, 200], "offset_mm": [-30, 30], "roller_radius_mm": [5, 20]})
    base_radius_mm: PositiveBounds | None = Field(None, description="the base radius [mm]")
    offset_mm: Bounds | None = Field(None, description="translating knife-edge or roller followers [mm]")
    roller_radius_mm: PositiveBounds | None = Field(None, description="roller followers [mm]")
    spring_rate_n_mm: PositiveBounds | None = Field(None, description="translating followers with mass_kg [N/mm]")
    preload_n: Bounds | None = Field(None, description="translating followers with mass_kg [N]")
    spring_rate_nm_rad: PositiveBounds | None = Field(
        None, description="oscillating followers with inertia_kgm2 [N·m/rad]")
    preload_nm: Bounds | None = Field(None, description="oscillating followers with inertia_kgm2 [N·m]")
    pivot_distance_mm: PositiveBounds | None = Field(
        None, description="oscillating followers: the distance from the cam's centre to the arm's pivot (the "
                          "follower's own value is then not used) [mm]")
    arm_length_mm: Bounds | None = Field(None, description="not searched, refused: the machine's linkage sets the arm; "
                                                           "give it in follower and free pivot_distance_mm")

    def core(self) -> dict[str, tuple[float, float]]:
        return {name: (float(value[0]), float(value[1])) for name, value in self.model_dump().items()
                if value is not None}


#: the request's rules, each said by the validator at its field. The document states the two that shape most
#: bodies (the lift given once, the fields of the follower's motion); the others are statable one by one, but
#: schemathesis 4 (the fuzz tests' generator) resolves no more than two of them together on one model (it
#: raises UnsupportedSchema), so they are listed in the request's description instead
SPEED_RULE = "a follower's mass (or inertia) needs speed_rpm"
BASE_RADIUS_RULE = "give base_radius_mm, or free it (free.base_radius_mm)"
OFFSET_RULE = "free.offset_mm is a translating knife-edge or roller follower's (a flat face's offset does not change its cam)"
ROLLER_RADIUS_RULE = "free.roller_radius_mm needs a roller follower"
SPRING_UNITS_RULE = ("a translating follower's spring is free.spring_rate_n_mm and free.preload_n, an oscillating one's "
                     "free.spring_rate_nm_rad and free.preload_nm")
NOT_SEARCHED_RULE = ("free.arm_length_mm is not searched (the machine's linkage sets the arm): give it in follower, and "
                     "free pivot_distance_mm to place the arm")
NO_MASS_RULE = ("a spring (its rate, its preload or their bounds in free), allowed_stress_mpa and safety_margin_n need the "
                "follower's mass_kg (inertia_kgm2 for an oscillating one)")
SPRING_RULE = "the follower's mass needs a spring: give spring_rate_n_mm (spring_rate_nm_rad) or free it"
STRESS_ROLLER_RULE = "limits.allowed_stress_mpa needs roller (its width and materials)"
ROLLER_LIMITS_RULE = "min_radius_of_curvature_roller_multiple and allowed_stress_mpa are a roller follower's limits"
DESIGN_ROLLER_RULE = "roller (width and materials) goes with a roller follower's stress limit"
#: the rule of the document that sums the motion's
MOTION_RULE = ("a follower's fields are of its motion: a translating one's load is mass_kg, spring_rate_n_mm, preload_n, "
               "external_force_n, damping_n_s_mm, its free spring free.spring_rate_n_mm and free.preload_n, its lift in mm, "
               "and it may free offset_mm unless it is flat-faced; an oscillating one's load is inertia_kgm2, "
               "spring_rate_nm_rad, preload_nm, external_torque_nm, damping_nm_s_rad, its free spring "
               "free.spring_rate_nm_rad and free.preload_nm, its swing in deg, and it has no offset (it may free pivot_distance_mm)")
#: the rules the validator says that the document does not state (the request's description lists them)
VALIDATOR_RULES = (SPEED_RULE, BASE_RADIUS_RULE, ROLLER_RADIUS_RULE, NOT_SEARCHED_RULE, NO_MASS_RULE, SPRING_RULE,
                   STRESS_ROLLER_RULE, ROLLER_LIMITS_RULE, DESIGN_ROLLER_RULE)


def _free(*names: str) -> dict[str, Any]:
    return {"properties": {"free": absent(*names)}}


def _in_segments(schema: dict[str, Any]) -> dict[str, Any]:
    return {"properties": {"segments": {"items": schema}}}


DESIGN_RULES = [
    rule("give the lift as segments, as one lift curve (bezier or points) or as a motion program",
         exactly_one("segments", "lift", "motion")),
    rule(MOTION_RULE, {
        "if": {"properties": {"follower": TRANSLATING}},
        "then": all_of(absent(*OSCILLATING_FIELDS), _free("spring_rate_nm_rad", "preload_nm", "pivot_distance_mm"),
                       {"properties": {"motion": {"properties": {"unit": {"const": "mm"}}}}},
                       _in_segments(absent("swing_deg")),
                       {"if": {"properties": {"follower": {"not": NOT_FLAT_FACED}}}, "then": _free("offset_mm")}),
        "else": all_of(absent(*TRANSLATING_FIELDS), _free("spring_rate_n_mm", "preload_n", "offset_mm"),
                       {"properties": {"motion": {"required": ["unit"], "properties": {"unit": {"const": "deg"}}}}},
                       _in_segments({"properties": {"lift_mm": {"maximum": 0}}}))}),
]


class ProfileDesignRequest(Spec):
    """A plate cam to design: its lift and follower, the follower's load, the limits, and the variables
    the design may move within their bounds (``free``). The objective is the smallest base radius, then
    the softest spring, then the smallest preload.

    Rules the validator also applies (each a 422 at its field): a follower's mass (or inertia) needs speed_rpm;
    give base_radius_mm, or free it; free.roller_radius_mm needs a roller follower; free.arm_length_mm is not
    searched; a spring (its rate, its preload or their bounds in free),
    allowed_stress_mpa and safety_margin_n need the follower's mass; the mass needs a spring (given or free);
    limits.allowed_stress_mpa needs roller; min_radius_of_curvature_roller_multiple and allowed_stress_mpa are a
    roller follower's; each free bound has lo ≤ hi; something to minimise moves (the base radius, or the spring).

    A variable not in ``free`` keeps its value here (``base_radius_mm``, the follower's ``offset_mm``,
    ``pivot_distance_mm`` and ``roller_radius_mm``, ``spring_rate_n_mm`` and ``preload_n``). A translating follower's load is
    ``mass_kg``, ``damping_n_s_mm`` and ``external_force_n``; an oscillating one's ``inertia_kgm2``,
    ``damping_nm_s_rad`` and ``external_torque_nm`` with its spring in N·m/rad. ``speed_rpm`` is one speed or
    a range [lo, hi]: the dynamic limits hold at every speed of it.
    """

    model_config = examples(DESIGN_EXAMPLE, rules=DESIGN_RULES)
    follower: FollowerSpec
    rotation: Literal["ccw", "cw"] = "ccw"
    rotation_ratio: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, le=1000)] = Field(
        1.0, description="cam turns per drive-shaft turn")
    segments: list[SegmentSpec] | None = Field(None, min_length=1, max_length=360)
    lift: Annotated[BezierCurveSpec | PointsCurveSpec, Field(discriminator="type")] | None = Field(
        None, description="one Bezier or points curve of lift over the drive angle")
    motion: MotionSpec | None = Field(None, description="a motion program over the drive angle that closes")
    base_radius_mm: Positive | None = Field(None, description="the base radius when it is not free [mm]")
    speed_rpm: SpeedRpm | Annotated[list[SpeedRpm], Field(min_length=2, max_length=2)] | None = Field(
        None, description="the camshaft's speed, or its range [lo, hi] [rpm]")
    mass_kg: Positive | None = Field(None, description="translating: the moving mass, with the spring's share")
    spring_rate_n_mm: Positive | None = Field(None, description="translating: the spring rate when not free")
    preload_n: Finite | None = Field(None, description="translating: the preload when not free; default 0")
    external_force_n: Finite | None = Field(None, description="translating: a constant force onto the cam; 0")
    damping_n_s_mm: NonNegative | None = Field(None, description="translating: viscous damping; 0")
    inertia_kgm2: Positive | None = Field(None, description="oscillating: the arm's inertia about its pivot")
    spring_rate_nm_rad: Positive | None = Field(None, description="oscillating: the spring rate when not free")
    preload_nm: Finite | None = Field(None, description="oscillating: the preload torque when not free; 0")
    external_torque_nm: Finite | None = Field(None, description="oscillating: a constant torque onto the cam; 0")
    damping_nm_s_rad: NonNegative | None = Field(None, description="oscillating: viscous damping; 0")
    roller: RollerSpec | None = Field(None, description="roller followers: width and materials, for the stress")
    limits: DesignLimitsSpec = Field(default_factory=DesignLimitsSpec)
    free: FreeSpec
    samples: Annotated[int, Field(ge=2), JSON_INTEGER] = Field(
        361, description="rows of the designed cam's profile, evenly over 0–360° of cam angle")

    _template: ProfileSpec | None = PrivateAttr(None)

    @model_validator(mode="after")
    def _check(self) -> ProfileDesignRequest:
        self._template = self._lift_spec()
        follower, free, limits = self.follower, self.free, self.limits
        oscillating = follower.motion == "oscillating"
        wrong = [name for name in (TRANSLATING_FIELDS if oscillating else OSCILLATING_FIELDS)
                 if getattr(self, name) is not None]
        if wrong:
            raise FieldRuleError(f"{OSCILLATING_RULE if oscillating else TRANSLATING_RULE} ({', '.join(wrong)} given)",
                                 wrong[0])
        mass = self.inertia_kgm2 if oscillating else self.mass_kg
        if mass is not None and self.speed_rpm is None:
            raise FieldRuleError(SPEED_RULE, "speed_rpm")
        if self.roller is not None and follower.type != "roller":
            raise FieldRuleError(f"{DESIGN_ROLLER_RULE}, not a {follower.type} follower", "roller")
        if free.base_radius_mm is None and self.base_radius_mm is None:
            raise FieldRuleError(BASE_RADIUS_RULE, "base_radius_mm")
        if free.offset_mm is not None and (oscillating or follower.type == "flat-faced"):
            raise FieldRuleError(f"{OFFSET_RULE} ({MOTION_RULE})", "free", "offset_mm")
        if free.pivot_distance_mm is not None and not oscillating:
            raise FieldRuleError(f"free.pivot_distance_mm is an oscillating follower's ({MOTION_RULE})", "free",
                                 "pivot_distance_mm")
        if free.roller_radius_mm is not None and follower.type != "roller":
            raise FieldRuleError(ROLLER_RADIUS_RULE, "free", "roller_radius_mm")
        other = ("spring_rate_n_mm", "preload_n") if oscillating else ("spring_rate_nm_rad", "preload_nm")
        for name in (*other, "arm_length_mm"):
            if getattr(free, name) is not None:
                raise FieldRuleError(f"{SPRING_UNITS_RULE} ({MOTION_RULE})" if name in other else NOT_SEARCHED_RULE,
                                     "free", name)
        rate, preload = (("spring_rate_nm_rad", "preload_nm") if oscillating else ("spring_rate_n_mm", "preload_n"))
        if mass is None:
            for where in ((rate,), (preload,), ("free", rate), ("free", preload), ("limits", "allowed_stress_mpa"),
                          ("limits", "safety_margin_n")):
                owner = self if len(where) == 1 else getattr(self, str(where[0]))
                if getattr(owner, str(where[-1])) is not None:
                    raise FieldRuleError(NO_MASS_RULE, *where)
        elif getattr(self, rate) is None and getattr(free, rate) is None:
            raise FieldRuleError(SPRING_RULE, rate)
        if limits.allowed_stress_mpa is not None and self.roller is None:
            raise FieldRuleError(STRESS_ROLLER_RULE, "roller")
        if follower.type != "roller":
            for name in ("min_radius_of_curvature_roller_multiple", "allowed_stress_mpa"):
                if getattr(limits, name) is not None:
                    raise FieldRuleError(ROLLER_LIMITS_RULE, "limits", name)
        try:  # camcore's rules of a design that JSON Schema cannot state (bounds compared), at their fields
            check_problem(self.problem(CamSpec(follower.core(), self.base_radius_mm or 1.0, None)))
        except InvalidParameterError as exc:
            raise FieldRuleError(str(exc), *exc.field) from None
        return self

    def _lift_spec(self) -> ProfileSpec:
        """The lift's own rules, checked as a profile's (a template follower any base radius assembles)."""
        where = "segments" if self.segments is not None else "lift" if self.lift is not None else "motion"
        try:
            template = FollowerSpec(type="knife-edge", motion=self.follower.motion, arm_length_mm=TEMPLATE_ARM_MM,
                                    pivot_distance_mm=TEMPLATE_ARM_MM)
            return ProfileSpec(follower=template, base_radius_mm=1.0, rotation=self.rotation,
                               rotation_ratio=self.rotation_ratio, segments=self.segments, lift=self.lift,
                               motion=self.motion)
        except ValidationError as exc:
            error = exc.errors()[0]
            message = str(error.get("msg", "")).removeprefix("Value error, ")
            raise FieldRuleError(message, *(error.get("loc") or (where,))) from None

    @property
    def template(self) -> ProfileSpec:
        """The lift as a profile spec (its follower a placeholder)."""
        assert self._template is not None
        return self._template

    def load(self) -> FollowerLoad | None:
        """The follower's load as camcore takes it (None without a mass or inertia)."""
        oscillating = self.follower.motion == "oscillating"
        mass = self.inertia_kgm2 if oscillating else self.mass_kg
        if mass is None:
            return None
        speeds = self.speed_rpm if isinstance(self.speed_rpm, list) else [self.speed_rpm or 0.0] * 2
        damping = self.damping_nm_s_rad if oscillating else self.damping_n_s_mm
        external = self.external_torque_nm if oscillating else self.external_force_n
        return FollowerLoad(float(mass), (float(speeds[0]), float(speeds[1])), float(damping or 0.0),
                            float(external or 0.0), None if self.roller is None else self.roller.core())

    def problem(self, cam: CamSpec) -> DesignProblem:
        """The design problem on this cam (its lift; the follower and base radius replaced by the request's)."""
        oscillating = self.follower.motion == "oscillating"
        rate = self.spring_rate_nm_rad if oscillating else self.spring_rate_n_mm
        preload = self.preload_nm if oscillating else self.preload_n
        return DesignProblem(cam, self.free.core(), self.limits.core(), self.load(), rate, preload)


#: an oscillating roller arm swinging 20° (the dynamics' example), its base radius and spring at 300-400 rpm
OSCILLATING_DESIGN: dict[str, Any] = {
    "segments": OSCILLATING_PROFILE["segments"],
    "follower": {"type": "roller", "motion": "oscillating", "roller_radius_mm": 6, "arm_length_mm": 45,
                 "pivot_distance_mm": 60},
    "speed_rpm": [300, 400], "inertia_kgm2": 0.004, "damping_nm_s_rad": 0.002,
    "limits": {"max_pressure_angle_deg": 45, "min_radius_of_curvature_mm": 2, "safety_margin_n": 5},
    "free": {"base_radius_mm": [5, 50], "spring_rate_nm_rad": [1, 100], "preload_nm": [0, 50]}}
#: request examples of designProfile (Swagger UI pre-fills the first)
DESIGN_EXAMPLES: dict[str, Example] = {
    "roller": {"summary": "a roller cam rising 30 mm in 80°: base radius, offset, roller and spring at 600 rpm",
               "description": "the smallest cam for a 30° pressure angle and 15 mm radius of curvature, then the "
                              "softest spring that keeps 5 N of contact force",
               "value": DESIGN_EXAMPLE},
    "geometry": {"summary": "the base radius alone for a 30° pressure angle (sizeBaseCircle's answer)",
                 "value": {"segments": DESIGN_SEGMENTS, "follower": {"type": "roller", "roller_radius_mm": 10},
                           "limits": {"max_pressure_angle_deg": 30}, "free": {"base_radius_mm": [10, 200]}}},
    "stress": {"summary": "a 230 MPa contact-stress limit over 400-600 rpm: base radius, roller and preload",
               "description": "a 5 N/mm spring; the roller 12 mm wide, steel on steel",
               "value": {**DESIGN_EXAMPLE, "speed_rpm": [400, 600], "spring_rate_n_mm": 5, "roller": {"width_mm": 12},
                         "limits": {**DESIGN_EXAMPLE["limits"], "allowed_stress_mpa": 230},
                         "free": {"base_radius_mm": [10, 200], "roller_radius_mm": [5, 20], "preload_n": [0, 500]}}},
    "oscillating": {"summary": "an oscillating roller arm: base radius and spring (N·m/rad) at 300-400 rpm",
                    "value": OSCILLATING_DESIGN},
    "pivot": {"summary": "the same arm placed: its pivot's distance and the base radius for a 30° pressure angle",
              "description": "the smallest cam lies where the pressure angle's least value over the base radius "
                             "just reaches 30° (a pivot nearer the cam meets it at no base radius)",
              "value": {"segments": OSCILLATING_PROFILE["segments"], "follower": OSCILLATING_DESIGN["follower"],
                        "limits": {"max_pressure_angle_deg": 30, "min_radius_of_curvature_mm": 2},
                        "free": {"base_radius_mm": [5, 80], "pivot_distance_mm": [30, 120]}}},
}


# ----------------------------------------------------------------------------- answers
DesignAnswerBase = answer_model(ProfileDesign, "ProfileDesignAnswer")
ProfileDesignAnswer = create_model(
    "ProfileDesignAnswer",
    __base__=DesignAnswerBase,
    __doc__="The design, every limit and free bound at it, computeProfile's answer for the designed cam, and how "
            "the search went.",
    profile=(ProfileAnswer, Field(description="computeProfile's answer for the designed cam (samples rows)")),
)
ProfileDesignAnswer.__module__ = __name__
