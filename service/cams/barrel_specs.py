"""Specs and answers of ``POST /v1/cams/barrel`` (docs/api.md: barrel cams)."""

from __future__ import annotations

from typing import Annotated, Literal

from fastapi.openapi.models import Example
from pydantic import Field, model_validator

from camcore.cams.barrel import BarrelChecks, check_barrel_geometry
from camcore.cams.barrel.geometry import MAX_ARM_ANGLE_DEG
from service.curves.specs import MS_SPEC
from service.models import answer_model
from service.motions.specs import FEED_CYCLE, MotionSpec
from service.profiles.specs import PositiveLength, SegmentSpec
from service.specs import (
    BIG,
    JSON_INTEGER,
    DefaultsInDescriptions,
    DeferredModel,
    FieldRuleError,
    Spec,
    absent,
    all_of,
    exactly_one,
    examples,
    given,
    one_of_values,
    rule,
)

#: points along the roller per flank and cam angle, at most (a grid of samples × this per flank)
MAX_LENGTH_SAMPLES = 101

#: a translating follower: rise 30 mm over 120° (MS), dwell, return, dwell, on a 50 mm pitch radius
BARREL_EXAMPLE: dict[str, object] = {
    "pitch_radius_mm": 50, "roller_radius_mm": 10, "roller_length_mm": 12, "roller": "cylindrical",
    "segments": [{"type": "rise", "angle_deg": 120, "lift_mm": 30, "curve": MS_SPEC},
                 {"type": "dwell", "angle_deg": 60}, {"type": "return", "angle_deg": 120, "lift_mm": 30},
                 {"type": "dwell", "angle_deg": 60}],
    "samples": 73}
#: an oscillating arm of 80 mm swinging 30° (square to the cam axis at mid-swing)
OSCILLATING_BARREL_EXAMPLE: dict[str, object] = {
    "pitch_radius_mm": 60, "roller_radius_mm": 8, "roller_length_mm": 10, "follower": "oscillating",
    "arm_length_mm": 80, "initial_arm_angle_deg": -15,
    "segments": [{"type": "rise", "angle_deg": 150, "swing_deg": 30}, {"type": "dwell", "angle_deg": 30},
                 {"type": "return", "angle_deg": 150, "swing_deg": 30}, {"type": "dwell", "angle_deg": 30}],
    "samples": 73, "length_samples": 3}
#: a conical roller driven by a motion program (rest, matched quintics round a constant-velocity feed)
CONICAL_BARREL_EXAMPLE: dict[str, object] = {
    "pitch_radius_mm": 80, "roller_radius_mm": 10, "roller_length_mm": 16, "groove_depth_mm": 18,
    "roller": "conical", "motion": FEED_CYCLE, "samples": 73}

OSCILLATING = one_of_values("follower", "oscillating", default="translating")
TRANSLATING = one_of_values("follower", "translating", default="translating")
CONICAL = one_of_values("roller", "conical", default="cylindrical")


#: the cross-field rules of a barrel cam request, as JSON Schema (the validator gives their sentences)
BARREL_RULES = [
    rule("give the barrel cam's lift as segments or as a motion program", exactly_one("segments", "motion")),
    rule("an oscillating barrel-cam follower needs arm_length_mm", {"if": OSCILLATING,
                                                                   "then": given("arm_length_mm")}),
    rule("a conical roller rolls on a translating follower only (an oscillating arm moves its apex off "
         "the cam axis)", {"not": all_of(OSCILLATING, CONICAL)}),
    rule("an oscillating barrel-cam follower's motion program is in deg (of swing)",
         {"if": OSCILLATING, "then": {"properties": {"motion": {
             "required": ["unit"], "properties": {"unit": {"const": "deg"}}}}}}),
    rule("a translating barrel-cam follower's motion program is in mm",
         {"if": TRANSLATING, "then": {"properties": {"motion": {"properties": {"unit": {"const": "mm"}}}}}}),
    rule("an oscillating barrel-cam follower's lift is swing_deg, not lift_mm",
         {"if": OSCILLATING,
          "then": {"properties": {"segments": {"items": {"properties": {"lift_mm": {"maximum": 0}}}}}}}),
    rule("a translating barrel-cam follower's lift is lift_mm, not swing_deg",
         {"if": TRANSLATING, "then": {"properties": {"segments": {"items": absent("swing_deg")}}}})]


