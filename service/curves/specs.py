"""Curve specs (one per kind of camcore.curves.kinds.CURVE_KINDS), the curve requests and
answers."""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Annotated, Any, ClassVar, Literal, Union

from fastapi.openapi.models import Example
from pydantic import Field, GetJsonSchemaHandler, PrivateAttr, create_model, model_validator
from pydantic.json_schema import JsonSchemaValue
from pydantic_core import CoreSchema

from camcore.curves import Characteristics, Law
from camcore.curves.kinds import CURVE_KINDS, POLYNOMIAL_NAMES, CurveKind, Parameter
from camcore.curves.makino import MAKINO_BREAK_POINTS, MAKINO_SPECIAL, check_makino_parameters
from camcore.curves.polynomial import check_choice
from camcore.curves.targets import TARGETS, curve_4_vm_range, solve_targets
from camcore.curves.universal import check_break_points
from service.models import answer_model
from service.specs import (
    BIG,
    JSON_INTEGER,
    DeferredModel,
    Direction,
    Finite,
    Spec,
    absent,
    all_of,
    examples,
    given,
    not_both,
    rule,
)

#: the guide's worked examples (INDEXMAN technical guide): the MS curve, Makino's universal
#: curve with MS's break points (Makino 1977, No. 26)
MS_SPEC: dict[str, Any] = {"type": "named", "name": "MS"}
UNIVERSAL_MS_SPEC: dict[str, Any] = {"type": "universal", "t": [0, 0.125, 0.125, 0.5, 0.5, 0.875, 0.875, 1]}


# ----------------------------------------------------------------------------- curve specs
class CurveKindSpec(Spec):
    """A curve spec: its ``type`` is a kind of camcore.curves.kinds.CURVE_KINDS, its other
    fields (but ``direction``) are that kind's parameters."""

    _law: Law | None = PrivateAttr(None)
    if TYPE_CHECKING:  # every kind's spec has them (its tag, and the direction)
        type: str
        direction: Direction

    @classmethod
    def __get_pydantic_json_schema__(cls, core_schema: CoreSchema, handler: GetJsonSchemaHandler) -> JsonSchemaValue:
        # a request always takes a curve spec through the CurveSpec union, whose discriminator
        # needs the tag: in JSON, ``type`` is required (its default serves Python callers only)
        schema = super().__get_pydantic_json_schema__(core_schema, handler)
        target = handler.resolve_ref_schema(schema)
        target["required"] = ["type", *(name for name in target.get("required", []) if name != "type")]
        return schema

    def parameters(self) -> dict[str, Any]:
        """The kind's parameters, as camcore's builder takes them."""
        return {name: getattr(self, name) if not isinstance(getattr(self, name), Spec)
                else getattr(self, name).model_dump()
                for name in type(self).model_fields if name not in ("type", "direction")}

    def core(self) -> Law:
        """The spec in camcore's terms (made once: specs are not changed after validation)."""
        if self._law is None:
            self._law = Law(self.type, self.parameters(), self.direction)
        return self._law


class NamedCurveSpec(CurveKindSpec):
    """A catalog curve by id, alias or Makino number (case-insensitive)."""

    model_config = examples(MS_SPEC, {"type": "named", "name": "cycloid", "direction": "return"})
    type: Literal["named"] = "named"
    name: str = Field(min_length=1, max_length=80, examples=["MS"])
    direction: Direction = "rise"


MAKINO_PARAMETERS = ("z", "t4", "t1", "t3")
#: targets a special curve may give instead of its own parameters (camcore.curves.targets.TARGETS)
MAKINO_TARGETS = ("vm", "t1_over_t3", "v_ratio")
#: a curve's own bound on a parameter, beyond the field's: trapecloid II's T2 = (2 − 6·T1 + π·T1)/(2 + π)
#: must not fall below T1, which is T1 ≤ 1/4 (its T3 ≤ 1 − T1 holds to T1 ≤ π/(3π − 2) ≈ 0.41)
MAKINO_PARAMETER_BOUNDS: dict[int, dict[str, dict[str, float]]] = {36: {"t1": {"maximum": 0.25}}}
#: curve 4's largest Vm, at T1 = T3 = 0.5: 1/(1 − 2/π) (camcore.curves.targets); a smaller T1/T3 reaches less
CURVE_4_VM_MAX = curve_4_vm_range(1.0)[1]


