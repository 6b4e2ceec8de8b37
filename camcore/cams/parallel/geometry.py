"""Parallel (conjugate plate) indexing cams: a turret of rollers driven by plate cams on the input shaft.

Frames and conventions
----------------------
* The cam (input) axis is the z axis through O; the turret (output) axis is parallel to it
  through A = (C, 0), C = ``center_distance_mm``. The cam turns counter-clockwise seen from +z
  by the cam angle θ; the plates' contours are given in the cam's own frame, the cam at θ = 0
  (a fixed-frame point p is R(−θ)·p there). θ = 0 is the start of the index.
* Each roller is an oscillating roller follower of :mod:`camcore.profile.followers` with the
  pivot at A, arm = the rollers' pitch radius Rp and the arm angle α from the line A→O: its
  centre is B(α) = (C − Rp·cos α, Rp·sin α). The turret turns clockwise seen from +z, so every
  arm angle grows by the turret's angle φ(θ) (α = α₀ + φ); φ = 0 → h over the index (the
  indexer's law, :class:`camcore.indexer.Indexer`), h = 360°/stops, then stands for the dwell,
  and advances by h every turn.
* Layout: plate p (0 … P−1, P = ``plates``) works with its own layer of m =
  ``rollers_per_plate`` rollers, a pitch 2π/m apart; the layers are staggered by 2π/(m·P). At
  θ = 0 roller k of plate p stands at α₀ = −π/m + p·2π/(m·P) + k·2π/m, so plate 0's first two
  rollers straddle the line of centres symmetrically in the dwell. m must be a multiple of the
  stops, so that after one index every layer stands where it stood and one plate serves every
  turn.

The plate
---------
Each plate is what its rollers leave of the plane about the cam axis: the part holding the axis
that no roller covers at any cam angle. Its contour is made of stretches of the rollers'
envelopes — each roller's pitch point (its centre, the oscillating follower's pitch curve in
the cam's frame) offset by Rr along the exact normal of that curve, in closed form from φ, φ′
(:mod:`.envelope`) — taken where the roller is in contact and trimmed where two rollers' pieces
meet, their crossing solved (:mod:`.trace`). At the roller and cam angle of each contour point
the follower model gives the pressure angle and the radius of curvature of the plate.

A roller is in contact with its plate at a cam angle where one of its two envelope points (the
follower model's contact point, or the opposite point of the roller where the roller overtakes
the cam's surface) lies on the contour (:mod:`.compute`). The force of the plate on the roller
acts along the contact normal (from the plate into the roller): it drives the turret forward
where the normal has a component along the roller's velocity, and holds it back otherwise. The
plates hold the turret (conjugacy) at a cam angle where some contact drives and some contact
holds.

References
----------
.. [1] INDEXMAN technical guide, sections 2-1 to 2-4 and 5: the index law (n = 360/ψ, θh,
   s = h·S) that the turret follows.
.. [2] Shinzato and Kunigami (1988): the oscillating roller follower's pitch curve and
   pressure angle (:mod:`camcore.profile.followers`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..._checks import count, positive
from ...curves.base import FEW_POINTS, FloatArray
from ...curves.curve import Curve
from ...errors import GeometryError, InvalidParameterError
from ...indexer import Indexer
from ...profile.followers import Follower, RollerOscillating
from ..turret import index_law

#: the smallest roller and pitch radius, as a share of the centre distance: a roller a thousandth
#: of the cam's size is below any plate a shop cuts, and its envelope's tolerances (shares of C,
#: :mod:`.trace`) would approach its own size
SMALLEST_SHARE = 1e-3


@dataclass(frozen=True)
class ParallelCam:
    """A parallel indexing cam's geometry and index law (see the module notes for the layout)."""

    stops: int
    plates: int
    rollers_per_plate: int
    center_distance_mm: float
    roller_pitch_radius_mm: float
    roller_radius_mm: float
    indexer: Indexer

    @property
    def pitch_rad(self) -> float:
        """2π/m, the angle between neighbouring rollers of one plate [rad]."""
        return 2 * math.pi / self.rollers_per_plate

    @property
    def index_rad(self) -> float:
        """h = 2π/stops, the turret's turn per index [rad]."""
        return 2 * math.pi / self.stops

    def start_angles(self, plate: int) -> FloatArray:
        """α₀ of the plate's rollers at θ = 0 [rad]."""
        k = np.arange(self.rollers_per_plate, dtype=np.float64)
        return np.asarray(-self.pitch_rad / 2 + plate * self.pitch_rad / self.plates + k * self.pitch_rad)

    def turret(self, theta: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """φ, dφ/dθ, d²φ/dθ² at any cam angles (turn k adds k·h) [rad, -, 1/rad].

        :func:`camcore.cams.turret.turret_motion`'s values (tests/camcore/cams/test_parallel_contour.py
        checks they agree), from the index law's curve directly: the plates' tracing and fitting ask
        for a few angles at a time, thousands of times, where the indexer's motion table (times,
        speeds, jerks) costs 0.2 ms a call and this 0.03 ms.
        """
        curve, t_start, s_start, d_t, scales, theta_h, h = self._law
        theta = np.asarray(theta, dtype=np.float64)
        if theta.size <= FEW_POINTS:
            few = self._turret_few(theta)
            if few is not None:
                return few
        turns = np.floor(theta * (0.5 / math.pi))
        within = theta - turns * (2 * math.pi)
        s, v, a = curve.derivatives((t_start + d_t * np.minimum(within / theta_h, 1.0)).reshape(-1), 2)
        index = (within <= theta_h).reshape(-1)
        phi = np.where(index, scales[0] * (s - s_start), h).reshape(theta.shape) + turns * h
        d1 = np.where(index, scales[1] * v, 0.0).reshape(theta.shape)
        d2 = np.where(index, scales[2] * a, 0.0).reshape(theta.shape)
        return phi, d1, d2

    def _turret_few(self, theta: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray] | None:
        """:meth:`turret` at a few finite angles in Python floats: the same operations, so the same
        numbers to the bit, without numpy's fixed cost per call (None: an angle is not finite, or its
        time has no point formulas). An angle in the dwell needs no curve: φ = h a turn, φ′ = φ″ = 0."""
        curve, t_start, s_start, d_t, scales, theta_h, h = self._law
        angles = theta.reshape(-1).tolist()
        if not all(math.isfinite(x) for x in angles):
            return None
        phi, d1, d2 = [], [], []
        for x in angles:
            turns = float(math.floor(x * (0.5 / math.pi)))
            within = x - turns * (2 * math.pi)
            if within <= theta_h:
                row = curve.point_derivatives(t_start + d_t * min(within / theta_h, 1.0))
                if row is None:
                    return None
                phi.append(scales[0] * (row[0] - s_start) + turns * h)
                d1.append(scales[1] * row[1])
                d2.append(scales[2] * row[2])
            else:
                phi.append(h + turns * h)
                d1.append(0.0)
                d2.append(0.0)
        shape = theta.shape
        return np.array(phi).reshape(shape), np.array(d1).reshape(shape), np.array(d2).reshape(shape)

    def centres(self, alpha0: FloatArray | float, theta: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Roller centres in the cam's frame: α₀ broadcast against θ [mm]."""
        phi = self.turret(theta)[0]
        alpha = alpha0 + phi
        bx = self.center_distance_mm - self.roller_pitch_radius_mm * np.cos(alpha)
        by = self.roller_pitch_radius_mm * np.sin(alpha)
        c, s = np.cos(theta), np.sin(theta)
        return c * bx + s * by, -s * bx + c * by

    def follower(self, alpha0: float) -> _TurretRoller:
        """Roller of arm angle α₀ at θ = 0 as the profile module's oscillating roller follower."""
        if alpha0 == 0.0:
            return self.roller_model
        return _TurretRoller(Follower(type="roller", motion="oscillating", roller_radius_mm=self.roller_radius_mm,
                                      arm_length_mm=self.roller_pitch_radius_mm,
                                      pivot_distance_mm=self.center_distance_mm), alpha0)

    @cached_property
    def _law(self) -> tuple[Curve, float, float, float, tuple[float, float, float], float, float]:
        """The index law's curve, its start (t, S), span of t, the scales of S, S′, S″ to φ, φ′, φ″,
        θh [rad] and h [rad] (:class:`camcore.indexer.Indexer`'s motion over the input angle)."""
        curve = self.indexer.curve
        assert isinstance(curve, Curve)  # the indexer makes a name its catalog curve
        d_t, d_s = self.indexer.spans
        theta_h = math.radians(self.indexer.indexing_angle_deg)
        h = self.index_rad
        scales = (h / d_s, h * d_t / (theta_h * d_s), h * d_t * d_t / (theta_h * theta_h * d_s))
        return curve, float(curve.t_start), float(curve.s_start), float(d_t), scales, theta_h, h

    @cached_property
    def roller_model(self) -> _TurretRoller:
        """The roller whose arm angle is the lift (α₀ = 0), made once: the envelopes add α₀ to the lift."""
        return _TurretRoller(Follower(type="roller", motion="oscillating", roller_radius_mm=self.roller_radius_mm,
                                      arm_length_mm=self.roller_pitch_radius_mm,
                                      pivot_distance_mm=self.center_distance_mm), 0.0)


class _TurretRoller(RollerOscillating):
    """A turret roller: the oscillating roller follower whose arm starts at a given angle (not at
    the base circle's contact) and swings by the turret's angle."""

    def __init__(self, follower: Follower, alpha0: float):
        super().__init__(follower)
        self._alpha0 = alpha0

    def alpha0(self, base_radius_mm: float) -> float:
        """The roller's arm angle at θ = 0, whatever the base radius [rad]."""
        return self._alpha0


def check_parallel_geometry(stops: int, plates: int, rollers_per_plate: int, center_distance_mm: float,
                            roller_pitch_radius_mm: float, roller_radius_mm: float) -> None:
    """Raise :class:`InvalidParameterError` or :class:`GeometryError` for a turret that cannot be built.

    Parameters
    ----------
    stops : int
        Stops per turret turn [-].
    plates : int
        Plate cams, 2 or 3 [-].
    rollers_per_plate : int
        Rollers in each plate's layer, a multiple of ``stops`` [-].
    center_distance_mm : float
        Cam axis to turret axis, C [mm].
    roller_pitch_radius_mm : float
        The rollers' pitch radius on the turret, Rp [mm].
    roller_radius_mm : float
        Rr [mm].

    Returns
    -------
    None

    References
    ----------
    INDEXMAN technical guide, section 2-1 (n = 360/ψ).
    """
    count("stops", stops)
    count("rollers_per_plate", rollers_per_plate)
    if plates not in (2, 3):
        raise InvalidParameterError(f"plates must be 2 or 3, not {plates!r}.", field=("plates",))
    if rollers_per_plate % stops:
        raise InvalidParameterError(
            f"rollers_per_plate must be a multiple of stops (each index moves every layer onto itself), "
            f"got {rollers_per_plate} rollers for {stops} stops.", field=("rollers_per_plate",))
    c = positive("center_distance_mm", center_distance_mm)
    rp = positive("roller_pitch_radius_mm", roller_pitch_radius_mm)
    rr = positive("roller_radius_mm", roller_radius_mm)
    if min(rp, rr) < SMALLEST_SHARE * c:
        raise GeometryError(
            f"roller_pitch_radius_mm {rp!r} and roller_radius_mm {rr!r} must each be at least "
            f"{SMALLEST_SHARE:.1%} of center_distance_mm {c!r}: smaller ones are below the plates' resolution.",
            field=("roller_pitch_radius_mm",) if rp <= rr else ("roller_radius_mm",))
    chord = 2 * rp * math.sin(math.pi / rollers_per_plate)
    if rollers_per_plate > 1 and not chord > 2 * rr:
        raise GeometryError(
            f"The rollers of a plate collide: neighbours {chord!r} mm apart (2·Rp·sin(180°/m)) need more than "
            f"twice the roller radius, {2 * rr!r} mm.", field=("roller_radius_mm",))
    if not c - rp - rr > 0:
        raise GeometryError(
            f"The rollers reach the cam axis: center_distance_mm {c!r} must exceed roller_pitch_radius_mm + "
            f"roller_radius_mm = {rp + rr!r}.", field=("center_distance_mm",))


def make_parallel_cam(stops: int, center_distance_mm: float, roller_pitch_radius_mm: float,
                      roller_radius_mm: float, indexing_angle_deg: float, curve: Curve | str = "MS",
                      plates: int = 2, rollers_per_plate: int | None = None) -> ParallelCam:
    """A parallel indexing cam, its geometry checked.

    Parameters
    ----------
    stops : int
        Stops per turret turn; the turret moves h = 360°/stops per index [-].
    center_distance_mm : float
        C, cam axis to turret axis [mm].
    roller_pitch_radius_mm : float
        Rp, the rollers' centres' radius on the turret [mm].
    roller_radius_mm : float
        Rr [mm].
    indexing_angle_deg : float
        θh, the cam angle of the index, 0 < θh < 360 [deg].
    curve : Curve or str
        The index law (a curve or a catalog name) [-].
    plates : int
        2 or 3 [-].
    rollers_per_plate : int, optional
        m, a multiple of ``stops``; default ``stops`` [-].

    Returns
    -------
    ParallelCam

    References
    ----------
    INDEXMAN technical guide, sections 2-1 to 2-4 (n, θh), section 5 (the index law).
    """
    m = stops if rollers_per_plate is None else rollers_per_plate
    check_parallel_geometry(stops, plates, m, center_distance_mm, roller_pitch_radius_mm, roller_radius_mm)
    indexer = index_law(stops, indexing_angle_deg, curve)
    return ParallelCam(stops, plates, m, float(center_distance_mm), float(roller_pitch_radius_mm),
                       float(roller_radius_mm), indexer)
