"""Solids of /v1/profiles: ``?format=step`` and ``?format=stl`` with a ``solid`` in the body.

The plate cam extruded with its bore (:mod:`camcore.export.solid`, OpenCASCADE). Each format
also has an operation of its own (``/solid.step``, ``/solid.stl``) whose body needs the
``solid``. :func:`register` adds those to the profiles router.
"""

from __future__ import annotations

from typing import Annotated, Any

from fastapi import APIRouter, Body, Depends, Request
from fastapi.openapi.models import Example
from pydantic import Field
from starlette.concurrency import run_in_threadpool
from starlette.responses import Response

from camcore.errors import InvalidParameterError
from camcore.export import SOLID_FORMATS, FileFormat, SolidCam
from camcore.export.solid import load_kernel
from camcore.work import WorkEstimate, WorkTerm, fit_elements_estimate, fit_work
from service.admission import WorkGate
from service.curves.routes import ERRORS
from service.deps import profile_service, work_gate
from service.profiles.service import ProfileService
from service.profiles.specs import ROLLER_PROFILE_EXAMPLE, ProfileRequest, ProfileSpec, SolidSpec
from service.profiles.toolpath import schedule, strokes_mm
from service.specs import examples

Service = Annotated[ProfileService, Depends(profile_service)]
Gate = Annotated[WorkGate, Depends(work_gate)]

SOLID_EXAMPLE: dict[str, object] = {"thickness_mm": 12, "bore_diameter_mm": 20, "tolerance_mm": 0.01}


class SolidRequest(ProfileRequest):
    """A profile request whose ``solid`` is required (the solid operations)."""

    model_config = examples({"profile": ROLLER_PROFILE_EXAMPLE, "solid": SOLID_EXAMPLE})
    solid: SolidSpec = Field(description="thickness, bore and tolerance of the solid")


SOLID_EXAMPLES: dict[str, Example] = {
    "roller": {"summary": "the roller-follower cam, 12 mm thick with a 20 mm bore, within 0.01 mm",
               "value": {"profile": ROLLER_PROFILE_EXAMPLE, "solid": SOLID_EXAMPLE}},
}


def solid_work(service: ProfileService, spec: ProfileSpec, solid: SolidSpec, fmt: str) -> WorkEstimate:
    """The curves, the contour's fit (at half the tolerance for an STL) and the kernel's work."""
    laws, work = service.laws(spec)
    tolerance = solid.tolerance_mm / (2 if fmt == "stl" else 1)
    segments, field = schedule(spec)
    elements = fit_elements_estimate(strokes_mm(spec), segments, tolerance)
    work += fit_work(laws, elements, 1, field, ("solid", "tolerance_mm"))
    return work + WorkEstimate((WorkTerm(("solid", "tolerance_mm"), f"the {fmt} solid of about {elements} edges",
                                         SOLID_FORMATS[fmt].cost(elements)),))


def solid_file(service: ProfileService, spec: ProfileSpec, solid: SolidSpec, fmt: str) -> bytes:
    """The solid written in one of :data:`camcore.export.SOLID_FORMATS`."""
    settings = service.curves.settings
    item = SolidCam(service.cam(spec), solid.thickness_mm, solid.bore_diameter_mm, solid.tolerance_mm,
                    settings.max_toolpath_elements, settings.max_stl_triangles)
    return SOLID_FORMATS[fmt].write(item)


async def solid_response(request: Request, gate: WorkGate, service: ProfileService, body: ProfileRequest,
                         fmt: FileFormat[SolidCam]) -> Response:
    """The solid as a download; 422 when the body has no ``solid``."""
    if body.solid is None:
        raise InvalidParameterError(f"format {fmt.name} is a solid: give solid {{thickness_mm, bore_diameter_mm}}.",
                                    field=("solid",))
    work = solid_work(service, body.profile, body.solid, fmt.name)
    # the CAD kernel loads on the first solid a worker makes (~1 s, once), in a thread and
    # outside the request's budget and deadline: it is the worker's start-up, not the request's
    # work, and loading it at start would delay every worker's first answer by as much
    await run_in_threadpool(load_kernel)
    payload = await gate.run(request, work, solid_file, service, body.profile, body.solid, fmt.name)
    return Response(payload, media_type=fmt.media_type,
                    headers={"Content-Disposition": f'attachment; filename="{fmt.file_name}"'})


def content(fmt: FileFormat[Any]) -> dict[str, Any]:
    """A download's OpenAPI media type: text for text/*, else bytes."""
    schema = {"type": "string"} if fmt.is_text else {"type": "string", "format": "binary"}
    return {fmt.media_type.split(";")[0]: {"schema": schema}}


SolidBody = Annotated[SolidRequest, Body(openapi_examples=SOLID_EXAMPLES)]


def register(router: APIRouter) -> None:
    """One operation per solid format (``/solid.<ext>``), whose only answer is that file."""
    for fmt in SOLID_FORMATS.values():
        _route(router, fmt)


def _route(router: APIRouter, fmt: FileFormat[SolidCam]) -> None:
    extension = fmt.file_name.rsplit(".", 1)[-1]
    camel = fmt.name.capitalize()

    async def export_solid(body: SolidBody, request: Request, service: Service, gate: Gate) -> Response:
        return await solid_response(request, gate, service, body, fmt)

    export_solid.__doc__ = f"The plate cam as {fmt.description} (``computeProfile`` with ``?format={fmt.name}``)."
    router.add_api_route(f"/solid.{extension}", export_solid, methods=["POST"], operation_id=f"exportProfile{camel}",
                         response_class=Response, summary=f"Export Profile {camel}",
                         responses={**ERRORS, 200: {"content": content(fmt), "description": fmt.description}})
