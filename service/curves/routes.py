"""/v1/curves: the catalog, characteristic values, tables and inverse lookups.

Each table operation answers JSON, or CSV on ``Accept: text/csv`` / ``?format=csv`` (for
browsers and spreadsheets); its ``….csv`` twin answers only CSV, for generated clients,
which read one media type per operation (openapi-python-client parses the first it knows).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Annotated, Any, Literal, TypeVar

from fastapi import APIRouter, Body, Depends, Path, Query, Request
from fastapi.exceptions import RequestValidationError
from starlette.responses import PlainTextResponse, Response

import camcore
from camcore.work import WorkEstimate
from service.admission import WorkGate
from service.curves.service import CurveService
from service.curves.specs import (
    CHARACTERISTICS_EXAMPLES,
    INVERSE_EXAMPLES,
    QM_CONVENTIONS,
    TABLE_EXAMPLES,
    CatalogAnswer,
    CatalogEntryAnswer,
    CharacteristicsRequest,
    CurveCharacteristicsAnswer,
    CurveSpec,
    CurveTable,
    InverseRequest,
    InverseTable,
    NamedCurveSpec,
    TableRequest,
)
from service.deps import curve_service, work_gate
from service.errors import ErrorAnswer, relocate, within
from service.responses import JSONBody, Responses, encoded_response, table_response, wants_csv
from service.routing import OrjsonRoute
from service.specs import QueryNumbers

T = TypeVar("T")

router = APIRouter(prefix="/v1/curves", tags=["curves"], route_class=OrjsonRoute)

ERRORS: Responses = {
    400: {"model": ErrorAnswer, "description": "Malformed body"},
    404: {"model": ErrorAnswer, "description": "Unknown curve name (close matches listed)"},
    413: {"model": ErrorAnswer, "description": "Over a configured limit or the work budget (named in the answer)"},
    422: {"model": ErrorAnswer, "description": "Invalid request (field and reason given)"},
    503: {"model": ErrorAnswer, "description": "Busy, or the computation ran past its deadline: retry after "
          "the seconds in Retry-After"},
}
CSV: dict[str, Any] = {"content": {"text/csv": {"schema": {"type": "string"}}}, "description": "Columns as JSON, or CSV"}
#: the 200 answer of an operation that answers only CSV (the twin of a JSON table operation)
CSV_FILE: dict[str, Any] = {"content": {"text/csv": {"schema": {"type": "string"}}},
            "description": "The table as CSV: a header row, then one row per point, one column per quantity"}
Service = Annotated[CurveService, Depends(curve_service)]
Gate = Annotated[WorkGate, Depends(work_gate)]
CurveName = Annotated[str, Path(min_length=1, max_length=80, description="id, alias or Makino number")]
Format = Annotated[Literal["json", "csv"] | None, Query(description="csv for spreadsheets")]


@router.get("", operation_id="listCurves", response_model=CatalogAnswer, responses=ERRORS)
def list_curves(service: Service) -> Response:
    """The catalog: every named curve with its aliases, source and characteristic values."""
    return JSONBody({"curves": service.catalog(), "conventions": QM_CONVENTIONS})


@router.get("/{name}", operation_id="getCurve", response_model=CatalogEntryAnswer, responses=ERRORS)
def get_curve(name: CurveName, service: Service) -> Response:
    """One catalog entry, by id, alias or Makino number (case-insensitive)."""
    with within("path"):
        return JSONBody(service.catalog_entry(camcore.lookup(name)))


@router.post("/characteristics", operation_id="getCurveCharacteristics",
             response_model=CurveCharacteristicsAnswer, responses=ERRORS)
async def characteristics(body: Annotated[CharacteristicsRequest, Body(openapi_examples=CHARACTERISTICS_EXAMPLES)],
                          request: Request, service: Service, gate: Gate) -> Response:
    """Vm, Am±, Jm±, Qm± (and raw A·V extremes) with the T where each occurs."""
    quick = service.is_built(body.curve)
    work = service.characteristics_work(body.curve)
    return JSONBody(await compute(request, gate, quick, work, service.characteristics, body.curve))


@router.post("/table", operation_id="sampleCurve", response_model=CurveTable, responses={**ERRORS, 200: CSV})
async def sample_curve(body: Annotated[TableRequest, Body(openapi_examples=TABLE_EXAMPLES)], request: Request,
                       service: Service, gate: Gate) -> Response:
    """Columns t, s, v, a, j, q at evenly spaced samples or at given times."""
    return await _table(request, gate, service, body, wants_csv(request))


@router.post("/table.csv", operation_id="sampleCurveCsv", response_class=Response,
             responses={**ERRORS, 200: CSV_FILE})
async def sample_curve_csv(body: Annotated[TableRequest, Body(openapi_examples=TABLE_EXAMPLES)], request: Request,
                           service: Service, gate: Gate) -> Response:
    """The table of ``sampleCurve`` as CSV."""
    return await _table(request, gate, service, body, True)


async def _table(request: Request, gate: WorkGate, service: CurveService, body: TableRequest, csv: bool) -> Response:
    if body.samples is not None:
        return await _sampled_table(request, gate, service, body.curve, body.samples, csv)
    assert body.t is not None  # TableRequest requires samples or t
    work = service.table_work(body.curve, len(body.t), csv, ("t",))
    quick = service.is_quick_table(body.curve, len(body.t))
    return table_response(await compute(request, gate, quick, work, service.table_columns, body.curve, None, body.t),
                          csv)


async def compute(request: Request, gate: WorkGate, quick: bool, work: WorkEstimate,
                  job: Callable[..., T], *args: Any) -> T:
    """Quick work (see CurveService.is_quick_table) on the event loop, other work through
    the gate (budget, admission, deadline) in a worker thread."""
    if quick:
        gate.check_budget(work)
        return job(*args)
    return await gate.run(request, work, job, *args)


async def _sampled_table(request: Request, gate: WorkGate, service: CurveService, spec: CurveSpec, samples: int,
                         csv: bool) -> Response:
    """A cached table, or a small one on a built curve, is answered on the event loop;
    other work goes through the gate; a large table is streamed."""
    payload = service.table_if_cached(spec, samples, csv)  # a hit passed every limit when it was cached
    if payload is not None:
        return encoded_response(payload, csv)
    work = service.table_work(spec, samples, csv, ("samples",))
    if samples > service.settings.table_cache_max_rows:
        return table_response(await compute(request, gate, False, work, service.table_columns, spec, samples, None),
                              csv)
    payload = await compute(request, gate, service.is_quick_table(spec, samples), work, service.cached_table,
                            spec, samples, csv)
    return encoded_response(payload, csv)


@router.get("/{name}/table", operation_id="sampleNamedCurve", response_model=CurveTable,
            responses={**ERRORS, 200: CSV})
async def sample_named_curve(
    name: CurveName,
    request: Request,
    service: Service,
    gate: Gate,
    samples: Annotated[int, Query(ge=2)] = 101,
    direction: Literal["rise", "return"] = "rise",
    format: Format = None,
) -> Response:
    """The table of a catalog curve, for spreadsheets (``?format=csv``)."""
    return await _named_table(request, gate, service, name, samples, direction, format == "csv")


@router.get("/{name}/table.csv", operation_id="sampleNamedCurveCsv", response_class=Response,
            responses={**ERRORS, 200: CSV_FILE})
async def sample_named_curve_csv(
    name: CurveName,
    request: Request,
    service: Service,
    gate: Gate,
    samples: Annotated[int, Query(ge=2)] = 101,
    direction: Literal["rise", "return"] = "rise",
) -> Response:
    """The table of a catalog curve as CSV (``sampleNamedCurve`` with ``?format=csv``)."""
    return await _named_table(request, gate, service, name, samples, direction, True)


async def _named_table(request: Request, gate: WorkGate, service: CurveService, name: str, samples: int,
                       direction: str, csv: bool) -> Response:
    with relocate(("curve",), ("path",)):  # the spec's name is the path's
        return await _sampled_table(request, gate, service, NamedCurveSpec(name=name, direction=direction), samples,
                                    csv)


@router.post("/inverse", operation_id="invertCurve", response_model=InverseTable, responses={**ERRORS, 200: CSV})
async def invert_curve(body: Annotated[InverseRequest, Body(openapi_examples=INVERSE_EXAMPLES)], request: Request,
                       service: Service, gate: Gate) -> Response:
    """T (and V, A) where S(T) = s: exact, or the catalog's table interpolation."""
    return await _inverse(request, gate, service, body.curve, body.s, body.method, body.table_step, body.table_decimals,
                          wants_csv(request))


