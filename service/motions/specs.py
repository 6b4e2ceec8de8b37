"""Specs and answers of /v1/motions (docs/api.md: MotionSpec)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated, Any, ClassVar, Literal

from fastapi.openapi.models import Example
from pydantic import Field, PrivateAttr, create_model, model_validator

from camcore.motion import (
    SOLVE,
    SOLVED_PARAMETERS,
    Join,
    MotionCharacteristics,
    MotionSegment,
    MotionTable,
    ResolvedSegment,
    check_program,
    check_segment,
)
from camcore.motion import MotionSpec as CoreMotionSpec
from service.curves.specs import (
    KIND_SPECS,
    BoundaryConditions,
    CurveKindSpec,
    CurveSpec,
    MakinoCurveSpec,
    PolynomialCurveSpec,
    UniversalCurveSpec,
    curve_spec_union,
    makino_rules,
)
from service.models import answer_model
from service.specs import (
    BIG,
    JSON_INTEGER,
    Finite,
    Spec,
    absent,
    all_of,
    examples,
    given,
    not_both,
    one_of_values,
    rule,
)

#: a span shorter than this would put the program's derivatives beyond any machine (v ~ h/β)
MIN_SPAN_DEG = 1e-6
Span = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=MIN_SPAN_DEG, le=BIG)]

#: Makino 1977, §5.3 (Fig. 6-9): the cutting-unit feed cam — rapid feed, cutting feed (T4 and
#: its stroke solved for continuity), rapid return, dwell
MAKINO_CYCLE: dict[str, Any] = {
    "unit": "mm", "start": 0, "period_deg": 360,
    "segments": [
        {"span_deg": 60, "to": 40, "curve": {"type": "makino", "number": 1, "z": 0.9}},
        {"span_deg": 120, "to": None, "curve": {"type": "makino", "number": 2}},
        {"span_deg": 90, "to": 0, "curve": {"type": "named", "name": "48", "direction": "return"}},
        {"span_deg": 90, "type": "dwell"}]}
#: rest → constant-velocity feed → rest with matched quintics, and a cycloid back
FEED_CYCLE: dict[str, Any] = {
    "unit": "mm",
    "segments": [
        {"span_deg": 30, "type": "dwell"},
        {"span_deg": 60, "to": 10, "curve": {"type": "polynomial"}},
        {"span_deg": 120, "to": 50, "curve": {"type": "named", "name": "constant-velocity"}},
        {"span_deg": 60, "to": 60, "curve": {"type": "polynomial"}},
        {"span_deg": 30, "type": "dwell"},
        {"span_deg": 60, "to": 0}]}


# ----------------------------------------------------------------------------- laws in a program
class ProgramMakinoSpec(MakinoCurveSpec):
    """Makino's curve by number, as in a curve spec; in a program, curve 2 may leave out
    ``t4``: it is solved so that the acceleration is continuous at its end (Makino 1977, §5.3)."""

    model_config = examples({"type": "makino", "number": 2}, {"type": "makino", "number": 1, "z": 0.9},
                            rules=makino_rules({n: (p[0],) for n, p in SOLVED_PARAMETERS.items()}))
    solvable: ClassVar[dict[int, tuple[str, ...]]] = {n: (p[0],) for n, p in SOLVED_PARAMETERS.items()}


class ProgramUniversalSpec(UniversalCurveSpec):
    """Makino's universal curve, as in a curve spec; in a program, an omitted ``v0`` (or
    ``v7``, with ``m`` omitted too) takes the neighbour's velocity at that end (for a return,
    ``v7`` is the segment's start and ``v0`` its end)."""

    model_config = examples({"type": "universal", "t": [0, 0.1, 0.1, 0.3, 0.5, 0.75, 0.75, 1], "v7": 0},
                            rules=[rule("give either m or v7, not both: with m fixed, V7 is a result",
                                        not_both("m", "v7"))])
    v0: Finite | None = Field(None, description="velocity at T0; omitted: the neighbour's velocity")  # type: ignore[assignment]  # omitted = matched
    v7: Finite | None = Field(None, description="velocity at T7 when m is omitted; omitted: the neighbour's velocity")


class ProgramPolynomialSpec(PolynomialCurveSpec):
    """A polynomial law by name, or from end conditions; in a program ``start`` and/or ``end``
    may be left out: that end meets the neighbour's s, v, a (and j with the segment's
    ``match: jerk``). Given ends are normalised to the law (s = 0 at the start, 1 at the end)."""

    model_config = examples({"type": "polynomial"}, {"type": "polynomial", "start": {"s": 0, "v": 0, "a": 0}},
                            rules=[rule("give a polynomial name or boundary conditions, not both",
                                        {"if": given("name"), "then": absent("start", "end")}),
                                   rule("with one end omitted, the given one is normalised: s = 0 at the start, 1 at "
                                        "the end (a law in a program runs from s = 0 to 1)",
                                        {"if": {"not": given("start", "end")},
                                         "then": {"properties": {"start": {"properties": {"s": {"const": 0}}},
                                                                 "end": {"properties": {"s": {"const": 1}}}}}})])
    start: BoundaryConditions | None = Field(None, description="omitted: matched to the previous segment")
    end: BoundaryConditions | None = Field(None, description="omitted: matched to the next segment")

    @model_validator(mode="after")
    def _check(self) -> ProgramPolynomialSpec:
        if self.name is not None and (self.start is not None or self.end is not None):
            raise ValueError("give a polynomial name or boundary conditions, not both")
        return self


