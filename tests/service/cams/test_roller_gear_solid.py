"""POST /v1/cams/roller-gear as a solid (?format=step, solid-stl; the twins .step, .solid-stl), over ASGI
in-process, the kernel in its own process (service/cad_pool.py).

The STEP file is the one camcore writes for the same cam (the kernel's reader takes it back as one valid
solid; the solid's own checks are tests/camcore/export/test_roller_gear_solid.py); the STL is read by
numpy, closed, of the STEP's volume; bad input is a 422 at its field, whether the service's spec or the
kernel's process finds it; too much work a 413 at solid.tolerance_mm before any of it.
"""

from __future__ import annotations

import re
from typing import Any

import httpx
import numpy as np
import pytest

from camcore.cams.roller_gear import make_roller_gear_cam
from camcore.export.roller_gear_solid import RollerGearSolid
from camcore.export.solid import load_kernel, solid_step
from service.app import create_app
from service.cams.roller_gear_specs import ROLLER_GEAR_EXAMPLE, SOLID_EXAMPLE, SOLID_STL_EXAMPLE
from service.settings import Settings
from tests.estimates import within_estimate
from tests.readers import count_solids, step_shape
from tests.stl_mesh import directed_edges, read_stl

pytestmark = pytest.mark.anyio
PATH = "/v1/cams/roller-gear"
STAMP = re.compile(rb"FILE_NAME\('[^']*','[^']*'")  # the moment of writing, in the header


def volume(shape: Any) -> float:
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, props, 1e-10, True)
    return props.Mass()


async def test_step_is_camcore_s_solid_of_the_cam(client: httpx.AsyncClient) -> None:
    from OCP.BRepCheck import BRepCheck_Analyzer

    one = await client.post(PATH + "?format=step", json=SOLID_EXAMPLE)
    twin = await client.post(PATH + ".step", json=SOLID_EXAMPLE)
    assert one.status_code == twin.status_code == 200, one.text
    assert one.headers["content-type"] == "model/step"
    assert 'filename="roller-gear-cam.step"' in one.headers["content-disposition"]
    shape = step_shape(one.content)
    assert count_solids(shape) == 1 and BRepCheck_Analyzer(shape).IsValid()
    geometry = {k: SOLID_EXAMPLE[k] for k in ("stops", "center_distance_mm", "roller_pitch_radius_mm",
                                              "roller_radius_mm", "roller_length_mm", "indexing_angle_deg")}
    own = solid_step(RollerGearSolid(make_roller_gear_cam(**geometry, curve="MS"), 0.01, 20.0))  # type: ignore[arg-type]
    assert STAMP.sub(b"", one.content) == STAMP.sub(b"", twin.content) == STAMP.sub(b"", own)


async def test_without_solid_the_defaults_make_it(client: httpx.AsyncClient) -> None:
    a = await client.post(PATH + "?format=step", json=ROLLER_GEAR_EXAMPLE)
    b = await client.post(PATH + "?format=step", json=SOLID_EXAMPLE)
    assert a.status_code == b.status_code == 200, a.text
    # no bore: the 20 mm bore's volume more, π·10²·2H with H = 42.43 + 5 mm (the rib's extent, half a roller radius)
    half = (70 * np.sin(np.pi / 4) - 10 * np.cos(np.pi / 4)) + 5
    assert volume(step_shape(a.content)) - volume(step_shape(b.content)) == pytest.approx(np.pi * 100 * 2 * half, rel=1e-6)


async def test_solid_stl_is_the_step_s_solid_closed(client: httpx.AsyncClient) -> None:
    r = await client.post(PATH + "?format=solid-stl", json=SOLID_STL_EXAMPLE)
    assert r.status_code == 200, r.text
    assert r.headers["content-type"] == "model/stl"
    assert 'filename="roller-gear-cam.stl"' in r.headers["content-disposition"]
    facets = read_stl(r.content)
    edges = directed_edges(facets)
    assert all(n == 1 for n in edges.values()) and all(edges[(q, p)] == 1 for p, q in edges)
    mesh_volume = float(np.einsum("ij,ij->i", facets[:, 0], np.cross(facets[:, 1], facets[:, 2])).sum() / 6.0)
    area = float(0.5 * np.linalg.norm(np.cross(facets[:, 1] - facets[:, 0], facets[:, 2] - facets[:, 0]), axis=1).sum())
    step = await client.post(PATH + "?format=step", json=SOLID_STL_EXAMPLE)
    tolerance = SOLID_STL_EXAMPLE["solid"]["tolerance_mm"]  # type: ignore[index]
    # every facet within the tolerance of the exact surface, the STEP's patches within it too
    assert abs(mesh_volume - volume(step_shape(step.content))) <= 2 * area * tolerance


