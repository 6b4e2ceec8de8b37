"""Specs and answers of ``POST /v1/cams/roller-gear`` (docs/api.md: roller-gear cams)."""

from __future__ import annotations

from typing import Annotated

from fastapi.openapi.models import Example
from pydantic import Field, model_validator

from camcore.cams.roller_gear import RibChecks, check_roller_gear_geometry
from camcore.cams.roller_gear.body import check_solid_body
from camcore.cams.roller_gear.geometry import MIN_STOPS
from service.curves.specs import MS_SPEC, CurveSpec, NamedCurveSpec
from service.models import answer_model
from service.profiles.specs import PositiveLength
from service.specs import BIG, JSON_INTEGER, DefaultsInDescriptions, DeferredModel, Spec, examples

#: sampled cam angles over the rib's turn, at most
MAX_ROLLER_GEAR_SAMPLES = 3601
#: points along the roller per flank and cam angle, at most
MAX_ROLLER_GEAR_LENGTH_SAMPLES = 41

#: eight stops, index over 120° (MS), rollers 20 mm across and 20 mm long on a 60 mm pitch radius
ROLLER_GEAR_EXAMPLE: dict[str, object] = {
    "stops": 8, "center_distance_mm": 100, "roller_pitch_radius_mm": 60, "roller_radius_mm": 10,
    "roller_length_mm": 20, "indexing_angle_deg": 120, "curve": MS_SPEC, "samples": 121}
#: the same over a 30° index: the flanks fold (undercut), reported in the checks
UNDERCUT_EXAMPLE: dict[str, object] = {**ROLLER_GEAR_EXAMPLE, "indexing_angle_deg": 30}
#: the example's solid: a 20 mm bore, the flanks within 0.01 mm (STEP); its STL within 0.05 mm (24 000
#: facets, 0.31 s; 0.01 mm would be 115 000 facets and 1.1 s)
SOLID_EXAMPLE: dict[str, object] = {**ROLLER_GEAR_EXAMPLE, "solid": {"tolerance_mm": 0.01, "bore_diameter_mm": 20}}
SOLID_STL_EXAMPLE: dict[str, object] = {**ROLLER_GEAR_EXAMPLE, "solid": {"tolerance_mm": 0.05, "bore_diameter_mm": 20}}


class RollerGearSolidSpec(Spec):
    """The cam as a solid (``?format=step`` or ``solid-stl``): the rib on its globoidal body (docs/api.md).

    The body is the hourglass about the cam axis under the circle the rollers' outer rims sweep round the
    turret axis (throat radius center_distance_mm − √(r_out² + roller_radius_mm²) − root_clearance_mm,
    r_out = roller_pitch_radius_mm + roller_length_mm/2); the rib stands on it between the two flanks up
    to the turned globoid through the lowest point of the rollers' inner-end line.
    """

    model_config = examples({"tolerance_mm": 0.01, "bore_diameter_mm": 20})
    tolerance_mm: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=1e-4, le=10)] = Field(
        0.01, description="largest deviation of the solid's flanks from the exact flanks [mm]: the B-spline patches "
                          "are fitted to half of it (an STL: a quarter, and its facets to half)")
    bore_diameter_mm: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0, le=BIG)] = Field(
        0.0, description="bore about the cam axis [mm], leaving a wall at the body's throat; 0: none")
    root_clearance_mm: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0, le=BIG)] = Field(
        0.0, description="how far the body's surface lies beyond the circle of the rollers' outer rims [mm]: 0 "
                         "touches them there in the dwell")
    body_length_mm: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, le=BIG)] | None = Field(
        None, description="the body's length along the cam axis [mm], more than the rib's extent; null: the rib's "
                          "extent and half a roller radius at each end")


