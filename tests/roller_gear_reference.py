"""The roller-gear cam's solid rebuilt by the tests' own means, for the tests of its STEP and STL files.

Nothing here goes through camcore.cams.roller_gear.surfaces: the flanks' crossings of the tori are
found by bisection on the exact flank points (``flank_state``, itself checked against the rollers in
tests/camcore/cams/test_roller_gear.py), the body's volume is the closed form of a solid of
revolution, the rib's volume the divergence theorem over a triangle mesh of its boundary built here,
and contact and interference are scanned over the cam angle against the rollers placed by the index
law.
"""

from __future__ import annotations

import math

import numpy as np

from camcore.cams.roller_gear import flank_state
from camcore.cams.roller_gear.geometry import RollerGearCam
from camcore.cams.turret import turret_motion


def torus_distance(c_mm: float, points: np.ndarray) -> np.ndarray:
    """A point's distance from the circle of radius C about the cam axis in the plane z = 0 [mm]."""
    return np.hypot(c_mm - np.hypot(points[..., 0], points[..., 1]), points[..., 2])


def onto_torus(c_mm: float, radius_mm: float, points: np.ndarray) -> np.ndarray:
    """The nearest points of the torus d = R: each point moved along its meridian plane."""
    rho = np.hypot(points[..., 0], points[..., 1])
    depth, z = c_mm - rho, points[..., 2]
    scale = radius_mm / np.hypot(depth, z)
    ring = c_mm - depth * scale
    return np.stack([points[..., 0] * ring / rho, points[..., 1] * ring / rho, z * scale], axis=-1)


def crossing(cam: RollerGearCam, flank: str, theta: np.ndarray, radius_mm: float, lo: float, hi: float) -> np.ndarray:
    """r along the roller where the flank crosses the torus d = R, by bisection in [lo, hi] (60 halvings)."""
    c = cam.center_distance_mm
    a, b = np.full(theta.size, lo), np.full(theta.size, hi)

    def d(r: np.ndarray) -> np.ndarray:  # one position along the roller per cam angle
        return torus_distance(c, flank_state(cam, flank, theta, r[:, None]).q[:, 0])

    rising = d(b) > d(a)
    for _ in range(60):
        mid = 0.5 * (a + b)
        above = (d(mid) > radius_mm) == rising
        b, a = np.where(above, mid, b), np.where(above, a, mid)
    return 0.5 * (a + b)


def rib_rings(cam: RollerGearCam, theta: np.ndarray, top_mm: float, root_mm: float, across: int
              ) -> np.ndarray:
    """Closed cross-section rings of the rib at each θ: the forward flank from the top to the root, the
    root (on its torus) to the back flank, the back flank up, the top back: shape (θ, 4·across, 3) [mm]."""
    r_in, r_out = cam.roller_ends_mm
    rr = cam.roller_radius_mm
    c = cam.center_distance_mm
    s = np.linspace(0.0, 1.0, across + 1)
    flanks = {}
    for flank in ("forward", "back"):
        top = crossing(cam, flank, theta, top_mm, r_in - rr, r_out)
        root = crossing(cam, flank, theta, root_mm, r_in, r_out + 2 * rr)
        r = top[:, None] + s[None, :] * (root - top)[:, None]
        flanks[flank] = flank_state(cam, flank, theta, r).q
    f, b = flanks["forward"], flanks["back"]
    w = s[1:-1, None]
    root_arc = onto_torus(c, root_mm, f[:, -1:, :] * (1 - w) + b[:, -1:, :] * w)
    top_arc = onto_torus(c, top_mm, b[:, :1, :] * (1 - w) + f[:, :1, :] * w)
    return np.concatenate([f, root_arc, b[:, ::-1], top_arc], axis=1)


def ring_mesh_volume_area(rings: np.ndarray) -> tuple[float, float]:
    """Volume and outer area of the closed mesh of consecutive rings, capped at both ends by fans
    (the divergence theorem: the sum of the facets' signed tetrahedra from the origin) [mm³, mm²]."""
    a, b = rings[:-1], np.roll(rings[:-1], -1, axis=1)
    c, d = np.roll(rings[1:], -1, axis=1), rings[1:]
    facets = [np.stack([a, b, c], axis=-2).reshape(-1, 3, 3), np.stack([a, c, d], axis=-2).reshape(-1, 3, 3)]
    for ring, sign in ((rings[0], -1), (rings[-1], 1)):
        centre = ring.mean(axis=0)
        fan = np.stack([np.broadcast_to(centre, ring.shape), np.roll(ring, -1, axis=0), ring], axis=1)
        facets.append(fan if sign > 0 else fan[:, ::-1])
    tri = np.concatenate(facets)
    volume = float(np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])).sum() / 6.0)
    area = float(0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1).sum())
    return abs(volume), area