@router.post("/inverse.csv", operation_id="invertCurveCsv", response_class=Response,
             responses={**ERRORS, 200: CSV_FILE})
async def invert_curve_csv(body: Annotated[InverseRequest, Body(openapi_examples=INVERSE_EXAMPLES)],
                           request: Request, service: Service, gate: Gate) -> Response:
    """The answer of ``invertCurve`` as CSV."""
    return await _inverse(request, gate, service, body.curve, body.s, body.method, body.table_step, body.table_decimals, True)


async def _inverse(request: Request, gate: WorkGate, service: CurveService, spec: CurveSpec, s: list[float],
                   method: str, table_step: float, table_decimals: int | None, csv: bool) -> Response:
    work = service.inverse_work(spec, len(s), method, table_step, csv)
    quick = service.is_quick_inverse(spec, len(s), method)
    columns = await compute(request, gate, quick, work, service.inverse_columns, spec, s, method, table_step,
                            table_decimals)
    return table_response(columns, csv)


@router.get("/{name}/inverse", operation_id="invertNamedCurve", response_model=InverseTable,
            responses={**ERRORS, 200: CSV})
async def invert_named_curve(
    name: CurveName,
    request: Request,
    service: Service,
    gate: Gate,
    s: Annotated[QueryNumbers, Query(min_length=1, description="S values: repeat ?s= or separate by commas")],
    method: Literal["exact", "table"] = "exact",
    table_step: Annotated[float, Query(ge=1e-4, le=0.5)] = 0.01,
    table_decimals: Annotated[int | None, Query(ge=0, le=15)] = None,
    direction: Literal["rise", "return"] = "rise",
    format: Format = None,
) -> Response:
    """The inverse lookup of a catalog curve, for spreadsheets (``?s=0.1833&format=csv``)."""
    spec = NamedCurveSpec(name=name, direction=direction)
    with relocate(("curve",), ("path",)):  # the spec's name is the path's
        return await _inverse(request, gate, service, spec, s, method, table_step, table_decimals, format == "csv")


