"""The rib of a roller-gear cam: both flanks as point grids, pressure angles, checks, and the rib as a
closed triangle mesh (the method: :mod:`camcore.cams.roller_gear`)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..._checks import count
from ..._maxima import local_grid_max
from ...results import doc
from ..turret import turret_motion
from .geometry import FLANKS, FloatArray, RollerGearCam, flank_state, pressure_angle_rad

#: cam angles over the index at which the largest pressure angle is bracketed before local grids
#: refine it: |β| follows |φ'|, which a catalog law has one hump of, so one grid step brackets it
PRESSURE_GRID = 1025
#: the refined maximum's bracket, at most [rad]
REFINED_WIDTH = 1e-12
#: sampled cam angles listed in the checks where a flank folds, at most
LISTED_ANGLES = 10


@dataclass(frozen=True)
class RibFlank:
    """One flank of the rib in the cam's frame: one row per cam angle, one column per position along the roller."""

    flank: str = field(metadata=doc("forward: faces the roller ahead of the rib; back: the roller behind"))
    x_mm: FloatArray = field(metadata=doc("cam frame"))
    y_mm: FloatArray = field(metadata=doc("cam frame"))
    z_mm: FloatArray = field(metadata=doc("along the cam axis"))
    pressure_angle_deg: FloatArray = field(metadata=doc("at each point: atan(φ'·r / (C − r·cos α))"))
    regular: np.ndarray = field(metadata=doc("false where the flank folds (undercut)"))


@dataclass(frozen=True)
class RibChecks:
    """What limits the cam."""

    max_pressure_angle_deg: float = field(metadata=doc(
        "the largest |pressure angle| at the rollers' pitch radius over the index, both flanks (refined, not sampled)"))
    max_pressure_angle_at_deg: float = field(metadata=doc("the cam angle of it"))
    max_pressure_angle_along_roller_deg: float = field(metadata=doc(
        "the same at the roller's end nearest the cam axis, where it is largest along the roller"))
    undercut: bool = field(metadata=doc("a flank folds at some sampled point: the roller would cut away flank it made"))
    undercut_cam_angles_deg: list[float] = field(metadata=doc(
        "the first sampled cam angles (at most 10) where a flank folds"))
    min_regularity: float = field(metadata=doc(
        "smallest n·(Q_θ × Q_r)/(|Q_θ||Q_r|) over both flank grids: 1 where the flank is swept square to itself, "
        "≤ 0 where it folds"))
    min_rib_thickness_mm: float = field(metadata=doc(
        "smallest distance between the two flanks' points at one cam angle and position along the roller"))
    cam_root_radius_mm: float = field(metadata=doc("the flank points' smallest distance from the cam axis"))
    cam_outer_radius_mm: float = field(metadata=doc("the flank points' largest distance from the cam axis"))


@dataclass(frozen=True)
class RollerGearResult:
    """The turret's motion and the pitch-radius pressure angles over the turn, both flanks, the checks."""

    cam_angle_deg: FloatArray = field(metadata=doc("sampled evenly over the rib's turn, 0 ≤ θ ≤ 360 (both ends)"))
    turret_angle_deg: FloatArray = field(metadata=doc("φ: the turret's turn"))
    pressure_angle_deg: FloatArray = field(metadata=doc("forward flank, at the rollers' pitch radius"))
    back_pressure_angle_deg: FloatArray = field(metadata=doc("back flank, at the rollers' pitch radius"))
    roller_position_mm: FloatArray = field(metadata=doc("r of the flank grids' columns, from the turret axis"))
    forward: RibFlank = field(metadata=doc("the flank facing the roller ahead"))
    back: RibFlank = field(metadata=doc("the flank facing the roller behind"))
    checks: RibChecks = field(metadata=doc("the cam's checks"))