def makino_rules(solvable: dict[int, tuple[str, ...]] | None = None) -> list[dict[str, Any]]:
    """camcore's table of Makino's numbers and the parameters each needs and takes, as rules;
    ``solvable``: parameters a curve may leave out where it is solved (a motion program)."""
    rules = []
    for number, special in sorted(MAKINO_SPECIAL.items()):
        takes = special.parameters + special.optional
        required = tuple(p for p in special.parameters if p not in (solvable or {}).get(number, ()))
        targets, replaced = TARGETS.get(number, ((), ()))
        needs = f"needs {', '.join(required)}" if required else f"takes {', '.join(takes)}"
        own = given(*required) if required else None
        if targets:  # the parameters, or the target (with its options) instead of them
            needs += f" (or {targets[0]}{''.join(', optional ' + t for t in targets[1:])} instead of " \
                     f"{', '.join(replaced)})"
            own = {"anyOf": [all_of(*([own] if own else []), absent(*targets)),
                             all_of(given(targets[0]), absent(*replaced))]}
        then = all_of(*([own] if own else []),
                      absent(*(p for p in (*MAKINO_PARAMETERS, *MAKINO_TARGETS) if p not in takes + targets)),
                      {"properties": MAKINO_PARAMETER_BOUNDS.get(number, {})})
        rules.append(rule(f"Makino curve {number} {needs} and no other parameter",
                          {"if": {"properties": {"number": {"const": number}}}, "then": then}))
    rules.append(rule("any other number is one of Makino's table 2 (or 11), which take no parameters",
                      {"if": {"properties": {"number": {"not": {"enum": sorted(MAKINO_SPECIAL)}}}},
                       "then": all_of({"properties": {"number": {"enum": sorted(MAKINO_BREAK_POINTS)}}},
                                      absent(*MAKINO_PARAMETERS, *MAKINO_TARGETS))}))
    return rules


class MakinoCurveSpec(CurveKindSpec):
    """Makino's curve by classification number, with its own parameters.

    1: ``z`` (0 < z ≤ 1) or ``v_ratio`` = V7/V3 = 1 − z; 2: ``t4`` (0 ≤ T4 < 1);
    4: ``t1``, ``t3`` (0 < T1 ≤ T3 ≤ 0.5), or the target ``vm`` with ``t1_over_t3``
    (default 0.25): the T1, T3 that give that Vm (Makino §5.1); 36: optional ``t1`` (0 < T1 ≤ 1/4);
    the numbers of Makino's table 2 and 11 take none.
    """

    model_config = examples({"type": "makino", "number": 4, "t1": 0.0625, "t3": 0.25}, {"type": "makino", "number": 26},
                            {"type": "makino", "number": 4, "vm": 1.27526},
                            {"type": "makino", "number": 1, "v_ratio": 0.1},
                            rules=makino_rules())
    type: Literal["makino"] = "makino"
    number: Annotated[int, Field(ge=1, le=99), JSON_INTEGER] = Field(examples=[4])
    z: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, le=1)] | None = None
    t4: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0, lt=1)] | None = None
    t1: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, le=0.5)] | None = Field(None, examples=[0.0625])
    t3: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, le=0.5)] | None = Field(None, examples=[0.25])
    vm: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=1, le=CURVE_4_VM_MAX)] | None = Field(
        None, description="curve 4: target peak velocity Vm instead of t1, t3 (1 < Vm ≤ 1/(1 − c/2), "
        "c = 2(1 − k) + (4/π)(2k − 1), k = t1_over_t3)", examples=[1.27526])
    t1_over_t3: Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, le=1)] | None = Field(
        None, description="curve 4 with vm: T1/T3 (omitted: 0.25, Makino §5.1)")
    v_ratio: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0, lt=1)] | None = Field(
        None, description="curve 1: V7/V3, cutting-feed over rapid-feed speed, instead of z (z = 1 − v_ratio)")
    direction: Direction = "rise"
    #: parameters a curve may leave out, by number: none here (a motion program solves curve 2's t4)
    solvable: ClassVar[dict[int, tuple[str, ...]]] = {}

    @model_validator(mode="after")
    def _check(self) -> MakinoCurveSpec:
        # the rules makino_rules states, checked here (422) before any size limit (413) is:
        # camcore's builder would check them only when the curve is built
        solved = self.solved_parameters()
        given = [name for name in MAKINO_PARAMETERS if solved.get(name) is not None]
        check_makino_parameters(self.number, given, self.solvable.get(self.number, ()))
        for name, bound in MAKINO_PARAMETER_BOUNDS.get(self.number, {}).items():
            value = getattr(self, name)
            if value is not None and value > bound["maximum"]:
                raise ValueError(f"{MAKINO_SPECIAL[self.number].name} needs {name} ≤ {bound['maximum']:g}, "
                                 f"got {value!r}")
        return self

    def solved_parameters(self) -> dict[str, float]:
        """The curve's own parameters given or solved from its target (camcore's solve_targets)."""
        return solved_parameters(self.parameters())


