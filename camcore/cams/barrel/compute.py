"""A barrel cam sampled over the cam angle (developed groove, pressure angles, flank radii,
3-D flanks) and its checks over the whole turn.

References
----------
.. [1] Shinzato and Kunigami (1988), eq. (6): the pressure angle, atan(s'/radius of the contact).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from ..._maxima import periodic_grid_maxima
from ...curves.base import FloatArray
from ...errors import InvalidParameterError
from ...profile.checks import lift_corners as corners
from ...results import doc
from .geometry import BarrelCam, _curvature, _pitch_x, _pressure, _state, check_grid, flank_points

#: radii evenly across the roller's length (ends included) where the checks draw the developed curve
ACROSS_LENGTH = 9


# ---------------------------------------------------------------------------- results
@dataclass(frozen=True)
class BarrelChecks:
    """Exact extremes over the whole cam turn (grid of 7200 angles with the break points, refined by
    golden section), and the groove's dimensions."""

    max_pressure_angle_deg: float = field(metadata=doc("largest |pressure angle| at the pitch radius [deg]"))
    max_pressure_angle_at_deg: float = field(metadata=doc("cam angle where it occurs [deg]"))
    max_pressure_angle_inner_deg: float = field(metadata=doc("largest |pressure angle| at the roller's inner end [deg]"))
    max_pressure_angle_outer_deg: float = field(metadata=doc("largest |pressure angle| at the roller's outer end [deg]"))
    min_pitch_radius_of_curvature_mm: float | None = field(metadata=doc(
        "smallest |radius of curvature| of the developed pitch curve [mm]; null: straight (no curvature)"))
    min_radius_of_curvature_upper_mm: float | None = field(metadata=doc(
        "smallest radius of curvature of the upper flank where it is convex towards the roller [mm] (≤ 0: "
        "undercut; 0 at a corner); null: never convex"))
    min_radius_of_curvature_upper_at_deg: float | None = field(metadata=doc("cam angle where it occurs [deg]"))
    min_radius_of_curvature_lower_mm: float | None = field(metadata=doc(
        "the same for the lower flank [mm]"))
    min_radius_of_curvature_lower_at_deg: float | None = field(metadata=doc("cam angle where it occurs [deg]"))
    min_radius_of_curvature_across_length_mm: float | None = field(metadata=doc(
        "the smallest convex radius of either flank at any of 9 radii evenly across the roller's length and the pitch "
        "radius: the developed curve drawn at that radius, offset by the roller's radius there [mm] (≤ 0: "
        "undercut); null: never convex"))
    min_radius_of_curvature_across_length_at_deg: float | None = field(metadata=doc("cam angle where it occurs [deg]"))
    min_radius_of_curvature_across_length_at_radius_mm: float | None = field(metadata=doc(
        "position along the roller's axis where it occurs [mm]"))
    undercut_upper: bool = field(metadata=doc(
        "at some radius across the roller's length, the roller's radius ≥ the developed curve's radius where the "
        "upper flank is convex: the roller cannot generate the flank there"))
    undercut_lower: bool = field(metadata=doc("the same for the lower flank"))
    undercut: bool = field(metadata=doc("either flank is undercut"))
    corners_deg: tuple[float, ...] = field(metadata=doc(
        "cam angles where the lift's velocity jumps: the groove has a corner there [deg]"))
    cone_half_angle_deg: float = field(metadata=doc("conical roller: α, tan α = roller radius / pitch radius; "
                                                    "0 for a cylindrical roller [deg]"))
    outer_radius_mm: float = field(metadata=doc("the cam's outer radius, pitch radius + roller length/2 [mm]"))
    groove_bottom_radius_mm: float = field(metadata=doc("outer radius − groove depth [mm]"))
    bottom_clearance_mm: float = field(metadata=doc(
        "groove depth − roller length: room below the roller's inner end, ≥ 0 [mm]"))


@dataclass(frozen=True)
class BarrelFlank:
    """One groove wall: the contact points along the roller's length, and its developed radius."""

    x_mm: FloatArray = field(metadata=doc("cam frame, one row per cam angle, one column per roller position [mm]"))
    y_mm: FloatArray = field(metadata=doc("cam frame, as x_mm [mm]"))
    z_mm: FloatArray = field(metadata=doc("along the cam axis, as x_mm [mm]"))
    radius_of_curvature_mm: FloatArray = field(metadata=doc(
        "of the developed flank at the pitch radius, per cam angle: positive convex towards the roller, negative "
        "concave; NaN (null) where straight [mm]"))


