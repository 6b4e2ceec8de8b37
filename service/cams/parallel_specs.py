"""Specs and answers of ``POST /v1/cams/parallel`` (docs/api.md: parallel indexing cams)."""

from __future__ import annotations

from typing import Annotated, Literal

from fastapi.openapi.models import Example
from pydantic import Field, model_validator

from camcore.cams.parallel import Contacts, ParallelChecks, PlateChecks, check_parallel_geometry
from service.curves.specs import MS_SPEC, CurveSpec, NamedCurveSpec
from service.models import answer_model
from service.profiles.specs import PositiveLength, SolidSpec
from service.specs import BIG, JSON_INTEGER, DefaultsInDescriptions, FieldRuleError, Spec, examples

#: sampled cam angles per turn, at most: 0.1° (the cost model refuses the largest turrets sooner)
MAX_PARALLEL_SAMPLES = 3601

#: four stops, three plates of four rollers, index over 120° (MS) — conjugate, pressure angle ≈ 54°
PARALLEL_EXAMPLE: dict[str, object] = {
    "stops": 4, "plates": 3, "center_distance_mm": 100, "roller_pitch_radius_mm": 60, "roller_radius_mm": 12,
    "indexing_angle_deg": 120, "curve": MS_SPEC, "samples": 121}
#: the same turret with two plates: the checks list where the turret is not held both ways
TWO_PLATE_EXAMPLE: dict[str, object] = {**PARALLEL_EXAMPLE, "plates": 2}

MULTIPLE_RULE = "rollers_per_plate must be a multiple of stops (each index moves every layer onto itself)"
#: the plates as solids: 12 mm thick with a 20 mm bore, touching (the spacing is the thickness), within 0.01 mm
PARALLEL_SOLID_EXAMPLE: dict[str, object] = {"thickness_mm": 12, "bore_diameter_mm": 20, "tolerance_mm": 0.01}
#: an STL's: 2 mm apart, facets within 0.1 mm (finer, three plates' meshes are estimated near or over the default
#: budget: 0.99 s at 0.05 mm, 1.2 s at 0.01 mm)
PARALLEL_STL_SOLID: dict[str, object] = {**PARALLEL_SOLID_EXAMPLE, "tolerance_mm": 0.1, "spacing_mm": 14}


class ParallelSolidSpec(SolidSpec):
    """The plates as solids (``?format=step`` or ``stl``): each extruded along the cam axis and bored, plate p from
    z = p·spacing_mm; one solid per plate, together in one file."""

    model_config = examples(PARALLEL_SOLID_EXAMPLE)
    spacing_mm: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, le=BIG)] | None = Field(
        None, description="the plates' pitch along the cam axis, from one plate's lower face to the next one's (their "
                          "rollers' layers stand as far apart), at least thickness_mm; omitted: thickness_mm, the "
                          "plates touching [mm]")

    @model_validator(mode="after")
    def _check(self) -> ParallelSolidSpec:
        if self.spacing_mm is not None and self.spacing_mm < self.thickness_mm:
            raise FieldRuleError(f"spacing_mm must be at least thickness_mm, {self.thickness_mm!r} mm: it is the plates' "
                                 "pitch along the cam axis, face to face, and the plates would overlap", "spacing_mm")
        return self


class ParallelCamRequest(Spec):
    """A parallel indexing cam: the turret (stops, rollers), the centre distance, the plates and the index law.

    The rollers of one plate must not touch (2·Rp·sin(180°/m) > 2·Rr) and must stay clear of the cam axis
    (center_distance_mm > roller_pitch_radius_mm + roller_radius_mm); each plate must leave room for the
    turret's shaft (a 422 names the plate otherwise).
    """

    model_config = examples(PARALLEL_EXAMPLE, TWO_PLATE_EXAMPLE)
    stops: Annotated[int, Field(ge=1, le=36), JSON_INTEGER] = Field(
        description="stops per turret turn: the turret moves 360°/stops per index")
    plates: Literal[2, 3] = Field(
        3, description="plate cams on the input shaft, each with its own layer of rollers (staggered by the roller "
                       "pitch / plates)")
    rollers_per_plate: Annotated[int, Field(ge=1, le=72), JSON_INTEGER] | None = Field(
        None, description="rollers in each plate's layer, a multiple of stops; default stops")
    center_distance_mm: PositiveLength = Field(description="C: cam axis to turret axis [mm]")
    roller_pitch_radius_mm: PositiveLength = Field(description="Rp: the rollers' centres' radius on the turret [mm]")
    roller_radius_mm: PositiveLength = Field(description="Rr [mm]")
    indexing_angle_deg: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=1, le=359)] = Field(
        description="θh: the cam angle of the index; the plates hold the turret for the rest of the turn [deg]")
    curve: CurveSpec = Field(default_factory=lambda: NamedCurveSpec(name="MS"),
                             description="the index law, as the indexers take it")
    samples: Annotated[int, Field(ge=16, le=MAX_PARALLEL_SAMPLES), JSON_INTEGER] = Field(
        181, description="cam angles evenly over the turn (0 ≤ θ < 360°) at which contacts are found and the plates' "
                         "contours have a point (they are traced at no fewer than 720 a turn)")
    solid: ParallelSolidSpec | None = Field(
        None, description="the plates as solids for ?format=step or stl (needed there, unused otherwise)")

    @model_validator(mode="after")
    def _check(self) -> ParallelCamRequest:
        m = self.rollers_per_plate or self.stops
        if m % self.stops:
            raise FieldRuleError(f"{MULTIPLE_RULE}, got {m} rollers for {self.stops} stops", "rollers_per_plate")
        # camcore's rules and sentences (a ValueError: 422)
        check_parallel_geometry(self.stops, self.plates, m, self.center_distance_mm, self.roller_pitch_radius_mm,
                                self.roller_radius_mm)
        return self


