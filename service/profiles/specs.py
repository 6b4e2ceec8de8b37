"""Specs and answers of /v1/profiles (docs/api.md: ProfileSpec)."""

from __future__ import annotations

from typing import Annotated, Literal

from fastapi.openapi.models import Example
from pydantic import Field, PrivateAttr, model_validator

from camcore.export.solid import MIN_THICKNESS_MM
from camcore.profile import BaseCircleResult, Follower, ProfileChecks
from camcore.profile.followers import check_follower
from service.curves.specs import MS_SPEC, BezierCurveSpec, CurveSpec, PointsCurveSpec
from service.models import answer_model
from service.motions.specs import FEED_CYCLE, MotionSpec
from service.specs import (
    BIG,
    JSON_INTEGER,
    DefaultsInDescriptions,
    Spec,
    absent,
    all_of,
    exactly_one,
    examples,
    given,
    not_both,
    one_of_values,
    rule,
)

Length = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=-BIG, le=BIG)]
PositiveLength = Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, le=BIG)]

#: a roller cam, rise–dwell–return–dwell: 20 mm over 120° (MS), 60° dwell, return, 60° dwell
ROLLER_PROFILE_EXAMPLE: dict[str, object] = {
    "follower": {"type": "roller", "roller_radius_mm": 10}, "base_radius_mm": 40,
    "segments": [{"type": "rise", "angle_deg": 120, "lift_mm": 20, "curve": MS_SPEC},
                 {"type": "dwell", "angle_deg": 60}, {"type": "return", "angle_deg": 120, "lift_mm": 20},
                 {"type": "dwell", "angle_deg": 60}]}
#: a knife-edge cam rising 20 mm over 180° and returning (cycloid both ways)
KNIFE_EDGE_PROFILE_EXAMPLE: dict[str, object] = {
    "follower": {"type": "knife-edge"}, "base_radius_mm": 15,
    "segments": [{"type": "rise", "angle_deg": 180, "lift_mm": 20},
                 {"type": "return", "angle_deg": 180, "lift_mm": 20}]}

#: a roller cam driven by a motion program: dwell, rise with a matched quintic into a
#: constant-velocity stretch, matched quintic to rest, dwell, cycloid back
MOTION_PROFILE_EXAMPLE: dict[str, object] = {
    "follower": {"type": "roller", "roller_radius_mm": 10}, "base_radius_mm": 50, "motion": FEED_CYCLE}


#: conditions on a follower spec, a missing field read as its default
OSCILLATING = one_of_values("motion", "oscillating", default="translating")
TRANSLATING = one_of_values("motion", "translating", default="translating")
NOT_FLAT_FACED = one_of_values("type", "knife-edge", "roller", default="knife-edge")


class FollowerSpec(Spec):
    # check_follower's rules
    model_config = examples(
        {"type": "roller", "roller_radius_mm": 10},
        rules=[rule("a roller follower needs a roller radius > 0",
                    {"if": one_of_values("type", "roller", default="knife-edge"),
                     "then": {"required": ["roller_radius_mm"], "properties": {"roller_radius_mm": {"exclusiveMinimum": 0}}}}),
               rule("an oscillating follower needs pivot_distance_mm > 0", {"if": OSCILLATING, "then": given("pivot_distance_mm")}),
               rule("an oscillating follower other than a flat-faced one needs arm_length_mm > 0",
                    {"if": all_of(OSCILLATING, NOT_FLAT_FACED), "then": given("arm_length_mm")})])
    type: Literal["knife-edge", "roller", "flat-faced"] = "knife-edge"
    motion: Literal["translating", "oscillating"] = "translating"
    offset_mm: Length = Field(0.0, description="offset e of a translating follower's line of motion")
    roller_radius_mm: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0, le=BIG)] = 0.0
    arm_length_mm: PositiveLength | None = Field(None, description="oscillating: pivot to contact")
    pivot_distance_mm: PositiveLength | None = Field(None, description="oscillating: cam centre to pivot")

    _core: Follower | None = PrivateAttr(None)

    @model_validator(mode="after")
    def _check(self) -> FollowerSpec:
        check_follower(self.core())  # camcore's rule and sentence (a ValueError: 422)
        return self

    def core(self) -> Follower:
        """The follower as camcore takes it; made once."""
        if self._core is None:
            self._core = Follower(**self.model_dump())
        return self._core