class RollerGearCamRequest(Spec):
    """A roller-gear (globoidal) cam: the turret (stops, one roller per stop), the rollers, the centre distance
    and the index law.

    The rollers stand radially on the turret's rim from roller_pitch_radius_mm − roller_length_mm/2 to
    roller_pitch_radius_mm + roller_length_mm/2; neighbours must leave room for the rib at their inner ends
    (2·r_in·sin(180°/stops) > 2·roller_radius_mm) and their outer ends must stop short of the cam axis
    (center_distance_mm > roller_pitch_radius_mm + roller_length_mm/2).
    """

    model_config = examples(ROLLER_GEAR_EXAMPLE, UNDERCUT_EXAMPLE)
    stops: Annotated[int, Field(ge=MIN_STOPS, le=72), JSON_INTEGER] = Field(
        description="stops per turret turn, one roller per stop: the turret moves 360°/stops per index; at least 5 "
                    "(the rollers making the rib swing through ±360°/stops about the line of centres)")
    center_distance_mm: PositiveLength = Field(description="C: cam axis to turret axis (square to each other) [mm]")
    roller_pitch_radius_mm: PositiveLength = Field(
        description="Rp: the rollers' mid-length distance from the turret axis [mm]")
    roller_radius_mm: PositiveLength = Field(description="Rr [mm]")
    roller_length_mm: PositiveLength = Field(description="ℓ: the roller's working length along its axis [mm]")
    indexing_angle_deg: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=1, le=359)] = Field(
        description="θh: the cam angle of the index; the rib holds the turret for the rest of the turn [deg]")
    curve: CurveSpec = Field(default_factory=lambda: NamedCurveSpec(name="MS"),
                             description="the index law, as the indexers take it")
    samples: Annotated[int, Field(ge=2, le=MAX_ROLLER_GEAR_SAMPLES), JSON_INTEGER] = Field(
        361, description="cam angles evenly over the rib's turn, 0–360° with both ends (the rib's two ends)")
    length_samples: Annotated[int, Field(ge=2, le=MAX_ROLLER_GEAR_LENGTH_SAMPLES), JSON_INTEGER] = Field(
        5, description="flank points per cam angle, evenly along the roller from its inner to its outer end")
    solid: RollerGearSolidSpec | None = Field(
        None, description="the solid of ?format=step or solid-stl (its defaults when null; unused otherwise); the "
                          "solid is the whole cam whatever the samples")

    @model_validator(mode="after")
    def _check(self) -> RollerGearCamRequest:
        # camcore's rules and sentences (a ValueError: 422)
        check_roller_gear_geometry(self.stops, self.center_distance_mm, self.roller_pitch_radius_mm,
                                   self.roller_radius_mm, self.roller_length_mm)
        if self.solid is not None:
            check_solid_body(self.center_distance_mm, self.roller_pitch_radius_mm + 0.5 * self.roller_length_mm,
                             self.roller_radius_mm, self.solid.root_clearance_mm, self.solid.bore_diameter_mm)
        return self


class RollerGearSolidStlRequest(RollerGearCamRequest):
    """A roller-gear cam request whose ``solid`` is given (the solid-stl twin: an STL's cost is its
    tolerance's choice, 115 000 facets at the default 0.01 mm for the example)."""

    model_config = examples(SOLID_STL_EXAMPLE)
    solid: RollerGearSolidSpec = Field(description="the solid's tolerance, bore, clearance and length")


SOLID_EXAMPLES: dict[str, Example] = {
    "eight stops": {"summary": "the eight-stop cam with a 20 mm bore, its flanks within 0.01 mm", "value": SOLID_EXAMPLE}}
SOLID_STL_EXAMPLES: dict[str, Example] = {
    "eight stops": {"summary": "the eight-stop cam with a 20 mm bore, its facets within 0.05 mm",
                    "value": SOLID_STL_EXAMPLE}}

ROLLER_GEAR_EXAMPLES: dict[str, Example] = {
    "eight stops": {"summary": "8 stops, index over 120° (MS): largest pressure angle ≈ 42° at the pitch radius",
                    "value": ROLLER_GEAR_EXAMPLE},
    "undercut": {"summary": "the same over a 30° index: the flanks fold, the checks say where",
                 "value": UNDERCUT_EXAMPLE},
}

RibChecksAnswer = answer_model(RibChecks, "RibChecksAnswer")


class RibFlankAnswer(DeferredModel):
    """One flank of the rib in the cam's frame (camcore.cams.roller_gear.RibFlank): x_mm, y_mm, z_mm and
    pressure_angle_deg have one row per cam angle and one column per roller_position_mm."""

    x_mm: list[list[float]]
    y_mm: list[list[float]]
    z_mm: list[list[float]] = Field(description="along the cam axis")
    pressure_angle_deg: list[list[float]] = Field(description="atan(φ'·r / (C − r·cos α)) at each point [deg]")
    regular: list[list[bool]] = Field(description="false where the flank folds (undercut)")


class RibFlanks(DeferredModel):
    forward: RibFlankAnswer = Field(description="faces the roller ahead of the rib: pushes the turret on")
    back: RibFlankAnswer = Field(description="faces the roller behind the rib: holds the turret back")


class RollerGearCamAnswer(DefaultsInDescriptions):
    """Columns over the rib's turn (the turret's angle, the pressure angles at the rollers' pitch radius), both
    flanks as point grids in the cam's frame, the checks."""

    cam_angle_deg: list[float] = Field(description="0–360°, both ends")
    turret_angle_deg: list[float] = Field(description="φ: the turret's turn, the index law over the index [deg]")
    pressure_angle_deg: list[float] = Field(description="forward flank, at the rollers' pitch radius [deg]")
    back_pressure_angle_deg: list[float] = Field(description="back flank, at the rollers' pitch radius [deg]")
    roller_position_mm: list[float] = Field(
        description="distance from the turret axis along the roller of the flank grids' columns [mm]")
    flanks: RibFlanks
    checks: RibChecksAnswer  # type: ignore[valid-type]  # derived answer model (service.models)
