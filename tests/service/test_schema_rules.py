"""The OpenAPI document states the request specs' cross-field rules, so "valid by the schema" means valid.

The specs' validators check rules between fields (a rise segment needs ``lift_mm``; stops or a
swing angle, not both; a Makino number with that curve's parameters...). The document states
each rule JSON Schema can say (service/specs.py: ``examples(..., rules=...)``), so a generated
client or a schema-driven fuzzer does not build bodies the service refuses.

- Each stated rule, one by one: a body that breaks it is invalid by the document and refused
  by the app (422, the validator's sentence), and valid by the document with just that rule
  taken out (so it is this rule the body breaks); a body that keeps it is valid and answered 200.
- A bounded generation run: schemathesis's generator (the one the fuzz tests use) builds bodies
  from each POST body schema; every one the document calls valid is accepted, except for the
  rules JSON Schema cannot state (:data:`NOT_STATABLE`, each with its reason).
"""

from __future__ import annotations

import copy
import functools
import json
import re
from collections import Counter
from collections.abc import Iterator
from typing import Any

import httpx
import hypothesis
import jsonschema
import numpy as np
import pytest
import referencing.jsonschema
import schemathesis
from hypothesis import HealthCheck, given
from referencing import Registry, Resource
from schemathesis import GenerationMode

from service.app import create_app
from service.specs import model_rules
from tests.service.apps import UNHURRIED

pytestmark = pytest.mark.anyio

APP = create_app(UNHURRIED)  # its answers are not the machine's speed (tests/service/apps.py)
DOCUMENT = APP.openapi()


def body_schema_name(path: str, document: dict[str, Any] = DOCUMENT) -> str:
    ref = document["paths"][path]["post"]["requestBody"]["content"]["application/json"]["schema"]["$ref"]
    return str(ref.rsplit("/", 1)[1])


def is_valid(body: object, path: str, document: dict[str, Any] = DOCUMENT) -> bool:
    """``body`` against the request body schema of ``POST path``, JSON Schema 2020-12 (OpenAPI 3.1)."""
    registry = Registry().with_resource(
        "urn:document", Resource.from_contents(document, default_specification=referencing.jsonschema.DRAFT202012))
    schema = {"$ref": f"urn:document#/components/schemas/{body_schema_name(path, document)}"}
    return jsonschema.Draft202012Validator(schema, registry=registry).is_valid(body)


def stated_rules(document: dict[str, Any] = DOCUMENT) -> dict[str, list[tuple[str, int]]]:
    """Each model rule's description → where it is: (schema name, index among its rules)."""
    found: dict[str, list[tuple[str, int]]] = {}
    for name, schema in document["components"]["schemas"].items():
        for index, member in enumerate(model_rules(schema)):
            if "description" in member:
                found.setdefault(member["description"], []).append((name, index))
    return found


def without(rule: str) -> dict[str, Any]:
    """The document with one rule taken out: a model rule by its description, or a keyword by its
    JSON pointer (``/components/schemas/...``)."""
    document = copy.deepcopy(DOCUMENT)
    if rule.startswith("/"):
        *parents, last = rule.strip("/").split("/")
        node: Any = document
        for part in parents:
            node = node[int(part)] if isinstance(node, list) else node[part]
        del node[int(last) if isinstance(node, list) else last]
        return document
    for name, index in sorted(stated_rules(document)[rule], key=lambda place: -place[1]):
        del model_rules(document["components"]["schemas"][name])[index]
    return document


# ----------------------------------------------------------------------------- bodies
MS = {"type": "named", "name": "MS"}
INDEXER = {"stops": 6, "indexing_angle_deg": 270, "speed_rpm": 60}
DISC = {"shape": "disc", "mass_kg": 50, "diameter_mm": 600}


def segments(lift: dict[str, float], rise: dict[str, Any] | None = None) -> list[dict[str, Any]]:
    """Rise 120°, dwell 60°, return 120°, dwell 60°, each moving segment with ``lift``."""
    return [{"type": "rise", "angle_deg": 120, **lift, **(rise or {})}, {"type": "dwell", "angle_deg": 60},
            {"type": "return", "angle_deg": 120, **lift}, {"type": "dwell", "angle_deg": 60}]


ROLLER = {"type": "roller", "roller_radius_mm": 10}
OSCILLATING = {"type": "roller", "roller_radius_mm": 10, "motion": "oscillating", "pivot_distance_mm": 100,
               "arm_length_mm": 80}


def profile(follower: dict[str, Any] = ROLLER, **fields: Any) -> dict[str, Any]:
    """A cam profile; segments rising 20 mm unless ``fields`` say otherwise."""
    spec = {"follower": follower, "base_radius_mm": 40, "segments": segments({"lift_mm": 20})}
    spec.update(fields)
    return {k: v for k, v in spec.items() if v is not None}


def curve(spec: dict[str, Any]) -> tuple[str, dict[str, Any]]:
    return "/v1/curves/characteristics", {"curve": spec}


def table(**fields: Any) -> tuple[str, dict[str, Any]]:
    return "/v1/curves/table", {"curve": MS, **fields}


def indexer(**fields: Any) -> tuple[str, dict[str, Any]]:
    spec = {**INDEXER, **fields}
    return "/v1/indexers/motion", {"indexer": {k: v for k, v in spec.items() if v is not None}, "samples": 11}


#: 6 stops as a timing chart: 60° over 270° of input (MS), dwell 90°
TIMING_CHART = {"unit": "deg", "segments": [{"span_deg": 270, "stroke": 60, "curve": MS},
                                            {"span_deg": 90, "type": "dwell"}]}
#: a closed program in mm: rise 20 mm, dwell, return, dwell
CLOSED_MM = {"segments": [{"span_deg": 120, "to": 20}, {"span_deg": 60, "type": "dwell"}, {"span_deg": 120, "to": 0},
                          {"span_deg": 60, "type": "dwell"}]}


def timing(**fields: Any) -> tuple[str, dict[str, Any]]:
    """An indexer driven by :data:`TIMING_CHART` at 60 rpm; ``fields`` add or replace (None removes)."""
    spec = {"speed_rpm": 60, "timing": TIMING_CHART, **fields}
    return "/v1/indexers/motion", {"indexer": {k: v for k, v in spec.items() if v is not None}, "samples": 11}


def load(**fields: Any) -> tuple[str, dict[str, Any]]:
    spec = {"parts": [DISC], **fields}
    return "/v1/indexers/sizing", {"indexer": INDEXER, "load": spec}


def cam(follower: dict[str, Any] = ROLLER, **fields: Any) -> tuple[str, dict[str, Any]]:
    return "/v1/profiles", {"profile": profile(follower, **fields), "samples": 37}


def base_circle(follower: dict[str, Any], **fields: Any) -> tuple[str, dict[str, Any]]:
    return "/v1/profiles/base-circle", {"profile": profile(follower), **fields}


def barrel(**fields: Any) -> tuple[str, dict[str, Any]]:
    """A barrel cam (translating, 30 mm rise) with ``fields`` changed; None removes a field."""
    spec: dict[str, Any] = {"pitch_radius_mm": 50, "roller_radius_mm": 10, "segments": segments({"lift_mm": 30}),
                            "samples": 9, "length_samples": 2}
    spec.update(fields)
    return "/v1/cams/barrel", {k: v for k, v in spec.items() if v is not None}


#: an oscillating barrel cam's arm and swing; motion programs of each unit
BARREL_ARM = {"follower": "oscillating", "arm_length_mm": 80, "initial_arm_angle_deg": -10,
              "segments": segments({"swing_deg": 20})}