class ParallelSolidRequest(ParallelCamRequest):
    """A parallel cam request whose ``solid`` is required (its STEP and STL files)."""

    model_config = examples({**PARALLEL_EXAMPLE, "solid": PARALLEL_SOLID_EXAMPLE})
    solid: ParallelSolidSpec = Field(description="thickness, bore, spacing and tolerance of the plates' solids")


class ParallelSolidStlRequest(ParallelCamRequest):
    """A parallel cam request whose ``solid`` is required, its example an STL's (its cost is its tolerance's
    choice: about 4 400 facets a plate at 0.01 mm, three plates estimated over the default budget)."""

    model_config = examples({**PARALLEL_EXAMPLE, "solid": PARALLEL_STL_SOLID})
    solid: ParallelSolidSpec = Field(description="thickness, bore, spacing and tolerance of the plates' solids")


PARALLEL_SOLID_EXAMPLES: dict[str, Example] = {
    "three plates": {"summary": "the three plates, 12 mm thick with a 20 mm bore, touching, within 0.01 mm",
                     "value": {**PARALLEL_EXAMPLE, "solid": PARALLEL_SOLID_EXAMPLE}}}
#: an STL's facets are many more than a STEP's edges: a mesh to look at, within 0.1 mm
PARALLEL_STL_EXAMPLES: dict[str, Example] = {
    "three plates": {"summary": "the three plates, 12 mm thick with a 20 mm bore, 2 mm apart, facets within 0.1 mm",
                     "value": {**PARALLEL_EXAMPLE, "solid": PARALLEL_STL_SOLID}}}

PARALLEL_EXAMPLES: dict[str, Example] = {
    "three plates": {"summary": "4 stops, 3 plates of 4 rollers, index 120° (MS): held both ways throughout",
                     "value": PARALLEL_EXAMPLE},
    "two plates": {"summary": "the same with 2 plates: the checks list where the turret is not held both ways",
                   "value": TWO_PLATE_EXAMPLE},
}

PlateChecksAnswer = answer_model(PlateChecks, "PlateChecksAnswer")
ParallelChecksAnswer = answer_model(ParallelChecks, "ParallelChecksAnswer")
ContactsAnswer = answer_model(Contacts, "ContactsAnswer")


class PlateAnswer(DefaultsInDescriptions):
    """One plate (camcore.cams.parallel.Plate): its exact contour in the cam's frame, closed (the first point not
    repeated), counter-clockwise round the cam axis, within 1e-4·Rr of it between the points; at each point the
    roller that touches it there, when, that contact's pressure angle and the contour's radius of curvature; every
    contact over the sampled turn; the plate's checks."""

    plate: int
    roller_start_angle_deg: list[float] = Field(description="arm angle of each roller of its layer at θ = 0 [deg]")
    x_mm: list[float]
    y_mm: list[float]
    roller: list[int] = Field(description="the roller touching the contour at each vertex")
    contact_cam_angle_deg: list[float] = Field(description="the cam angle at which it touches there")
    pressure_angle_deg: list[float] = Field(description="of that contact, within ±90° [deg]")
    radius_of_curvature_mm: list[float] = Field(description="of the contour: positive convex, negative concave [mm]")
    contacts: ContactsAnswer  # type: ignore[valid-type]  # derived answer model (service.models)
    checks: PlateChecksAnswer  # type: ignore[valid-type]


class ParallelCamAnswer(DefaultsInDescriptions):
    """Columns over the sampled turn (the turret's angle, whether it is held each way, the best drive and hold
    pressure angles), the plates, the checks."""

    cam_angle_deg: list[float]
    turret_angle_deg: list[float] = Field(description="φ: the turret's turn, the index law over the index [deg]")
    held_forward: list[bool] = Field(description="some contact drives the turret forward")
    held_back: list[bool] = Field(description="some contact holds the turret back")
    drive_pressure_angle_deg: list[float | None] = Field(
        description="smallest |pressure angle| of the contacts that drive; null: none [deg]")
    hold_pressure_angle_deg: list[float | None] = Field(
        description="smallest |pressure angle| of the contacts that hold; null: none [deg]")
    plates: list[PlateAnswer]
    checks: ParallelChecksAnswer  # type: ignore[valid-type]