def _largest_pressures(cam: RollerGearCam, radii_mm: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The largest |β| over the index and both flanks at each radius: (cam angles, angles) [rad],
    every flank and radius refined together."""
    index = math.radians(cam.indexer.indexing_angle_deg)
    behind = np.repeat([cam.behind_rad(f) for f in FLANKS], radii_mm.size)[:, None]  # lanes: flank × radius
    radius = np.tile(radii_mm, len(FLANKS))[:, None]

    def size(theta: FloatArray) -> FloatArray:  # one row per lane
        phi, d1, _ = turret_motion(cam.indexer, theta)
        return np.abs(pressure_angle_rad(cam, phi - behind, d1, radius))

    grid = np.linspace(0.0, index, PRESSURE_GRID)
    k = np.argmax(size(np.broadcast_to(grid, (behind.size, grid.size))), axis=1)
    at, value = local_grid_max(size, grid[np.maximum(k - 1, 0)], grid[np.minimum(k + 1, grid.size - 1)],
                               width=REFINED_WIDTH)
    best = np.argmax(value.reshape(len(FLANKS), -1), axis=0)  # the worse flank at each radius
    lanes = best * radii_mm.size + np.arange(radii_mm.size)
    return at[lanes], value[lanes]


def sample_roller_gear(cam: RollerGearCam, samples: int = 361, length_samples: int = 5) -> RollerGearResult:
    """The rib of a roller-gear cam: both flanks, the pressure angles and the checks.

    Parameters
    ----------
    cam : RollerGearCam
        The cam (:func:`camcore.cams.roller_gear.make_roller_gear_cam`).
    samples : int
        Cam angles evenly over the turn, both ends included (the rib's two ends) [-].
    length_samples : int
        Positions evenly along the roller, both ends included [-].

    Returns
    -------
    RollerGearResult
        The turret's angle and the pressure angles at the pitch radius over the turn [deg],
        both flank grids in the cam's frame [mm] and the checks.

    References
    ----------
    INDEXMAN technical guide, section 5 (the index law); Litvin and Fuentes (2004), ch. 6 (the
    envelope and its singular points).
    """
    n, k = count("samples", samples), count("length_samples", length_samples)
    if n < 2 or k < 2:
        raise ValueError("samples and length_samples must each be at least 2 (both ends).")
    theta = np.linspace(0.0, 2 * math.pi, n)
    r_in, r_out = cam.roller_ends_mm
    positions = np.linspace(r_in, r_out, k)
    # once: both flanks and the columns read it; its derivatives at 360° the dwell's (there the law
    # gives the next index's start, whose acceleration a law like constant acceleration jumps to)
    turret = (turret_motion(cam.indexer, theta)[0],
              *turret_motion(cam.indexer, np.minimum(theta, np.nextafter(2 * math.pi, 0.0)))[1:])
    phi, d1, _ = turret
    states = {f: flank_state(cam, f, theta, positions, turret) for f in FLANKS}
    flanks = {f: RibFlank(f, np.ascontiguousarray(s.q[..., 0]), np.ascontiguousarray(s.q[..., 1]),
                          np.ascontiguousarray(s.q[..., 2]), np.degrees(s.pressure_angle_rad), s.regularity > 0)
              for f, s in states.items()}
    folded = np.flatnonzero(~(flanks["forward"].regular.all(axis=1) & flanks["back"].regular.all(axis=1)))
    (at, _), (largest, along) = _largest_pressures(cam, np.array([cam.roller_pitch_radius_mm, r_out]))
    radii = np.concatenate([np.hypot(s.q[..., 0], s.q[..., 1]).ravel() for s in states.values()])
    checks = RibChecks(
        max_pressure_angle_deg=math.degrees(largest), max_pressure_angle_at_deg=math.degrees(at),
        max_pressure_angle_along_roller_deg=math.degrees(along), undercut=bool(folded.size),
        undercut_cam_angles_deg=[float(np.degrees(theta[i])) for i in folded[:LISTED_ANGLES]],
        min_regularity=float(min(s.regularity.min() for s in states.values())),
        min_rib_thickness_mm=float(np.linalg.norm(states["forward"].q - states["back"].q, axis=-1).min()),
        cam_root_radius_mm=float(radii.min()), cam_outer_radius_mm=float(radii.max()))
    pitch = cam.roller_pitch_radius_mm
    return RollerGearResult(
        np.degrees(theta), np.degrees(phi),
        np.degrees(pressure_angle_rad(cam, phi - cam.behind_rad("forward"), d1, pitch)),
        np.degrees(pressure_angle_rad(cam, phi - cam.behind_rad("back"), d1, pitch)),
        positions, flanks["forward"], flanks["back"], checks)


def rib_triangles(result: RollerGearResult) -> FloatArray:
    """The rib as a closed, outward-oriented triangle mesh between its two flank grids.

    Each sampled cam angle gives a cross-section ring: the forward flank's points from the
    roller's inner end to its outer end, then the back flank's back again. Consecutive rings are
    joined by quads (the flanks, the rib's tip along the rollers' inner ends and its root along
    their outer ends) and the first and last rings are closed by caps (the rib's two ends), so
    every edge is shared by exactly two facets.

    Parameters
    ----------
    result : RollerGearResult
        The sampled rib (:func:`sample_roller_gear`).

    Returns
    -------
    ndarray
        Facets, shape (m, 3, 3): three vertices each, counter-clockwise seen from outside [mm].

    References
    ----------
    3D Systems (1989), "StereoLithography Interface Specification": facets of a closed surface,
    vertices counter-clockwise seen from outside.
    """
    f, b = result.forward, result.back
    fwd = np.stack([f.x_mm, f.y_mm, f.z_mm], axis=-1)
    back = np.stack([b.x_mm, b.y_mm, b.z_mm], axis=-1)
    rings = np.concatenate([fwd, back[:, ::-1]], axis=1)  # (angles, 2k, 3)
    n, m = rings.shape[:2]
    vertices = rings.reshape(-1, 3)
    i, j = np.meshgrid(np.arange(n - 1), np.arange(m), indexing="ij")
    a, b_, c, d = i * m + j, i * m + (j + 1) % m, (i + 1) * m + (j + 1) % m, (i + 1) * m + j
    side = np.concatenate([np.stack([a, b_, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    k = m // 2
    jj = np.arange(k - 1)
    # a cap: quads between the forward flank's points j, j+1 and the back flank's (ring positions m−1−j, m−2−j)
    cap = np.concatenate([np.stack([jj, m - 2 - jj, jj + 1], -1), np.stack([jj, m - 1 - jj, m - 2 - jj], -1)])
    faces = np.concatenate([side, cap, (n - 1) * m + cap[:, ::-1]])
    # the facets face out when the rings, in their order, turn positively about the way the rib
    # runs: the sign of Σ A·Δc (A a ring's vector area, c its mean point), the swept volume's
    swept = np.einsum("ij,ij->", 0.5 * np.cross(rings, np.roll(rings, -1, axis=1)).sum(axis=1)[:-1],
                      np.diff(rings.mean(axis=1), axis=0))
    return vertices[faces if swept > 0 else faces[:, ::-1]]