class SegmentSpec(Spec):
    """One stretch of the lift schedule; its type sets the direction of its curve."""

    model_config = examples(
        {"type": "rise", "angle_deg": 120, "lift_mm": 20, "curve": MS_SPEC},
        rules=[rule("a rise or return segment needs lift_mm (or swing_deg for an oscillating follower)",
                    {"if": one_of_values("type", "rise", "return"),
                     "then": {"anyOf": [given("lift_mm"), given("swing_deg")]}}),
               rule("give lift_mm or swing_deg, not both", not_both("lift_mm", "swing_deg")),
               rule("a segment's type sets its direction: give the rise law with direction 'rise'",
                    {"not": {"required": ["curve"], "properties": {"curve": {
                        "type": "object", "required": ["direction"], "properties": {"direction": {"const": "return"}}}}}})])
    type: Literal["rise", "dwell", "return"]
    angle_deg: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, le=360)]
    lift_mm: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0, le=BIG)] | None = None
    swing_deg: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0, le=180)] | None = None
    curve: CurveSpec | None = Field(None, description="the rise law (a return plays it backwards); default cycloid")

    @model_validator(mode="after")
    def _check(self) -> SegmentSpec:
        if self.type != "dwell" and self.lift_mm is None and self.swing_deg is None:
            raise ValueError(f"a {self.type} segment needs lift_mm (or swing_deg for an oscillating follower)")
        if self.lift_mm is not None and self.swing_deg is not None:
            raise ValueError("give lift_mm or swing_deg, not both")
        if self.curve is not None and self.curve.direction == "return":
            raise ValueError("a segment's type sets its direction: give the rise law with direction 'rise'")
        return self


class ProfileSpec(Spec):
    """The cam: follower, base circle, and the lift as segments, as one curve or as a motion program.

    Segment angles add to 360°, and the schedule closes (it returns to the lift it starts at).
    A translating follower other than a flat-faced one needs |offset_mm| < base_radius_mm +
    roller_radius_mm, else its line of motion misses the cam.
    """

    model_config = examples(
        ROLLER_PROFILE_EXAMPLE, MOTION_PROFILE_EXAMPLE,
        rules=[rule("give the lift as segments, as one lift curve (bezier or points) or as a motion program",
                    exactly_one("segments", "lift", "motion")),
               rule("an oscillating follower's motion program is in deg (of swing)",
                    {"if": {"properties": {"follower": OSCILLATING}},
                     "then": {"properties": {"motion": {"required": ["unit"], "properties": {"unit": {"const": "deg"}}}}}}),
               rule("a translating follower's motion program is in mm",
                    {"if": {"properties": {"follower": TRANSLATING}},
                     "then": {"properties": {"motion": {"properties": {"unit": {"const": "mm"}}}}}}),
               rule("an oscillating follower's lift is swing_deg, not lift_mm",
                    {"if": {"properties": {"follower": OSCILLATING}},
                     "then": {"properties": {"segments": {"items": {"properties": {"lift_mm": {"maximum": 0}}}}}}}),
               rule("a translating follower's lift is lift_mm, not swing_deg",
                    {"if": {"properties": {"follower": TRANSLATING}},
                     "then": {"properties": {"segments": {"items": absent("swing_deg")}}}})])
    follower: FollowerSpec
    base_radius_mm: PositiveLength
    rotation: Literal["ccw", "cw"] = "ccw"
    rotation_ratio: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, le=1000)] = Field(
        1.0, description="cam turns per drive-shaft turn")
    segments: list[SegmentSpec] | None = Field(None, min_length=1, max_length=360)
    lift: Annotated[BezierCurveSpec | PointsCurveSpec, Field(discriminator="type")] | None = Field(
        None, description="one Bezier or points curve of lift over the drive angle, ending at the lift it starts with")
    motion: MotionSpec | None = Field(
        None, description="a motion program over the drive angle that closes (ends where it starts): one cam turn is "
                          "360/rotation_ratio degrees of it, a whole number of its periods; mm for a translating "
                          "follower, deg of swing for an oscillating one")

    @model_validator(mode="after")
    def _check(self) -> ProfileSpec:
        if sum(given is not None for given in (self.segments, self.lift, self.motion)) != 1:
            raise ValueError("give the lift as segments, as one lift curve (bezier or points) or as a motion program")
        if self.motion is not None:
            oscillating = self.follower.motion == "oscillating"
            if oscillating and self.motion.unit != "deg":
                raise ValueError("an oscillating follower's motion program is in deg (of swing)")
            if not oscillating and self.motion.unit != "mm":
                raise ValueError("a translating follower's motion program is in mm")
        if self.segments is not None:
            total = sum(s.angle_deg for s in self.segments)
            if abs(total - 360) > 1e-9:
                raise ValueError(f"segment angles must add to 360°, but they add to {total}°")
            oscillating = self.follower.motion == "oscillating"
            for i, seg in enumerate(self.segments):
                if oscillating and seg.lift_mm is not None and seg.lift_mm > 0:
                    raise ValueError(f"segments[{i}]: an oscillating follower's lift is swing_deg, not lift_mm")
                if not oscillating and seg.swing_deg is not None:
                    raise ValueError(f"segments[{i}]: a translating follower's lift is lift_mm, not swing_deg")
        if (self.follower.motion == "translating" and self.follower.type != "flat-faced"
                and abs(self.follower.offset_mm) >= self.base_radius_mm + self.follower.roller_radius_mm):
            raise ValueError("the offset must be smaller than the base radius (plus roller radius): "
                             "the follower line would miss the cam")
        return self