@pytest.mark.parametrize(("change", "loc", "words"), [
    ({"solid": {"bore_diameter_mm": 80}}, ["body", "solid", "bore_diameter_mm"], "leave a wall at the body's throat"),
    ({"solid": {"root_clearance_mm": 30}}, ["body", "solid", "root_clearance_mm"], "no throat"),
    ({"solid": {"tolerance_mm": 0}}, ["body", "solid", "tolerance_mm"], "greater than or equal"),
    # found in the kernel's process, raised in the worker with its field
    ({"solid": {"body_length_mm": 50}}, ["body", "solid", "body_length_mm"], "must cover the rib"),
    ({"curve": {"type": "named", "name": "constant-velocity"}}, ["body", "curve"], "starts at rest"),
    ({"indexing_angle_deg": 30}, ["body", "indexing_angle_deg"], "undercut"),
])
async def test_a_solid_that_cannot_be_made_is_a_422_at_its_field(client: httpx.AsyncClient, change: dict[str, Any],
                                                                 loc: list[str], words: str) -> None:
    r = await client.post(PATH + "?format=step", json={**SOLID_EXAMPLE, **change})
    assert r.status_code == 422, r.text
    error = r.json()["errors"][0]
    assert error["loc"][:len(loc)] == loc and words in r.text


async def test_too_much_work_is_a_413_at_the_tolerance_before_the_work() -> None:
    app = create_app(Settings(max_stl_triangles=10_000))
    async with httpx.AsyncClient(transport=httpx.ASGITransport(app=app), base_url="http://test") as c:
        for path, body, words in (
                (PATH + "?format=solid-stl", SOLID_STL_EXAMPLE, "STL facets"),  # 34 858 facets estimated
                (PATH + "?format=solid-stl", {**SOLID_EXAMPLE, "solid": {"tolerance_mm": 0.01}}, "STL facets"),
        ):
            r = await c.post(path, json=body)
            assert r.status_code == 413, r.text
            assert words in r.text and r.json()["errors"][0]["loc"] == ["body", "solid", "tolerance_mm"]
    # the default budget (1 s): an STL within 0.01 mm is 115 000 facets, 1.1 s measured, 2.8 s estimated
    async with httpx.AsyncClient(transport=httpx.ASGITransport(app=create_app()), base_url="http://test") as c:
        r = await c.post(PATH + "?format=solid-stl", json={**SOLID_EXAMPLE, "solid": {"tolerance_mm": 0.01}})
        assert r.status_code == 413 and r.json()["errors"][0]["loc"] == ["body", "solid", "tolerance_mm"], r.text


class InProcessKernel:
    """The CAD kernel's process stood in for by this one, its process time counted."""

    def __init__(self) -> None:
        self.seconds = 0.0

    def write(self, fmt: str, solid: Any) -> bytes:
        import time

        from camcore.export import SOLID_FORMATS

        start = time.process_time()
        try:
            return SOLID_FORMATS[fmt].write(solid)
        finally:
            self.seconds += time.process_time() - start


WIDE = {"stops": 5, "center_distance_mm": 100, "roller_pitch_radius_mm": 50, "roller_radius_mm": 5,
        "roller_length_mm": 60, "indexing_angle_deg": 100, "curve": {"type": "named", "name": "MT"}}
LARGE = {**ROLLER_GEAR_EXAMPLE, "center_distance_mm": 1000, "roller_pitch_radius_mm": 600, "roller_radius_mm": 100,
         "roller_length_mm": 200}


@pytest.mark.timing
@pytest.mark.parametrize(("fmt", "body"), [
    ("step", SOLID_EXAMPLE), ("solid-stl", SOLID_STL_EXAMPLE),
    ("step", {**SOLID_EXAMPLE, "solid": {"tolerance_mm": 1e-4}}),
    ("step", {**WIDE, "solid": {"tolerance_mm": 1e-4}}),  # the most cam angles for its size measured
    ("step", {**LARGE, "solid": {"tolerance_mm": 1e-4}}),  # 234 cam angles
    ("solid-stl", {**WIDE, "solid": {"tolerance_mm": 0.2}}),
    ("solid-stl", {**ROLLER_GEAR_EXAMPLE, "solid": {"tolerance_mm": 0.5}}),
])
def test_the_estimate_bounds_the_kernel_s_work(fmt: str, body: dict[str, Any]) -> None:
    """The work the kernel's process does (in this one here, its process time) against the estimate
    made before it, the curve built from cold; measured 0.09-0.3 s against 0.27-0.8 s."""
    from service.cams.roller_gear_specs import RollerGearCamRequest
    from service.context import Context
    from service.registry import OPERATIONS

    load_kernel()  # as the kernel's process does before its first solid (service/cad_child.py)
    operation = next(op for op in OPERATIONS if op.id == "computeRollerGearCam")
    ctx = Context.create(Settings())
    kernel = InProcessKernel()
    ctx.cad = kernel  # type: ignore[assignment]
    core = operation.convert(ctx, RollerGearCamRequest.model_validate(body), {})
    estimate = operation.estimate(ctx, core, operation.format(fmt)).seconds
    operation.compute(ctx, core, operation.format(fmt))
    assert kernel.seconds > 0 and within_estimate(kernel.seconds, estimate)


async def test_the_stl_twin_needs_solid_and_the_step_twin_does_not(client: httpx.AsyncClient) -> None:
    r = await client.post(PATH + ".solid-stl", json=ROLLER_GEAR_EXAMPLE)
    assert r.status_code == 422 and r.json()["errors"][0]["loc"] == ["body", "solid"], r.text
    assert (await client.post(PATH + ".solid-stl", json=SOLID_STL_EXAMPLE)).status_code == 200
    assert (await client.post(PATH + ".step", json=ROLLER_GEAR_EXAMPLE)).status_code == 200
