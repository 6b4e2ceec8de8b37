"""The roller-gear cam's solid, its dimensions chosen from the cam: the body's torus, the rib's top,
the body's length and bore, and the rules a cam must keep to have a solid (the faces are fitted by
:mod:`camcore.cams.roller_gear.surfaces`, the solid made by :mod:`camcore.export.roller_gear_solid`).

The cam
-------
Let d(X) = √((C − ρ)² + z²) be a point's distance from the circle the turret axis's point A = (C, 0,
0) sweeps about the cam axis (ρ its distance from the cam axis): a surface d = R is a torus about the
cam axis, an hourglass on the cam's side of the turret. The cam is

* the **body**: d ≥ R_root, |z| ≤ H (less a bore), the globoidal core. R_root = √(r_out² + Rr²) +
  clearance: the circle the rim of the rollers' outer ends sweeps (a roller's axis point at r_out is
  at d = r_out, the rim of its flat end at up to √(r_out² + Rr²): a core at d = r_out would cut
  Rr²/(2·r_out) into every roller's end edge). Its throat radius is C − R_root.
* the **rib** on it: R_top ≤ d ≤ R_root between the two flanks over the rib's turn, θ from 0 to 2π.
  R_top is the smallest d of the flanks' line at the rollers' inner end, r = r_in, over the turn
  (found on a grid over the index and refined): the rib's top then lies nowhere above that line,
  so every roller meets flank over its whole working length at every cam angle. A flank point at
  r is at d ≤ √(r² + Rr²), equal in the dwell (β = 0) and less where the contact moves off the
  plane of the line of centres, so in the dwell the rib stands up to √(r_in² + Rr²) − R_top above
  the rollers' inner ends (the flank there is the envelope of the roller's cylinder continued).
  Likewise below: a flank point at r_out is at d ≤ √(r_out² + Rr²) ≤ R_root, so the flank reaches
  the body nowhere above the rollers' outer ends. The rib's ends are its sections at θ = 0 and 2π,
  in the plane of the line of centres (y = 0) when the law starts at rest.
* H, half the body's length: the rib's largest |z| plus half a roller radius, unless given.

References
----------
.. [1] INDEXMAN technical guide, sections 2-1 to 2-4 (the roller-gear cam, its rollers and rib).
.. [2] Litvin and Fuentes (2004), ch. 6 (the flank as an envelope: camcore.cams.roller_gear).
"""

from __future__ import annotations

import math

import numpy as np

from ..._maxima import local_grid_max
from ...curves.base import FloatArray
from ...errors import GeometryError, InvalidParameterError
from ..turret import turret_motion
from ._splines import torus_distance
from .geometry import FLANKS, Flank, RollerGearCam, flank_state

#: the index law's velocity at the start of an index, at most, for the rib's end to lie in the plane
#: of the line of centres
REST = 1e-9
#: the cam angles over the index at which R_top is bracketed before it is refined to TOP_WIDTH [rad]:
#: d at the rollers' inner end dips once, where β is largest, as |β| follows |φ'| (compute.py)
TOP_GRID = 1025
TOP_WIDTH = 1e-12
#: the default body reaches this share of a roller radius beyond the rib at each end
BODY_MARGIN_SHARE = 0.5

#: the thinnest wall a bore may leave at the body's throat, as a share of the throat radius
MIN_WALL_SHARE = 0.01