MM_PROGRAM = {"unit": "mm", "segments": [{"span_deg": 180, "to": 20}, {"span_deg": 180, "to": 0}]}
DEG_PROGRAM = {"unit": "deg", "segments": [{"span_deg": 180, "to": 20}, {"span_deg": 180, "to": 0}]}


POLY = {"type": "polynomial"}


def program(feed: dict[str, Any] | None = None, **fields: Any) -> tuple[str, dict[str, Any]]:
    """Dwell, rise to 10 mm with a matched quintic (``feed`` replaces that segment), constant
    velocity, quintic, dwell, cycloid back: a motion program."""
    segments = [{"span_deg": 30, "type": "dwell"}, feed or {"span_deg": 60, "to": 10, "curve": POLY},
                {"span_deg": 120, "to": 50, "curve": {"type": "named", "name": "constant-velocity"}},
                {"span_deg": 60, "to": 60, "curve": POLY}, {"span_deg": 30, "type": "dwell"}, {"span_deg": 60, "to": 0}]
    return "/v1/motions", {"motion": {"segments": segments}, "samples": 11, **fields}


def cutting_feed(curve_2: dict[str, Any], to: float | None = None) -> tuple[str, dict[str, Any]]:
    """Makino's cutting-unit cycle (1977, §5.3) with ``curve_2`` as the cutting feed."""
    segments = [{"span_deg": 60, "to": 40, "curve": {"type": "makino", "number": 1, "z": 0.9}},
                {"span_deg": 120, "to": to, "curve": curve_2},
                {"span_deg": 90, "to": 0, "curve": {"type": "named", "name": "48", "direction": "return"}},
                {"span_deg": 90, "type": "dwell"}]
    return "/v1/motions", {"motion": {"segments": segments}, "samples": 11}


def dynamics(follower: dict[str, Any] = ROLLER, lift: dict[str, float] | None = None,
             **fields: Any) -> tuple[str, dict[str, Any]]:
    """A follower on the cam of :func:`profile` at 300 rpm; ``fields`` give its load (None: left out)."""
    body = {"profile": profile(follower, segments=segments(lift or {"lift_mm": 20})), "speed_rpm": 300,
            "samples": 11, **fields}
    return "/v1/profiles/dynamics", {k: v for k, v in body.items() if v is not None}


TRANSLATING_LOAD = {"mass_kg": 0.5, "spring_rate_n_mm": 2, "preload_n": 30}
OSCILLATING_LOAD = {"inertia_kgm2": 0.004, "spring_rate_nm_rad": 20, "preload_nm": 3}
def vibration(**fields: Any) -> tuple[str, dict[str, Any]]:
    return "/v1/curves/vibration", {"curve": MS, **fields}


def indexer_vibration(**fields: Any) -> tuple[str, dict[str, Any]]:
    return "/v1/indexers/vibration", {"indexer": INDEXER, "stiffness_nm_rad": 2e5, "tolerance_arcsec": 10, **fields}


TAU_RANGE = {"start": 0.5, "stop": 5, "samples": 10}


#: a machine: one translating roller cam, and a 6-stop table at 200° (service/machines/specs.py)
MACHINE_CAM = {"profile": profile(), "mass_kg": 0.5, "spring_rate_n_mm": 2, "preload_n": 30}
MACHINE_TABLE = {"indexer": {"stops": 6, "indexing_angle_deg": 90}, "load": {"parts": [DISC]}}


def machine(axes: list[dict[str, Any]] | None = None, **fields: Any) -> tuple[str, dict[str, Any]]:
    body = {"master": {"speed_rpm": 60}, "samples": 11,
            "axes": axes or [{"name": "feed", "plate_cam": MACHINE_CAM},
                             {"name": "table", "phase_deg": 200, "indexer": MACHINE_TABLE}], **fields}
    return "/v1/machines", {k: v for k, v in body.items() if v is not None}


def design(follower: dict[str, Any] = ROLLER, lift: dict[str, float] | None = None,
           **fields: Any) -> tuple[str, dict[str, Any]]:
    """The base radius of the cam of :func:`profile` designed for a 30° pressure angle; ``fields`` add or
    replace (None removes)."""
    body = {"follower": follower, "segments": segments(lift or {"lift_mm": 20}),
            "limits": {"max_pressure_angle_deg": 30}, "free": {"base_radius_mm": [10, 200]}, **fields}
    return "/v1/profiles/design", {k: v for k, v in body.items() if v is not None}


#: rule → (bodies that keep it, [(a body that breaks it, words of the app's 422)]).
#: A model rule is named by its description in the document, a keyword by its JSON pointer.
#: a parallel cam of two plates (a toolpath's plate numbers them)
TWO_PLATES = {"stops": 4, "plates": 2, "center_distance_mm": 100, "roller_pitch_radius_mm": 60, "roller_radius_mm": 12,
              "indexing_angle_deg": 120, "samples": 61}