class SolidSpec(Spec):
    """The plate cam as a solid (``?format=step`` or ``stl``): extruded along its axis from z = 0."""

    model_config = examples({"thickness_mm": 12, "bore_diameter_mm": 20})
    thickness_mm: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=MIN_THICKNESS_MM, le=BIG)] = Field(
        description="extrusion along the cam axis [mm], at least 1 µm (the CAD kernel makes no thinner solid)")
    bore_diameter_mm: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0, le=BIG)] = Field(
        0.0, description="bore about the axis, smaller than the cam at its narrowest [mm]; 0: none")
    tolerance_mm: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=1e-4, le=10)] = Field(
        0.01, description="largest deviation of the solid's surface from the exact cam surface [mm]: the contour "
                          "is fitted with lines and arcs within it (an STL: half for the arcs, half for the facets)")


#: the rules of a profile request, stated by every model that keeps them (the solids' too)
PROFILE_REQUEST_RULES = [rule("give either samples or cam_angle_deg, not both", not_both("samples", "cam_angle_deg"))]


class ProfileRequest(Spec):
    model_config = examples({"profile": ROLLER_PROFILE_EXAMPLE, "samples": 361}, rules=PROFILE_REQUEST_RULES)
    profile: ProfileSpec
    samples: Annotated[int, Field(ge=2), JSON_INTEGER] | None = Field(None, description="evenly over 0–360° of cam angle, both ends included")
    # minItems states the validator's rule in the schema (the validator gives the sentence)
    cam_angle_deg: Annotated[list[Annotated[float, Field(strict=True, allow_inf_nan=False, ge=-1e5, le=1e5)]],
                             Field(json_schema_extra={"minItems": 1})] | None = None
    solid: SolidSpec | None = Field(None, description="the solid of ?format=step or stl (needed there, unused "
                                                      "otherwise); the solid is the whole turn whatever the samples")

    @model_validator(mode="after")
    def _check(self) -> ProfileRequest:
        if self.samples is not None and self.cam_angle_deg is not None:
            raise ValueError("give either samples or cam_angle_deg, not both")
        if self.samples is None and self.cam_angle_deg is None:
            self.samples = 361
        if self.cam_angle_deg is not None and not self.cam_angle_deg:
            raise ValueError("cam_angle_deg must list at least one angle")
        return self


