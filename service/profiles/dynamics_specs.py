"""Specs and answers of POST /v1/profiles/dynamics (docs/api.md: follower dynamics)."""

from __future__ import annotations

from typing import Annotated, Any

from fastapi.openapi.models import Example
from pydantic import Field, create_model, model_validator

from camcore.profile.dynamics import (
    DynamicsSummary,
    DynamicsTable,
    FollowerLoad,
    OscillatingLoad,
    RollerMaterials,
    TranslatingLoad,
)
from camcore.profile.dynamics.load import STEEL_POISSON_RATIO, STEEL_YOUNGS_MODULUS_MPA
from service.models import answer_model
from service.motions.specs import MAKINO_CYCLE
from service.profiles.specs import OSCILLATING, ROLLER_PROFILE_EXAMPLE, TRANSLATING, ProfileSpec
from service.specs import BIG, JSON_INTEGER, Finite, Spec, SpeedRpm, absent, examples, given, rule

Positive = Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, le=BIG)]
NonNegative = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0, le=BIG)]
Poisson = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0, le=0.5)]
#: Young's moduli from 1 MPa (soft polymers) to 10⁷ MPa (beyond diamond)
Modulus = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=1, le=1e7)]

#: the fields of each motion's load, in its own units
TRANSLATING_FIELDS = ("mass_kg", "spring_rate_n_mm", "preload_n", "external_force_n", "damping_n_s_mm")
OSCILLATING_FIELDS = ("inertia_kgm2", "spring_rate_nm_rad", "preload_nm", "external_torque_nm", "damping_nm_s_rad")
TRANSLATING_RULE = ("a translating follower's load is mass_kg and spring_rate_n_mm (with preload_n, external_force_n, "
                    "damping_n_s_mm), not the torques of an oscillating one")
OSCILLATING_RULE = ("an oscillating follower's load is inertia_kgm2 and spring_rate_nm_rad (with preload_nm, "
                    "external_torque_nm, damping_nm_s_rad), not the forces of a translating one")
ROLLER_RULE = "roller (width and materials, for the contact stress) needs a roller follower"

IS_TRANSLATING = {"properties": {"profile": {"properties": {"follower": TRANSLATING}}}}
IS_OSCILLATING = {"properties": {"profile": {"properties": {"follower": OSCILLATING}}}}
NOT_ROLLER = {"properties": {"profile": {"properties": {"follower": {
    "not": {"required": ["type"], "properties": {"type": {"const": "roller"}}}}}}}}

#: the roller cam of computeProfile's example, 0.5 kg on a 2 N/mm spring preloaded to 30 N, at 600 rpm
DYNAMICS_EXAMPLE: dict[str, Any] = {
    "profile": ROLLER_PROFILE_EXAMPLE, "speed_rpm": 600, "mass_kg": 0.5, "spring_rate_n_mm": 2, "preload_n": 30,
    "safety_margin_n": 5, "roller": {"width_mm": 12}, "samples": 361}
OSCILLATING_PROFILE: dict[str, Any] = {
    "follower": {"type": "roller", "motion": "oscillating", "roller_radius_mm": 6, "arm_length_mm": 45,
                 "pivot_distance_mm": 60},
    "base_radius_mm": 25,
    "segments": [{"type": "rise", "angle_deg": 100, "swing_deg": 20}, {"type": "dwell", "angle_deg": 40},
                 {"type": "return", "angle_deg": 120, "swing_deg": 20}, {"type": "dwell", "angle_deg": 100}]}


class RollerSpec(Spec):
    """The roller's width and the elastic constants of roller and cam, for the Hertz stress."""

    model_config = examples({"width_mm": 12}, {"width_mm": 10, "cam_youngs_modulus_mpa": 110000,
                                               "cam_poisson_ratio": 0.27})
    width_mm: Positive = Field(description="length of the line contact")
    youngs_modulus_mpa: Modulus = Field(STEEL_YOUNGS_MODULUS_MPA, description="the roller's Young's modulus [MPa]")
    poisson_ratio: Poisson = Field(STEEL_POISSON_RATIO, description="the roller's Poisson's ratio")
    cam_youngs_modulus_mpa: Modulus | None = Field(None, description="the cam's Young's modulus [MPa]; "
                                                                     "omitted: the roller's")
    cam_poisson_ratio: Poisson | None = Field(None, description="the cam's Poisson's ratio; omitted: the roller's")

    def core(self) -> RollerMaterials:
        return RollerMaterials(self.width_mm, self.youngs_modulus_mpa, self.poisson_ratio,
                               self.cam_youngs_modulus_mpa, self.cam_poisson_ratio)