@dataclass(frozen=True)
class BarrelResult:
    """The developed groove and both flanks at the sampled cam angles, with the checks."""

    cam_angle_deg: FloatArray
    lift: FloatArray  # mm (translating) or deg of swing (oscillating)
    u_mm: FloatArray
    y_mm: FloatArray
    pressure_angle_deg: FloatArray
    pressure_angle_inner_deg: FloatArray
    pressure_angle_outer_deg: FloatArray
    pitch_radius_of_curvature_mm: FloatArray
    roller_position_mm: FloatArray
    upper: BarrelFlank
    lower: BarrelFlank
    checks: BarrelChecks


def barrel_profile(cam: BarrelCam, cam_angle_deg: ArrayLike, length_samples: int = 5) -> BarrelResult:
    """The developed groove, pressure angles, flank radii and 3-D flanks at cam angles.

    Parameters
    ----------
    cam : BarrelCam
        The cam (:func:`make_barrel_cam`).
    cam_angle_deg : array_like
        Cam angles θ [deg].
    length_samples : int
        Points along the roller's length per flank and angle, evenly from its inner to its outer end [-].

    Returns
    -------
    BarrelResult
        Columns over θ (pressure angles [deg], radii [mm]; a straight stretch's radius is NaN),
        the flank grids and :class:`BarrelChecks`.

    References
    ----------
    Shinzato and Kunigami (1988), eq. (6) (tan φ = s'/R at the pitch radius); the module notes.
    """
    if isinstance(length_samples, bool) or not (isinstance(length_samples, int) and length_samples >= 2):
        raise InvalidParameterError("length_samples must be a whole number ≥ 2.", field=("length_samples",))
    deg = np.asarray(cam_angle_deg, dtype=np.float64).reshape(-1)
    theta = np.radians(deg)
    st = _state(cam, theta)
    x_in, x_out = cam.roller_ends_mm
    with np.errstate(divide="ignore"):
        rho_p = 1.0 / _curvature(st)
    rho = cam.roller_radius_mm
    finite = np.isfinite(rho_p)
    positions = np.linspace(x_in, x_out, length_samples)
    grids = flank_points(cam, deg, positions)
    flanks = {name: BarrelFlank(*grids[name], np.where(finite, sign * rho_p - rho, np.nan))
              for name, sign in (("upper", 1.0), ("lower", -1.0))}
    return BarrelResult(deg, st.lift, st.u, st.y, np.degrees(_pressure(cam, st, _pitch_x(cam, st))),
                        np.degrees(_pressure(cam, st, x_in)), np.degrees(_pressure(cam, st, x_out)),
                        np.where(finite, rho_p, np.nan), positions, flanks["upper"], flanks["lower"],
                        barrel_checks(cam))


