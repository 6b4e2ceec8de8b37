"""What every request spec shares: the base class, bounded finite numbers, examples, rules.

Every number is bounded and finite; cross-field rules are checked in validators that
say, in a sentence, what is wrong (calling camcore's own checks where camcore has the
rule), and the OpenAPI document states the same rules where JSON Schema can (see
:func:`examples`). Sizes that depend on the configured limits (table samples, inverse list
lengths, Bezier degree, point counts) are checked by the service layer, which answers 413
naming the limit.
"""

from __future__ import annotations

import json
import sys
from collections.abc import Mapping, Sequence
from typing import Annotated, Any, Literal, Self, get_args

import numpy as np
from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, GetJsonSchemaHandler, PrivateAttr, field_validator
from pydantic.json_schema import JsonSchemaValue
from pydantic_core import CoreSchema, PydanticCustomError

#: magnitude bound for dimensionless inputs: far beyond any cam, small enough that
#: squares and products of a few of them stay finite in float64
BIG = 1e6


def _not_bool_or_text(value: object) -> object:
    """A JSON number only: pydantic's lax mode would read true as 1 and "5" as 5, which the
    OpenAPI document (type integer) refuses."""
    if isinstance(value, bool | str):
        raise PydanticCustomError("int_type", "Input should be a valid integer")  # pydantic's own words
    return value


#: Numbers of a request body are JSON numbers, as the document says: floats are strict (an
#: integer is a number, true and "5" are not); an integer field refuses true and "5" with this,
#: after its constraints: ``Annotated[int, Field(ge=1), JSON_INTEGER]`` (2.0 is an integer in
#: JSON Schema, and stays one)
JSON_INTEGER = BeforeValidator(_not_bool_or_text)
Finite = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=-BIG, le=BIG)]
Direction = Literal["rise", "return"]


class FieldRuleError(ValueError):
    """A rule between fields broken, raised by a model's validator and located at the field that
    breaks it (a path below the model, as a request field is): pydantic places a model
    validator's error at the model itself, so the 422 would name only the body, and the service's
    handler appends ``field`` to that location (service.errors)."""

    def __init__(self, message: str, *field: str | int):
        super().__init__(message)
        self.field = field


def _split_commas(values: object) -> object:
    """Query values, each possibly a comma-separated list: ?s=0.1&s=0.2,0.3 → [0.1, 0.2, 0.3]."""
    if isinstance(values, str):
        values = [values]
    if not isinstance(values, list):
        return values
    return [part.strip() for raw in values for part in str(raw).split(",") if part.strip()]


def _number(value: object) -> object:
    if isinstance(value, str):
        try:
            return float(value)
        except ValueError:
            raise ValueError(f"'{value[:40]}' is not a number") from None
    return value


#: a list of finite numbers in a query string: repeat the parameter or separate by commas
#: (a spreadsheet cell builds ?s=0.1,0.2 more easily than ?s=0.1&s=0.2); typed as numbers in
#: the OpenAPI document, so generated clients send numbers
QueryNumbers = Annotated[list[Annotated[Finite, BeforeValidator(_number)]], BeforeValidator(_split_commas)]


class DeferredModel(BaseModel):
    """The service's base model: its validator, serializer and schema are built when first used,
    not when the module is imported (FastAPI's adapter of a route's body or answer model defers
    with it), so a worker starts without building the ~150 models of operations it may never serve."""

    model_config = ConfigDict(defer_build=True)


def build_models(annotation: Any, _visiting: frozenset[type] = frozenset()) -> None:
    """Build the deferred models a type names (a model, or a union, list or Annotated of models),
    the models of their fields first: a model built after them takes their schemas as built, where
    it would make a field model's schema again inside every model that holds one (a curve spec is
    in dozens). A model that holds itself is built with the others inside it."""
    for arg in get_args(annotation):
        build_models(arg, _visiting)
    if (isinstance(annotation, type) and issubclass(annotation, BaseModel) and annotation not in _visiting
            and not annotation.__pydantic_complete__):
        for field in annotation.model_fields.values():
            build_models(field.annotation, _visiting | {annotation})
        annotation.model_rebuild()