#: the load's rules as JSON Schema (the validator below says the same)
FOLLOWER_LOAD_RULES = [
    rule(TRANSLATING_RULE, {"if": IS_TRANSLATING, "then": {"allOf": [given("mass_kg", "spring_rate_n_mm"),
                                                                     absent(*OSCILLATING_FIELDS)]}}),
    rule(OSCILLATING_RULE, {"if": IS_OSCILLATING, "then": {"allOf": [given("inertia_kgm2", "spring_rate_nm_rad"),
                                                                     absent(*TRANSLATING_FIELDS)]}}),
    rule(ROLLER_RULE, {"if": given("roller"), "then": {"not": NOT_ROLLER}})]


class ForceClosedFollower(Spec):
    """A plate cam and the load of its force-closed follower (what computeFollowerDynamics takes besides the
    speed and the rows; a machine's plate-cam axis).

    A translating follower gives its load in N and mm (mass_kg, spring_rate_n_mm, preload_n,
    external_force_n, damping_n_s_mm); an oscillating one about its pivot in N·m and rad
    (inertia_kgm2, spring_rate_nm_rad, preload_nm, external_torque_nm, damping_nm_s_rad).
    safety_margin_n is a force at the follower point for both. The roller's width and materials
    (roller followers only) add the Hertz contact stress.
    """

    model_config = examples({k: v for k, v in DYNAMICS_EXAMPLE.items() if k not in ("speed_rpm", "samples")},
                            rules=FOLLOWER_LOAD_RULES)
    profile: ProfileSpec
    mass_kg: Positive | None = Field(None, description="translating: the moving mass, with the spring's share")
    spring_rate_n_mm: Positive | None = Field(None, description="translating: the spring rate k")
    preload_n: Finite | None = Field(None, description="translating: the spring force F0 at zero lift; default 0")
    external_force_n: Finite | None = Field(
        None, description="translating: a constant force, positive pressing the follower onto the cam; default 0")
    damping_n_s_mm: NonNegative | None = Field(None, description="translating: viscous damping c; default 0")
    inertia_kgm2: Positive | None = Field(None, description="oscillating: the arm's inertia about its pivot")
    spring_rate_nm_rad: Positive | None = Field(None, description="oscillating: the spring rate about the pivot")
    preload_nm: Finite | None = Field(None, description="oscillating: the spring torque T0 at zero swing; default 0")
    external_torque_nm: Finite | None = Field(
        None, description="oscillating: a constant torque, positive pressing the follower onto the cam; default 0")
    damping_nm_s_rad: NonNegative | None = Field(None, description="oscillating: viscous damping; default 0")
    safety_margin_n: NonNegative = Field(0.0, description="the contact force the follower must keep, at the "
                                                          "follower point (oscillating: the torque over the lever arm)")
    roller: RollerSpec | None = Field(None, description="roller followers: width and materials, for the Hertz stress")

    @model_validator(mode="after")
    def _check(self) -> ForceClosedFollower:
        oscillating = self.profile.follower.motion == "oscillating"
        own, other = (OSCILLATING_FIELDS, TRANSLATING_FIELDS) if oscillating else (TRANSLATING_FIELDS,
                                                                                  OSCILLATING_FIELDS)
        sentence = OSCILLATING_RULE if oscillating else TRANSLATING_RULE
        wrong = [name for name in other if getattr(self, name) is not None]
        missing = [name for name in own[:2] if getattr(self, name) is None]
        if wrong or missing:
            what = f"missing {', '.join(missing)}" if missing else f"{', '.join(wrong)} given"
            raise ValueError(f"{sentence} ({what})")
        if self.roller is not None and self.profile.follower.type != "roller":
            raise ValueError(f"{ROLLER_RULE}, not a {self.profile.follower.type} follower")
        return self

    def follower_load(self) -> FollowerLoad:
        """The follower's load as camcore takes it (the validator made sure the motion's own fields are given)."""
        if self.profile.follower.motion == "oscillating":
            assert self.inertia_kgm2 is not None and self.spring_rate_nm_rad is not None
            return OscillatingLoad(self.inertia_kgm2, self.spring_rate_nm_rad, self.preload_nm or 0.0,
                                   self.external_torque_nm or 0.0, self.damping_nm_s_rad or 0.0)
        assert self.mass_kg is not None and self.spring_rate_n_mm is not None
        return TranslatingLoad(self.mass_kg, self.spring_rate_n_mm, self.preload_n or 0.0,
                               self.external_force_n or 0.0, self.damping_n_s_mm or 0.0)