class BarrelSolidSpec(Spec):
    """The barrel cam as a solid (``?format=step`` or ``stl``): a cylinder of the cam's outer radius
    with the groove cut, the cam axis along z."""

    model_config = examples({"tolerance_mm": 0.01, "bore_diameter_mm": 20})
    tolerance_mm: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=1e-4, le=10)] = Field(
        0.01, description="largest deviation of the solid's surfaces from the exact ones [mm] (an STL: half for the "
                          "surfaces, half for the facets)")
    end_margin_mm: PositiveLength | None = Field(
        None, description="the cylinder's length beyond the groove at each end [mm]; omitted: the roller's radius")
    bore_diameter_mm: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0, le=BIG)] = Field(
        0.0, description="bore about the cam axis, smaller than the groove's bottom diameter [mm]; 0: none")


class BarrelCamRequest(Spec):
    """A barrel cam: pitch cylinder, roller, follower and lift (segments or a motion program).

    The roller is centred on the pitch radius: it works from pitch_radius_mm − roller_length_mm/2 to
    pitch_radius_mm + roller_length_mm/2 (the cam's outer radius), so roller_length_mm < 2·pitch_radius_mm;
    the groove is groove_depth_mm deep below the outer radius, at least the roller's length and less than
    the outer radius. Segment angles add to 360°.
    """

    model_config = examples(BARREL_EXAMPLE, OSCILLATING_BARREL_EXAMPLE, CONICAL_BARREL_EXAMPLE, rules=BARREL_RULES)
    pitch_radius_mm: PositiveLength = Field(description="R: the developed groove is drawn on this cylinder [mm]")
    roller_radius_mm: PositiveLength = Field(description="the roller's radius (a cone's at the pitch radius) [mm]")
    roller: Literal["cylindrical", "conical"] = Field(
        "cylindrical", description="conical: apex on the cam axis, half-angle α with tan α = roller_radius_mm / "
                                   "pitch_radius_mm")
    roller_length_mm: PositiveLength | None = Field(
        None, description="the roller's working length, centred on the pitch radius; default roller_radius_mm [mm]")
    groove_depth_mm: PositiveLength | None = Field(
        None, description="depth below the cam's outer radius (pitch radius + roller length/2); default "
                          "roller_length_mm [mm]")
    follower: Literal["translating", "oscillating"] = Field(
        "translating", description="translating: along the cam axis; oscillating: an arm pivoting about an axis "
                                   "square to the cam axis")
    arm_length_mm: PositiveLength | None = Field(None, description="oscillating: pivot axis to roller axis [mm]")
    initial_arm_angle_deg: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=-MAX_ARM_ANGLE_DEG,
                                                  lt=MAX_ARM_ANGLE_DEG)] = Field(
        0.0, description="oscillating: the arm's angle at zero swing, from square to the cam axis, positive "
                         "towards +z [deg]")
    segments: list[SegmentSpec] | None = Field(None, min_length=1, max_length=360)
    motion: MotionSpec | None = Field(
        None, description="a closed motion program over one cam turn (period 360° or a whole fraction of it): mm "
                          "for a translating follower, deg of swing for an oscillating one")
    samples: Annotated[int, Field(ge=2), JSON_INTEGER] = Field(
        361, description="cam angles evenly over 0–360°, both ends included")
    length_samples: Annotated[int, Field(ge=2, le=MAX_LENGTH_SAMPLES), JSON_INTEGER] = Field(
        5, description="flank points per cam angle, evenly along the roller from its inner to its outer end")
    solid: BarrelSolidSpec | None = Field(
        None, description="the solid of ?format=step or stl (needed there; unused otherwise, and in a toolpath's or "
                          "a machine's cam); the solid is the whole turn whatever the samples")

    @model_validator(mode="after")
    def _check(self) -> BarrelCamRequest:
        if (self.segments is None) == (self.motion is None):
            raise ValueError("give the barrel cam's lift as segments or as a motion program")
        oscillating = self.follower == "oscillating"
        if oscillating and self.arm_length_mm is None:
            raise FieldRuleError("an oscillating barrel-cam follower needs arm_length_mm", "arm_length_mm")
        if oscillating and self.roller == "conical":
            raise FieldRuleError("a conical roller rolls on a translating follower only (an oscillating arm moves "
                                 "its apex off the cam axis)", "roller")
        if self.motion is not None:
            if oscillating and self.motion.unit != "deg":
                raise FieldRuleError("an oscillating barrel-cam follower's motion program is in deg (of swing)",
                                     "motion", "unit")
            if not oscillating and self.motion.unit != "mm":
                raise FieldRuleError("a translating barrel-cam follower's motion program is in mm", "motion", "unit")
        if self.segments is not None:
            total = sum(s.angle_deg for s in self.segments)
            if abs(total - 360) > 1e-9:
                raise FieldRuleError(f"segment angles must add to 360°, but they add to {total}°", "segments")
            for i, seg in enumerate(self.segments):
                if oscillating and seg.lift_mm is not None and seg.lift_mm > 0:
                    raise FieldRuleError("an oscillating barrel-cam follower's lift is swing_deg, not lift_mm",
                                         "segments", i, "lift_mm")
                if not oscillating and seg.swing_deg is not None:
                    raise FieldRuleError("a translating barrel-cam follower's lift is lift_mm, not swing_deg",
                                         "segments", i, "swing_deg")
        length = self.roller_length_mm or self.roller_radius_mm
        # camcore's rules and sentences (a ValueError: 422)
        check_barrel_geometry(self.pitch_radius_mm, self.roller_radius_mm, length, self.groove_depth_mm or length,
                              self.roller, self.follower, self.arm_length_mm)
        bottom = self.pitch_radius_mm + 0.5 * length - (self.groove_depth_mm or length)
        if self.solid is not None and not self.solid.bore_diameter_mm < 2 * bottom:
            raise FieldRuleError(f"the bore must be smaller than the groove's bottom diameter, {2 * bottom!r} mm",
                                 "solid", "bore_diameter_mm")
        return self


