"""Contact force, jump speed, camshaft torque and Hertz stress of a force-closed follower.

The follower is rigid and held on the cam by a spring (:mod:`.load`). In its own coordinate
q (the lift in metres, or the swing in radians) and at the camshaft speed ω = 2πN/60, with
q' = dq/dθ and q'' = d²q/dθ² from the lift's analytic derivatives (never differences),

    Q(θ, ω) = M·q''·ω² + C·q'·ω + K·q + Q0 + Q_ext,

the force (translating) or the torque about the pivot (oscillating) the cam exerts on the
follower along its motion. The contact force along the motion is F = Q/r, with r = 1 for a
translating follower and r the lever arm of the follower point for an oscillating one (the
arm length to the roller centre or knife point; for a flat face, the contact's distance from
the pivot along the face, where the normal force acts). Then

* the normal force is F/cos φ (φ the pressure angle, 0 for a flat face);
* the camshaft torque, by virtual work (T·ω = Q·q̇, no friction), is T = Q·q';
* the Hertz pressure of a roller is p0 = sqrt(F_n·E*/(π·b·R)), 1/R = 1/Rr + 1/ρ (:mod:`.hertz`).

The follower leaves the cam where F falls below the safety margin F_m. For each angle, the
condition Q(θ, ω) = F_m·r is a quadratic in ω, a·ω² + b·ω + c = 0 with a = M·q'', b = C·q',
c = K·q + Q0 + Q_ext − F_m·r: its smallest positive root ω*(θ) is the speed at which the
contact at θ is first lost (no root: never), and the jump speed is the minimum of ω*(θ) over
the turn. The smallest preload that keeps the margin at the given speed follows in closed
form: Q0_min = Q0 − min_θ(Q − F_m·r), Q being linear in Q0.

Every extreme (minimum contact force, jump speed, torques, stress) is found on a grid that
holds every break point of the lift and refined by shrinking local grids between grid points
(:mod:`._extremes`), so it is the function's own extreme, not a sample's. The RMS torque is
Gauss-Legendre quadrature on cells of at most 1° between break points.

References
----------
.. [1] Norton, *Cam Design and Manufacturing Handbook*: the force-closed follower's dynamic
   force m·a + c·v + k·x + F_pl, follower jump where it falls to zero, and the camshaft torque
   by the power balance T·ω = F·v.
.. [2] Makino (1977), §5.2: spring-loaded plate cams lift off where the negative acceleration
   outruns the spring force (the reason for the trapecloid II curve).
.. [3] Johnson (1985), §4.2: the Hertz pressure of two cylinders in line contact.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from ..._checks import non_negative, positive
from ...curves.base import FloatArray
from ...deadline import checkpoint
from ...errors import GeometryError, InvalidParameterError
from ..cam import CamSpec
from ..checks import check_grid, corners
from ..lift import TWO_PI
from ._extremes import refine_maxima
from .hertz import effective_modulus_mpa, line_contact_pressure_mpa, roller_contact_radius_mm
from .load import FollowerLoad, RollerMaterials
from .results import DynamicsSummary, DynamicsTable, FollowerDynamics

#: Gauss-Legendre nodes per cell of the RMS quadrature, and the widest cell [rad]: 8 nodes are
#: exact for polynomials of degree 15, so on 1° cells of a smooth piece the rule's error is far
#: below the rounding of the torque itself
GAUSS_NODES = 8
RMS_CELL_RAD = math.radians(1.0)
#: ``separates`` needs the force below the margin by more than this share of the largest force: a
#: minimum that meets the margin exactly (a preload of ``min_preload_n``, the jump speed itself)
#: comes out a few ulp either side of it
SEPARATION_ROUNDING = 1e-12


@dataclass(frozen=True)
class _State:
    """Everything at some cam angles that does not depend on the speed."""

    theta: FloatArray  # cam angle [rad]
    lift: list[FloatArray]  # h, h', h'' in the lift's unit per rad^k
    q: FloatArray  # q, q', q'' in SI (m or rad, per rad^k)
    q1: FloatArray
    q2: FloatArray
    arm: FloatArray  # r: 1 (translating) or the lever arm [m]
    cos_phi: FloatArray
    kappa: FloatArray  # signed curvature of the pitch curve [1/mm]


class LoadedFollower:
    """The follower's equation of motion on one cam, evaluated at any cam angles (a machine's
    plate-cam axis uses it as :func:`follower_dynamics` does, so both give the same numbers)."""

    def __init__(self, spec: CamSpec, load: FollowerLoad, margin_n: float, roller: RollerMaterials | None):
        self.spec = spec
        self.model = spec.model
        self.co = load.coefficients()
        self.margin_n = margin_n
        self.oscillating = spec.follower.motion == "oscillating"
        #: the lift's unit to SI: mm → m, or deg → rad
        self.to_si = math.radians(1.0) if self.oscillating else 1e-3
        self.roller = roller
        self.e_star = (None if roller is None else
                       effective_modulus_mpa(roller.youngs_modulus_mpa, roller.poisson_ratio,
                                             roller.cam_modulus_mpa, roller.cam_poisson))

    def state(self, theta: FloatArray) -> _State:
        checkpoint()
        theta = np.asarray(theta, dtype=np.float64)
        lift = self.spec.lift.derivatives(theta, 2)
        kin = self.model.kinematics(self.spec.base_radius_mm, self.spec.sigma, theta, lift)
        if not self.oscillating:
            arm = np.ones_like(theta)
        elif self.model.flat_faced:
            assert kin.offset is not None  # a flat face reports where it touches
            arm = 1e-3 * kin.offset
        else:
            arm = np.full_like(theta, 1e-3 * float(self.spec.follower.arm_length_mm or 0.0))
        q, q1, q2 = (self.to_si * x for x in lift)
        return _State(theta, lift, q, q1, q2, arm, np.cos(kin.pressure), kin.kappa_pitch)

    # ---------------------------------------------------------------- at a speed
    def static(self, st: _State) -> FloatArray:
        """K·q + Q0 + Q_ext: what holds the follower at rest [N or N·m]."""
        return self.co.stiffness * st.q + self.co.preload + self.co.external

    def pivot_force(self, st: _State, omega: float) -> FloatArray:
        """Q = M·q''·ω² + C·q'·ω + K·q + Q0 + Q_ext [N or N·m]."""
        return self.co.mass * st.q2 * omega**2 + self.co.damping * st.q1 * omega + self.static(st)

    def jump_omega(self, st: _State) -> FloatArray:
        """ω*(θ): the smallest ω > 0 with Q(θ, ω) = F_m·r, +inf where there is none, 0 where
        the margin is not met even at rest [rad/s]."""
        return self._first_root(self.co.mass * st.q2, self.co.damping * st.q1,
                                self.static(st) - self.margin_n * st.arm)

    @staticmethod
    def _first_root(a: FloatArray, b: FloatArray, c: FloatArray) -> FloatArray:
        """The smallest ω > 0 with a·ω² + b·ω + c = 0 (c > 0 at rest), +inf where there is none,
        0 where c ≤ 0 [rad/s]."""
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            disc = b * b - 4.0 * a * c
            root = np.sqrt(np.maximum(disc, 0.0))
            # the two forms of the same root, each free of cancellation on its side of b = 0
            rising = (root + b) / (-2.0 * a)  # b > 0: a root only when a < 0
            falling = 2.0 * c / (root - b)  # b ≤ 0: a root when a < 0, or a > 0 with disc ≥ 0
            omega = np.where(b > 0, np.where(a < 0, rising, np.inf),
                             np.where((disc >= 0) & (root - b > 0), falling, np.inf))
        return np.where(c <= 0, 0.0, np.where(np.isfinite(omega) & (omega > 0), omega, np.inf))

    def stress_omega(self, st: _State, allowed_mpa: float) -> FloatArray:
        """ω at which the Hertz pressure first reaches ``allowed_mpa`` at each angle, +inf where it
        never does, 0 where it is exceeded at rest [rad/s].

        p0 ≤ p_allowed is F_n ≤ F_allowed = p_allowed²·π·b·R/E* (:mod:`.hertz`), so, with
        F_n = Q/(r·cos φ), the speed solves M·q''·ω² + C·q'·ω + (static − F_allowed·r·cos φ) = 0
        rising through zero: :meth:`jump_omega`'s quadratic with every sign turned."""
        assert self.roller is not None and self.e_star is not None
        radius = roller_contact_radius_mm(self.model.roller_radius_mm, st.kappa)
        allowed_n = allowed_mpa**2 * math.pi * self.roller.width_mm * radius / self.e_star
        return self._first_root(-self.co.mass * st.q2, -self.co.damping * st.q1,
                                allowed_n * st.arm * st.cos_phi - self.static(st))

    def torque(self, st: _State, omega: float) -> FloatArray:
        """T = Q·q', the camshaft torque by virtual work [N·m] (as :meth:`quantities`)."""
        return self.pivot_force(st, omega) * st.q1

    def stress(self, st: _State, normal_n: FloatArray) -> FloatArray:
        """Hertz pressure p0 of the roller on the cam [MPa]."""
        assert self.roller is not None and self.e_star is not None
        radius = roller_contact_radius_mm(self.model.roller_radius_mm, st.kappa)
        return line_contact_pressure_mpa(normal_n, self.roller.width_mm, self.e_star, radius)

    def quantities(self, st: _State, omega: float) -> dict[str, FloatArray]:
        """Q, F, F_n, T (and p0 with a roller) at the state's angles."""
        pivot = self.pivot_force(st, omega)
        contact = pivot / st.arm
        normal = contact / st.cos_phi
        out = {"pivot": pivot, "contact": contact, "normal": normal, "torque": pivot * st.q1}
        if self.roller is not None:
            out["stress"] = self.stress(st, normal)
        return out


