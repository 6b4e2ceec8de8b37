"""/v1/profiles: plate-cam contours with checks, contour export, base-circle sizing.

``computeProfile`` answers JSON, or a file on ``?format=`` (csv, dxf, xyz, contour-csv); each
file also has an operation of its own (``/table.csv``, ``/contour.dxf``, ``/contour.xyz``,
``/contour.csv``) whose only answer is that file, for generated clients, which read one media
type per operation.
"""

from __future__ import annotations

from typing import Annotated, Literal

import numpy as np
from fastapi import APIRouter, Body, Depends, Query, Request
from starlette.responses import Response

from ..deps import profile_service
from ..profile_schemas import (
    BASE_CIRCLE_EXAMPLES,
    PROFILE_EXAMPLES,
    BaseCircleAnswer,
    BaseCircleRequest,
    ProfileAnswer,
    ProfileRequest,
)
from ..profiles import UNBOUNDED_COLUMNS, ProfileService
from ..responses import JSONBody, check_finite, table_response, wants_csv
from ..routing import OrjsonRoute
from .curves import CSV_FILE, ERRORS

router = APIRouter(prefix="/v1/profiles", tags=["profiles"], route_class=OrjsonRoute)
Service = Annotated[ProfileService, Depends(profile_service)]

EXPORTS = {
    "content": {
        "text/csv": {"schema": {"type": "string"}},
        "application/dxf": {"schema": {"type": "string", "format": "binary"}},
        "text/plain": {"schema": {"type": "string"}},
    },
    "description": "Columns and checks as JSON; the table as CSV; the contour as DXF or X Y Z text",
}
DXF_FILE = {"content": {"application/dxf": {"schema": {"type": "string", "format": "binary"}}},
            "description": "The contour as a DXF drawing (mm)"}
XYZ_FILE = {"content": {"text/plain": {"schema": {"type": "string"}}},
            "description": "The contour as plain text, one 'X Y Z' point per line (mm, Z = 0)"}
CONTOUR_CSV_FILE = {"content": {"text/csv": {"schema": {"type": "string"}}},
                    "description": "The contour as CSV: cam_angle_deg, x_mm, y_mm, z_mm (= 0)"}
ProfileBody = Annotated[ProfileRequest, Body(openapi_examples=PROFILE_EXAMPLES)]


@router.post("", operation_id="computeProfile", response_model=ProfileAnswer, responses={**ERRORS, 200: EXPORTS})
def compute_profile(
    body: Annotated[ProfileRequest, Body(openapi_examples=PROFILE_EXAMPLES)],
    request: Request,
    service: Service,
    format: Annotated[Literal["json", "csv", "dxf", "xyz", "contour-csv"] | None,
                      Query(description="dxf / xyz / contour-csv download the contour")] = None,
) -> Response:
    """Cam surface, pitch curve, lift, pressure angle, radius of curvature, and the checks."""
    result = service.profile(body.profile, body.samples, body.cam_angle_deg)
    if format in ("dxf", "xyz", "contour-csv"):
        payload, media, name = service.export(result, "csv" if format == "contour-csv" else format,
                                              body.profile.base_radius_mm)
        return Response(payload, media_type=media, headers={"Content-Disposition": f'attachment; filename="{name}"'})
    columns = service.columns(result)
    bounded = {k: v for k, v in columns.items() if k not in UNBOUNDED_COLUMNS}
    check_finite(bounded)
    if format == "csv" or (format is None and wants_csv(request)):
        return table_response({k: np.asarray(v) for k, v in columns.items()}, True, filename="profile.csv",
                              allow_null=UNBOUNDED_COLUMNS)
    return JSONBody({**columns, "checks": service.checks(result)})


@router.post("/table.csv", operation_id="computeProfileCsv", response_class=Response,
             responses={**ERRORS, 200: CSV_FILE})
def compute_profile_csv(body: ProfileBody, service: Service) -> Response:
    """The columns of ``computeProfile`` as CSV (null radius = an empty cell: a straight stretch)."""
    columns = service.columns(service.profile(body.profile, body.samples, body.cam_angle_deg))
    check_finite({k: v for k, v in columns.items() if k not in UNBOUNDED_COLUMNS})
    return table_response({k: np.asarray(v) for k, v in columns.items()}, True, filename="profile.csv",
                          allow_null=UNBOUNDED_COLUMNS)


@router.post("/contour.dxf", operation_id="exportProfileDxf", response_class=Response,
             responses={**ERRORS, 200: DXF_FILE})
def export_profile_dxf(body: ProfileBody, service: Service) -> Response:
    """The cam contour as DXF (``computeProfile`` with ``?format=dxf``)."""
    return _contour_file(body, service, "dxf")


@router.post("/contour.xyz", operation_id="exportProfileXyz", response_class=Response,
             responses={**ERRORS, 200: XYZ_FILE})
def export_profile_xyz(body: ProfileBody, service: Service) -> Response:
    """The cam contour as X Y Z text (``computeProfile`` with ``?format=xyz``)."""
    return _contour_file(body, service, "xyz")


@router.post("/contour.csv", operation_id="exportProfileContourCsv", response_class=Response,
             responses={**ERRORS, 200: CONTOUR_CSV_FILE})
def export_profile_contour_csv(body: ProfileBody, service: Service) -> Response:
    """The cam contour as CSV (``computeProfile`` with ``?format=contour-csv``)."""
    return _contour_file(body, service, "csv")


def _contour_file(body: ProfileRequest, service: ProfileService, fmt: str) -> Response:
    result = service.profile(body.profile, body.samples, body.cam_angle_deg)
    payload, media, name = service.export(result, fmt, body.profile.base_radius_mm)
    return Response(payload, media_type=media, headers={"Content-Disposition": f'attachment; filename="{name}"'})


@router.post("/base-circle", operation_id="sizeBaseCircle", response_model=BaseCircleAnswer, responses=ERRORS)
def size_base_circle(body: Annotated[BaseCircleRequest, Body(openapi_examples=BASE_CIRCLE_EXAMPLES)],
                     service: Service) -> Response:
    """The smallest base radius meeting a pressure-angle limit and/or a curvature limit."""
    result = service.base_circle(body.profile, body.max_pressure_angle_deg, body.min_radius_of_curvature_mm)
    return JSONBody(result)
