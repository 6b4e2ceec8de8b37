"""Contour downloads come from one registry (camcore.export.FORMATS): the service's
``?format=`` values, answer headers and OpenAPI media types are read from it, so a new
format is one entry there (issue 14)."""

from __future__ import annotations

import io

import ezdxf
import httpx
import numpy as np
import pytest

from camcore import export
from service.app import create_app

ROLLER = {"follower": {"type": "roller", "roller_radius_mm": 10}, "base_radius_mm": 40,
          "segments": [{"type": "rise", "angle_deg": 180, "lift_mm": 20, "curve": {"type": "named", "name": "MS"}},
                       {"type": "return", "angle_deg": 180, "lift_mm": 20}]}
BODY = {"profile": ROLLER, "samples": 37}


@pytest.mark.anyio
@pytest.mark.parametrize("name", list(export.FORMATS))
async def test_every_registered_format_is_served_as_registered(client: httpx.AsyncClient, name: str) -> None:
    fmt = export.FORMATS[name]
    r = await client.post(f"/v1/profiles?format={name}", json=BODY)
    assert r.status_code == 200, r.text
    assert r.headers["content-type"] == fmt.media_type
    assert r.headers["content-disposition"] == f'attachment; filename="{fmt.file_name}"'
    cols = (await client.post("/v1/profiles", json=BODY)).json()
    contour = export.Contour(np.array(cols["x_mm"]), np.array(cols["y_mm"]), np.array(cols["cam_angle_deg"]),
                             ROLLER["base_radius_mm"])
    if fmt.is_text:
        assert r.content == fmt.write(contour)
    else:  # a DXF carries its creation time and fresh GUIDs: compare what it draws
        assert _drawing(r.content) == _drawing(fmt.write(contour))


def _drawing(dxf: bytes) -> tuple[object, ...]:
    """A DXF's extents and its entities: type, layer and geometry."""
    doc = ezdxf.read(io.StringIO(dxf.decode()))
    entities = []
    for e in doc.modelspace():
        if e.dxftype() == "LWPOLYLINE":
            shape: object = list(e.get_points("xy"))
        elif e.dxftype() == "SPLINE":
            shape = [tuple(p) for p in e.fit_points]
        else:
            shape = (tuple(e.dxf.center), e.dxf.radius)
        entities.append((e.dxftype(), e.dxf.layer, shape))
    return tuple(doc.header["$EXTMIN"]), tuple(doc.header["$EXTMAX"]), entities


def test_the_openapi_document_offers_every_registered_format() -> None:
    op = create_app().openapi()["paths"]["/v1/profiles"]["post"]
    (param,) = [p for p in op["parameters"] if p["name"] == "format"]
    enum = param["schema"]["enum"]
    assert enum == ["json", "csv", *export.FORMATS, *export.SOLID_FORMATS]
    content = op["responses"]["200"]["content"]
    for fmt in [*export.FORMATS.values(), *export.SOLID_FORMATS.values()]:
        schema = content[fmt.media_type.split(";")[0]]["schema"]
        assert schema == ({"type": "string"} if fmt.is_text else {"type": "string", "format": "binary"})
        assert f"`{fmt.name}`" in param["description"] and fmt.description in param["description"]