def body_volume(c_mm: float, root_mm: float, half_mm: float, bore_mm: float = 0.0) -> float:
    """The hourglass ρ ≤ C − √(R² − z²), |z| ≤ H, less a bore: π∫(C − √(R² − z²))² dz − π·b²·2H [mm³]."""
    chord = half_mm * math.sqrt(root_mm ** 2 - half_mm ** 2) + root_mm ** 2 * math.asin(half_mm / root_mm)
    whole = math.pi * ((c_mm ** 2 + root_mm ** 2) * 2 * half_mm - 2 * half_mm ** 3 / 3 - 2 * c_mm * chord)
    return whole - math.pi * (0.5 * bore_mm) ** 2 * 2 * half_mm


def clearance_table(cam: RollerGearCam, points: np.ndarray, theta: np.ndarray, rollers: range,
                    reach_mm: float = 0.0) -> np.ndarray:
    """Each point's distance from the nearest listed roller's surface at each cam angle of its row of
    ``theta`` (shape (points, angles)): from the roller's axis − Rr, where the foot of the perpendicular
    lies on the roller, its ends moved out by ``reach_mm`` (else inf) [mm]; negative inside a roller.
    Roller j stands at α = φ(θ) + j·360°/stops, its axis from A = (C, 0, 0) along (−cos α, 0, sin α)."""
    rr, c = cam.roller_radius_mm, cam.center_distance_mm
    r_in, r_out = cam.roller_ends_mm
    phi, _, _ = turret_motion(cam.indexer, theta.reshape(-1))
    phi = phi.reshape(theta.shape)
    cos_t, sin_t = np.cos(theta), np.sin(theta)
    x = cos_t * points[:, None, 0] - sin_t * points[:, None, 1] - c
    y = sin_t * points[:, None, 0] + cos_t * points[:, None, 1]
    z = np.broadcast_to(points[:, None, 2], x.shape)
    best = np.full(x.shape, np.inf)
    for j in rollers:
        alpha = phi + j * cam.index_rad
        ux, uz = -np.cos(alpha), np.sin(alpha)
        t = x * ux + z * uz
        dist = np.sqrt(np.maximum((x - t * ux) ** 2 + y ** 2 + (z - t * uz) ** 2, 0.0)) - rr
        dist = np.where((t >= r_in - reach_mm) & (t <= r_out + reach_mm), dist, np.inf)
        best = np.minimum(best, dist)
    return best


def least_clearance(cam: RollerGearCam, points: np.ndarray, rollers: range, reach_mm: float = 0.0,
                    step_deg: float = 0.25) -> np.ndarray:
    """The smallest of :func:`clearance_table` over the whole turn: every ``step_deg``, then twice over
    each point's best angle ± one step at a fiftieth of it (the distance is smooth in θ near its
    minimum, so the last grid's error is of order (step/2500)² times its curvature) [mm]."""
    grid = np.radians(np.arange(0.0, 360.0 + step_deg, step_deg))
    table = clearance_table(cam, points, np.broadcast_to(grid, (points.shape[0], grid.size)), rollers, reach_mm)
    at, width = grid[np.argmin(table, axis=1)], math.radians(step_deg)
    for _ in range(2):
        local = at[:, None] + np.linspace(-width, width, 101)[None, :]
        table = clearance_table(cam, points, local, rollers, reach_mm)
        at, width = local[np.arange(points.shape[0]), np.argmin(table, axis=1)], width / 50
    return table.min(axis=1)


def top_radius(cam: RollerGearCam) -> float:
    """The rib's top by a scan: the smallest d of both flanks at the rollers' inner end over the index,
    every 0.01°, then ±0.01° every 1e-6° (d is smooth in θ: ½·d″·(1e-6°)² is below 1e-13 mm)."""
    r_in = cam.roller_ends_mm[0]
    best = math.inf
    for flank in ("forward", "back"):
        grid = np.radians(np.arange(0.0, cam.indexer.indexing_angle_deg + 0.01, 0.01))
        for _ in range(2):
            d = torus_distance(cam.center_distance_mm, flank_state(cam, flank, grid, [r_in]).q[:, 0])
            k = int(np.argmin(d))
            grid = np.linspace(grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)], 20001)
        best = min(best, float(d.min()))
    return min(best, math.hypot(r_in, cam.roller_radius_mm))
