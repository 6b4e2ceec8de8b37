"""``?format=step`` and ``stl`` on POST /v1/cams/barrel (and their twins) over ASGI in-process.

The file is camcore's solid as it is (camcore.export.barrel_solid, checked against the exact
groove in tests/camcore/export/test_barrel_solid.py): here the service's STEP, read back by the
kernel's reader, is one valid solid with the volume of the same solid built here; the STL is
closed; a body without ``solid`` or with a bore through the groove's floor is a 422 at that
field; an STL too fine for the budget a 413 before any work; and the estimate bounds the work of
each example, the work measured here in this process (the service does it in the CAD kernel's).
"""

from __future__ import annotations

import copy
import gc
import time
from typing import Any

import httpx
import pytest

from camcore.export import SOLID_FORMATS
from camcore.export.barrel_solid import BarrelSolid
from camcore.export.solid import load_kernel
from service.app import create_app
from service.cams import barrel
from service.cams.barrel_specs import (
    BARREL_EXAMPLE,
    BARREL_SOLID_EXAMPLE,
    CONICAL_BARREL_EXAMPLE,
    OSCILLATING_BARREL_EXAMPLE,
    BarrelSolidRequest,
)
from service.context import Context
from service.settings import Settings
from tests.camcore.export.test_barrel_solid import kernel_volume
from tests.estimates import within_estimate
from tests.readers import count_solids, step_shape
from tests.stl_mesh import directed_edges, read_stl

pytestmark = pytest.mark.anyio


def with_solid(base: dict[str, Any], **solid: Any) -> dict[str, Any]:
    out = copy.deepcopy(base)
    out["solid"] = solid
    return out


async def test_step_and_stl_by_format_and_by_their_twins(client: httpx.AsyncClient) -> None:
    from OCP.BRepCheck import BRepCheck_Analyzer

    answers = {}
    for name, fmt in SOLID_FORMATS.items():
        r = await client.post(f"/v1/cams/barrel?format={name}", json=BARREL_SOLID_EXAMPLE)
        assert r.status_code == 200, r.text
        assert r.headers["content-type"] == fmt.media_type
        assert r.headers["content-disposition"] == f'attachment; filename="barrel_cam.{name}"'
        twin = await client.post(f"/v1/cams/barrel.{name}", json=BARREL_SOLID_EXAMPLE)
        assert twin.status_code == 200 and twin.headers["content-type"] == fmt.media_type
        answers[name] = r.content
    shape = step_shape(answers["step"])
    assert count_solids(shape) == 1 and BRepCheck_Analyzer(shape).IsValid()
    # the same solid built here from the cam the service builds: the service adds nothing and drops nothing
    spec = BarrelSolidRequest.model_validate(BARREL_SOLID_EXAMPLE)
    own = BarrelSolid(barrel.barrel_cam(Context.create(Settings()), spec), 0.05, None, 20.0)
    assert kernel_volume(shape) == pytest.approx(kernel_volume(step_shape(SOLID_FORMATS["step"].write(own))),
                                                 rel=1e-12)
    facets = read_stl(answers["stl"])
    edges = directed_edges(facets)
    assert all(n == 1 for n in edges.values()) and all(edges[(q, p)] == 1 for p, q in edges)


@pytest.mark.parametrize("example", [OSCILLATING_BARREL_EXAMPLE, CONICAL_BARREL_EXAMPLE],
                         ids=["oscillating", "conical"])
async def test_the_other_followers_are_solids_too(client: httpx.AsyncClient, example: dict[str, Any]) -> None:
    r = await client.post("/v1/cams/barrel.step", json=with_solid(example, tolerance_mm=0.05))
    assert r.status_code == 200, r.text
    assert count_solids(step_shape(r.content)) == 1


@pytest.mark.parametrize(("body", "loc"), [
    (BARREL_EXAMPLE, ["body", "solid"]),
    (with_solid(BARREL_EXAMPLE, bore_diameter_mm=88), ["body", "solid", "bore_diameter_mm"]),
    (with_solid(BARREL_EXAMPLE, tolerance_mm=0), ["body", "solid", "tolerance_mm"]),
    (with_solid(BARREL_EXAMPLE, end_margin_mm=0), ["body", "solid", "end_margin_mm"]),
])
async def test_refusals_name_the_field(client: httpx.AsyncClient, body: dict[str, Any], loc: list[str]) -> None:
    r = await client.post("/v1/cams/barrel?format=step", json=body)
    assert r.status_code == 422, r.text
    assert r.json()["errors"][0]["loc"] == loc


async def test_a_corner_is_a_422_and_a_fine_stl_a_413() -> None:
    corner = with_solid(BARREL_EXAMPLE, tolerance_mm=0.05)
    corner["segments"] = [{"type": "rise", "angle_deg": 180, "lift_mm": 20,
                           "curve": {"type": "named", "name": "constant-velocity"}},
                          {"type": "return", "angle_deg": 180, "lift_mm": 20,
                           "curve": {"type": "named", "name": "constant-velocity"}}]
    async with httpx.AsyncClient(transport=httpx.ASGITransport(app=create_app()), base_url="http://t") as client:
        r = await client.post("/v1/cams/barrel?format=step", json=corner)
        assert r.status_code == 422 and r.json()["errors"][0]["loc"] == ["body", "solid"], r.text
        fine = with_solid(BARREL_EXAMPLE, tolerance_mm=0.001)
        r = await client.post("/v1/cams/barrel?format=stl", json=fine)
        assert r.status_code == 413 and r.json()["errors"][0]["loc"] == ["body", "solid", "tolerance_mm"], r.text


#: (body, format): every example as STEP and STL; a fine STEP (an STL at 1e-3 mm takes ~6 s, and is refused)
CASES = [(body, fmt) for body in (BARREL_SOLID_EXAMPLE, with_solid(OSCILLATING_BARREL_EXAMPLE, tolerance_mm=0.01),
                                  with_solid(CONICAL_BARREL_EXAMPLE, tolerance_mm=0.01)) for fmt in SOLID_FORMATS]
CASES.append((with_solid(BARREL_EXAMPLE, tolerance_mm=1e-3), "step"))


@pytest.mark.timing
@pytest.mark.parametrize(("value", "fmt"), CASES,
                         ids=[f"{n}-{f}" for n in ("example", "oscillating", "conical") for f in SOLID_FORMATS]
                         + ["fine-step"])
def test_the_estimate_bounds_the_work(value: dict[str, Any], fmt: str) -> None:
    """The estimate against the solid's work done here, in this thread (the service's work is the
    kernel process's, whose CPU time the common test cannot see), from cold caches; the kernel
    loaded first, as the service's warm-up loads it outside the budget."""
    load_kernel()
    (operation,) = barrel.OPERATIONS
    spec = BarrelSolidRequest.model_validate(value)
    ctx = Context.create(Settings())
    chosen = operation.format(fmt)
    estimate = operation.estimate(ctx, operation.convert(ctx, spec, {}), chosen).seconds
    gc.disable()
    try:
        start = time.thread_time()
        item = BarrelSolid(barrel.barrel_cam(ctx, spec), spec.solid.tolerance_mm, spec.solid.end_margin_mm,
                           spec.solid.bore_diameter_mm)
        SOLID_FORMATS[fmt].write(item)
        seconds = time.thread_time() - start
    finally:
        gc.enable()
    assert within_estimate(seconds, estimate), f"{seconds:.3f} s, estimated {estimate:.3f} s"