def check_solid_body(center_distance_mm: float, roller_outer_end_mm: float, roller_radius_mm: float,
                     root_clearance_mm: float = 0.0, bore_diameter_mm: float = 0.0) -> float:
    """Raise for a body without a throat or a bore that leaves no wall there; the body's torus radius.

    Parameters
    ----------
    center_distance_mm : float
        C [mm].
    roller_outer_end_mm : float
        r_out, the rollers' outer end from the turret axis [mm].
    roller_radius_mm : float
        Rr [mm].
    root_clearance_mm : float
        The body's torus beyond the circle of the rollers' outer rims, ≥ 0 [mm].
    bore_diameter_mm : float
        The bore, ≥ 0 and at most the throat's diameter less :data:`MIN_WALL_SHARE` [mm].

    Returns
    -------
    float
        R_root = √(r_out² + Rr²) + clearance (module notes) [mm].

    Raises
    ------
    InvalidParameterError, GeometryError
        With the field: solid.root_clearance_mm, center_distance_mm or solid.bore_diameter_mm.

    References
    ----------
    The module notes (the body's torus under the rollers' outer rims).
    """
    if not (math.isfinite(root_clearance_mm) and root_clearance_mm >= 0):
        raise InvalidParameterError(f"root_clearance_mm must be at least 0, got {root_clearance_mm!r}.",
                                    field=("solid", "root_clearance_mm"))
    root = math.hypot(roller_outer_end_mm, roller_radius_mm) + root_clearance_mm
    throat = center_distance_mm - root
    if not throat > 0:
        raise GeometryError(
            f"The body would have no throat: its radius there, center_distance_mm − √(r_out² + roller_radius_mm²) − "
            f"root_clearance_mm = {throat:.6g} mm, must be positive (r_out = roller_pitch_radius_mm + "
            "roller_length_mm/2).", field=("solid", "root_clearance_mm") if root_clearance_mm > 0 else ("center_distance_mm",))
    largest = 2 * throat * (1.0 - MIN_WALL_SHARE)
    if not (math.isfinite(bore_diameter_mm) and 0.0 <= bore_diameter_mm <= largest):
        raise InvalidParameterError(
            f"bore_diameter_mm must be at least 0 and leave a wall at the body's throat: at most {largest:.6g} mm (the "
            f"throat's diameter, {2 * throat:.6g} mm, less {MIN_WALL_SHARE:.0%}), got {bore_diameter_mm!r}.",
            field=("solid", "bore_diameter_mm"))
    return root


def top_radius(cam: RollerGearCam) -> float:
    """R_top: the smallest d of both flanks at the rollers' inner end over the turn (module notes).

    Parameters
    ----------
    cam : RollerGearCam
        The cam.

    Returns
    -------
    float
        The rib's top torus radius [mm].

    References
    ----------
    The module notes; Kiefer (1953) for the refinement (camcore._maxima.local_grid_max).
    """
    r_in, c = cam.roller_ends_mm[0], cam.center_distance_mm
    grid = np.linspace(0.0, math.radians(cam.indexer.indexing_angle_deg), TOP_GRID)

    def height(flank: Flank, theta: FloatArray) -> FloatArray:  # −d: the search finds maxima
        return -torus_distance(c, flank_state(cam, flank, theta, [r_in]).p[:, 0])

    brackets = []
    for f in FLANKS:
        k = int(np.argmax(height(f, grid)))
        brackets.append((grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]))
    lo, hi = (np.array(ends) for ends in zip(*brackets, strict=True))
    _, best = local_grid_max(lambda x: np.stack([height(f, row) for f, row in zip(FLANKS, x, strict=True)]),
                             lo, hi, width=TOP_WIDTH)
    return min(-float(best.max()), math.hypot(r_in, cam.roller_radius_mm))