class DynamicsRequest(ForceClosedFollower):
    """A force-closed follower on a plate cam at a constant camshaft speed.

    A translating follower gives its load in N and mm (mass_kg, spring_rate_n_mm, preload_n,
    external_force_n, damping_n_s_mm); an oscillating one about its pivot in N·m and rad
    (inertia_kgm2, spring_rate_nm_rad, preload_nm, external_torque_nm, damping_nm_s_rad).
    safety_margin_n is a force at the follower point for both. The roller's width and materials
    (roller followers only) add the Hertz contact stress. speed_rpm and samples: the speed and the rows.
    """

    model_config = examples(DYNAMICS_EXAMPLE, rules=FOLLOWER_LOAD_RULES)
    speed_rpm: SpeedRpm = Field(description="N, the camshaft's speed")
    samples: Annotated[int, Field(ge=2), JSON_INTEGER] = Field(
        361, description="rows of the table, evenly over 0-360° of cam angle, both ends included")


#: request examples of computeFollowerDynamics (Swagger UI pre-fills the first)
DYNAMICS_EXAMPLES: dict[str, Example] = {
    "roller": {"summary": "roller cam (MS rise, cycloid return) at 600 rpm: holds, with its jump speed",
               "value": DYNAMICS_EXAMPLE},
    "separates": {"summary": "the same cam at 1500 rpm: the follower jumps; min_preload_n says what holds it",
                  "value": {**DYNAMICS_EXAMPLE, "speed_rpm": 1500}},
    "motion": {"summary": "Makino's cutting-unit cycle (1977, §5.3) as the lift: the rapid feed decelerates hardest",
               "value": {"profile": {"follower": {"type": "roller", "roller_radius_mm": 10}, "base_radius_mm": 60,
                                     "motion": MAKINO_CYCLE},
                         "speed_rpm": 60, "mass_kg": 2, "spring_rate_n_mm": 1, "preload_n": 50, "samples": 73}},
    "oscillating": {"summary": "an oscillating roller arm, with damping and the contact stress on a cast-iron cam",
                    "value": {"profile": OSCILLATING_PROFILE, "speed_rpm": 400, "inertia_kgm2": 0.004,
                              "spring_rate_nm_rad": 20, "preload_nm": 3, "damping_nm_s_rad": 0.002,
                              "roller": {"width_mm": 10, "cam_youngs_modulus_mpa": 110000, "cam_poisson_ratio": 0.27},
                              "samples": 181}},
}


# ----------------------------------------------------------------------------- answers
DynamicsSummaryAnswer = answer_model(DynamicsSummary, "DynamicsSummaryAnswer")
DynamicsAnswer = create_model(
    "DynamicsAnswer",
    __base__=answer_model(DynamicsTable, "DynamicsAnswer"),
    __doc__="Columns over cam_angle_deg (lift, velocity, acceleration in mm, mm/s, mm/s² for a translating follower; "
            "deg, deg/s, deg/s² of swing for an oscillating one: see unit), and the summary over the whole turn.",
    unit=(str, Field(description="the unit of lift: mm (translating) or deg (oscillating)")),
    summary=(DynamicsSummaryAnswer, Field(description="exact figures over the whole turn")),
)
DynamicsAnswer.__module__ = __name__
