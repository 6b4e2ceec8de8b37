"""/v1/profiles: plate-cam contours with checks, contour export, base-circle sizing.

``computeProfile`` answers JSON, or a file on ``?format=`` (csv, dxf, xyz, contour-csv); each
file also has an operation of its own (``/table.csv``, ``/contour.dxf``, ``/contour.xyz``,
``/contour.csv``) whose only answer is that file, for generated clients, which read one media
type per operation.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from fastapi import APIRouter, Body, Depends, Query, Request
from starlette.responses import Response

from camcore.export import FORMATS, SOLID_FORMATS, ContourFormat, FileFormat
from service.admission import WorkGate
from service.curves.routes import CSV_FILE, ERRORS
from service.deps import profile_service, work_gate
from service.profiles import solids, toolpath
from service.profiles.service import UNBOUNDED_COLUMNS, ProfileService
from service.profiles.specs import (
    BASE_CIRCLE_EXAMPLES,
    PROFILE_EXAMPLES,
    BaseCircleAnswer,
    BaseCircleRequest,
    ProfileAnswer,
    ProfileRequest,
)
from service.responses import JSONBody, check_finite, json_response, table_response, wants_csv
from service.routing import OrjsonRoute

router = APIRouter(prefix="/v1/profiles", tags=["profiles"], route_class=OrjsonRoute)
Service = Annotated[ProfileService, Depends(profile_service)]
Gate = Annotated[WorkGate, Depends(work_gate)]


def _content(fmt: ContourFormat) -> dict[str, Any]:
    """A download's OpenAPI media type: text for text/*, else bytes (generated clients return bytes)."""
    schema = {"type": "string"} if fmt.is_text else {"type": "string", "format": "binary"}
    return {fmt.media_type.split(";")[0]: {"schema": schema}}


EXPORTS: dict[str, Any] = {
    "content": {"text/csv": {"schema": {"type": "string"}}}
    | {key: value for fmt in FORMATS.values() for key, value in _content(fmt).items()}
    | {key: value for fmt in SOLID_FORMATS.values() for key, value in _content(fmt).items()},
    "description": "Columns and checks as JSON; the table as CSV; the contour as DXF or X Y Z text; the solid as "
                   "STEP or STL",
}
#: ``?format=``: the table as JSON or CSV, a contour download (camcore.export.FORMATS) or a
#: solid (camcore.export.SOLID_FORMATS, with ``solid`` in the body)
ProfileFormat = Literal[("json", "csv", *FORMATS, *SOLID_FORMATS)]  # type: ignore[valid-type]  # from the registries
_DOWNLOADS: list[FileFormat[Any]] = [*FORMATS.values(), *SOLID_FORMATS.values()]
FORMAT_HELP = " / ".join(FORMATS) + " download the contour, " + " / ".join(SOLID_FORMATS) + \
    " the solid (give `solid` in the body):\n\n" + "\n".join(
    f"- `{fmt.name}` ({fmt.media_type.split(';')[0]}, {fmt.file_name}): {fmt.description}"
    for fmt in _DOWNLOADS)
ProfileBody = Annotated[ProfileRequest, Body(openapi_examples=PROFILE_EXAMPLES)]


@router.post("", operation_id="computeProfile", response_model=ProfileAnswer, responses={**ERRORS, 200: EXPORTS})
async def compute_profile(
    body: Annotated[ProfileRequest, Body(openapi_examples=PROFILE_EXAMPLES)],
    request: Request,
    service: Service,
    gate: Gate,
    format: Annotated[ProfileFormat | None, Query(description=FORMAT_HELP)] = None,
) -> Response:
    """Cam surface, pitch curve, lift, pressure angle, radius of curvature, and the checks."""
    if format in FORMATS:
        return await _contour(request, gate, service, body, FORMATS[format])
    if format in SOLID_FORMATS:
        return await solids.solid_response(request, gate, service, body, SOLID_FORMATS[format])
    csv = format == "csv" or (format is None and wants_csv(request))
    return await _table(request, gate, service, body, csv)


@router.post("/table.csv", operation_id="computeProfileCsv", response_class=Response,
             responses={**ERRORS, 200: CSV_FILE})
async def compute_profile_csv(body: ProfileBody, request: Request, service: Service, gate: Gate) -> Response:
    """The columns of ``computeProfile`` as CSV (null radius = an empty cell: a straight stretch)."""
    return await _table(request, gate, service, body, True)


async def _table(request: Request, gate: WorkGate, service: ProfileService, body: ProfileRequest,
                 csv: bool) -> Response:
    work = service.profile_work(body.profile, body.samples, body.cam_angle_deg, "csv" if csv else "json")
    columns, checks = await gate.run(request, work, service.table, body.profile, body.samples, body.cam_angle_deg)
    if csv:
        return table_response(columns, True, filename="profile.csv", allow_null=UNBOUNDED_COLUMNS)
    check_finite({k: v for k, v in columns.items() if k not in UNBOUNDED_COLUMNS})
    return json_response({**columns, "checks": checks})


async def _contour(request: Request, gate: WorkGate, service: ProfileService, body: ProfileRequest,
                   fmt: ContourFormat) -> Response:
    work = service.profile_work(body.profile, body.samples, body.cam_angle_deg, fmt.name)
    payload = await gate.run(request, work, service.contour_file, body.profile, body.samples, body.cam_angle_deg,
                             fmt.name)
    return Response(payload, media_type=fmt.media_type,
                    headers={"Content-Disposition": f'attachment; filename="{fmt.file_name}"'})


def _contour_route(fmt: ContourFormat) -> None:
    """One operation per contour format (``/contour.<ext>``), whose only answer is that file."""
    extension = fmt.file_name.rsplit(".", 1)[-1]
    camel = "".join(part.capitalize() for part in fmt.name.split("-"))

    async def export_contour(body: ProfileBody, request: Request, service: Service, gate: Gate) -> Response:
        return await _contour(request, gate, service, body, fmt)

    export_contour.__doc__ = f"The cam contour as {fmt.description} (``computeProfile`` with ``?format={fmt.name}``)."
    router.add_api_route(f"/contour.{extension}", export_contour, methods=["POST"],
                         operation_id=f"exportProfile{camel}", response_class=Response,
                         responses={**ERRORS, 200: {"content": _content(fmt), "description": fmt.description}},
                         summary=f"Export Profile {camel}")


for _fmt in FORMATS.values():
    _contour_route(_fmt)
solids.register(router)
toolpath.register(router)


@router.post("/base-circle", operation_id="sizeBaseCircle", response_model=BaseCircleAnswer, responses=ERRORS)
async def size_base_circle(body: Annotated[BaseCircleRequest, Body(openapi_examples=BASE_CIRCLE_EXAMPLES)],
                           request: Request, service: Service, gate: Gate) -> Response:
    """The smallest base radius meeting a pressure-angle limit and/or a curvature limit."""
    work = service.base_circle_work(body.profile, body.max_pressure_angle_deg, body.min_radius_of_curvature_mm)
    result = await gate.run(request, work, service.base_circle, body.profile, body.max_pressure_angle_deg,
                            body.min_radius_of_curvature_mm)
    return JSONBody(result)