#: what a program may leave out of a law to match or solve it (camcore.motion.laws.law_role)
PROGRAM_VARIANTS: dict[str, type[CurveKindSpec]] = {
    "makino": ProgramMakinoSpec, "universal": ProgramUniversalSpec, "polynomial": ProgramPolynomialSpec}
#: every kind of CURVE_KINDS, as a program takes it
PROGRAM_SPECS = {name: PROGRAM_VARIANTS.get(name, spec) for name, spec in KIND_SPECS.items()}

if TYPE_CHECKING:  # a type checker sees the base of the kinds' specs
    ProgramCurveSpec = CurveSpec
else:
    ProgramCurveSpec = curve_spec_union(PROGRAM_SPECS)

DWELL = one_of_values("type", "dwell")
MOVE = one_of_values("type", "move", default="move")
#: laws that leave something to the program (camcore.motion.laws.law_role), as JSON Schema
MATCHED_POLYNOMIAL = all_of({"required": ["type"], "properties": {"type": {"const": "polynomial"}}}, absent("name"),
                            {"not": given("start", "end")})
MATCHED_UNIVERSAL = all_of({"required": ["type"], "properties": {"type": {"const": "universal"}}},
                           {"not": all_of(given("v0"), {"anyOf": [given("v7"), given("m")]})})
SOLVED_T4 = all_of({"required": ["type", "number"], "properties": {"type": {"const": "makino"}, "number": {"const": 2}}},
                   absent("t4"))


class MotionSegmentSpec(Spec):
    """One segment of a program: a move to ``to`` (absolute; null = solved so that the
    velocity is continuous at its start) or by ``stroke`` (signed), over ``span_deg`` of
    master angle, with a law (default cycloid); or a dwell."""

    model_config = examples(
        {"span_deg": 60, "to": 40, "curve": {"type": "makino", "number": 1, "z": 0.9}},
        {"span_deg": 90, "type": "dwell"},
        rules=[rule("a move gives to (absolute; null = solved) or stroke (relative), not both",
                    {"if": MOVE, "then": {"if": {"required": ["to"]}, "then": absent("stroke"),
                                          "else": given("stroke")}}),
               rule("a dwell holds its position; give it no to, stroke or curve",
                    {"if": DWELL, "then": {"allOf": [{"not": {"required": ["to"]}}, absent("stroke", "curve")]}}),
               rule("match: jerk applies to a polynomial law with omitted start or end",
                    {"if": {"required": ["match"], "properties": {"match": {"const": "jerk"}}},
                     "then": {"required": ["curve"], "properties": {"curve": MATCHED_POLYNOMIAL}}}),
               rule("to: null solves the stroke from the law's start velocity, so the law must be given in full (not "
                    "matched to its neighbours)",
                    {"if": {"required": ["to"], "properties": {"to": {"type": "null"}}},
                     "then": {"properties": {"curve": {"not": {"anyOf": [MATCHED_POLYNOMIAL, MATCHED_UNIVERSAL]}}}}}),
               rule("a polynomial with omitted start/end, or curve 2 without t4, runs as a rise: give it direction 'rise'",
                    {"if": {"required": ["curve"], "properties": {"curve": {"anyOf": [MATCHED_POLYNOMIAL, SOLVED_T4]}}},
                     "then": {"properties": {"curve": {"properties": {"direction": {"const": "rise"}}}}}})],
        nested=False)  # nested, its five rules are past schemathesis's canonical form (service.specs.examples)
    type: Literal["move", "dwell"] = "move"
    span_deg: Span = Field(description="master angle of the segment")
    to: Finite | None = Field(None, description="absolute end position [unit]; null: the stroke that makes the "
                                                "velocity continuous at the segment's start")
    stroke: Finite | None = Field(None, description="signed travel [unit] (instead of to)")
    curve: ProgramCurveSpec | None = Field(None, description="the law, run from 0 to 1 over the segment; default "
                                                             "cycloid")
    match: Literal["acceleration", "jerk"] = Field(
        "acceleration", description="what a polynomial with omitted start/end meets there: s, v, a (quintic) or "
                                    "also j (septic)")

    _core: MotionSegment | None = PrivateAttr(None)

    @model_validator(mode="after")
    def _check(self) -> MotionSegmentSpec:
        check_segment(None, self.core())  # camcore's rules and sentences (422)
        return self

    def core(self) -> MotionSegment:
        """The segment as camcore takes it (``to`` given as null: solved); made once."""
        if self._core is None:
            to: float | Literal["solve"] | None = self.to
            if self.to is None and "to" in self.model_fields_set:
                to = SOLVE
            law = None if self.curve is None else self.curve.core()
            self._core = MotionSegment(self.span_deg, to=to, stroke=self.stroke, law=law, type=self.type,
                                       match=self.match)
        return self._core