def solved_parameters(parameters: Mapping[str, Any]) -> dict[str, float]:
    """A makino law's own parameters, given or solved from its target (camcore's solve_targets)."""
    solved = solve_targets(parameters["number"], {name: parameters.get(name)
                                                   for name in (*MAKINO_PARAMETERS, *MAKINO_TARGETS)})
    return {name: value for name, value in solved.items() if value is not None}


class UniversalCurveSpec(CurveKindSpec):
    """Makino's universal cam curve directly: break points and end conditions."""

    model_config = examples(UNIVERSAL_MS_SPEC,
                            {"type": "universal", "t": [0, 0.2, 0.2, 0.4, 0.4, 0.7, 0.7, 1], "m": 0.5},
                            rules=[rule("give either m or v7, not both: with m fixed, V7 is a result",
                                        not_both("m", "v7"))])
    type: Literal["universal"] = "universal"
    t: list[Finite] = Field(min_length=8, max_length=8, description="break points T0 ≤ T1 ≤ … ≤ T7, T7 > T0",
                            examples=[[0, 0.125, 0.125, 0.5, 0.5, 0.875, 0.875, 1]])
    m: Finite | None = Field(None, description="Amm/Amp; omitted = solved so that the curve ends at V7")
    v0: Finite = 0.0
    v7: Finite | None = Field(None, description="end velocity when m is omitted (default V0)")
    s0: Finite = 0.0
    s7: Finite = 1.0
    direction: Direction = "rise"

    @model_validator(mode="after")
    def _check(self) -> UniversalCurveSpec:
        check_break_points(self.t)  # camcore's rule and sentence (422)
        if self.m is not None and self.v7 is not None:
            raise ValueError("give either m or v7, not both: with m fixed, V7 is a result")
        return self


class BoundaryConditions(Spec):
    """Values at one end of a polynomial law; ``s`` is required, the rest optional."""

    model_config = examples({"s": 0, "v": 0, "a": 0})
    s: Finite
    v: Finite | None = None
    a: Finite | None = None
    j: Finite | None = None


class PolynomialCurveSpec(CurveKindSpec):
    """A polynomial law by name, or the least-degree polynomial meeting end conditions."""

    model_config = examples({"type": "polynomial", "name": "3-4-5"},
                            {"type": "polynomial", "start": {"s": 0, "v": 0, "a": 0}, "end": {"s": 1, "v": 0, "a": 0}},
                            rules=[rule("give a polynomial name, or both start and end boundary conditions, not both",
                                        {"if": given("name"), "then": absent("start", "end"),
                                         "else": given("start", "end")})])
    type: Literal["polynomial"] = "polynomial"
    name: Literal[POLYNOMIAL_NAMES] | None = None  # type: ignore[valid-type]  # the registry's names
    start: BoundaryConditions | None = None
    end: BoundaryConditions | None = None
    direction: Direction = "rise"

    @model_validator(mode="after")
    def _check(self) -> PolynomialCurveSpec:
        check_choice(self.name, self.start, self.end)  # camcore's rule and sentence (422)
        return self


class BezierCurveSpec(CurveKindSpec):
    """Lift h [mm] over drive angle θ [deg] as a Bezier curve in the (θ, h) plane."""

    model_config = examples({"type": "bezier", "control_points": [[0, 0], [30, 0], [60, 10], [90, 10]]})
    type: Literal["bezier"] = "bezier"
    control_points: list[tuple[Annotated[float, Field(strict=True, allow_inf_nan=False, ge=-BIG, le=BIG)],
                               Annotated[float, Field(strict=True, allow_inf_nan=False, ge=-BIG, le=BIG)]]] = Field(
        min_length=2, description="[[theta_deg, h], ...], θ increasing along the curve (the lift a function of θ)",
        examples=[[[0, 0], [30, 0], [60, 10], [90, 10]]])
    direction: Direction = "rise"