def half_length(cam: RollerGearCam, root_mm: float, extent_mm: float, body_length_mm: float | None,
                tolerance_mm: float) -> float:
    """H, half the body's length: given, or the rib's extent and half a roller radius (module notes).

    Parameters
    ----------
    cam : RollerGearCam
        The cam.
    root_mm : float
        R_root [mm].
    extent_mm : float
        The rib's largest |z| [mm].
    body_length_mm : float or None
        The length asked for, if any [mm].
    tolerance_mm : float
        The fit's tolerance: the body reaches at least this far past the rib [mm].

    Returns
    -------
    float
        H [mm].

    Raises
    ------
    InvalidParameterError
        A length not covering the rib, or reaching the torus's top (field solid.body_length_mm).

    References
    ----------
    The module notes.
    """
    if body_length_mm is None:
        return extent_mm + BODY_MARGIN_SHARE * min(cam.roller_radius_mm, root_mm - extent_mm)
    half = 0.5 * body_length_mm
    if not (math.isfinite(half) and extent_mm + tolerance_mm <= half < root_mm - tolerance_mm):
        raise InvalidParameterError(
            f"body_length_mm must cover the rib, at least {2 * (extent_mm + tolerance_mm):.6g} mm (its extent along the "
            f"cam axis, {2 * extent_mm:.6g} mm, and the tolerance at each end), and stay under {2 * (root_mm - tolerance_mm):.6g} "
            "mm (twice the body's torus radius, where the hourglass would close on the turret's axis), got "
            f"{body_length_mm!r}.", field=("solid", "body_length_mm"))
    return half




def check_request(cam: RollerGearCam, tolerance_mm: float, root_clearance_mm: float) -> tuple[float, float]:
    """Raise for a solid that cannot be made; R_top and R_root.

    Parameters
    ----------
    cam : RollerGearCam
        The cam: its index law must start at rest.
    tolerance_mm : float
        > 0 [mm].
    root_clearance_mm : float
        ≥ 0 [mm].

    Returns
    -------
    tuple of float
        R_top, R_root [mm].

    Raises
    ------
    InvalidParameterError, GeometryError
        With the field (solid.tolerance_mm, curve, and those of :func:`check_solid_body`).

    References
    ----------
    The module notes.
    """
    if not (math.isfinite(tolerance_mm) and tolerance_mm > 0):
        raise InvalidParameterError(f"tolerance_mm must be positive, got {tolerance_mm!r}.", field=("solid", "tolerance_mm"))
    _, start_speed, _ = turret_motion(cam.indexer, np.array([0.0]))
    if abs(float(start_speed[0])) > REST:
        raise InvalidParameterError(
            "the solid needs an index law that starts at rest (V = 0 at its start): the rib's ends then lie in the "
            f"plane of the line of centres; this one starts at dφ/dθ = {float(start_speed[0]):.6g}.", field=("curve",))
    r_out = cam.roller_ends_mm[1]
    root = check_solid_body(cam.center_distance_mm, r_out, cam.roller_radius_mm, root_clearance_mm)
    check_unfolded(cam)
    return top_radius(cam), root


#: the grid the flanks' regularity is checked on before the fit (which checks its own nodes after):
#: cam angles over the index, positions along the roller
FOLD_GRID = (721, 9)
#: a regularity under this is a fold: a flank swept nearly along itself (n·(Q_θ × Q_r)/(|Q_θ||Q_r|))
#: has a fold within a grid step of it
FOLD_LIMIT = 0.0


def check_unfolded(cam: RollerGearCam) -> None:
    """Raise :class:`GeometryError` (field indexing_angle_deg) where a flank folds (undercut) on a grid.

    Parameters
    ----------
    cam : RollerGearCam
        The cam.

    Returns
    -------
    None

    References
    ----------
    Litvin and Fuentes (2004), ch. 6 (singular points of an envelope); camcore.cams.roller_gear.
    """
    theta = np.linspace(0.0, math.radians(cam.indexer.indexing_angle_deg), FOLD_GRID[0])
    r_in, r_out = cam.roller_ends_mm
    for flank in FLANKS:
        if flank_state(cam, flank, theta, np.linspace(r_in, r_out, FOLD_GRID[1])).regularity.min() <= FOLD_LIMIT:
            raise GeometryError(
                "The flanks fold (undercut, see checks.undercut): a rib the rollers cut into has no solid; a longer "
                "indexing_angle_deg or a smaller turret turn per index unfolds them.", field=("indexing_angle_deg",))