def _check_inputs(spec: CamSpec, load: FollowerLoad, roller: RollerMaterials | None) -> None:
    motion = spec.follower.motion
    if load.motion != motion:
        wanted = "mass_kg and spring_rate_n_mm" if motion == "translating" else "inertia_kgm2 and spring_rate_nm_rad"
        raise InvalidParameterError(f"A {motion} follower's load is given by {wanted} (its own units).")
    if roller is not None and spec.follower.type != "roller":
        raise InvalidParameterError(
            f"roller (width and materials, for the contact stress) needs a roller follower, not a {spec.follower.type}.")
    jumps = corners(spec)
    if jumps:
        where = ", ".join(f"{a:.6g}°" for a in jumps[:5])
        raise GeometryError(
            f"The lift's velocity jumps at {where}: the follower's acceleration is infinite there (an impact), so "
            "its contact force is not defined. Use motion laws whose velocity is continuous at every join.")


def _gauss_cells(breaks: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Nodes and weights of composite Gauss-Legendre over one turn, no cell across a break."""
    ends = np.sort(np.mod(breaks, TWO_PI)) if breaks.size else np.zeros(1)
    ends = np.append(ends, ends[0] + TWO_PI)
    x, w = np.polynomial.legendre.leggauss(GAUSS_NODES)
    nodes, weights = [], []
    for a, b in itertools.pairwise(ends.tolist()):
        if b - a <= 0:
            continue
        cells = max(1, math.ceil((b - a) / RMS_CELL_RAD))
        edges = np.linspace(a, b, cells + 1)
        half = 0.5 * np.diff(edges)[:, None]
        mid = 0.5 * (edges[:-1] + edges[1:])[:, None]
        nodes.append((mid + half * x).ravel())
        weights.append((half * w).ravel())
    return np.concatenate(nodes), np.concatenate(weights)


def follower_dynamics(spec: CamSpec, load: FollowerLoad, speed_rpm: float, samples: int = 361, *,
                      safety_margin_n: float = 0.0, roller: RollerMaterials | None = None) -> FollowerDynamics:
    """Contact force, jump speed, minimum preload, camshaft torque and Hertz stress of a
    force-closed follower on a plate cam at a constant camshaft speed.

    Parameters
    ----------
    spec : CamSpec
        The cam and its follower (lift in mm, or degrees of swing).
    load : TranslatingLoad or OscillatingLoad
        Mass or inertia, spring, preload, external force or torque, damping, in the
        follower's own units; its motion must be the follower's.
    speed_rpm : float
        N, the camshaft's speed (> 0) [rpm].
    samples : int
        Rows of the table, evenly over 0-360° of cam angle, both ends included (≥ 2) [-].
    safety_margin_n : float
        F_m, the contact force the follower must keep (≥ 0) [N].
    roller : RollerMaterials, optional
        Width and materials of a roller follower, for the Hertz stress.

    Returns
    -------
    FollowerDynamics
        The table over the cam angle and the summary over the turn (units in the field names:
        [N], [N·m], [MPa], [rpm], [deg]).

    Raises
    ------
    InvalidParameterError
        A value out of its range, a load of the other motion, a roller on another follower.
    GeometryError
        A lift whose velocity jumps (an impact), or a roller that undercuts the cam.

    References
    ----------
    Norton, *Cam Design and Manufacturing Handbook* (dynamic force, jump, camshaft torque);
    Makino (1977), §5.2 (lift-off of spring-loaded plate cams); Johnson (1985), §4.2 (Hertz).
    """
    positive("speed_rpm", speed_rpm)
    margin = non_negative("safety_margin_n", safety_margin_n)
    if isinstance(samples, bool) or not isinstance(samples, int | np.integer) or samples < 2:
        raise InvalidParameterError(f"samples must be a whole number ≥ 2, not {samples!r}.")
    _check_inputs(spec, load, roller)
    follower = LoadedFollower(spec, load, margin, roller)
    omega = 2.0 * math.pi * speed_rpm / 60.0
    if not math.isfinite(TWO_PI / omega):  # the time column: a subnormal ω's reciprocal overflows
        raise InvalidParameterError(f"speed_rpm={speed_rpm!r} is too slow: one turn would last longer than the "
                                    "largest number of seconds a double holds.", field=("speed_rpm",))
    grid = check_grid(spec)
    if roller is not None:
        radius = roller_contact_radius_mm(follower.model.roller_radius_mm, follower.state(grid).kappa)
        if not radius.min() > 0:
            near = math.degrees(float(grid[int(np.argmin(radius))]))
            raise GeometryError(f"The roller undercuts the cam near {near:.4g}° (its radius reaches the pitch curve's "
                                "radius of curvature there): the contact stress is not defined. Use a smaller roller "
                                "or a larger base circle.")

    def objectives(theta: FloatArray) -> FloatArray:
        st = follower.state(theta)
        values = follower.quantities(st, omega)
        reserve = values["pivot"] - margin * st.arm
        rows = [-values["contact"], -reserve, -follower.jump_omega(st), values["normal"], values["torque"],
                -values["torque"]]
        if roller is not None:
            rows.append(values["stress"])
        return np.vstack(rows)

    at, best = refine_maxima(objectives, grid)
    at_deg = np.degrees(at)
    jump = -best[2]
    co = follower.co
    min_preload = co.preload + best[1]  # Q0 − min(Q − F_m·r)
    t_max, t_min = best[4], -best[5]
    peak = (t_max, at_deg[4]) if abs(t_max) >= abs(t_min) else (abs(t_min), at_deg[5])
    nodes, weights = _gauss_cells(np.asarray(spec.lift.breaks_rad, dtype=np.float64))
    torque_at_nodes = follower.quantities(follower.state(nodes), omega)["torque"]
    rms = math.sqrt(float(np.dot(weights, torque_at_nodes**2)) / TWO_PI)
    summary = DynamicsSummary(
        speed_rpm=float(speed_rpm),
        safety_margin_n=margin,
        min_contact_force_n=float(-best[0]),
        min_contact_force_at_deg=float(at_deg[0]),
        separates=bool(-best[0] < margin - SEPARATION_ROUNDING * max(abs(best[0]), abs(best[3]), margin)),
        jump_speed_rpm=float(jump * 60.0 / (2.0 * math.pi)) if math.isfinite(jump) else None,
        jump_at_deg=float(at_deg[2]) if math.isfinite(jump) else None,
        min_preload_n=None if follower.oscillating else float(min_preload),
        min_preload_nm=float(min_preload) if follower.oscillating else None,
        max_normal_force_n=float(best[3]),
        max_normal_force_at_deg=float(at_deg[3]),
        peak_camshaft_torque_nm=float(peak[0]),
        peak_camshaft_torque_at_deg=float(peak[1]),
        max_camshaft_torque_nm=float(t_max),
        max_camshaft_torque_at_deg=float(at_deg[4]),
        min_camshaft_torque_nm=float(t_min),
        min_camshaft_torque_at_deg=float(at_deg[5]),
        rms_camshaft_torque_nm=rms,
        max_contact_stress_mpa=float(best[6]) if roller is not None else None,
        max_contact_stress_at_deg=float(at_deg[6]) if roller is not None else None,
        effective_modulus_mpa=follower.e_star,
    )
    return FollowerDynamics(spec.lift.unit, _table(follower, omega, samples), summary)


def _table(follower: LoadedFollower, omega: float, samples: int) -> DynamicsTable:
    angle_deg = np.linspace(0.0, 360.0, samples)
    st = follower.state(np.radians(angle_deg))
    values = follower.quantities(st, omega)
    h, h1, h2 = st.lift
    return DynamicsTable(
        cam_angle_deg=angle_deg,
        time_s=st.theta / omega,
        lift=h,
        velocity=h1 * omega,
        acceleration=h2 * omega**2,
        spring_force=follower.co.stiffness * st.q + follower.co.preload,
        contact_force_n=values["contact"],
        normal_force_n=values["normal"],
        camshaft_torque_nm=values["torque"],
        contact_stress_mpa=values.get("stress"),
        contact_torque_nm=values["pivot"] if follower.oscillating else None,
    )