class PointsCurveSpec(CurveKindSpec):
    """A measured or spreadsheet table (t, s), interpolated by a smooth spline."""

    model_config = examples({"type": "points", "t": [0, 10, 20, 30, 40], "s": [0, 1, 4, 7, 8]})
    type: Literal["points"] = "points"
    t: list[Finite] = Field(min_length=2, description="strictly increasing", examples=[[0, 10, 20, 30, 40]])
    s: list[Finite] = Field(min_length=2, description="as many as t", examples=[[0, 1, 4, 7, 8]])
    v: list[Finite] | None = Field(None, description="optional slopes ds/dt at the points, as many as t")
    direction: Direction = "rise"

    @model_validator(mode="after")
    def _check(self) -> PointsCurveSpec:
        if len(self.s) != len(self.t):
            raise ValueError(f"t and s must have the same length (t has {len(self.t)}, s has {len(self.s)})")
        if self.v is not None and len(self.v) != len(self.t):
            raise ValueError(f"v must have one slope per point ({len(self.t)}), got {len(self.v)}")
        for i in range(len(self.t) - 1):
            if not self.t[i + 1] > self.t[i]:
                raise ValueError(f"t must be strictly increasing, but t[{i + 1}] = {self.t[i + 1]} ≤ t[{i}] = {self.t[i]}")
        return self


# ----------------------------------------------------------------------------- one spec per kind
#: the kinds whose spec is written here (their rules need more than bounds on each parameter)
WRITTEN_SPECS: dict[str, type[CurveKindSpec]] = {
    "named": NamedCurveSpec, "makino": MakinoCurveSpec, "universal": UniversalCurveSpec,
    "polynomial": PolynomialCurveSpec, "bezier": BezierCurveSpec, "points": PointsCurveSpec}


def _field(parameter: Parameter) -> tuple[Any, Any]:
    """A pydantic field from a kind's declared parameter (camcore.curves.kinds.Parameter)."""
    given = {"ge": parameter.minimum, "le": parameter.maximum, "gt": parameter.above, "lt": parameter.below}
    bounds: dict[str, Any] = {k: v for k, v in given.items() if v is not None}
    if parameter.type is int:
        annotation: Any = Annotated[int, Field(**bounds), JSON_INTEGER]
    elif parameter.type is list:
        annotation = list[Annotated[float, Field(strict=True, allow_inf_nan=False, ge=-BIG, le=BIG)]]
    else:
        annotation = Annotated[float, Field(strict=True, allow_inf_nan=False, **{"ge": -BIG, "le": BIG, **bounds})]
    if parameter.required:
        return annotation, Field(description=parameter.description)
    return annotation | None, Field(parameter.default, description=parameter.description)


def kind_spec(kind: CurveKind) -> type[CurveKindSpec]:
    """The spec of a kind: written here, or made from the kind's declared parameters (a new law
    is then served by every operation that takes a curve with no line of the service changed)."""
    if kind.name in WRITTEN_SPECS:
        return WRITTEN_SPECS[kind.name]
    camel = "".join(part.capitalize() for part in kind.name.replace("_", "-").split("-"))
    fields: dict[str, Any] = {"type": (Literal[kind.name], kind.name), **{p.name: _field(p) for p in kind.fields},
                              "direction": (Direction, "rise")}
    model = create_model(f"{camel}CurveSpec", __base__=CurveKindSpec, __doc__=kind.description, **fields)
    model.model_config.update(examples({"type": kind.name, **kind.example}))  # read when it is built (deferred)
    model.__module__ = __name__
    return model


def curve_spec_union(specs: dict[str, type[CurveKindSpec]]) -> Any:
    """The request field of a curve: one of the kinds' specs, chosen by ``type``."""
    return Annotated[Union[tuple(specs.values())], Field(discriminator="type")]  # noqa: UP007  # made at run time


#: every kind of CURVE_KINDS, by name
KIND_SPECS: dict[str, type[CurveKindSpec]] = {name: kind_spec(kind) for name, kind in CURVE_KINDS.items()}

if TYPE_CHECKING:  # a type checker sees the base of the kinds' specs
    CurveSpec = Annotated[CurveKindSpec, Field(discriminator="type")]
else:
    CurveSpec = curve_spec_union(KIND_SPECS)


# ----------------------------------------------------------------------------- curve requests
class CharacteristicsRequest(Spec):
    model_config = examples({"curve": MS_SPEC})
    curve: CurveSpec


class TableRequest(Spec):
    model_config = examples({"curve": MS_SPEC, "samples": 101},
                            rules=[rule("give either samples or t, not both", not_both("samples", "t"))])
    curve: CurveSpec
    samples: Annotated[int, Field(ge=2), JSON_INTEGER] | None = Field(
        None, description="evenly spaced over [T0, T7], both ends included")
    # minItems states the validator's rule in the schema (the validator gives the sentence)
    t: Annotated[list[Finite], Field(json_schema_extra={"minItems": 1})] | None = Field(
        None, description="explicit times T instead of samples")

    @model_validator(mode="after")
    def _check(self) -> TableRequest:
        if self.samples is not None and self.t is not None:
            raise ValueError("give either samples or t, not both")
        if self.samples is None and self.t is None:
            self.samples = 101
        if self.t is not None and len(self.t) == 0:
            raise ValueError("t must list at least one time")
        return self