@router.get("/{name}/inverse.csv", operation_id="invertNamedCurveCsv", response_class=Response,
            responses={**ERRORS, 200: CSV_FILE})
async def invert_named_curve_csv(
    name: CurveName,
    request: Request,
    service: Service,
    gate: Gate,
    s: Annotated[QueryNumbers, Query(min_length=1, description="S values: repeat ?s= or separate by commas")],
    method: Literal["exact", "table"] = "exact",
    table_step: Annotated[float, Query(ge=1e-4, le=0.5)] = 0.01,
    table_decimals: Annotated[int | None, Query(ge=0, le=15)] = None,
    direction: Literal["rise", "return"] = "rise",
) -> Response:
    """The inverse lookup of a catalog curve as CSV (``invertNamedCurve`` with ``?format=csv``)."""
    spec = NamedCurveSpec(name=name, direction=direction)
    with relocate(("curve",), ("path",)):
        return await _inverse(request, gate, service, spec, s, method, table_step, table_decimals, True)


VALUE: dict[str, Any] = {
    "content": {"text/plain": {"schema": {"type": "string"}, "example": "0.17788776262872125"}},
    "description": "One bare number (Python's shortest round-trip form), e.g. S of MS at T = 0.3",
}


def _value_query(t: float | None, s: float | None, quantity: str | None) -> str:
    """The quantity a /value query asks for; t or s, not both, and a quantity that fits."""
    def invalid(field: str, msg: str) -> RequestValidationError:
        return RequestValidationError([{"type": "value_error", "loc": ("query", field), "msg": msg}])

    if t is not None and s is not None:
        raise invalid("s", "give t (a time, for s, v, a, j or q) or s (a displacement, for its t), not both")
    if t is None and s is None:
        raise invalid("t", "give t (a time, e.g. ?t=0.3) or s (a displacement, e.g. ?s=0.1833)")
    if s is not None:
        if quantity not in (None, "t"):
            raise invalid("quantity", f"with s the answer is the time t of the exact inverse, not {quantity}")
        return "t"
    if quantity == "t":
        raise invalid("quantity", "with t the quantity is one of s, v, a, j, q (to find t, give s)")
    return quantity or "s"


@router.get("/{name}/value", operation_id="getCurveValue", response_class=Response,
            responses={**ERRORS, 200: VALUE})
async def curve_value(
    name: CurveName,
    request: Request,
    service: Service,
    gate: Gate,
    t: Annotated[float | None, Query(allow_inf_nan=False, description="time T; answers quantity at T")] = None,
    s: Annotated[float | None, Query(allow_inf_nan=False,
                                     description="displacement S; answers T of the exact inverse")] = None,
    quantity: Annotated[Literal["t", "s", "v", "a", "j", "q"] | None,
                        Query(description="with t: s (default), v, a, j or q; with s: t")] = None,
    direction: Literal["rise", "return"] = "rise",
) -> Response:
    """One number for a spreadsheet cell (``=WEBSERVICE(...)``): S, V, A, J or Q at T, or T
    where S = s (exact inverse), as ``text/plain``; errors are JSON as everywhere."""
    what = _value_query(t, s, quantity)
    spec = NamedCurveSpec(name=name, direction=direction)
    quick = service.is_quick_inverse(spec, 1, "exact") if s is not None else service.is_quick_table(spec, 1)
    with relocate(("curve",), ("path",)):  # the spec's name is the path's
        work = service.curve_work(spec)
        return PlainTextResponse(await compute(request, gate, quick, work, service.value, spec, what, t, s))