RULES: dict[str, tuple[list[tuple[str, dict[str, Any]]], list[tuple[tuple[str, dict[str, Any]], str]]]] = {
    # curve specs: the tag of the CurveSpec union is required (its default serves Python callers)
    "/components/schemas/NamedCurveSpec/required/0": (
        [curve(MS)], [(curve({"name": "MS"}), "Unable to extract tag using discriminator 'type'")]),
    "/components/schemas/PointsCurveSpec/required/0": (
        [curve({"type": "points", "t": [0, 1], "s": [0, 1]})],
        [(curve({"t": [0, 1], "s": [0, 1]}), "Unable to extract tag using discriminator 'type'")]),
    "Makino curve 1 needs z (or v_ratio instead of z) and no other parameter": (
        [curve({"type": "makino", "number": 1, "z": 0.5}), curve({"type": "makino", "number": 1, "v_ratio": 0.1})],
        [(curve({"type": "makino", "number": 1}), "Makino curve 1 needs z"),
         (curve({"type": "makino", "number": 1, "z": 0.9, "v_ratio": 0.1}), "give v_ratio or z, not both"),
         (curve({"type": "makino", "number": 1, "z": 0.5, "t4": 0.5}), "Makino curve 1 takes no parameter t4")]),
    "Makino curve 2 needs t4 and no other parameter": (
        [curve({"type": "makino", "number": 2, "t4": 0.5})],
        [(curve({"type": "makino", "number": 2, "t4": None}), "Makino curve 2 needs t4")]),
    "Makino curve 4 needs t1, t3 (or vm, optional t1_over_t3 instead of t1, t3) and no other parameter": (
        [curve({"type": "makino", "number": 4, "t1": 0.0625, "t3": 0.25}),
         curve({"type": "makino", "number": 4, "vm": 1.27526}),
         curve({"type": "makino", "number": 4, "vm": 2.5, "t1_over_t3": 1})],
        [(curve({"type": "makino", "number": 4, "t1": 0.0625}), "Makino curve 4 needs t3"),
         (curve({"type": "makino", "number": 4, "vm": 1.3, "t3": 0.25}), "give vm or t1, t3, not both"),
         (curve({"type": "makino", "number": 4, "t1_over_t3": 0.25}), "t1_over_t3 goes with vm"),
         (curve({"type": "makino", "number": 4, "vm": 1.3, "v_ratio": 0.1}), "takes no target v_ratio"),
         (curve({"type": "makino", "number": 4, "t1": 0.0625, "t3": 0.25, "z": 1}), "takes no parameter z")]),
    "Makino curve 36 takes t1 and no other parameter": (
        # T1 = 1/4 is the bound itself: T2 = (2 − 6·T1 + π·T1)/(2 + π) = 1/4 = T1
        [curve({"type": "makino", "number": 36}), curve({"type": "makino", "number": 36, "t1": 0.25})],
        [(curve({"type": "makino", "number": 36, "t1": 0.2501}), "trapecloid II needs"),
         (curve({"type": "makino", "number": 36, "t3": 0.25}), "Makino curve 36 takes no parameter t3")]),
    "any other number is one of Makino's table 2 (or 11), which take no parameters": (
        [curve({"type": "makino", "number": 26}), curve({"type": "makino", "number": 11})],
        [(curve({"type": "makino", "number": 3}), "Makino curve number 3 is not one of"),
         (curve({"type": "makino", "number": 26, "z": 0.5}), "Makino curve 26 takes no parameter z"),
         (curve({"type": "makino", "number": 26, "vm": 1.5}), "Makino curve 26 takes no target vm")]),
    "a makino spec varies z, t4, t1, t3, vm, t1_over_t3, v_ratio": (
        [("/v1/curves/characteristics/sweep", {"curve": {"type": "makino", "number": 4, "t1": 0.05, "t3": 0.2},
                                               "vary": {"t3": [0.2, 0.3]}})],
        [(("/v1/curves/characteristics/sweep", {"curve": {"type": "makino", "number": 4, "t1": 0.05, "t3": 0.2},
                                                "vary": {"m": [0.5]}}), "a makino spec varies")]),
    "a universal spec varies t0, t1, t2, t3, t4, t5, t6, t7, m, v0, v7, s0, s7": (
        [("/v1/curves/characteristics/sweep", {"curve": {"type": "universal", "t": [0, 0.1, 0.1, 0.3, 0.5, 0.75, 0.75, 1]},
                                               "vary": {"t3": [0.2, 0.3]}})],
        [(("/v1/curves/characteristics/sweep", {"curve": {"type": "universal", "t": [0, 0.1, 0.1, 0.3, 0.5, 0.75, 0.75, 1]},
                                                "vary": {"vm": [1.2]}}), "a universal spec varies")]),
    "give either m or v7, not both: with m fixed, V7 is a result": (
        [curve({"type": "universal", "t": [0, 0.2, 0.2, 0.4, 0.4, 0.7, 0.7, 1], "m": 0.5})],
        [(curve({"type": "universal", "t": [0, 0.2, 0.2, 0.4, 0.4, 0.7, 0.7, 1], "m": 0.5, "v7": 0}),
          "give either m or v7, not both")]),
    "give a polynomial name, or both start and end boundary conditions, not both": (
        [curve({"type": "polynomial", "name": "3-4-5"}),
         curve({"type": "polynomial", "start": {"s": 0, "v": 0, "a": 0}, "end": {"s": 1, "v": 0, "a": 0}})],
        [(curve({"type": "polynomial"}), "give a polynomial name, or both start and end boundary conditions"),
         (curve({"type": "polynomial", "start": {"s": 0}}), "give a polynomial name, or both start and end"),
         (curve({"type": "polynomial", "name": "3-4-5", "end": {"s": 1}}),
          "give a polynomial name or boundary conditions, not both")]),
    "give either samples or t, not both": (
        [table(t=[0.5]), table(samples=11)], [(table(samples=11, t=[0.5]), "give either samples or t, not both")]),
    "/components/schemas/TableRequest/properties/t/anyOf/0/minItems": (
        [table(t=[0.5])], [(table(t=[]), "t must list at least one time")]),
    # residual vibration
    "give either tau (a list of values) or tau_range: one of them, not both": (
        [vibration(tau=[1, 2]), vibration(tau_range=TAU_RANGE)],
        [(vibration(), "give either tau (a list of values) or tau_range"),
         (vibration(tau=[1], tau_range=TAU_RANGE), "give either tau (a list of values) or tau_range")]),
    "/components/schemas/VibrationRequest/properties/tau/anyOf/0/minItems": (
        [vibration(tau=[1])], [(vibration(tau=[]), "tau must list at least one value")]),
    "give the load's inertia as inertia_kgm2 or as load: one of them, not both": (
        [indexer_vibration(inertia_kgm2=2.25), indexer_vibration(load={"parts": [DISC]})],
        [(indexer_vibration(), "give the load's inertia as inertia_kgm2 or as load"),
         (indexer_vibration(inertia_kgm2=2.25, load={"parts": [DISC]}), "give the load's inertia as inertia_kgm2")]),
    "the residual vibration takes an indexer with one curve (stops or swing_angle_deg, indexing_angle_deg, curve), "
    "not a timing chart": (
        [indexer_vibration(inertia_kgm2=2.25)],
        [(("/v1/indexers/vibration", {"indexer": {"speed_rpm": 60, "timing": TIMING_CHART}, "inertia_kgm2": 2.25,
                                      "stiffness_nm_rad": 2e5, "tolerance_arcsec": 10}), "not a timing chart")]),
    # indexer and load
    "give exactly one of stops (n) and swing_angle_deg (ψ, oscillating units)": (
        [indexer(), indexer(stops=None, swing_angle_deg=60), timing()],
        [(indexer(swing_angle_deg=60), "give exactly one of stops (n) and swing_angle_deg"),
         (indexer(stops=None), "give exactly one of stops (n) and swing_angle_deg")]),
    "a timing chart replaces stops, swing_angle_deg, indexing_angle_deg, dwells and curve: give none of them": (
        [timing(), timing(cycle_time_s=1.5, speed_rpm=None)],
        [(timing(stops=6), "a timing chart replaces stops"), (timing(dwells=1), "a timing chart replaces stops"),
         (timing(indexing_angle_deg=270), "a timing chart replaces stops"),
         (timing(curve=MS), "a timing chart replaces stops")]),
    "indexing_angle_deg (θh) is needed without a timing chart": (
        [indexer()], [(indexer(indexing_angle_deg=None), "indexing_angle_deg (θh) is needed")]),
    "a timing chart gives the output angle in deg over one input turn (period_deg 360)": (
        [timing()],
        [(timing(timing={**TIMING_CHART, "unit": "mm"}), "a timing chart gives the output angle in 'deg'"),
         (timing(timing={k: v for k, v in TIMING_CHART.items() if k != "unit"}),
          "a timing chart gives the output angle in 'deg'"),
         (timing(timing={**TIMING_CHART, "period_deg": 720, "segments": [
             {"span_deg": 540, "stroke": 60, "curve": MS}, {"span_deg": 180, "type": "dwell"}]}),
          "a timing chart spans one input turn")]),
    "input_angle_origin dwell-centre is for a single-curve indexer: a timing chart starts at its own 0°": (
        [timing(input_angle_origin="index-start"), indexer(input_angle_origin="dwell-centre")],
        [(timing(input_angle_origin="dwell-centre"), "a timing chart starts at its own 0°")]),
    "give exactly one of speed_rpm (N) and cycle_time_s (t0 = 60/(N·z))": (
        [indexer(speed_rpm=None, cycle_time_s=2)],
        [(indexer(cycle_time_s=1), "give exactly one of speed_rpm (N) and cycle_time_s"),
         (indexer(speed_rpm=None), "give exactly one of speed_rpm (N) and cycle_time_s")]),
    "a disc part needs diameter_mm": (
        [load(parts=[DISC])], [(load(parts=[{"shape": "disc", "mass_kg": 5}]), "a disc part needs diameter_mm")]),
    "a ring part needs diameter_mm, inner_diameter_mm": (
        [load(parts=[{"shape": "ring", "mass_kg": 5, "diameter_mm": 300, "inner_diameter_mm": 200}]),
         load(parts=[{"shape": "point", "mass_kg": 5, "offset_mm": 100}])],
        [(load(parts=[{"shape": "ring", "mass_kg": 5, "diameter_mm": 300}]), "a ring part needs inner_diameter_mm"),
         (load(parts=[{"shape": "ring", "mass_kg": 5, "inner_diameter_mm": 200}]), "a ring part needs diameter_mm")]),
    "a block part needs a_mm, b_mm": (
        [load(parts=[{"shape": "block", "mass_kg": 5, "a_mm": 300, "b_mm": 200}])],
        [(load(parts=[{"shape": "block", "mass_kg": 5, "a_mm": 300, "b_mm": None}]), "a block part needs b_mm")]),
    "friction_coefficient and friction_radius_mm go together (Tf = μ·m·g·R)": (
        [load(friction_coefficient=0.1, friction_radius_mm=200)],
        [(load(friction_coefficient=0.1), "friction_coefficient and friction_radius_mm go together"),
         (load(friction_radius_mm=200), "friction_coefficient and friction_radius_mm go together")]),
    "give friction as friction_coefficient with friction_radius_mm, or friction_torque_nm, not both": (
        [load(friction_torque_nm=10)],
        [(load(friction_coefficient=0.1, friction_radius_mm=200, friction_torque_nm=10),
          "give friction as friction_coefficient with friction_radius_mm, or friction_torque_nm, not both")]),
    "friction_coefficient needs parts with mass_kg (friction torque μ·m·g·R uses the parts' masses)": (
        [load(friction_coefficient=0.1, friction_radius_mm=200)],
        [(load(parts=[], inertia_kgm2=2, friction_coefficient=0.1, friction_radius_mm=200),
          "friction_coefficient needs parts with mass_kg")]),
    "accuracy_arc_seconds and accuracy_radius_mm go together": (
        [load(accuracy_arc_seconds=30, accuracy_radius_mm=200)],
        [(load(accuracy_arc_seconds=30), "accuracy_arc_seconds and accuracy_radius_mm go together")]),
    # follower, segments, profile
    "a roller follower needs a roller radius > 0": (
        [cam(ROLLER)],
        [(cam({"type": "roller"}), "A roller follower needs a roller radius > 0"),
         (cam({"type": "roller", "roller_radius_mm": 0}), "A roller follower needs a roller radius > 0")]),
    "an oscillating follower needs pivot_distance_mm > 0": (
        [cam(OSCILLATING, segments=segments({"swing_deg": 20}))],
        [(cam({**OSCILLATING, "pivot_distance_mm": None}, segments=segments({"swing_deg": 20})),
          "An oscillating follower needs pivot_distance_mm > 0")]),
    "an oscillating follower other than a flat-faced one needs arm_length_mm > 0": (
        [cam({"type": "flat-faced", "motion": "oscillating", "pivot_distance_mm": 100}, base_radius_mm=60,
             segments=segments({"swing_deg": 5}))],
        [(cam({**OSCILLATING, "arm_length_mm": None}, segments=segments({"swing_deg": 20})),
          "An oscillating follower needs arm_length_mm > 0"),
         (cam({"type": "knife-edge", "motion": "oscillating", "pivot_distance_mm": 100},
              segments=segments({"swing_deg": 20})), "An oscillating follower needs arm_length_mm > 0")]),
    "a rise or return segment needs lift_mm (or swing_deg for an oscillating follower)": (
        [cam(ROLLER)],
        [(cam(ROLLER, segments=segments({}, rise={"lift_mm": 20})), "a return segment needs lift_mm"),
         (cam(ROLLER, segments=segments({"lift_mm": None}, rise={"lift_mm": 20})), "a return segment needs lift_mm")]),
    "give lift_mm or swing_deg, not both": (
        [cam(OSCILLATING, segments=segments({"swing_deg": 20}))],
        [(cam(OSCILLATING, segments=segments({"swing_deg": 20}, rise={"lift_mm": 0})),
          "give lift_mm or swing_deg, not both")]),
    "a segment's type sets its direction: give the rise law with direction 'rise'": (
        [cam(ROLLER, segments=segments({"lift_mm": 20}, rise={"curve": {**MS, "direction": "rise"}}))],
        [(cam(ROLLER, segments=segments({"lift_mm": 20}, rise={"curve": {**MS, "direction": "return"}})),
          "a segment's type sets its direction")]),
    "give the lift as segments, as one lift curve (bezier or points) or as a motion program": (
        [cam(ROLLER, segments=None, lift={"type": "points", "t": [0, 180, 360], "s": [0, 10, 0]}),
         cam(ROLLER, segments=None, motion=CLOSED_MM)],
        [(cam(ROLLER, segments=None), "give the lift as segments, as one lift curve"),
         (cam(ROLLER, lift={"type": "points", "t": [0, 180, 360], "s": [0, 10, 0]}),
          "give the lift as segments, as one lift curve"),
         (cam(ROLLER, motion=CLOSED_MM), "give the lift as segments, as one lift curve")]),
    "an oscillating follower's motion program is in deg (of swing)": (
        [cam(OSCILLATING, segments=None, motion={**CLOSED_MM, "unit": "deg"})],
        [(cam(OSCILLATING, segments=None, motion=CLOSED_MM), "an oscillating follower's motion program is in deg"),
         (cam(OSCILLATING, segments=None, motion={**CLOSED_MM, "unit": "mm"}),
          "an oscillating follower's motion program is in deg")]),
    "a translating follower's motion program is in mm": (
        [cam(ROLLER, segments=None, motion={**CLOSED_MM, "unit": "mm"})],
        [(cam(ROLLER, segments=None, motion={**CLOSED_MM, "unit": "deg"}),
          "a translating follower's motion program is in mm")]),
    "an oscillating follower's lift is swing_deg, not lift_mm": (
        [cam(OSCILLATING, segments=segments({"swing_deg": 20}))],
        [(cam(OSCILLATING, segments=segments({"lift_mm": 20})), "an oscillating follower's lift is swing_deg")]),
    "a translating follower's lift is lift_mm, not swing_deg": (
        [cam(ROLLER)],
        [(cam(ROLLER, segments=segments({"swing_deg": 20})), "a translating follower's lift is lift_mm")]),
    "give either samples or cam_angle_deg, not both": (
        [("/v1/profiles", {"profile": profile(), "cam_angle_deg": [10]}),
         ("/v1/profiles.step", {"profile": profile(), "solid": {"thickness_mm": 5}, "cam_angle_deg": [10]})],
        [(("/v1/profiles", {"profile": profile(), "cam_angle_deg": [10], "samples": 5}),
          "give either samples or cam_angle_deg, not both"),
         # the solids' own body (SolidRequest) keeps the rule it inherits, and states it (issue 34)
         (("/v1/profiles.stl", {"profile": profile(), "solid": {"thickness_mm": 5}, "cam_angle_deg": [10], "samples": 5}),
          "give either samples or cam_angle_deg, not both")]),
    "/components/schemas/ProfileRequest/properties/cam_angle_deg/anyOf/0/minItems": (
        [("/v1/profiles", {"profile": profile(), "cam_angle_deg": [10]})],
        [(("/v1/profiles", {"profile": profile(), "cam_angle_deg": []}), "cam_angle_deg must list at least one angle")]),
    # motion programs
    "Makino curve 2 takes t4 and no other parameter": (
        [cutting_feed({"type": "makino", "number": 2}), cutting_feed({"type": "makino", "number": 2, "t4": 0.9}, 53)],
        [(cutting_feed({"type": "makino", "number": 2, "z": 0.5}), "Makino curve 2 takes no parameter z")]),
    "give a polynomial name or boundary conditions, not both": (
        [program(), program({"span_deg": 60, "to": 10, "curve": {"type": "polynomial", "name": "3-4-5"}})],
        [(program({"span_deg": 60, "to": 10, "curve": {"type": "polynomial", "name": "3-4-5", "start": {"s": 0}}}),
          "give a polynomial name or boundary conditions, not both")]),
    "with one end omitted, the given one is normalised: s = 0 at the start, 1 at the end (a law in a program runs "
    "from s = 0 to 1)": (
        [program({"span_deg": 60, "to": 10, "curve": {"type": "polynomial", "start": {"s": 0, "v": 0, "a": 0}}})],
        [(program({"span_deg": 60, "to": 10, "curve": {"type": "polynomial", "start": {"s": 0.5}}}),
          "a law in a program runs from s = 0 to 1")]),
    "a move gives to (absolute; null = solved) or stroke (relative), not both": (
        [program({"span_deg": 60, "stroke": 10, "curve": POLY})],
        [(program({"span_deg": 60, "to": 10, "stroke": 10, "curve": POLY}), ("give to (absolute; null = solved) or "
                                                                             "stroke (relative), not both")),
         (program({"span_deg": 60, "curve": POLY}), "a move needs to (an absolute end position, or null to solve it)")]),
    "a dwell holds its position; give it no to, stroke or curve": (
        [program({"span_deg": 60, "type": "dwell"}, samples=None)],
        [(program({"span_deg": 60, "type": "dwell", "curve": POLY}), "a dwell holds its position"),
         (program({"span_deg": 60, "type": "dwell", "to": None}), "a dwell holds its position")]),
    "match: jerk applies to a polynomial law with omitted start or end": (
        [program({"span_deg": 60, "to": 10, "curve": POLY, "match": "jerk"})],
        [(program({"span_deg": 60, "to": 10, "match": "jerk"}), "match applies to a polynomial law"),
         (program({"span_deg": 60, "to": 10, "match": "jerk", "curve": {"type": "polynomial", "name": "3-4-5"}}),
          "match applies to a polynomial law")]),
    "to: null solves the stroke from the law's start velocity, so the law must be given in full (not matched to its "
    "neighbours)": (
        [cutting_feed({"type": "makino", "number": 2})],
        [(cutting_feed(POLY), "so the law must be given in full"),
         (cutting_feed({"type": "universal", "t": [0, 0, 0, 0, 0.5, 1, 1, 1], "v7": 0}),
          "so the law must be given in full")]),
    "a polynomial with omitted start/end, or curve 2 without t4, runs as a rise: give it direction 'rise'": (
        [program({"span_deg": 60, "to": 10, "curve": {"type": "polynomial", "direction": "rise"}})],
        [(program({"span_deg": 60, "to": 10, "curve": {"type": "polynomial", "direction": "return"}}),
          "give it direction 'rise'"),
         (cutting_feed({"type": "makino", "number": 2, "direction": "return"}), "give it direction 'rise'")]),
    "give either samples or x_deg, not both": (
        [program(samples=None, x_deg=[10])], [(program(x_deg=[10]), "give either samples or x_deg, not both")]),
    "/components/schemas/MotionProgramRequest/properties/x_deg/anyOf/0/minItems": (
        [program(samples=None, x_deg=[10])], [(program(samples=None, x_deg=[]), "x_deg must list at least one angle")]),
    # follower dynamics
    "a translating follower's load is mass_kg and spring_rate_n_mm (with preload_n, external_force_n, damping_n_s_mm), "
    "not the torques of an oscillating one": (
        [dynamics(**TRANSLATING_LOAD), dynamics({"type": "knife-edge"}, mass_kg=1, spring_rate_n_mm=1)],
        [(dynamics(mass_kg=1), "(missing spring_rate_n_mm)"),
         (dynamics(**TRANSLATING_LOAD, preload_nm=3), "(preload_nm given)"),
         (dynamics(**TRANSLATING_LOAD, damping_nm_s_rad=0.1), "(damping_nm_s_rad given)")]),
    "an oscillating follower's load is inertia_kgm2 and spring_rate_nm_rad (with preload_nm, external_torque_nm, "
    "damping_nm_s_rad), not the forces of a translating one": (
        [dynamics(OSCILLATING, {"swing_deg": 20}, **OSCILLATING_LOAD)],
        [(dynamics(OSCILLATING, {"swing_deg": 20}, inertia_kgm2=0.004), "(missing spring_rate_nm_rad)"),
         (dynamics(OSCILLATING, {"swing_deg": 20}, **OSCILLATING_LOAD, external_force_n=3),
          "(external_force_n given)")]),
    "roller (width and materials, for the contact stress) needs a roller follower": (
        [dynamics(**TRANSLATING_LOAD, roller={"width_mm": 10})],
        [(dynamics({"type": "flat-faced"}, **TRANSLATING_LOAD, roller={"width_mm": 10}),
          "needs a roller follower, not a flat-faced follower"),
         (dynamics({"type": "knife-edge"}, **TRANSLATING_LOAD, roller={"width_mm": 10}),
          "needs a roller follower, not a knife-edge follower")]),
    "give max_pressure_angle_deg and/or min_radius_of_curvature_mm (a flat-faced follower may give neither)": (
        [base_circle(ROLLER, max_pressure_angle_deg=30), base_circle({"type": "flat-faced"})],
        [(base_circle(ROLLER), "give max_pressure_angle_deg and/or min_radius_of_curvature_mm")]),
    # toolpaths
    "a groove is the track of a roller: give a roller follower": (
        [("/v1/profiles/toolpath", {"profile": profile(), "tool_radius_mm": 6, "side": "groove"}),
         ("/v1/profiles/toolpath", {"profile": profile({"type": "knife-edge"}), "tool_radius_mm": 6, "side": "inside"})],
        [(("/v1/profiles/toolpath", {"profile": profile({"type": "knife-edge"}), "tool_radius_mm": 6,
                                     "side": "groove"}), "a groove is the track of a roller")]),
    # barrel cams
    "give the barrel cam's lift as segments or as a motion program": (
        [barrel(), barrel(segments=None, motion=MM_PROGRAM)],
        [(barrel(motion=MM_PROGRAM), "give the barrel cam's lift as segments or as a motion program"),
         (barrel(segments=None), "give the barrel cam's lift as segments or as a motion program")]),
    "an oscillating barrel-cam follower needs arm_length_mm": (
        [barrel(**BARREL_ARM)],
        [(barrel(**{**BARREL_ARM, "arm_length_mm": None}), "an oscillating barrel-cam follower needs arm_length_mm")]),
    "a conical roller rolls on a translating follower only (an oscillating arm moves its apex off the cam axis)": (
        [barrel(roller="conical"), barrel(**BARREL_ARM, roller="cylindrical")],
        [(barrel(**BARREL_ARM, roller="conical"), "a conical roller rolls on a translating follower only")]),
    "an oscillating barrel-cam follower's motion program is in deg (of swing)": (
        [barrel(**{**BARREL_ARM, "segments": None}, motion=DEG_PROGRAM)],
        [(barrel(**{**BARREL_ARM, "segments": None}, motion=MM_PROGRAM), "motion program is in deg (of swing)")]),
    "a translating barrel-cam follower's motion program is in mm": (
        [barrel(segments=None, motion=MM_PROGRAM)],
        [(barrel(segments=None, motion=DEG_PROGRAM), "a translating barrel-cam follower's motion program is in mm")]),
    "an oscillating barrel-cam follower's lift is swing_deg, not lift_mm": (
        [barrel(**BARREL_ARM)],
        [(barrel(**{**BARREL_ARM, "segments": segments({"lift_mm": 20})}),
          "an oscillating barrel-cam follower's lift is swing_deg, not lift_mm")]),
    "a translating barrel-cam follower's lift is lift_mm, not swing_deg": (
        [barrel()],
        [(barrel(segments=segments({"swing_deg": 20})), "a translating barrel-cam follower's lift is lift_mm")]),
    # machines
    "give exactly one mechanism: plate_cam, barrel_cam, indexer or motion": (
        [machine()],
        [(machine([{"name": "feed", "plate_cam": MACHINE_CAM, "indexer": MACHINE_TABLE}]), "give exactly one mechanism"),
         (machine([{"name": "feed"}]), "give exactly one mechanism")]),
    "give exactly one of moving, at_most and at_least": (
        [machine(rules=[{"while": {"axis": "table", "moving": True}, "require": {"axis": "feed", "at_most": 1}}])],
        [(machine(rules=[{"while": {"axis": "table", "moving": True, "at_least": 3},
                          "require": {"axis": "feed", "at_most": 1}}]), "give exactly one of moving"),
         (machine(rules=[{"while": {"axis": "table"}, "require": {"axis": "feed", "at_most": 1}}]),
          "give exactly one of moving")]),
    "give exactly one of speed_rpm and cycle_time_s": (
        [machine(master={"cycle_time_s": 0.5})],
        [(machine(master={"speed_rpm": 60, "cycle_time_s": 1}), "give exactly one of speed_rpm and cycle_time_s"),
         (machine(master={}), "give exactly one of speed_rpm and cycle_time_s")]),
    "allowed_stress_mpa needs the roller's width and materials (roller)": (
        [machine([{"name": "feed", "plate_cam": {**MACHINE_CAM, "roller": {"width_mm": 10},
                                                 "allowed_stress_mpa": 900}}])],
        [(machine([{"name": "feed", "plate_cam": {**MACHINE_CAM, "allowed_stress_mpa": 900}}]),
          "allowed_stress_mpa needs the roller")]),
    "an indexer geared to the camshaft turns with it: its input cannot stand still (input_stop_time_s must be 0)": (
        [machine()],
        [(machine([{"name": "table", "indexer": {**MACHINE_TABLE, "indexer": {
            **MACHINE_TABLE["indexer"], "input_stop_time_s": 0.1}}}]), "its input cannot stand still")]),
    "a driven load in mm (a translating follower, a motion in mm) is mass_kg and force_n; in deg (an oscillating "
    "follower, a motion in deg) inertia_kgm2 and torque_nm": (
        [machine([{"name": "push", "motion": {"motion": CLOSED_MM, "mass_kg": 2}}]),
         machine([{"name": "swing", "motion": {"motion": {**CLOSED_MM, "unit": "deg"}, "inertia_kgm2": 0.1}}])],
        [(machine([{"name": "push", "motion": {"motion": CLOSED_MM, "inertia_kgm2": 2}}]), "a driven load in mm"),
         (machine([{"name": "swing", "motion": {"motion": {**CLOSED_MM, "unit": "deg"}, "mass_kg": 1,
                                                "inertia_kgm2": 0.1}}]), "a driven load in mm")]),
    "plate must be below cam.plates (plates are numbered from 0)": (
        [("/v1/cams/parallel/toolpath", {"cam": TWO_PLATES, "plate": 1, "tool_radius_mm": 5, "tolerance_mm": 0.05})],
        [(("/v1/cams/parallel/toolpath", {"cam": TWO_PLATES, "plate": 2, "tool_radius_mm": 5}),
          "plate must be below cam.plates")]),
    "give exactly one of speed_rpm (N) and cycle_time_s (t0)": (
        [("/v1/indexers/design", {"stops": 6, "load": {"parts": [DISC]}, "speed_rpm": 60,
                                  "indexing_angles_deg": [120], "curves": [MS]})],
        [(("/v1/indexers/design", {"stops": 6, "load": {"parts": [DISC]}, "speed_rpm": 60, "cycle_time_s": 1}),
          "give exactly one of speed_rpm (N) and cycle_time_s (t0)"),
         (("/v1/indexers/design", {"stops": 6, "load": {"parts": [DISC]}}),
          "give exactly one of speed_rpm (N) and cycle_time_s (t0)")]),
    "ranking by motor needs motors to choose from": (
        [("/v1/indexers/design", {"stops": 6, "load": {"parts": [DISC]}, "speed_rpm": 60, "criterion": "rms_input_torque",
                                  "indexing_angles_deg": [120], "curves": [MS]})],
        [(("/v1/indexers/design", {"stops": 6, "load": {"parts": [DISC]}, "speed_rpm": 60, "criterion": "motor"}),
          "ranking by motor needs motors")]),
    # a plate-cam design: the fields of the follower's motion (service/profiles/design_specs.py MOTION_RULE)
    "a follower's fields are of its motion: a translating one's load is mass_kg, spring_rate_n_mm, preload_n, "
    "external_force_n, damping_n_s_mm, its free spring free.spring_rate_n_mm and free.preload_n, its lift in mm, "
    "and it may free offset_mm unless it is flat-faced; an oscillating one's load is inertia_kgm2, "
    "spring_rate_nm_rad, preload_nm, external_torque_nm, damping_nm_s_rad, its free spring "
    "free.spring_rate_nm_rad and free.preload_nm, its swing in deg, and it has no offset (it may free "
    "pivot_distance_mm)": (
        [design(), design(OSCILLATING, {"swing_deg": 20}), design(free={"base_radius_mm": [10, 200],
                                                                         "offset_mm": [-5, 5]}),
         design(OSCILLATING, {"swing_deg": 20}, free={"base_radius_mm": [10, 200], "pivot_distance_mm": [60, 120]})],
        [(design(inertia_kgm2=0.004), "not the torques of an oscillating one"),
         (design(OSCILLATING, {"swing_deg": 20}, mass_kg=0.5), "not the forces of a translating one"),
         (design(OSCILLATING, {"swing_deg": 20}, free={"base_radius_mm": [10, 200], "offset_mm": [-5, 5]}),
          "free.offset_mm is a translating knife-edge or roller follower's"),
         (design({"type": "flat-faced"}, free={"base_radius_mm": [10, 200], "offset_mm": [-5, 5]}),
          "a flat face's offset does not change its cam"),
         (design(free={"base_radius_mm": [10, 200], "spring_rate_nm_rad": [1, 5]}),
          "a translating follower's spring is free.spring_rate_n_mm"),
         (design(free={"base_radius_mm": [10, 200], "pivot_distance_mm": [60, 120]}),
          "free.pivot_distance_mm is an oscillating follower's"),
         (design(OSCILLATING), "an oscillating follower's lift is swing_deg, not lift_mm")]),
    "give exactly one of speed_fluctuation and inertia_kgm2": (
        [machine(flywheel={"speed_fluctuation": 0.05}), machine(flywheel={"inertia_kgm2": 2})],
        [(machine(flywheel={"speed_fluctuation": 0.05, "inertia_kgm2": 2}), "give exactly one of speed_fluctuation"),
         (machine(flywheel={}), "give exactly one of speed_fluctuation")]),
}