class InverseRequest(Spec):
    model_config = examples({"curve": MS_SPEC, "s": [0.1833], "method": "exact"})
    curve: CurveSpec
    s: list[Finite] = Field(min_length=1, description="displacements S to look up")
    method: Literal["exact", "table"] = "exact"
    table_step: Annotated[float, Field(strict=True, allow_inf_nan=False, ge=1e-4, le=0.5)] = Field(
        0.01, description="row step of the table (method = table)")
    table_decimals: Annotated[int, Field(ge=0, le=15), JSON_INTEGER] | None = Field(
        None, description="round the table as printed (the catalog prints 5)")


#: request examples of the POST operations (Swagger UI pre-fills the first); numbers from the guide
CHARACTERISTICS_EXAMPLES: dict[str, Example] = {
    "MS": {"summary": "MS (modified sine)",
           "description": "INDEXMAN MS: Vm = 1.76, Am = ±5.53, Qm = ±0.99", "value": {"curve": MS_SPEC}},
    "universal": {"summary": "Makino's universal curve with MS's break points",
                  "value": {"curve": UNIVERSAL_MS_SPEC}},
}
TABLE_EXAMPLES: dict[str, Example] = {
    "MS": {"summary": "MS, 101 rows (T = 0, 0.01, …, 1)",
           "description": "the catalog's MS table: row T = 0.30 has S = 0.17789",
           "value": {"curve": MS_SPEC, "samples": 101}},
    "universal": {"summary": "Makino's universal curve, 101 rows",
                  "value": {"curve": UNIVERSAL_MS_SPEC, "samples": 101}},
    "times": {"summary": "Makino curve 4 at given times",
              "value": {"curve": {"type": "makino", "number": 4, "t1": 0.0625, "t3": 0.25}, "t": [0.1, 0.2, 0.3]}},
}
INVERSE_EXAMPLES: dict[str, Example] = {
    "exact": {"summary": "T where S = 0.1833 on MS, exact",
              "description": "the guide's example: an output angle of 11° of 60° is S = 0.1833; T ≈ 0.3040",
              "value": {"curve": MS_SPEC, "s": [0.1833], "method": "exact"}},
    "table": {"summary": "the same by the catalog's table method",
              "description": "interpolation between rows T = 0.30 and 0.31 of the 5-decimal table: T = 0.304",
              "value": {"curve": MS_SPEC, "s": [0.1833], "method": "table", "table_decimals": 5}},
}


# ----------------------------------------------------------------------------- curve answers
class CurveTable(DeferredModel):
    t: list[float]
    s: list[float]
    v: list[float]
    a: list[float]
    j: list[float]
    q: list[float]


class InverseTable(DeferredModel):
    s: list[float]
    t: list[float]
    v: list[float]
    a: list[float]


CharacteristicsAnswer = answer_model(Characteristics, "CharacteristicsAnswer",
                                     "Characteristic values over [T0, T7] and the T of each.")

#: the answer of POST /v1/curves/characteristics: the values, and a makino spec's parameters as built
CurveCharacteristicsAnswer = create_model(
    "CurveCharacteristicsAnswer", __base__=CharacteristicsAnswer,
    __doc__="Characteristic values over [T0, T7] and the T of each; for a makino spec, its parameters as built.",
    parameters=(dict[str, float] | None, Field(
        None, description="makino spec: the parameters the curve was built with, those solved from a target "
        "among them (t1, t3 from vm; z from v_ratio)")))
CurveCharacteristicsAnswer.__module__ = __name__


class CatalogEntryAnswer(DeferredModel):
    id: str
    aliases: list[str]
    name: str
    family: str
    source: str
    makino_number: int | None
    parameters: dict[str, object]
    characteristics: CharacteristicsAnswer  # type: ignore[valid-type]  # derived answer model (service.models)


#: which torque coefficient is which: the catalog's and Makino's tables differ by the factor Am
QM_CONVENTIONS: dict[str, str] = {
    "qm": "qm_pos, qm_neg: Q = A·V/Am, the torque coefficient of the indexer catalog (the cycloid's is 1.30)",
    "qm_raw": "qm_raw_pos, qm_raw_neg: A·V, as Makino and most Japanese tables print (AV)max (the cycloid's is "
              "8.16)",
}


class CatalogAnswer(DeferredModel):
    curves: list[CatalogEntryAnswer]
    conventions: dict[str, str] = Field(description="which Qm is which (qm: A·V/Am; qm_raw: A·V)")
