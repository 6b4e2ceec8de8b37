"""The roller-gear cam, its dimensions and the contact of its rib with the rollers (the frames and
formulas: :mod:`camcore.cams.roller_gear`).

References
----------
.. [1] INDEXMAN technical guide, sections 2-1 to 2-4 and 5.
.. [2] Litvin and Fuentes (2004), ch. 6: envelopes of surfaces.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from ..._checks import count, positive
from ...curves.base import FloatArray
from ...curves.curve import Curve
from ...errors import GeometryError, InvalidParameterError
from ...indexer import Indexer
from ..turret import index_law, turret_motion

Flank = Literal["forward", "back"]
#: the rib's two flanks: facing the roller ahead of it, and the roller behind
FLANKS: tuple[Flank, Flank] = ("forward", "back")
#: σ: the side of its roller the rib is on (+1 along w: the roller behind the rib)
SIDE: dict[Flank, float] = {"forward": -1.0, "back": 1.0}
#: the fewest stops: each roller making a flank swings through ±h about the line of centres and
#: must stay short of 90°, where its axis would stand parallel to the cam's
MIN_STOPS = 5
#: the smallest roller radius, length and pitch radius, as a share of the centre distance
SMALLEST_SHARE = 1e-3


@dataclass(frozen=True)
class RollerGearCam:
    """A roller-gear cam's geometry and index law (see the module notes for the layout)."""

    stops: int
    center_distance_mm: float
    roller_pitch_radius_mm: float
    roller_radius_mm: float
    roller_length_mm: float
    indexer: Indexer

    @property
    def index_rad(self) -> float:
        """h = 2π/stops, the turret's turn per index [rad]."""
        return 2 * math.pi / self.stops

    @property
    def roller_ends_mm(self) -> tuple[float, float]:
        """r_in, r_out: the roller's ends along its axis from the turret axis [mm]."""
        half = 0.5 * self.roller_length_mm
        return self.roller_pitch_radius_mm - half, self.roller_pitch_radius_mm + half

    def behind_rad(self, flank: Flank) -> float:
        """How far the roller making ``flank`` stands behind the turret's angle: α = φ − this [rad]."""
        return self.index_rad if flank == "back" else 0.0

    def roller_angle(self, flank: Flank, cam_angle_rad: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """α, dα/dθ, d²α/dθ² of the roller making ``flank`` [rad, -, 1/rad]."""
        phi, d1, d2 = turret_motion(self.indexer, cam_angle_rad)
        return phi - self.behind_rad(flank), d1, d2


@dataclass(frozen=True)
class FlankState:
    """The contact of a roller with the rib at cam angles × positions along the roller (fixed frame but Q)."""

    q: FloatArray  # (..., 3): the flank point in the cam's frame [mm]
    p: FloatArray  # (..., 3): the same point in the fixed frame [mm]
    normal: FloatArray  # (..., 3): unit normal from the roller into the rib, fixed frame
    pressure_angle_rad: FloatArray  # β
    q_theta: FloatArray  # (..., 3): ∂Q/∂θ turned into the fixed frame [mm/rad]
    q_r: FloatArray  # (..., 3): ∂Q/∂r turned into the fixed frame [-]
    regularity: FloatArray  # n·(Q_θ × Q_r)·(−σ)/(|Q_θ||Q_r|): > 0 where the flank is regular, ≤ 0 undercut


def check_roller_gear_geometry(stops: int, center_distance_mm: float, roller_pitch_radius_mm: float,
                               roller_radius_mm: float, roller_length_mm: float) -> None:
    """Raise :class:`InvalidParameterError` or :class:`GeometryError` for a turret and cam that cannot be built.

    Parameters
    ----------
    stops : int
        Stops per turret turn, ≥ 5 (module notes) [-].
    center_distance_mm : float
        C, cam axis to turret axis [mm].
    roller_pitch_radius_mm : float
        Rp, the rollers' mid-length radius on the turret [mm].
    roller_radius_mm : float
        Rr [mm].
    roller_length_mm : float
        ℓ, along the roller's axis [mm].

    Returns
    -------
    None

    References
    ----------
    INDEXMAN technical guide, section 2-1 (n = 360/ψ).
    """
    n = count("stops", stops)
    if n < MIN_STOPS:
        raise InvalidParameterError(
            f"stops must be at least {MIN_STOPS} for a roller-gear cam with one rib: the rollers making its flanks "
            f"swing through ±360°/stops about the line of centres and must stay short of 90°, got {n}.", field=("stops",))
    c = positive("center_distance_mm", center_distance_mm)
    rp = positive("roller_pitch_radius_mm", roller_pitch_radius_mm)
    rr = positive("roller_radius_mm", roller_radius_mm)
    length = positive("roller_length_mm", roller_length_mm)
    if min(rp, rr, length) < SMALLEST_SHARE * c:
        raise GeometryError(
            f"roller_pitch_radius_mm {rp!r}, roller_radius_mm {rr!r} and roller_length_mm {length!r} must each be at "
            f"least {SMALLEST_SHARE:.1%} of center_distance_mm {c!r}.",
            field=(min((rp, "roller_pitch_radius_mm"), (rr, "roller_radius_mm"), (length, "roller_length_mm"))[1],))
    r_in, r_out = rp - length / 2, rp + length / 2
    if not r_in > 0:
        raise GeometryError(
            f"The rollers cross the turret's axis: roller_length_mm {length!r} must be less than twice "
            f"roller_pitch_radius_mm, {2 * rp!r}.", field=("roller_length_mm",))
    half_pitch = math.pi / n
    if not r_in * math.sin(half_pitch) > rr:
        raise GeometryError(
            f"The rollers leave no room for the rib: neighbours stand 2·r_in·sin(180°/stops) = "
            f"{2 * r_in * math.sin(half_pitch)!r} mm apart at their inner ends (r_in = roller_pitch_radius_mm − "
            f"roller_length_mm/2), which must exceed twice the roller radius, {2 * rr!r} mm.", field=("roller_radius_mm",))
    if not c - r_out > 0:
        raise GeometryError(
            f"The rollers reach the cam axis: center_distance_mm {c!r} must exceed roller_pitch_radius_mm + "
            f"roller_length_mm/2 = {r_out!r}.", field=("center_distance_mm",))


def make_roller_gear_cam(stops: int, center_distance_mm: float, roller_pitch_radius_mm: float,
                         roller_radius_mm: float, roller_length_mm: float, indexing_angle_deg: float,
                         curve: Curve | str = "MS") -> RollerGearCam:
    """A roller-gear cam, its geometry checked.

    Parameters
    ----------
    stops : int
        Stops per turret turn (one roller per stop); the turret moves h = 360°/stops per index [-].
    center_distance_mm : float
        C, cam axis to turret axis [mm].
    roller_pitch_radius_mm : float
        Rp, the rollers' mid-length radius on the turret [mm].
    roller_radius_mm : float
        Rr [mm].
    roller_length_mm : float
        ℓ [mm].
    indexing_angle_deg : float
        θh, the cam angle of the index, 1 ≤ θh ≤ 359 [deg].
    curve : Curve or str
        The index law (a curve or a catalog name) [-].

    Returns
    -------
    RollerGearCam

    References
    ----------
    INDEXMAN technical guide, sections 2-1 to 2-4 (n, θh), section 5 (the index law).
    """
    check_roller_gear_geometry(stops, center_distance_mm, roller_pitch_radius_mm, roller_radius_mm, roller_length_mm)
    indexer = index_law(stops, indexing_angle_deg, curve)
    return RollerGearCam(stops, float(center_distance_mm), float(roller_pitch_radius_mm), float(roller_radius_mm),
                         float(roller_length_mm), indexer)


def pressure_angle_rad(cam: RollerGearCam, alpha_rad: FloatArray, dalpha: FloatArray, r_mm: FloatArray | float
                       ) -> FloatArray:
    """β = atan(α'·r / (C − r·cos α)): the contact's angle off the roller's direction of motion (module notes).

    Parameters
    ----------
    cam : RollerGearCam
        The cam.
    alpha_rad : ndarray
        α, the roller's turret angle [rad].
    dalpha : ndarray
        dα/dθ = φ' [-].
    r_mm : ndarray or float
        Distance from the turret axis along the roller [mm].

    Returns
    -------
    ndarray
        β [rad], broadcast over the arguments.

    References
    ----------
    Litvin and Fuentes (2004), ch. 6 (n·v_rel = 0); the derivation in the module notes.
    """
    return np.arctan(dalpha * r_mm / (cam.center_distance_mm - r_mm * np.cos(alpha_rad)))


def _vec(x: FloatArray, y: FloatArray | float, z: FloatArray) -> FloatArray:
    x = np.asarray(x, dtype=np.float64)
    return np.stack(np.broadcast_arrays(x, np.asarray(y, dtype=np.float64), np.asarray(z, dtype=np.float64)), axis=-1)


def flank_state(cam: RollerGearCam, flank: Flank, cam_angle_rad: ArrayLike, positions_mm: ArrayLike,
                turret: tuple[FloatArray, FloatArray, FloatArray] | None = None) -> FlankState:
    """The contact of the roller making ``flank`` with the rib: cam angles (rows) × positions along the roller.

    Parameters
    ----------
    cam : RollerGearCam
        The cam.
    flank : {"forward", "back"}
        The flank (module notes).
    cam_angle_rad : array_like
        θ, 1-D [rad].
    positions_mm : array_like
        r, distances from the turret axis along the roller's axis: 1-D (the same at every cam angle), or
        2-D with one row per cam angle (a row of its own at each) [mm].
    turret : tuple of ndarray, optional
        φ, φ', φ'' at ``cam_angle_rad`` when already evaluated (:func:`camcore.cams.turret.turret_motion`)
        [rad, -, 1/rad].

    Returns
    -------
    FlankState
        The flank point in both frames, the contact normal, the pressure angle and the flank's
        derivatives and regularity (undercut where ≤ 0), each of shape (angles, positions).

    References
    ----------
    Litvin and Fuentes (2004), ch. 6 (the envelope condition and its singular points); the
    derivation in the module notes.
    """
    theta = np.asarray(cam_angle_rad, dtype=np.float64).reshape(-1, 1)
    r = np.asarray(positions_mm, dtype=np.float64)
    r = r.reshape(theta.size, -1) if r.ndim == 2 else r.reshape(1, -1)
    if turret is None:
        alpha, d1, d2 = cam.roller_angle(flank, theta)
    else:
        phi, d1, d2 = (np.asarray(x, dtype=np.float64).reshape(-1, 1) for x in turret)
        alpha = phi - cam.behind_rad(flank)
    sigma, c_dist, rr = SIDE[flank], cam.center_distance_mm, cam.roller_radius_mm
    ca, sa = np.cos(alpha), np.sin(alpha)
    den = c_dist - r * ca  # > 0: the rollers stop short of the cam axis
    beta = pressure_angle_rad(cam, alpha, d1, r)
    cb, sb = np.cos(beta), np.sin(beta)
    u, w = _vec(-ca, 0.0, sa), _vec(sa, 0.0, ca)
    y_hat = np.array([0.0, 1.0, 0.0])
    normal = sigma * (cb[..., None] * w + sb[..., None] * y_hat)
    p = np.array([c_dist, 0.0, 0.0]) + r[..., None] * u + rr * normal
    # d(tan β)/dθ and /dr, times cos²β: β_θ and β_r
    beta_theta = cb**2 * (d2 * r * den - d1 * r * (r * sa * d1)) / den**2
    beta_r = cb**2 * d1 * c_dist / den**2
    t_beta = sigma * (-sb[..., None] * w + cb[..., None] * y_hat)  # ∂n/∂β
    dn_dalpha = -sigma * cb[..., None] * u
    dp_dtheta = d1[..., None] * (r[..., None] * w + rr * dn_dalpha) + rr * beta_theta[..., None] * t_beta
    z_cross_p = _vec(-p[..., 1], p[..., 0], np.zeros_like(p[..., 0]))
    q_theta = dp_dtheta - z_cross_p
    q_r = u + rr * beta_r[..., None] * t_beta
    cross = np.cross(q_theta, q_r)
    scale = np.linalg.norm(q_theta, axis=-1) * np.linalg.norm(q_r, axis=-1)
    regularity = -sigma * np.einsum("...i,...i->...", normal, cross) / scale
    c, s = np.cos(theta), np.sin(theta)
    q = _vec(c * p[..., 0] + s * p[..., 1], -s * p[..., 0] + c * p[..., 1], p[..., 2])
    return FlankState(q, p, normal, beta, q_theta, q_r, regularity)