def test_every_stated_rule_has_its_cases() -> None:
    stated = stated_rules()
    assert len(stated) >= 25  # the rules of service/*/specs.py (a lost `rules=` would drop some)
    assert set(stated) <= set(RULES), sorted(set(stated) - set(RULES))
    pointers = {rule for rule in RULES if rule.startswith("/")}
    assert set(RULES) - pointers <= set(stated), sorted(set(RULES) - pointers - set(stated))


async def answer(path: str, body: dict[str, Any]) -> httpx.Response:
    transport = httpx.ASGITransport(app=APP, raise_app_exceptions=False)  # a 500 is an answer, checked by the caller
    async with httpx.AsyncClient(transport=transport, base_url="http://testserver") as client:
        return await client.post(path, json=body)


def messages(response: httpx.Response) -> list[str]:
    return [str(error["msg"]) for error in response.json()["errors"]] or [response.json()["detail"]]


@pytest.mark.parametrize("rule", RULES)
async def test_schema_and_app_agree_on_the_rule(rule: str) -> None:
    keeping, breaking = RULES[rule]
    rest = without(rule)
    for path, body in keeping:
        assert is_valid(body, path), body
        response = await answer(path, body)
        assert response.status_code == 200, (body, response.text)
    for (path, body), words in breaking:
        assert not is_valid(body, path), f"the document takes a body that breaks the rule: {body}"
        assert is_valid(body, path, rest), f"the body breaks more than this rule: {body}"
        response = await answer(path, body)
        assert response.status_code == 422, (body, response.text)
        assert any(words in message for message in messages(response)), (words, response.text)