BARREL_EXAMPLES: dict[str, Example] = {
    "translating": {"summary": "translating follower, cylindrical roller: rise 30 mm (MS) / dwell / return / dwell",
                    "value": BARREL_EXAMPLE},
    "oscillating": {"summary": "oscillating arm of 80 mm swinging 30°, square to the cam axis at mid-swing",
                    "value": OSCILLATING_BARREL_EXAMPLE},
    "conical": {"summary": "conical roller driven by a motion program", "value": CONICAL_BARREL_EXAMPLE},
}

#: the example of the solid formats: 0.05 mm, an STL of ~20 000 facets within the work budget
BARREL_SOLID_EXAMPLE: dict[str, object] = {**BARREL_EXAMPLE, "solid": {"tolerance_mm": 0.05, "bore_diameter_mm": 20}}


class BarrelSolidRequest(BarrelCamRequest):
    """A barrel cam request whose ``solid`` is required (the solid files)."""

    # its own examples, and the rules it inherits with BarrelCamRequest's validator
    model_config = examples(BARREL_SOLID_EXAMPLE, rules=BARREL_RULES)
    solid: BarrelSolidSpec = Field(description="tolerance, end margins and bore of the solid")


BARREL_SOLID_EXAMPLES: dict[str, Example] = {
    "translating": {"summary": "the translating barrel cam as a solid with a 20 mm bore, within 0.05 mm",
                    "value": BARREL_SOLID_EXAMPLE}}

BarrelChecksAnswer = answer_model(BarrelChecks, "BarrelChecksAnswer")


class BarrelFlankAnswer(DeferredModel):
    """One groove wall in the cam's frame (camcore.cams.barrel.BarrelFlank): x_mm, y_mm, z_mm have one row
    per cam angle and one column per roller_position_mm (the contact line across the roller's length)."""

    x_mm: list[list[float]]
    y_mm: list[list[float]]
    z_mm: list[list[float]] = Field(description="along the cam axis")
    radius_of_curvature_mm: list[float | None] = Field(
        description="of the developed flank at the pitch radius, per cam angle: positive convex towards the roller, "
                    "negative concave; null where straight")


class BarrelFlanks(DeferredModel):
    upper: BarrelFlankAnswer = Field(description="the groove's wall on the +z side of the roller")
    lower: BarrelFlankAnswer = Field(description="the groove's wall on the −z side of the roller")


class BarrelCamAnswer(DefaultsInDescriptions):
    """Columns over cam_angle_deg (the developed groove at the pitch radius), both flanks in 3-D, checks."""

    cam_angle_deg: list[float]
    lift_mm: list[float] | None = Field(None, description="translating follower (absent for an oscillating one)")
    swing_deg: list[float] | None = Field(None, description="oscillating follower (absent for a translating one)")
    u_mm: list[float] = Field(description="developed groove centreline along the circumference, R·(cam-frame angle)")
    y_mm: list[float] = Field(description="developed groove centreline along the cam axis")
    pressure_angle_deg: list[float] = Field(description="at the pitch radius")
    pressure_angle_inner_deg: list[float] = Field(description="at the roller's inner end")
    pressure_angle_outer_deg: list[float] = Field(description="at the roller's outer end")
    pitch_radius_of_curvature_mm: list[float | None] = Field(
        description="developed pitch curve, positive bending towards +y; null where straight")
    roller_position_mm: list[float] = Field(description="positions along the roller's axis of the flank grids' columns")
    flanks: BarrelFlanks
    checks: BarrelChecksAnswer  # type: ignore[valid-type]  # derived answer model (service.models)