class MotionSpec(Spec):
    """A machine cycle of ``period_deg`` of master angle: segments from master angle 0,
    positions in ``unit``. Spans add up to the period (within 1e-9 of it)."""

    model_config = examples(MAKINO_CYCLE, FEED_CYCLE)
    unit: Literal["mm", "deg"] = Field("mm", description="mm (translating follower), deg (swing, indexer output)")
    start: Finite = Field(0.0, description="position at master angle 0 [unit]")
    period_deg: Span = Field(360.0, description="master angle of one cycle")
    # no maxItems: the number of segments is a setting (CAMCORE_MAX_MOTION_SEGMENTS, 413)
    segments: list[MotionSegmentSpec] = Field(min_length=1)

    _core: CoreMotionSpec | None = PrivateAttr(None)

    def core(self) -> CoreMotionSpec:
        """The program as camcore takes it; made once (from its segments' own)."""
        if self._core is None:
            self._core = CoreMotionSpec([s.core() for s in self.segments], start=self.start,
                                        period_deg=self.period_deg, unit=self.unit)
        return self._core

    @model_validator(mode="after")
    def _check(self) -> MotionSpec:
        # camcore's rules and sentences (422): here the spans, the period, the start and the unit; each
        # segment's own rules were checked by its validator, at its place in the request
        check_program(self.core(), segments=False)
        return self


class MotionProgramRequest(Spec):
    model_config = examples({"motion": MAKINO_CYCLE, "samples": 361},
                            rules=[rule("give either samples or x_deg, not both", not_both("samples", "x_deg"))])
    motion: MotionSpec
    samples: Annotated[int, Field(ge=2), JSON_INTEGER] | None = Field(
        None, description="evenly over 0 … period_deg of master angle, both ends included; default 361")
    # minItems states the validator's rule in the schema (the validator gives the sentence)
    x_deg: Annotated[list[Annotated[float, Field(strict=True, allow_inf_nan=False, ge=-BIG, le=BIG)]],
                     Field(json_schema_extra={"minItems": 1})] | None = Field(
        None, description="master angles instead of samples (any, wrapped into the cycle)")
    speed_rpm: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=1e-6, le=BIG)] | None = Field(
        None, description="master shaft speed: adds time_s, v_per_s, a_per_s2, j_per_s3")

    @model_validator(mode="after")
    def _check(self) -> MotionProgramRequest:
        if self.samples is not None and self.x_deg is not None:
            raise ValueError("give either samples or x_deg, not both")
        if self.samples is None and self.x_deg is None:
            self.samples = 361
        if self.x_deg is not None and not self.x_deg:
            raise ValueError("x_deg must list at least one angle")
        return self


#: request examples of computeMotion (Swagger UI pre-fills the first)
MOTION_EXAMPLES: dict[str, Example] = {
    "makino": {"summary": "Makino's cutting-unit feed cam (1977, Fig. 7): T4 and the cutting stroke solved",
               "description": "rapid feed (curve 1, z = 0.9), cutting feed (curve 2: T4 ≈ 0.9569, stroke ≈ 13.37 mm), "
                              "rapid return (curve 48 backwards), dwell; C2 at every join",
               "value": {"motion": MAKINO_CYCLE, "samples": 361}},
    "feed": {"summary": "rest → constant-velocity feed → rest with matched quintics, at 30 rpm",
             "value": {"motion": FEED_CYCLE, "samples": 73, "speed_rpm": 30}},
    "angles": {"summary": "the same at given master angles, as CSV with ?format=csv",
               "value": {"motion": FEED_CYCLE, "x_deg": [0, 45, 90, 150, 240, 330]}},
}


# ----------------------------------------------------------------------------- answers
ResolvedSegmentAnswer = answer_model(ResolvedSegment, "ResolvedSegmentAnswer")
JoinAnswer = answer_model(Join, "JoinAnswer")
MotionCharacteristicsAnswer = answer_model(MotionCharacteristics, "MotionCharacteristicsAnswer")
MotionProgramAnswer = create_model(
    "MotionProgramAnswer",
    __base__=answer_model(MotionTable, "MotionProgramAnswer"),
    __doc__="Columns over x_deg (the time columns with speed_rpm only), the resolved segments, every join "
            "(the wrap-around at period_deg last) and the characteristic values over the cycle.",
    unit=(str, Field(description="the unit of positions: mm or deg")),
    period_deg=(float, Field(description="master angle of one cycle [deg]")),
    segments=(list[ResolvedSegmentAnswer], Field(description="each segment as resolved")),  # type: ignore[valid-type]
    joins=(list[JoinAnswer], Field(description="every join, the wrap-around last")),  # type: ignore[valid-type]
    characteristics=(MotionCharacteristicsAnswer, Field(description="extremes over the cycle")),
)
MotionProgramAnswer.__module__ = __name__