#: The mirror image: what the document refuses, the app refuses too. A number field took true as 1
#: and "5" as 5 (pydantic's lax mode), and the fuzzer's type mutations met it once the rules let
#: the rest of its bodies through.
NOT_NUMBERS = [
    curve({"type": "polynomial", "start": {"s": 0, "v": False}, "end": {"s": 1, "v": False}}),
    curve({"type": "makino", "number": 1, "z": True}),
    curve({"type": "makino", "number": "4", "t1": 0.0625, "t3": 0.25}),
    curve({"type": "makino", "number": True, "z": 0.5}),
    table(samples=True),
    table(samples="11"),
    indexer(stops="6"),
    indexer(speed_rpm="60"),
    cam(ROLLER, base_radius_mm="40"),
    load(parts=[{**DISC, "count": True}]),
]


@pytest.mark.parametrize(("path", "body"), NOT_NUMBERS)
async def test_a_boolean_or_text_is_not_a_number(path: str, body: dict[str, Any]) -> None:
    assert not is_valid(body, path)
    response = await answer(path, body)
    assert response.status_code == 422, response.text
    assert any(m.startswith(("Input should be a valid number", "Input should be a valid integer"))
               for m in messages(response)), response.text


async def test_a_whole_float_is_an_integer() -> None:
    # 2.0 is an integer in JSON Schema 2020-12, and the app takes it as one
    path, body = table(samples=11.0)
    assert is_valid(body, path)
    response = await answer(path, body)
    assert response.status_code == 200 and len(response.json()["t"]) == 11, response.text