def deferred_models() -> list[type[DeferredModel]]:
    """Every model made so far on :class:`DeferredModel` (built or not)."""
    found: list[type[DeferredModel]] = []
    stack = [DeferredModel]
    while stack:
        for sub in stack.pop().__subclasses__():
            if sub not in found:
                found.append(sub)
                stack.append(sub)
    return found


class DefaultsInDescriptions(DeferredModel):
    """In the OpenAPI document a field's default is stated in its description, not as ``default``.

    openapi-typescript (v7, default options) types a property that has a ``default`` as always
    present. For a request body that makes every defaulted field required in TypeScript (the
    README's own bodies would not compile); for an answer field that is left out when it does
    not apply, it promises a value that is not there. Such a field is optional: not listing it
    in ``required`` says so to every generator, and the description keeps the value for people.
    Single-value fields (the ``type`` tag of a curve spec) keep theirs: a tag is not a choice.
    """

    @classmethod
    def __get_pydantic_json_schema__(cls, core_schema: CoreSchema, handler: GetJsonSchemaHandler) -> JsonSchemaValue:
        schema = handler(core_schema)
        resolved = handler.resolve_ref_schema(schema)
        _describe_rules(resolved)
        for prop in resolved.get("properties", {}).values():
            if "default" not in prop or "const" in prop:
                continue
            default = prop.pop("default")
            if default is not None:  # None: "not given", already said by the null type
                text = default if isinstance(default, str) else json.dumps(default)
                description = prop.get("description", "").rstrip(".")
                prop["description"] = f"{description}. Default: {text}." if description else f"Default: {text}."
        return schema


#: the slowest camshaft or input speed a request may give [rpm] (a turn in 1.9 years): slower, a speed's
#: square in the inertia forces and the flywheel underflows, and a turn's time overflows (the indexers'
#: own bound since the first round)
SLOWEST_RPM = 1e-6
#: a camshaft or input speed [rpm]
SpeedRpm = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=SLOWEST_RPM, le=BIG)]
#: one camshaft turn [s]: 60/N of a speed within SpeedRpm's bounds (a subnormal time made the speed inf)
CycleTimeS = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=60.0 / BIG, le=60.0 / SLOWEST_RPM)]

#: the smallest normal double; a nonzero number below it in magnitude is subnormal
SMALLEST_NORMAL = sys.float_info.min
SUBNORMAL_RULE = (f"must be 0 or at least {SMALLEST_NORMAL!r} in magnitude (the smallest normal double): a subnormal "
                  "number has too few significant digits to compute with, and its reciprocal or square overflows")


def _subnormal_at(value: object) -> tuple[int, ...] | None:
    """Where a subnormal number sits in a field's value (() for the value itself, list indices
    below it), or None. Nested models check their own fields."""
    if isinstance(value, float):
        return () if 0.0 < abs(value) < SMALLEST_NORMAL else None
    if not isinstance(value, list | tuple) or not value:
        return None
    try:  # lists of numbers (200 000 of them, or points), at numpy's pace
        array = np.abs(np.asarray(value, dtype=np.float64))
    except (TypeError, ValueError):  # models, text, ragged lists: one by one
        for i, item in enumerate(value):
            inner = _subnormal_at(item)
            if inner is not None:
                return (i, *inner)
        return None
    hits = np.flatnonzero((array > 0.0) & (array < SMALLEST_NORMAL))
    if not hits.size:
        return None
    return tuple(int(i) for i in np.unravel_index(int(hits[0]), array.shape))


