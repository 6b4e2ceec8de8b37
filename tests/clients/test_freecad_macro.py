"""The FreeCAD macro (clients/freecad) run headless with ``freecadcmd`` against a live server: the solids it
builds are valid and closed, their volumes and boxes are the service's cams, and the rollers touch them.

The macro builds the three cams of clients/freecad/cams.json at a cam angle of 60° (mid-rise of each)
and saves the document; tests/freecad_measure.py, in a second ``freecadcmd``, opens the saved file and
measures it (OpenCASCADE's volumes, validity, tight boxes and distances). Each expectation is computed
here from the service's own answers by another route than the macro's:

* plate cam (the macro reads the service's STEP): thickness × (the contour's area by the shoelace
  formula over 3600 of its points, less the bore);
* barrel cam (the macro lofts the flank grids, ruled): the blank cylinder less the groove, the groove's volume
  integrated over the radius as the area the roller sweeps on each cylinder round the axis, from the
  lift alone (a roller of infinite length on every 0.125° of cam angle);
* roller-gear rib (the macro lofts the flank grids, ruled): the service's STL of the rib, its volume
  summed over signed tetrahedra (tests/stl_mesh.py reads it), plus what the ruled faces add to its
  triangles, computed exactly from the grid.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import httpx
import numpy as np
import pytest

from tests.freecad import measure, run
from tests.stl_mesh import read_stl

ROOT = Path(__file__).resolve().parents[2]
MACRO = ROOT / "clients" / "freecad" / "CamcoreCams.FCMacro"
SPEC = json.loads((ROOT / "clients" / "freecad" / "cams.json").read_text(encoding="utf-8"))
pytestmark = [pytest.mark.e2e, pytest.mark.freecad]

#: OpenCASCADE's confusion tolerance is 1e-7 mm; volumes and distances it computes on exact (STEP or
#: lofted) faces agree with the construction to far better than this
KERNEL_MM = 1e-6
#: cam angles of the barrel's reference groove: 0.125° apart, where the top of the union of two rollers
#: one step apart dips below the true envelope by r²Δ²/(8ρ) ≈ 1e-4 mm (r ≤ 56 mm, ρ = 10 mm)
FINE_SAMPLES = 2881
#: Gauss–Legendre nodes over the groove's depth: the swept area grows smoothly with the radius
DEPTH_NODES = 8


def post(url: str, path: str, body: dict[str, Any]) -> httpx.Response:
    answer = httpx.post(f"{url}{path}", json=body, timeout=60)
    assert answer.status_code == 200, answer.text
    return answer


@pytest.fixture(scope="module")
def built(base_url: str, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """The macro run once headless as docs/ecosystem.md says, then its saved document measured."""
    folder = tmp_path_factory.mktemp("freecad")
    document = folder / "cams.FCStd"
    ran = run(MACRO, folder / "home", CAMCORE_URL=base_url, CAMCORE_SPEC=str(ROOT / "clients/freecad/cams.json"),
              CAMCORE_SAVE=str(document))
    assert document.exists() and "camcore: " in ran.stdout, ran.stdout
    report = json.loads(ran.stdout.split("camcore: ", 1)[1].splitlines()[0])
    return {"report": report, **measure(document, folder / "home")}


def _turned(x: np.ndarray, y: np.ndarray, angle_deg: float) -> tuple[np.ndarray, np.ndarray]:
    c, s = math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg))
    return c * x - s * y, s * x + c * y


def _box_near(got: dict[str, Any], low: np.ndarray, high: np.ndarray, tol_mm: float) -> None:
    assert np.allclose(got["box_min_mm"], low, rtol=0, atol=tol_mm), (got["box_min_mm"], low, tol_mm)
    assert np.allclose(got["box_max_mm"], high, rtol=0, atol=tol_mm), (got["box_max_mm"], high, tol_mm)


def _sound(obj: dict[str, Any]) -> None:
    assert (obj["shape_type"], obj["solids"], obj["valid"], obj["closed"]) == ("Solid", 1, True, True)


def _chord_sag_mm(points: np.ndarray, start: np.ndarray, end: np.ndarray, radius_mm: float) -> float:
    """How deep the straight segments between a flank's contact points along the roller cut into the roller
    (the loft is straight between the grid's points; the contact line curves round the roller)."""
    axis = (end - start) / np.linalg.norm(end - start)
    mid = 0.5 * (points[1:] - start + points[:-1] - start)
    off_axis = np.linalg.norm(mid - np.outer(mid @ axis, axis), axis=1)
    return float(max(0.0, (radius_mm - off_axis).max()))


def _facet_deviation(grid: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Quads between consecutive rows and columns (cyclic) of a point grid: their areas and how far two
    surfaces through the same corner points may stray from each other within them — the twist (the
    bilinear patch's centre lies |a − b + c − d|/4 off either diagonal's triangles) plus the chord's
    sagitta along the rows, |second difference|/8."""
    a, b = grid[:-1], np.roll(grid[:-1], -1, axis=1)
    c, d = np.roll(grid[1:], -1, axis=1), grid[1:]
    area = np.linalg.norm(np.cross(c - a, d - b), axis=-1) / 2
    twist = np.linalg.norm(a - b + c - d, axis=-1) / 4
    second = np.linalg.norm(grid[2:] - 2 * grid[1:-1] + grid[:-2], axis=-1) / 8
    sag = np.pad(second, ((1, 1), (0, 0)), mode="edge")
    sag = np.maximum(sag[:-1], sag[1:])
    return area, twist + np.maximum(sag, np.roll(sag, -1, axis=1))


def test_every_solid_is_valid_closed_and_where_the_report_says(built: dict[str, Any]) -> None:
    objects, report = built["objects"], built["report"]
    names = {n for part in report.values() for n in (part["cam"], *part["rollers"])}
    assert names == set(objects) == {"PlateCam", "PlateCamRoller", "BarrelCam", "BarrelCamRoller", "RollerGearRib",
                                     "RollerGearRollerAhead", "RollerGearRollerBehind"}
    for obj in objects.values():
        _sound(obj)
    for kind, part in report.items():
        assert objects[part["cam"]]["group"] == objects[part["rollers"][0]]["group"]
        # the grids' cam angles are 5° (barrel) and 3° (rib) apart: 60° is sampled
        assert part["cam_angle_deg"] == pytest.approx(SPEC["cam_angle_deg"], abs=1e-9), kind
    for name, contact in built["contacts"].items():
        length = np.linalg.norm(np.subtract(contact["axis_end_mm"], contact["axis_start_mm"]))
        assert objects[name]["volume_mm3"] == pytest.approx(math.pi * contact["radius_mm"] ** 2 * length, rel=1e-12)


def test_plate_cam_is_the_contour_area_times_the_thickness(base_url: str, built: dict[str, Any]) -> None:
    request = SPEC["plate"]["request"]
    solid = request["solid"]
    answer = post(base_url, "/v1/profiles", {"profile": request["profile"], "samples": 3601}).json()
    x, y = np.array(answer["x_mm"][:-1]), np.array(answer["y_mm"][:-1])  # the last point is the first
    area = 0.5 * abs(x @ np.roll(y, -1) - y @ np.roll(x, -1))
    chord = np.hypot(np.diff(answer["x_mm"]), np.diff(answer["y_mm"]))
    radius = np.array([math.inf if r is None else abs(r) for r in answer["radius_of_curvature_mm"]])
    # the polygon strays from the surface by a chord's sagitta, L²/(8ρ), ρ the nearer end's radius
    sag = float((chord**2 / (8 * np.minimum(radius[1:], radius[:-1]))).max())
    # the STEP's lines and arcs are within tolerance_mm of the exact surface, both ways (the service fits
    # and measures them): each strip of the outline may move by that and the sagitta
    band_mm = solid["tolerance_mm"] + sag
    cam = built["objects"]["PlateCam"]
    expected = solid["thickness_mm"] * (area - math.pi * solid["bore_diameter_mm"] ** 2 / 4)
    assert abs(cam["volume_mm3"] - expected) <= solid["thickness_mm"] * chord.sum() * band_mm
    # the cam turns by +θ into the fixed frame (ccw cam, camcore.profile.cam), about its origin
    turned_x, turned_y = _turned(x, y, SPEC["cam_angle_deg"])
    origin = np.array(SPEC["plate"]["origin_mm"], dtype=float)
    _box_near(cam, origin + [turned_x.min(), turned_y.min(), 0], origin + [turned_x.max(), turned_y.max(),
                                                                             solid["thickness_mm"]], band_mm)


def test_plate_roller_touches_the_cam_within_the_step_tolerance(built: dict[str, Any]) -> None:
    contact = built["contacts"]["PlateCamRoller"]
    # the roller stands on the exact pitch point; the STEP surface is within tolerance_mm of the exact
    # surface, which touches the roller: the clearance is at most that, either way
    tolerance_mm = SPEC["plate"]["request"]["solid"]["tolerance_mm"]
    assert abs(contact["clearance_mm"]) <= tolerance_mm + KERNEL_MM
    assert contact["solid_distance_mm"] <= tolerance_mm + KERNEL_MM


def _groove_volume_mm3(lift_mm: np.ndarray, roller_radius_mm: float, bottom_mm: float, outer_mm: float) -> float:
    """The groove of a translating, cylindrical roller between two radii, from the lift alone: on the cylinder
    of radius r the roller's axis at cam angle θ crosses at polar angle θ and height s(θ), and the roller
    (a cylinder of radius ρ round its radial axis, as long as the groove is deep) covers the heights
    s ± √(ρ² − r² sin²(φ − θ)) at polar angle φ. The groove at φ spans the union of these over θ; its
    height over φ, times r dφ, is the area on that cylinder, integrated over r."""
    s = lift_mm[:-1]  # evenly over the turn, the last (360°) left out
    step = 2 * math.pi / s.size
    nodes, weights = np.polynomial.legendre.leggauss(DEPTH_NODES)
    volume = 0.0
    for node, weight in zip(nodes, weights, strict=True):
        r = bottom_mm + (node + 1) / 2 * (outer_mm - bottom_mm)
        reach = math.ceil(math.asin(roller_radius_mm / r) / step)
        k = np.arange(-reach, reach + 1)
        half2 = roller_radius_mm**2 - (r * np.sin(k * step)) ** 2
        k, half = k[half2 >= 0], np.sqrt(half2[half2 >= 0])
        heights = np.stack([np.roll(s, -int(i)) for i in k])  # row i: the roller i steps away from φ
        span = (heights + half[:, None]).max(axis=0) - (heights - half[:, None]).min(axis=0)
        volume += weight * (outer_mm - bottom_mm) / 2 * span.sum() * r * step
    return volume


def _barrel_grid(answer: dict[str, Any], flank: str) -> np.ndarray:
    f = answer["flanks"][flank]
    return np.stack([f["x_mm"], f["y_mm"], f["z_mm"]], axis=-1)


def test_barrel_cam_is_the_blank_less_the_groove_the_roller_sweeps(base_url: str, built: dict[str, Any]) -> None:
    part, cam = SPEC["barrel"], built["objects"]["BarrelCam"]
    request = part["request"]
    rho, length = request["roller_radius_mm"], request["roller_length_mm"]
    outer = request["pitch_radius_mm"] + length / 2
    bottom = outer - length  # groove_depth_mm: its default, the roller's length
    answer = post(base_url, "/v1/cams/barrel", request).json()  # what the macro lofted
    lower, upper = _barrel_grid(answer, "lower"), _barrel_grid(answer, "upper")
    # the blank: the outer radius, from the lowest flank point to the highest, with the shoulders
    z_low, z_high = lower[..., 2].min() - part["shoulder_mm"], upper[..., 2].max() + part["shoulder_mm"]
    fine = post(base_url, "/v1/cams/barrel", {**request, "samples": FINE_SAMPLES, "length_samples": 2}).json()
    groove = _groove_volume_mm3(np.array(fine["lift_mm"]), rho, bottom, outer)
    expected = math.pi * outer**2 * (z_high - z_low) - groove
    # the macro's walls (ruled between consecutive sections) and the roller's exact envelope pass through
    # the same flank points; between them they may part by the grid's twist and sagitta over each quad
    # (the bottom and the outside are the same cylinders in both); the reference's own steps: a 1e-4 mm
    # dip over the groove's walls
    deviation = sum(float((area * stray).sum()) for area, stray in map(_facet_deviation, (lower, upper)))
    walls = sum(float(_facet_deviation(grid)[0].sum()) for grid in (lower, upper))
    assert abs(cam["volume_mm3"] - expected) <= deviation + 1e-4 * walls
    origin = np.array(part["origin_mm"], dtype=float)
    _box_near(cam, origin + [-outer, -outer, z_low], origin + [outer, outer, z_high], KERNEL_MM)


def test_barrel_roller_touches_both_flanks(base_url: str, built: dict[str, Any]) -> None:
    request = SPEC["barrel"]["request"]
    answer = post(base_url, "/v1/cams/barrel", request).json()
    i = answer["cam_angle_deg"].index(SPEC["cam_angle_deg"])
    theta = math.radians(SPEC["cam_angle_deg"])
    # in the cam's frame the roller's axis at cam angle θ is radial at polar angle θ, at the lift's height
    direction = np.array([math.cos(theta), math.sin(theta), 0.0])
    start = np.array([0.0, 0.0, answer["lift_mm"][i]])
    sag = max(_chord_sag_mm(_barrel_grid(answer, f)[i], start, start + direction, request["roller_radius_mm"])
              for f in ("lower", "upper"))
    contact = built["contacts"]["BarrelCamRoller"]
    # the groove's section at that cam angle is the row's points, which lie on the roller: touching, with
    # the straight stretches between them at most their sagitta deep in it
    assert -sag - KERNEL_MM <= contact["clearance_mm"] <= KERNEL_MM
    assert contact["solid_distance_mm"] <= KERNEL_MM


def _rib_rings(answer: dict[str, Any]) -> np.ndarray:
    f, b = answer["flanks"]["forward"], answer["flanks"]["back"]
    forward = np.stack([f["x_mm"], f["y_mm"], f["z_mm"]], axis=-1)
    back = np.stack([b["x_mm"], b["y_mm"], b["z_mm"]], axis=-1)
    return np.concatenate([forward, back[:, ::-1]], axis=1)


def _ruled_correction_mm3(rings: np.ndarray) -> float:
    """What the rib's ruled faces add to the volume of the STL's triangles (two per quad of the rings,
    split along a → c): per quad, a third of the flux of the position through the bilinear patch
    p(u, v) = a + u(b − a) + v(d − a) + uv(a − b + c − d) (2 × 2 Gauss points: exact, the integrand
    being quadratic in each of u and v) less that through the two triangles (divergence theorem)."""
    a, b = rings[:-1], np.roll(rings[:-1], -1, axis=1)
    c, d = np.roll(rings[1:], -1, axis=1), rings[1:]
    e1, e2, w = b - a, d - a, a - b + c - d
    flux = np.zeros(a.shape[:-1])
    for u in (0.5 - 0.5 / math.sqrt(3), 0.5 + 0.5 / math.sqrt(3)):
        for v in (0.5 - 0.5 / math.sqrt(3), 0.5 + 0.5 / math.sqrt(3)):
            p = a + u * e1 + v * e2 + u * v * w
            flux += 0.25 * np.einsum("...i,...i->...", p, np.cross(e1 + v * w, e2 + u * w))
    triangles = 0.5 * (np.einsum("...i,...i->...", a, np.cross(b, c)) + np.einsum("...i,...i->...", a, np.cross(c, d)))
    return float((flux - triangles).sum() / 3)


def _orientation(facets: np.ndarray, rings: np.ndarray) -> float:
    """+1 when the STL has the first quad's triangle (a, b, c) as the rings run, −1 when reversed."""
    def key(tri: np.ndarray) -> tuple[float, ...]:
        return tuple(np.round(tri, 3).ravel().tolist())
    written = {key(np.roll(f, k, axis=0)) for f in facets[:4 * rings.shape[1]] for k in range(3)}
    mine = np.array([rings[0, 0], rings[0, 1], rings[1, 1]], dtype=np.float32).astype(np.float64)
    if key(mine) in written:
        return 1.0
    assert key(mine[::-1]) in written, "the STL's first facets are not the rings' quads"
    return -1.0


def test_roller_gear_rib_has_the_volume_of_the_service_stl(base_url: str, built: dict[str, Any]) -> None:
    part, rib = SPEC["roller_gear"], built["objects"]["RollerGearRib"]
    facets = read_stl(post(base_url, "/v1/cams/roller-gear?format=stl", part["request"]).content)
    stl_volume = float(np.einsum("ij,ij->", facets[:, 0], np.cross(facets[:, 1], facets[:, 2])) / 6)
    # the macro's rib and the STL join the same points (the rings: forward flank out, back flank in), the
    # rib's faces ruled between consecutive rings, the STL's two triangles per quad: their difference
    # is computed exactly from the grid
    rings = _rib_rings(post(base_url, "/v1/cams/roller-gear", part["request"]).json())
    expected = stl_volume + _orientation(facets, rings) * _ruled_correction_mm3(rings)
    # the STL's vertices are float32 (a relative 6e-8 each, times the rib's area and extent, ~1e-3 mm³):
    # a relative 1e-7 of the volume covers it
    assert rib["volume_mm3"] == pytest.approx(expected, rel=1e-7)
    _, stray = _facet_deviation(rings)
    # the rib turns by +θ into the fixed frame (camcore.cams.roller_gear), about its origin; its ruled
    # faces reach out past the triangles' box by at most a quad's twist (within the stray)
    x, y = _turned(facets[..., 0].ravel(), facets[..., 1].ravel(), SPEC["cam_angle_deg"])
    z = facets[..., 2].ravel()
    origin = np.array(part["origin_mm"], dtype=float)
    _box_near(rib, origin + [x.min(), y.min(), z.min()], origin + [x.max(), y.max(), z.max()], float(stray.max()))


def test_roller_gear_rollers_touch_the_rib(base_url: str, built: dict[str, Any]) -> None:
    request = SPEC["roller_gear"]["request"]
    answer = post(base_url, "/v1/cams/roller-gear", request).json()
    i = int(np.argmin(np.abs(np.array(answer["cam_angle_deg"]) - SPEC["cam_angle_deg"])))
    theta = math.radians(answer["cam_angle_deg"][i])
    h = 2 * math.pi / request["stops"]
    rings = _rib_rings(answer)
    k = len(answer["roller_position_mm"])
    origin = np.array(SPEC["roller_gear"]["origin_mm"], dtype=float)
    turret = np.array([request["center_distance_mm"], 0.0, 0.0])
    rp, half = request["roller_pitch_radius_mm"], request["roller_length_mm"] / 2
    for name, flank, behind in (("RollerGearRollerAhead", rings[i, :k], 0.0),
                                ("RollerGearRollerBehind", rings[i, k:], h)):
        # the roller at turret angle α (φ ahead of the rib, φ − h behind it): axis A + r·(−cos α, 0, sin α)
        alpha = math.radians(answer["turret_angle_deg"][i]) - behind
        u = np.array([-math.cos(alpha), 0.0, math.sin(alpha)])
        # its axis in the cam's frame: turned back by θ (a fixed-frame point p is R_z(−θ)·p there)
        start, end = (np.array([*_turned(np.array(p[0]), np.array(p[1]), -math.degrees(theta)), p[2]], dtype=float)
                      for p in (turret + (rp - half) * u, turret + (rp + half) * u))
        sag = _chord_sag_mm(flank, start, end, request["roller_radius_mm"])
        contact = built["contacts"][name]
        # the roller stands where the service's turret angle puts it (same frame as the macro's axis)
        x, y = _turned(np.array([start[0], end[0]]), np.array([start[1], end[1]]), math.degrees(theta))
        fixed = np.column_stack([x, y, [start[2], end[2]]]) + origin
        assert np.allclose([contact["axis_start_mm"], contact["axis_end_mm"]], fixed, rtol=0, atol=KERNEL_MM)
        # the loft passes through the ring's points on the roller; straight between them along the roller
        assert -sag - KERNEL_MM <= contact["clearance_mm"] <= KERNEL_MM, (name, sag)
        assert contact["solid_distance_mm"] <= KERNEL_MM