def barrel_checks(cam: BarrelCam) -> BarrelChecks:
    """Largest pressure angles, smallest flank radii, undercut, corners, groove dimensions.

    Parameters
    ----------
    cam : BarrelCam
        The cam.

    Returns
    -------
    BarrelChecks
        Extremes over the whole turn: the best point of a 7200-angle grid (with every break
        point and its left neighbour), refined by local grids between its neighbours, every
        extreme in one search.

    References
    ----------
    Kiefer (1953), golden-section search; camcore.profile.checks (the plate cam's undercut rule).
    """
    grid = check_grid(cam.lift)
    x_in, x_out = cam.roller_ends_mm
    # the developed rule at each radius r across the roller: the curve (r·θ', y), the roller's radius there
    across = np.unique(np.append(np.linspace(x_in, x_out, ACROSS_LENGTH), cam.pitch_radius_mm)).tolist()

    def functions(theta: FloatArray) -> FloatArray:
        """Every extreme's function at once (the lift's derivatives taken once): |φ| at the pitch
        cylinder, the roller's inner and outer ends; ±κ of the pitch curve; ±κ at each radius across."""
        h, h1, h2 = cam.lift.derivatives(theta, 2)
        lift = (h, h1, h2)
        st = _state(cam, theta, None, lift)
        out = np.empty((5 + 2 * len(across), theta.size))
        out[0], out[1], out[2] = (np.abs(_pressure(cam, st, x)) for x in (_pitch_x(cam, st), x_in, x_out))
        out[3] = _curvature(st)
        for j, r in enumerate(across):
            # a translating follower's developed curve (rθ, s) bends by r·s''/(r² + s'²)^{3/2} at radius r
            out[5 + 2 * j] = (r * h2 / np.hypot(r, h1) ** 3 if cam.follower == "translating"
                          else _curvature(_state(cam, theta, r, lift)))
        out[4::2] = -out[3::2]  # each curvature's other sign: the other flank
        return out

    # all extremes refined together: the best point of the grid, then local grids (one evaluation of
    # the lift per round for all of them)
    found = periodic_grid_maxima(functions, grid, functions(grid))
    (t_p, p_max), (_, p_in), (_, p_out), (t_up, k_up), (t_lo, k_lo) = found[:5]
    rho = cam.roller_radius_mm
    kinks = corners(cam.lift)
    radii: dict[str, tuple[float | None, float | None]] = {}
    for name, t, k in (("upper", t_up, k_up), ("lower", t_lo, k_lo)):
        radii[name] = (1.0 / k - rho, math.degrees(t)) if k > 0 else (None, None)
        if kinks:
            radii[name] = (0.0, kinks[0])
    k_abs = max(k_up, k_lo)
    outer = float(cam.pitch_radius_mm + 0.5 * cam.roller_length_mm)
    worst: tuple[float, float, float] | None = None  # (radius of curvature, θ, r)
    under = {"upper": False, "lower": False}
    for i, r in enumerate(across):
        roller_r = r * math.tan(cam.cone_half_angle_rad) if cam.roller == "conical" else rho
        for name, (t, k) in zip(("upper", "lower"), found[5 + 2 * i:7 + 2 * i], strict=True):
            if k > 0:
                under[name] = under[name] or roller_r >= 1.0 / k
                if worst is None or 1.0 / k - roller_r < worst[0]:
                    worst = (1.0 / k - roller_r, math.degrees(t), r)
    if kinks:
        worst = (0.0, kinks[0], cam.pitch_radius_mm)
    under_up, under_lo = under["upper"], under["lower"]
    return BarrelChecks(
        max_pressure_angle_deg=math.degrees(p_max), max_pressure_angle_at_deg=math.degrees(t_p),
        max_pressure_angle_inner_deg=math.degrees(p_in), max_pressure_angle_outer_deg=math.degrees(p_out),
        min_pitch_radius_of_curvature_mm=(1.0 / k_abs if k_abs > 0 else None),
        min_radius_of_curvature_upper_mm=radii["upper"][0], min_radius_of_curvature_upper_at_deg=radii["upper"][1],
        min_radius_of_curvature_lower_mm=radii["lower"][0], min_radius_of_curvature_lower_at_deg=radii["lower"][1],
        min_radius_of_curvature_across_length_mm=None if worst is None else worst[0],
        min_radius_of_curvature_across_length_at_deg=None if worst is None else worst[1],
        min_radius_of_curvature_across_length_at_radius_mm=None if worst is None else worst[2],
        undercut_upper=under_up, undercut_lower=under_lo, undercut=under_up or under_lo,
        corners_deg=tuple(kinks), cone_half_angle_deg=math.degrees(cam.cone_half_angle_rad),
        outer_radius_mm=outer, groove_bottom_radius_mm=outer - cam.groove_depth_mm,
        bottom_clearance_mm=float(cam.groove_depth_mm - cam.roller_length_mm))


def sample_barrel(cam: BarrelCam, samples: int = 361, length_samples: int = 5) -> BarrelResult:
    """:func:`barrel_profile` at ``samples`` cam angles evenly over 0–360°, both ends included.

    Parameters
    ----------
    cam : BarrelCam
        The cam.
    samples : int
        Cam angles [-], ≥ 2.
    length_samples : int
        Points along the roller's length [-], ≥ 2.

    Returns
    -------
    BarrelResult
        As :func:`barrel_profile`.

    References
    ----------
    The module notes.
    """
    if isinstance(samples, bool) or not (isinstance(samples, int) and samples >= 2):
        raise InvalidParameterError("samples must be a whole number ≥ 2.", field=("samples",))
    return barrel_profile(cam, np.linspace(0.0, 360.0, samples), length_samples)