#: :data:`SUBNORMAL_RULE` in JSON Schema, on every number of a spec: not (nonzero and within ±SMALLEST_NORMAL)
NOT_SUBNORMAL: dict[str, Any] = {"not": {"exclusiveMinimum": -SMALLEST_NORMAL, "exclusiveMaximum": SMALLEST_NORMAL,
                                         "not": {"const": 0}}}


def _state_not_subnormal(schema: dict[str, Any]) -> None:
    """Add :data:`NOT_SUBNORMAL` to a field's number schemas (in place): the number itself, the
    items of its lists, the members of its unions (``null``); models state their own."""
    bounded = max(schema.get("minimum", -1.0), schema.get("exclusiveMinimum", -1.0)) >= SMALLEST_NORMAL
    if schema.get("type") == "number" and "not" not in schema and not bounded:  # a bound at 1 µm says it already
        schema.update(NOT_SUBNORMAL)
    for key in ("items", "additionalProperties"):
        if isinstance(schema.get(key), dict):
            _state_not_subnormal(schema[key])
    for key in ("anyOf", "oneOf", "prefixItems"):
        for member in schema.get(key, []):
            _state_not_subnormal(member)


class Spec(DefaultsInDescriptions):
    """A request model: unknown fields are refused, defaults are described (see the base class),
    and no number is subnormal (:data:`SUBNORMAL_RULE`)."""

    model_config = ConfigDict(extra="forbid")
    _cache_key: str | None = PrivateAttr(None)

    @classmethod
    def __get_pydantic_json_schema__(cls, core_schema: CoreSchema, handler: GetJsonSchemaHandler) -> JsonSchemaValue:
        schema = super().__get_pydantic_json_schema__(core_schema, handler)
        for prop in handler.resolve_ref_schema(schema).get("properties", {}).values():
            _state_not_subnormal(prop)
        return schema

    @field_validator("*", mode="after")
    @classmethod
    def _not_subnormal(cls, value: Any) -> Any:
        # 1e-310 in a length, speed or ratio passed every bound (> 0) and failed deep in camcore as
        # an overflow or a non-finite result that named no field (issue 34); no quantity of a cam
        # is that small, so it is refused here, at its field (and index)
        at = _subnormal_at(value)
        if at is not None:
            number = value
            for i in at:
                number = number[i]
            raise FieldRuleError(f"{number!r} {SUBNORMAL_RULE}", *at)
        return value

    def cache_key(self) -> str:
        """The spec's JSON with every field, defaults included: the key of the service's
        caches. Made once per spec (specs are not changed after validation): a request asks
        for it several times, and a 10 000-point spec takes ~1.5 ms to dump."""
        if self._cache_key is None:
            self._cache_key = self.model_dump_json()
        return self._cache_key

    def model_copy(self, *, update: Mapping[str, Any] | None = None, deep: bool = False) -> Self:
        copy = super().model_copy(update=update, deep=deep)
        if update:  # a changed copy is another spec: what was made from this one is made again
            for name, private in type(self).__private_attributes__.items():
                setattr(copy, name, private.get_default())
        return copy