# ----------------------------------------------------------------------------- generated bodies
#: The rules JSON Schema cannot state, so a body the document calls valid may break them; each
#: stays in its validator (the 422 names it) and is said in a description of the document.
NOT_STATABLE = re.compile("|".join(re.escape(words) for words in (
    # the order of an array's items (JSON Schema compares no two items)
    "break points must satisfy T0 ≤ T1 ≤ … ≤ T7", "the curve needs T7 > T0", "t must be strictly increasing",
    "are too close to tell apart relative to the range of t", "all points have the same s",
    "The lift curve does not close", "periods of the lift curve", "does not fit a whole number of times",
    # the lengths of two arrays
    "t and s must have the same length", "v must have one slope per point",
    # two numbers of a spec compared, or summed, or multiplied
    "curve 4 needs 0 < T1 ≤ T3 ≤ 0.5", "is out of reach", "a ring needs inner_diameter_mm ≤ diameter_mm",
    "the offset must be smaller than the base radius", "segment angles must add to 360°", "The schedule does not close",
    "the total indexing angle θt = θh·z must not exceed 360°",
    # the geometry of Bezier control points
    "the last control point's θ must be greater than the first one's", "so the lift is not a function of the drive angle",
    "the curve has a vertical tangent", "the drive angle spans only", "all control points give the same lift h",
    # what the curve or the cam turns out to be, known once computed
    "these break points cannot reach both S7 and V7", "is outside the stroke of this curve",
    "displacement S is not monotone over its stroke", "the curve must move", "is outside the index",
    "do not determine a polynomial of degree",
    "One cam turn is", "The arm cannot be assembled",
    # a toolpath: the tool against the cam's curvature or its roller (two numbers of different
    # objects compared), the heights compared, and what the fit turns out to need
    "is larger than the concave radius of curvature", "is undercut at cam angle", "has a sharp corner at cam angle",
    "a flat face cannot follow that corner", "is wider than the roller's track", "cut_z_mm must be below safe_z_mm",
    "the path could not be fitted within",
    # a motion program: its spans summed, two of its segments together (JSON Schema compares no two
    # items), and what it turns out to be once resolved (strokes, solved T4, matched laws)
    "but they must add up to period_deg", "vanishes against the master angle",
    "each take their conditions from the other", "cannot be resolved in order", "a stroke of 0 with the law",
    "no t4 in [0, 1) makes the acceleration continuous", "make the acceleration continuous at the end of this curve 2",
    "but this law starts at rest", "ends at rest, so that stroke is 0", "(nearly) dependent, so no one spline",
    "the law ends where it starts", "needs a stroke to scale its neighbours' velocities", "which is 0 here",
    "the neighbours' velocities scaled to this universal curve are not finite", "where the program has no other segment",
    # follower dynamics: what the cam turns out to be (an impact where its lift's velocity jumps, a
    # roller that undercuts it), known once the lift is evaluated
    "the follower's acceleration is infinite there (an impact)", "The roller undercuts the cam",
    # residual vibration: τ = th·fn from the indexer, the load and the stiffness together; a load's
    # inertia summed over its parts; what the curve's acceleration turns out to be
    "must lie within 0.001 ≤ τ ≤ 1000: change stiffness_nm_rad", "the load's inertia must be greater than 0",
    "the curve's acceleration is not", "the curve's displacement jumps",
    # barrel cams: the roller's length, the groove's depth and the pitch radius compared; the arm's
    # angle and offset over the turn, known once the lift is evaluated
    "must be less than twice pitch_radius_mm", "must be at least roller_length_mm",
    "the groove would cut through the axis", "of square to the cam axis", "beyond the radius of the roller's inner end",
    # parallel cams: one number a multiple of another, and the turret's radii, roller size and centre
    # distance compared (sums, a sine of the roller pitch, a share); the plates' extent, known once drawn
    "must be a multiple of stops", "The rollers reach the cam axis", "The rollers of a plate collide",
    "below the plates' resolution", "reaches the turret's axis", "sweep over the cam axis",
    # its plates' solids: two numbers of the solid compared
    "spacing_mm must be at least thickness_mm",
    # roller-gear cams: the rollers' length against their pitch radius, a sine of the roller pitch at the
    # inner end against the roller radius, sums against the centre distance, a share of it
    "The rollers leave no room for the rib", "The rollers cross the turret's axis",
    "must each be at least 0.1% of center_distance_mm",
    # a motion program that must close as a cam's lift: the sum of its strokes (solved ones among
    # them) compared with zero
    "the motion program does not close",
    # indexer design: motor names compared, a dwell against the cycle, what the candidates turn out to be
    "motor names must be unique", "is the whole cycle t0", "no candidate meets every requirement",
    # machines: names compared across the axes and the rules; an oscillating unit's strokes (ratio × dwells)
    "axis names must be unique", "is not an axis of this machine", "strokes per camshaft turn must be even",
    # a plate-cam design: its bounds compared (lo ≤ hi, something to minimise moves), the speeds' range, and
    # what the cam turns out to be (a corner of its lift, no design within the bounds); and the request's
    # rules statable one by one that the document leaves to the validator, schemathesis resolving no more
    # than two on one model (service/profiles/design_specs.py, VALIDATOR_RULES)
    "is above the upper bound", "nothing to minimise", "or a range [lo, hi] with 0 < lo ≤ hi",
    "the cam has a corner there (radius of curvature 0)", "reachable within the bounds",
    "the limits cannot all be met within the bounds", "the largest contact force the follower keeps within the bounds",
    "a follower's mass (or inertia) needs speed_rpm", "give base_radius_mm, or free it",
    "free.roller_radius_mm needs a roller follower", "free.arm_length_mm is not searched",
    "need the follower's mass_kg", "the follower's mass needs a spring", "limits.allowed_stress_mpa needs roller",
    "are a roller follower's limits", "roller (width and materials) goes with a roller follower's stress limit",
    # a result beyond the range of float64
    "produced a non-finite number",
)))