class BaseCircleRequest(Spec):
    model_config = examples(
        {"profile": KNIFE_EDGE_PROFILE_EXAMPLE, "max_pressure_angle_deg": 30},
        rules=[rule("give max_pressure_angle_deg and/or min_radius_of_curvature_mm (a flat-faced follower may give neither)",
                    {"if": {"properties": {"profile": {"properties": {"follower": NOT_FLAT_FACED}}}},
                     "then": {"anyOf": [given("max_pressure_angle_deg"), given("min_radius_of_curvature_mm")]}})])
    profile: ProfileSpec
    max_pressure_angle_deg: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, lt=90)] | None = None
    min_radius_of_curvature_mm: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0, le=BIG)] | None = None

    @model_validator(mode="after")
    def _check(self) -> BaseCircleRequest:
        if (self.max_pressure_angle_deg is None and self.min_radius_of_curvature_mm is None
                and self.profile.follower.type != "flat-faced"):
            raise ValueError("give max_pressure_angle_deg and/or min_radius_of_curvature_mm")
        return self


CONSTANT_VELOCITY: dict[str, object] = {"type": "named", "name": "constant-velocity"}
#: request examples of the POST operations (Swagger UI pre-fills the first)
PROFILE_EXAMPLES: dict[str, Example] = {
    "roller": {"summary": "roller follower: rise 20 mm / dwell / return / dwell, 361 points",
               "value": {"profile": ROLLER_PROFILE_EXAMPLE, "samples": 361}},
    "motion": {"summary": "roller follower driven by a motion program (rest, matched quintics around a constant "
                          "velocity feed, rest, cycloid back)",
               "value": {"profile": MOTION_PROFILE_EXAMPLE, "samples": 361}},
    "knife-edge": {"summary": "knife-edge follower at given cam angles",
                   "description": "Shinzato 1988, table 1 (constant velocity): pressure angle 21.56° at 10°",
                   "value": {"profile": {**KNIFE_EDGE_PROFILE_EXAMPLE, "segments": [
                       {"type": "rise", "angle_deg": 180, "lift_mm": 20, "curve": CONSTANT_VELOCITY},
                       {"type": "return", "angle_deg": 180, "lift_mm": 20, "curve": CONSTANT_VELOCITY}]},
                             "cam_angle_deg": [10, 30, 45, 120, 270]}},
}
BASE_CIRCLE_EXAMPLES: dict[str, Example] = {
    "pressure-angle": {"summary": "smallest base circle for a pressure angle of at most 30°",
                       "value": {"profile": KNIFE_EDGE_PROFILE_EXAMPLE, "max_pressure_angle_deg": 30}},
    "roller": {"summary": "roller follower: 30° and a radius of curvature of at least 5 mm",
               "value": {"profile": ROLLER_PROFILE_EXAMPLE, "max_pressure_angle_deg": 30,
                         "min_radius_of_curvature_mm": 5}},
}


ProfileChecksAnswer = answer_model(ProfileChecks, "ProfileChecksAnswer")


class ProfileAnswer(DefaultsInDescriptions):
    """Columns over cam_angle_deg; radius columns are null where the surface is straight."""

    cam_angle_deg: list[float]
    lift_mm: list[float] | None = Field(None, description="translating follower (absent for an oscillating one)")
    swing_deg: list[float] | None = Field(None, description="oscillating follower (absent for a translating one)")
    x_mm: list[float]
    y_mm: list[float]
    pitch_x_mm: list[float]
    pitch_y_mm: list[float]
    pressure_angle_deg: list[float]
    radius_of_curvature_mm: list[float | None]
    pitch_radius_of_curvature_mm: list[float | None]
    contact_offset_mm: list[float] | None = Field(
        None, description="flat-faced follower: where the face touches the cam (absent otherwise)")
    checks: ProfileChecksAnswer  # type: ignore[valid-type]  # derived answer model (service.models)


BaseCircleAnswer = answer_model(BaseCircleResult, "BaseCircleAnswer")