def examples(*values: dict[str, Any], rules: Sequence[dict[str, Any]] = (), nested: bool = True) -> ConfigDict:
    """A model's complete, valid examples, for the OpenAPI document: tools that build a body
    from the schema (Swagger UI's "Try it out" when an operation has no example of its own)
    take the first, instead of combining field examples into a contradiction.

    ``rules`` are the model's cross-field rules as JSON Schema (made with :func:`rule`), so that
    a client or a schema-driven fuzzer builds only bodies the validators accept. The validators
    stay: they give the 422 its sentence. Rules JSON Schema cannot state (numbers compared with
    each other, geometry) are said in descriptions only.

    The rules sit under ``then`` of an ``if`` every instance of the model meets
    (:data:`RULES_IF`), as an ``allOf`` there: validators apply them to every body all the same,
    but Swagger UI names a schema's type from its own ``allOf``/``anyOf``/``oneOf`` and reads a
    model with its rules at the top as ``object | (any & any & …)``, while ``if``/``then`` it
    leaves out of the type. ``nested=False`` keeps them at the top, as an ``allOf`` of the model
    itself: schemathesis (the fuzz tests' generator) gives up on some models' rules one level
    down (its canonical form of their negations grows past its limit). Each rule's sentence is
    also listed in the model's description (:func:`_describe_rules`), where a reader sees it.

    Each rule is written with ``if``/``then``/``else`` and ``not`` only, at its top: the client
    generators read ``properties``, ``required``, ``oneOf`` and ``anyOf`` in an ``allOf`` member
    as part of the type (openapi-python-client merges them into the model, openapi-typescript
    turns them into unions that refuse valid bodies), and leave these keywords alone.
    """
    extra: dict[str, Any] = {"examples": list(values)}
    if rules and nested:
        extra |= {"if": RULES_IF, "then": {"allOf": list(rules)}}
    elif rules:
        extra["allOf"] = list(rules)
    return ConfigDict(json_schema_extra=extra)


#: the ``if`` of a model's rules: every instance of a model is an object
RULES_IF: dict[str, Any] = {"type": "object"}
#: the line before a model's rules in its description
RULES_HEADING = "Rules between fields (a body that breaks one is answered 422 with its sentence):"


def model_rules(schema: dict[str, Any]) -> list[dict[str, Any]]:
    """The cross-field rules stated in a model's JSON Schema (see :func:`examples`): the list
    itself, in the schema, or an empty one."""
    if schema.get("if") == RULES_IF:
        rules: list[dict[str, Any]] = schema["then"]["allOf"]
        return rules
    return schema.get("allOf", [])


def _describe_rules(schema: dict[str, Any]) -> None:
    """List the model's rules, by their sentences, at the end of its description (in place)."""
    sentences = [member["description"] for member in model_rules(schema) if "description" in member]
    if sentences:
        listed = "\n".join(f"- {sentence}" for sentence in sentences)
        schema["description"] = f"{schema.get('description', '').rstrip()}\n\n{RULES_HEADING}\n\n{listed}".lstrip()


# ----------------------------------------------------------------------------- cross-field rules
# Building blocks of the rules' JSON Schema. An optional field also takes null, and the
# validators read null as "not given", so "given" means present and not null.

def rule(description: str, schema: dict[str, Any]) -> dict[str, Any]:
    """One cross-field rule: its JSON Schema, with the validator's sentence as description."""
    return {"description": description, **schema}


def given(*names: str) -> dict[str, Any]:
    """Each of the fields is present and not null."""
    return {"required": list(names), "properties": {name: {"not": {"type": "null"}} for name in names}}


def absent(*names: str) -> dict[str, Any]:
    """None of the fields is given: each is missing or null."""
    return {"properties": {name: {"type": "null"} for name in names}}


def one_of_values(name: str, *values: Any, default: Any = None) -> dict[str, Any]:
    """The field is one of the values; a missing field counts as its default."""
    condition: dict[str, Any] = {"properties": {name: {"enum": list(values)}}}
    if default not in values:
        condition["required"] = [name]
    return condition


def all_of(*schemas: dict[str, Any]) -> dict[str, Any]:
    return {"allOf": list(schemas)}


def exactly_one(first: str, *rest: str) -> dict[str, Any]:
    """Exactly one of the fields is given."""
    if len(rest) == 1:
        return {"if": given(first), "then": absent(*rest), "else": given(*rest)}
    return {"if": given(first), "then": absent(*rest), "else": exactly_one(*rest)}


def together(first: str, second: str) -> dict[str, Any]:
    """Both fields are given, or neither."""
    return {"if": given(first), "then": given(second), "else": absent(second)}


def not_both(first: str, second: str) -> dict[str, Any]:
    return {"not": given(first, second)}