#: per POST body schema, derandomized: the same bodies on every run
EXAMPLES = 50
#: one operation per body schema, the JSON one (the .csv and file variants take the same body)
PATHS = sorted({body_schema_name(path): path for path, item in reversed(DOCUMENT["paths"].items())
                if "post" in item and "." not in path}.values())


@functools.cache
def schema() -> Any:
    """The document as schemathesis reads it (made when a generation run first asks: ~1 s)."""
    return schemathesis.openapi.from_dict(DOCUMENT)


#: what the run saw, for the report: (path, status or rule) → count
SEEN: Counter[tuple[str, str]] = Counter()


def generated_bodies(path: str) -> list[Any]:
    bodies: list[Any] = []

    @hypothesis.settings(max_examples=EXAMPLES, deadline=None, derandomize=True, database=None,
                         suppress_health_check=list(HealthCheck), phases=[hypothesis.Phase.generate])
    @given(case=schema()[path]["POST"].as_strategy(GenerationMode.POSITIVE))
    def collect(case: schemathesis.Case) -> None:
        bodies.append(case.body)

    collect()
    return bodies


@pytest.fixture(scope="module", autouse=True)
def _print_counts() -> Iterator[None]:
    yield
    if SEEN:
        counts = {f"{path} {answer}": n for (path, answer), n in sorted(SEEN.items())}
        print("\nschema-valid generated bodies by answer:", json.dumps(counts, ensure_ascii=False, indent=1))


