"""Checks of a plate cam over the whole turn: largest pressure angle, smallest radius of
curvature, convexity, undercut, corners (exact extremes, not just the sampled angles).

References
----------
.. [1] Bezier valve-cam notes: convexity test cos φi > 0 and sin φi > 0 for consecutive
   chord vectors; a flat tappet needs a convex cam.
.. [2] Shinzato and Kunigami (1988), eq. (6): the pressure angle.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._maxima import periodic_grid_maxima
from ..curves.base import FloatArray
from .cam import CamSpec, kinematics, rotate
from .followers import Kinematics
from .lift import TWO_PI, Lift
from .points import chord_convexity

#: grid over one cam turn used to bracket the extremes of the checks
CHECK_GRID = 7200


@dataclass(frozen=True)
class ProfileChecks:
    """Exact extremes over the whole cam turn (not just the sampled angles).

    ``max_pressure_angle_deg`` is the largest |φ| (the signed value at that angle is
    ``max_pressure_angle_signed_deg``); ``min_radius_of_curvature_mm`` the smallest
    radius of curvature of the convex parts of the cam surface (knife-edge, roller:
    from the largest pitch-curve curvature; flat-faced: min of Rb + s + s'' or the
    oscillating equivalent, which may be negative = the cam cannot be made).
    ``convex``: the cam surface has no concave part (flat-faced: ρ > 0 everywhere AND the
    valve-cam document's neighbouring-chord test on the sampled contour).
    ``undercut``: roller radius ≥ the pitch curve's radius of curvature somewhere on a
    convex part (the roller cannot generate the surface). ``corners_deg``: cam angles where
    the lift's velocity jumps (the surface has a corner there, radius 0).
    """

    max_pressure_angle_deg: float
    max_pressure_angle_at_deg: float
    max_pressure_angle_signed_deg: float
    min_radius_of_curvature_mm: float
    min_radius_of_curvature_at_deg: float
    min_pitch_radius_of_curvature_mm: float | None
    convex: bool
    undercut: bool
    corners_deg: tuple[float, ...]
    face_min_mm: float | None
    face_max_mm: float | None
    face_width_mm: float | None


# ---------------------------------------------------------------- exact extremes
def check_grid(spec: CamSpec, n: int = CHECK_GRID) -> FloatArray:
    """:func:`lift_check_grid` of the cam's lift.

    Parameters
    ----------
    spec : CamSpec
        The cam: follower, base radius, rotation and lift.
    n : int
        Evenly spaced points before the break points are added [-].

    Returns
    -------
    ndarray
        Sorted, distinct cam angles [rad].

    References
    ----------
    Kiefer (1953), golden-section search.
    """
    return lift_check_grid(spec.lift, n)


def lift_check_grid(lift: Lift, n: int = CHECK_GRID) -> FloatArray:
    """A fine grid over [0, 2π) with every break point of the lift and its left neighbour.

    Parameters
    ----------
    lift : Lift
        The lift over one cam turn (a plate cam's, a barrel cam's).
    n : int
        Evenly spaced points before the break points are added [-].

    Returns
    -------
    ndarray
        Sorted, distinct cam angles [rad]: no jump of the lift's derivatives lies strictly
        between neighbours, so a refinement between them sees a smooth function.

    References
    ----------
    J. Kiefer, "Sequential minimax search for a maximum", Proc. AMS 4 (1953) 502-506
    (a unimodal function between the grid points).
    """
    base = np.linspace(0.0, TWO_PI, n, endpoint=False)
    br = np.asarray(lift.breaks_rad, dtype=np.float64)
    extra = np.unique(np.concatenate([br, np.mod(br - 1e-10, TWO_PI)]))
    if not base.size:
        return extra
    # np.unique of everything, without sorting the sorted base: the extra angles not in it, inserted
    # in order (all are ≥ +0, so equal angles are equal bits and which one stays does not matter)
    at = np.searchsorted(base, extra)
    new = ~((at < base.size) & (base[np.minimum(at, base.size - 1)] == extra))
    return np.insert(base, at[new], extra[new])


@dataclass(frozen=True)
class LiftGrid:
    """The check grid of one lift and the lift's h, h', h'' on it: what the checks of a cam
    need that does not change with the base radius (base-circle sizing reuses it)."""

    theta: FloatArray
    lift: list[FloatArray]

    def kinematics(self, spec: CamSpec) -> Kinematics:
        """The cam's kinematics on the grid (``spec`` must carry the lift the grid was made of)."""
        return spec.model.kinematics(spec.base_radius_mm, spec.sigma, self.theta, self.lift)


def lift_grid(spec: CamSpec) -> LiftGrid:
    """The check grid of the cam's lift (:func:`check_grid`) with h, h', h'' on it.

    Parameters
    ----------
    spec : CamSpec
        The cam: follower, base radius, rotation and lift.

    Returns
    -------
    LiftGrid
        Angles [rad] and the lift's derivatives there [lift unit, per rad, per rad²].

    References
    ----------
    Kiefer (1953), golden-section search (the grid's contract: no jump between neighbours).
    """
    theta = check_grid(spec)
    return LiftGrid(theta, spec.lift.derivatives(theta, 2))


def corners(spec: CamSpec, grid: LiftGrid | None = None) -> list[float]:
    """Cam angles where the lift's velocity jumps (the surface has a corner there) [deg].

    Parameters
    ----------
    spec : CamSpec
        The cam: follower, base radius, rotation and lift.
    grid : LiftGrid, optional
        The lift's check grid, if the caller has it (its h' gives the scale).

    Returns
    -------
    list of float
        :func:`lift_corners` of the cam's lift [deg].

    References
    ----------
    Bezier valve-cam notes, convexity test (a corner fails it).
    """
    return lift_corners(spec.lift, None if grid is None else grid.lift[1])


def lift_corners(lift: Lift, slope_on_grid: FloatArray | None = None) -> list[float]:
    """Cam angles where a lift's velocity jumps (a plate cam's surface, a barrel cam's groove
    has a corner there) [deg].

    Parameters
    ----------
    lift : Lift
        The lift over one cam turn.
    slope_on_grid : ndarray, optional
        dh/dθ on a check grid, if the caller has it (it gives the scale) [mm/rad or deg/rad].

    Returns
    -------
    list of float
        The break points where dh/dθ jumps by more than 1e-6 of max(1, its largest |value|) [deg].

    References
    ----------
    Bezier valve-cam notes, convexity test (a corner fails it); Makino (1977), eqs. (1)-(9)
    (the break points where a curve's derivatives may jump).
    """
    br = np.asarray(lift.breaks_rad, dtype=np.float64)
    if br.size == 0:
        return []
    # both sides of every break in one evaluation (a call costs mostly its fixed part)
    both = lift.derivatives(np.concatenate([br, br - 1e-9]), 1)
    jumps = np.abs(both[1][:br.size] - both[1][br.size:])
    if not bool((jumps > 1e-6).any()):  # the scale is at least 1: no jump can pass it (the grid's lift unasked)
        return []
    h1 = lift.derivatives(lift_check_grid(lift, 720), 1)[1] if slope_on_grid is None else slope_on_grid
    scale = max(1.0, float(np.abs(h1).max()))
    return [float(np.degrees(b)) for b in br[jumps > 1e-6 * scale]]


#: the quantities whose maxima the checks need, by follower kind: flat faces −ρ, the face
#: offset and its negative; point followers κp and −κp; both |φ| first
_FLAT = ("pressure", "neg_rho", "offset", "neg_offset")
_POINT = ("pressure", "kappa", "neg_kappa")


def _quantities(k: Kinematics, names: tuple[str, ...]) -> FloatArray:
    """The named quantities of kinematics ``k`` as rows of one array."""
    rows = {"pressure": lambda: np.abs(k.pressure), "kappa": lambda: k.kappa_pitch,
            "neg_kappa": lambda: -k.kappa_pitch, "neg_rho": lambda: -k.rho_cam}
    if k.offset is not None:
        offset = k.offset
        rows["offset"], rows["neg_offset"] = (lambda: offset), (lambda: -offset)
    return np.vstack([rows[n]() for n in names])


def check_maxima(spec: CamSpec, grid: LiftGrid, names: tuple[str, ...]) -> dict[str, tuple[float, float]]:
    """Exact maxima over the turn of the named quantities (|φ| as ``pressure``, κp as
    ``kappa``, −κp, −ρ as ``neg_rho``, the flat face's contact ``offset`` and its negative).

    Parameters
    ----------
    spec : CamSpec
        The cam: follower, base radius, rotation and lift.
    grid : LiftGrid
        The lift's check grid (:func:`lift_grid`).
    names : tuple of str
        The quantities wanted.

    Returns
    -------
    dict
        name → (angle of the maximum [rad], the maximum [rad, 1/mm or mm]): the best grid
        point refined by local grids between its neighbours, all quantities together.

    References
    ----------
    Shinzato and Kunigami (1988), eq. (6) (the pressure angle); Kiefer (1953) (a unimodal
    maximum lies between the neighbours of the best evaluated point).
    """
    values = _quantities(grid.kinematics(spec), names)
    found = periodic_grid_maxima(lambda t: _quantities(kinematics(spec, t), names), grid.theta, values)
    return dict(zip(names, found))


def profile_checks(spec: CamSpec, grid: LiftGrid | None = None) -> ProfileChecks:
    """Largest |pressure angle|, smallest radius of curvature, convexity, undercut.

    Parameters
    ----------
    spec : CamSpec
        The cam: follower, base radius, rotation and lift.
    grid : LiftGrid, optional
        The lift's check grid, if the caller has it (base-circle sizing reuses one).

    Returns
    -------
    ProfileChecks
        Exact extremes: the best point of a 7200-point grid (with every break point and
        its left neighbour), refined between its neighbours by local grids.

    References
    ----------
    Shinzato and Kunigami (1988), eq. (6); Bezier valve-cam notes (convexity test).
    """
    grid = lift_grid(spec) if grid is None else grid
    model = spec.model
    found = check_maxima(spec, grid, _FLAT if model.flat_faced else _POINT)
    t_p, v_p = found["pressure"]
    signed = float(kinematics(spec, np.array([t_p])).pressure[0])
    corner_angles = corners(spec, grid)
    face: dict[str, float | None] = {"face_min_mm": None, "face_max_mm": None, "face_width_mm": None}
    if model.flat_faced:
        t_r, neg = found["neg_rho"]
        rho_min = -neg
        rho_p_min: float | None = None
        off_max, off_min_neg = found["offset"][1], found["neg_offset"][1]
        face = {"face_min_mm": -off_min_neg, "face_max_mm": off_max, "face_width_mm": off_max + off_min_neg}
        # the chord test on an even 0.1° grid: the check grid's break-point neighbours sit an
        # ulp apart, and chords that short turn the cross product into rounding noise
        even = np.linspace(0.0, 2 * math.pi, 3601)[:-1]
        kin_even = kinematics(spec, even)
        sx, sy = rotate(kin_even.contact[0], kin_even.contact[1], -spec.sigma * even)
        convex = bool(rho_min > 0 and chord_convexity(sx, sy))
        undercut = False
    else:
        rr = model.roller_radius_mm
        t_r, kmax = found["kappa"]
        kmin_neg = found["neg_kappa"][1]
        rho_p_min = 1.0 / kmax if kmax > 0 else math.inf
        rho_min = rho_p_min - rr
        undercut = bool(rr > 0 and kmax > 0 and rr >= rho_p_min)
        convex = bool(-kmin_neg > 0 and not undercut)
    if corner_angles:
        rho_min, t_r = 0.0, math.radians(corner_angles[0])
        if model.flat_faced:
            convex = False
    return ProfileChecks(
        max_pressure_angle_deg=math.degrees(v_p),
        max_pressure_angle_at_deg=math.degrees(t_p),
        max_pressure_angle_signed_deg=math.degrees(signed),
        min_radius_of_curvature_mm=float(rho_min),
        min_radius_of_curvature_at_deg=math.degrees(t_r),
        min_pitch_radius_of_curvature_mm=rho_p_min,
        convex=convex,
        undercut=undercut,
        corners_deg=tuple(corner_angles),
        **face,
    )
