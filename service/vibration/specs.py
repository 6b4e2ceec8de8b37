"""Requests and answers of the residual-vibration operations (docs/api.md, "Residual vibration")."""

from __future__ import annotations

from typing import Annotated

from fastapi.openapi.models import Example
from pydantic import Field, model_validator

from camcore.dynamics import TAU_MAX, TAU_MIN, IndexerVibration, ResidualVibration, VibrationTable
from service.curves.specs import MS_SPEC, CurveSpec
from service.indexers.specs import INDEXER_EXAMPLE, LOAD_EXAMPLE, IndexerSpec, LoadSpec
from service.models import answer_model
from service.specs import JSON_INTEGER, Spec, exactly_one, examples, given, rule

#: τ = th·fn within camcore's range (camcore.dynamics.vibration.TAU_MIN, TAU_MAX say why)
Tau = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=TAU_MIN, le=TAU_MAX)]
#: ζ: underdamped only; at ζ ≥ 1 nothing vibrates and the envelope is undefined (ωd = 0)
DampingRatio = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0, lt=1)]
#: a positive physical quantity: far beyond any indexer (the τ range bounds the ratio k/I)
PositiveQuantity = Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0, le=1e12)]


class TauRange(Spec):
    """``samples`` values of τ evenly from ``start`` to ``stop`` (both included; either order)."""

    model_config = examples({"start": 0.5, "stop": 10, "samples": 96})
    start: Tau
    stop: Tau
    samples: Annotated[int, Field(ge=2), JSON_INTEGER] = Field(description="at least 2")


class VibrationRequest(Spec):
    model_config = examples(
        {"curve": MS_SPEC, "damping_ratio": 0, "tau_range": {"start": 0.5, "stop": 10, "samples": 96}},
        rules=[rule("give either tau (a list of values) or tau_range: one of them, not both", exactly_one("tau", "tau_range"))])
    curve: CurveSpec
    damping_ratio: DampingRatio = Field(0.0, description="ζ, 0 ≤ ζ < 1 (underdamped; ζ ≥ 1 is refused)")
    # minItems states the validator's rule in the schema (the validator gives the sentence)
    tau: Annotated[list[Tau], Field(json_schema_extra={"minItems": 1})] | None = Field(
        None, description=f"τ = th·fn (motion time over natural period) values, each {TAU_MIN:g} … {TAU_MAX:g}")
    tau_range: TauRange | None = Field(None, description="evenly spaced τ values instead of tau")

    @model_validator(mode="after")
    def _check(self) -> VibrationRequest:
        if (self.tau is None) == (self.tau_range is None):
            raise ValueError("give either tau (a list of values) or tau_range: one of them, not both")
        if self.tau is not None and len(self.tau) == 0:
            raise ValueError("tau must list at least one value")
        return self


#: one index along one curve: a timing chart (several moves over an input turn) is not modelled
SINGLE_CURVE = ("the residual vibration takes an indexer with one curve (stops or swing_angle_deg, indexing_angle_deg, "
                "curve), not a timing chart")


class IndexerVibrationRequest(Spec):
    model_config = examples(
        {"indexer": INDEXER_EXAMPLE, "inertia_kgm2": 2.25, "stiffness_nm_rad": 2e5, "damping_ratio": 0.05,
         "tolerance_arcsec": 10},
        rules=[rule("give the load's inertia as inertia_kgm2 or as load: one of them, not both",
                    exactly_one("inertia_kgm2", "load")),
               rule(SINGLE_CURVE, {"not": {"required": ["indexer"], "properties": {"indexer": given("timing")}}})])
    indexer: IndexerSpec
    inertia_kgm2: PositiveQuantity | None = Field(None, description="I, the load inertia on the output")
    load: LoadSpec | None = Field(None, description="the load (instead of inertia_kgm2): only its inertia is used")
    stiffness_nm_rad: PositiveQuantity = Field(description="k, torsional stiffness from the output shaft to the load")
    damping_ratio: DampingRatio = Field(0.0, description="ζ, 0 ≤ ζ < 1 (underdamped; ζ ≥ 1 is refused)")
    tolerance_arcsec: PositiveQuantity = Field(description="ε, the error allowed at the dwell")
    samples: Annotated[int, Field(ge=2), JSON_INTEGER] = Field(
        501, description="rows of the table over the index and the dwell, both ends included")

    @model_validator(mode="after")
    def _check(self) -> IndexerVibrationRequest:
        if (self.inertia_kgm2 is None) == (self.load is None):
            raise ValueError("give the load's inertia as inertia_kgm2 or as load: one of them, not both")
        if self.indexer.timing is not None:
            raise ValueError(SINGLE_CURVE)
        return self


#: request examples (Swagger UI pre-fills the first)
VIBRATION_EXAMPLES: dict[str, Example] = {
    "MS": {"summary": "MS, undamped, τ from 0.5 to 10",
           "description": "the residual-vibration spectrum of the modified sine",
           "value": {"curve": MS_SPEC, "damping_ratio": 0, "tau_range": {"start": 0.5, "stop": 10, "samples": 96}}},
    "cycloid": {"summary": "cycloid at τ = 1, 2, 3",
                "description": "undamped: 0.5 at τ = 1, nothing at every integer τ ≥ 2",
                "value": {"curve": {"type": "named", "name": "cycloid"}, "tau": [1, 2, 3]}},
}
INDEXER_VIBRATION_EXAMPLES: dict[str, Example] = {
    "guide": {"summary": "the guide's indexer and disc on a 2e5 N·m/rad drive",
              "description": "6 stops, θh = 270°, 60 rpm, MS; I = 2.25 kg·m²: fn = 47.45 Hz, τ = 35.6",
              "value": {"indexer": INDEXER_EXAMPLE, "inertia_kgm2": 2.25, "stiffness_nm_rad": 2e5,
                        "damping_ratio": 0.05, "tolerance_arcsec": 10}},
    "load": {"summary": "the same with the load given by its parts, a softer drive",
             "value": {"indexer": INDEXER_EXAMPLE, "load": LOAD_EXAMPLE, "stiffness_nm_rad": 2e4,
                       "damping_ratio": 0.02, "tolerance_arcsec": 10, "samples": 201}},
}


VibrationTableAnswer = answer_model(ResidualVibration, "ResidualVibrationTable",
                                    "Columns over τ: residual amplitude and peak deviation as fractions of the stroke.")
IndexerVibrationTableAnswer = answer_model(VibrationTable, "IndexerVibrationTable")
_IndexerVibrationFields = answer_model(IndexerVibration, "IndexerVibrationFields")


class IndexerVibrationAnswer(_IndexerVibrationFields):  # type: ignore[valid-type, misc]  # derived (service.models)
    """Natural frequency, τ, residual amplitude and settling time of an indexer's load, and its error over
    the index and the dwell."""

    table: IndexerVibrationTableAnswer  # type: ignore[valid-type]  # derived answer model (service.models)