# ----------------------------------------------------------------------------- bugs met on the way
#: Polynomial boundary conditions can leave the system singular (J without V or A at either end);
#: camcore let numpy's LinAlgError out (500). Found by the generation run and then by
#: tests/service/test_fuzz.py once the document made the fuzzer's polynomial specs valid.
ORDERS = ("v", "a", "j")


def polya_condition(start: dict[str, float], end: dict[str, float]) -> bool:
    """Pólya's condition on the orders given (both ends together): for each k, at least k + 1
    conditions of order ≤ k. For interpolation at two points it is necessary and sufficient for
    a unique polynomial of degree n − 1 (G. Pólya, ZAMM 11 (1931) 445-449; G. G. Lorentz,
    K. Jetter, S. D. Riemenschneider, Birkhoff Interpolation (1983), ch. 1)."""
    orders = sorted([0, 0] + [1 + ORDERS.index(key) for key in (*start, *end) if key != "s"])
    return all(order <= i for i, order in enumerate(orders))


def test_polynomial_boundary_conditions_solve_or_say_why() -> None:
    from itertools import product

    from camcore.curves.polynomial import polynomial_from_boundary
    from camcore.errors import InvalidParameterError

    # every choice of v, a, j at each end: 64 systems, s always given; values 0.3, -0.7, ... so no
    # condition holds by accident
    singular = 0
    for at_start, at_end in product(product((False, True), repeat=3), repeat=2):
        start = {"s": 0.0, **{k: 0.3 * (i + 1) for i, k in enumerate(ORDERS) if at_start[i]}}
        end = {"s": 1.0, **{k: -0.7 * (i + 1) for i, k in enumerate(ORDERS) if at_end[i]}}
        if not polya_condition(start, end):
            singular += 1
            with pytest.raises(InvalidParameterError, match="do not determine a polynomial"):
                polynomial_from_boundary(start, end)
            continue
        law = polynomial_from_boundary(start, end)
        poly = np.polynomial.Polynomial(law.coefficients)
        for where, conditions in ((0.0, start), (1.0, end)):
            for order, key in enumerate(("s", *ORDERS)):
                if key in conditions:
                    # degree ≤ 7 with coefficients of order 10–100: 1e-9 is far above float rounding
                    assert poly.deriv(order)(where) == pytest.approx(conditions[key], abs=1e-9), (start, end, key)
    # by hand from Pólya's condition: with s at both ends, it fails only when the third condition
    # is of order 3, i.e. j is all that is given beyond s (at the start, the end, or both)
    assert singular == 3


async def test_singular_polynomial_boundary_conditions_are_a_422() -> None:
    body = {"curve": {"type": "polynomial", "start": {"s": 0, "j": 0}, "end": {"s": 1}}}
    response = await answer("/v1/curves/characteristics", body)
    assert response.status_code == 422, response.text
    assert "do not determine a polynomial of degree 2" in response.text


# ----------------------------------------------------------------------------- bugs met on the way
async def test_a_vanishing_rotation_ratio_is_a_4xx() -> None:
    """The generation run met this 500: a rotation ratio so small that one cam turn (360°/ratio)
    overflowed to infinity and CurveLift rounded it (OverflowError). Now a 422 sentence; the subnormal
    5e-324 met is refused by every spec's rule against subnormal numbers (issue 34), at the field."""
    lift = {"type": "points", "t": [0, 180, 360], "s": [0, 10, 0]}
    for ratio, words in ((1e-300, "raise rotation_ratio"), (5e-324, "a subnormal number")):
        body = {"profile": profile(ROLLER, segments=None, lift=lift, rotation_ratio=ratio)}
        response = await answer("/v1/profiles", body)
        assert response.status_code == 422, response.text
        assert words in response.text
        assert response.json()["errors"][0]["loc"] == ["body", "profile", "rotation_ratio"]


@pytest.mark.fuzz
@pytest.mark.parametrize("path", PATHS)
async def test_generated_valid_bodies_are_accepted(path: str) -> None:
    refused: list[str] = []
    for body in generated_bodies(path):
        assert is_valid(body, path), f"the generator built a body the document refuses: {body}"
        response = await answer(path, body)
        assert response.status_code != 500, f"server error: {json.dumps(body)}"
        if response.status_code == 422:
            unexplained = [m for m in messages(response) if not NOT_STATABLE.search(m)]
            SEEN[(path, "422 unstatable" if not unexplained else "422 stated")] += 1
            if unexplained:
                refused.append(f"{json.dumps(body)} → {unexplained}")
        else:
            # 404: a curve name not in the catalog (a lookup, as GET /v1/curves/{name}); 413: a
            # configured size limit; neither is a rule of the body's form
            SEEN[(path, str(response.status_code))] += 1
            assert response.status_code in (200, 404, 413), (body, response.status_code, response.text)
    assert not refused, "valid by the document, refused by the app:\n" + "\n".join(refused)
