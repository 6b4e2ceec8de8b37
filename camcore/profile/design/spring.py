"""The spring of a design: the softest spring and smallest preload that keep the follower on the cam
over a range of speeds, and the force, contact stress and contact force those give.

With q the follower's coordinate (the lift in metres or the swing in radians), the cam's force
on the follower along its motion (the torque about the pivot) at camshaft speed ω is
(:mod:`camcore.profile.dynamics.compute`)

    Q(θ, ω) = M·q''·ω² + C·q'·ω + K·q + Q0 + Q_ext.

Over a speed range [ω_lo, ω_hi] the worst case at each angle is the extreme of the quadratic
a·ω² + b·ω (a = M·q'', b = C·q') over the range: its ends, or its vertex ω = −b/(2a) where that
lies inside (a minimum where a > 0, a maximum where a < 0), in closed form. The margin
Q ≥ F_m·r (r the lever arm of the follower point, 1 for a translating follower) then holds at
every speed of the range when

    Q0 ≥ Q0_min(K) = max_θ (F_m·r − min_ω(a·ω² + b·ω) − Q_ext − K·q),

a maximum of functions affine in K: convex, and non-increasing in K because the lift q ≥ 0.
So the softest spring whose preload fits under a cap is the root of Q0_min(K) = cap, found by
:func:`camcore._solvers.smallest_feasible` on the monotone margin cap − Q0_min(K).

References
----------
.. [1] Norton, *Cam Design and Manufacturing Handbook*: the force-closed follower's dynamic force
   m·a + c·v + k·x + F_pl and follower jump where it falls to zero.
.. [2] Dowell and Jarratt (1971), the Illinois method.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from ..._maxima import periodic_grid_maxima
from ..._solvers import smallest_feasible
from ...curves.base import FloatArray
from ..cam import CamSpec
from ..checks import LiftGrid, check_grid
from ..dynamics import LoadedFollower, OscillatingLoad, TranslatingLoad
from ..dynamics._extremes import refine_maxima
from .problem import FollowerLoad

#: relative width at which the softest spring's bracket is closed
SPRING_REL_TOL = 1e-10


def speed_extreme(a: FloatArray, b: FloatArray, omega_lo: float, omega_hi: float, lowest: bool) -> FloatArray:
    """The least (or greatest) of a·ω² + b·ω over ω ∈ [ω_lo, ω_hi], elementwise.

    Parameters
    ----------
    a, b : ndarray
        The quadratic's coefficients at each angle [N·s² or N·m·s², N·s or N·m·s].
    omega_lo, omega_hi : float
        The speed range [rad/s] (equal ends: one speed).
    lowest : bool
        The least value (else the greatest).

    Returns
    -------
    ndarray
        The extreme over the range [N or N·m]: at an end, or at the vertex −b/(2a) where it lies
        inside the range and the quadratic turns the right way there.

    References
    ----------
    Norton, *Cam Design and Manufacturing Handbook* (the inertia and damping forces m·a + c·v).
    """
    at_lo = a * omega_lo**2 + b * omega_lo
    at_hi = a * omega_hi**2 + b * omega_hi
    if omega_hi <= omega_lo:
        return at_lo
    with np.errstate(divide="ignore", invalid="ignore"):
        vertex = -b / (2.0 * a)
        at_vertex = -b * b / (4.0 * a)
    inside = (vertex > omega_lo) & (vertex < omega_hi) & ((a > 0) if lowest else (a < 0))
    ends = np.minimum(at_lo, at_hi) if lowest else np.maximum(at_lo, at_hi)
    return np.where(inside, np.minimum(ends, at_vertex) if lowest else np.maximum(ends, at_vertex), ends)


def follower_load(motion: str, load: FollowerLoad, rate: float, preload: float) -> TranslatingLoad | OscillatingLoad:
    """The dynamics' load of a follower with this spring (the follower's own units).

    Parameters
    ----------
    motion : str
        translating or oscillating.
    load : FollowerLoad
        Mass (or inertia), damping, external force (or torque).
    rate, preload : float
        The spring rate [N/mm or N·m/rad] and its preload [N or N·m].

    Returns
    -------
    TranslatingLoad or OscillatingLoad
        The load :func:`camcore.profile.dynamics.follower_dynamics` takes.

    References
    ----------
    Norton, *Cam Design and Manufacturing Handbook* (the force-closed follower's load).
    """
    if motion == "oscillating":
        return OscillatingLoad(load.mass, rate, preload, load.external, load.damping)
    return TranslatingLoad(load.mass, rate, preload, load.external, load.damping)


class SpringModel:
    """A follower's equation of motion on one cam, as the design needs it: the spring's own units
    turned into SI once, the worst speed of the range at each angle, every figure exact over the turn.

    For a roller or knife-edge follower, and every translating one, nothing here depends on the base
    radius (the lever arm is the arm length, or 1), so one model serves the whole search; a flat-faced
    oscillating follower's arm is where its face touches the cam, so its model is built at the final cam.
    """

    def __init__(self, spec: CamSpec, load: FollowerLoad, margin_n: float):
        self.spec, self.load, self.margin_n = spec, load, margin_n
        unit = follower_load(spec.follower.motion, load, 1.0, 0.0)
        co = unit.coefficients()
        #: SI stiffness of one unit of the spring rate (N/m per N/mm, or 1)
        self.per_rate = co.stiffness
        self.mass, self.damping, self.external = co.mass, co.damping, co.external
        self.loaded = LoadedFollower(spec, unit, margin_n, load.roller)
        self.omega_lo, self.omega_hi = (2.0 * math.pi * n / 60.0 for n in load.speed_rpm)
        self.grid = check_grid(spec)
        self.on_grid = self.loaded.state(self.grid)
        self.lift_grid = LiftGrid(self.grid, self.on_grid.lift)
        #: exact evaluations over the turn (each a grid and its refinement)
        self.exact_runs = 0

    # ------------------------------------------------------------------ on any angles
    def reserve(self, st: object, rate: float | FloatArray) -> FloatArray:
        """min_ω(Q) − F_m·r at preload 0: what the preload must add to keep the margin [N or N·m]."""
        q, q1, q2, arm = st.q, st.q1, st.q2, st.arm  # type: ignore[attr-defined]
        inertial = speed_extreme(self.mass * q2, self.damping * q1, self.omega_lo, self.omega_hi, lowest=True)
        return inertial + self.per_rate * np.asarray(rate)[..., None] * q + self.external - self.margin_n * arm

    def peak_force(self, st: object, rate: float | FloatArray, preload: float | FloatArray) -> FloatArray:
        """max_ω(Q) at each angle: the force (torque) that presses hardest [N or N·m]."""
        q, q1, q2 = st.q, st.q1, st.q2  # type: ignore[attr-defined]
        inertial = speed_extreme(self.mass * q2, self.damping * q1, self.omega_lo, self.omega_hi, lowest=False)
        return (inertial + self.per_rate * np.asarray(rate)[..., None] * q + np.asarray(preload)[..., None]
                + self.external)

    # ------------------------------------------------------------------ exact over the turn
    def min_preload(self, rate: float) -> float:
        """Q0_min(K): the smallest preload that keeps the margin at every speed of the range, exact over
        the turn (the grid's best point refined by local grids) [N or N·m]."""
        self.exact_runs += 1

        def rows(theta: FloatArray) -> FloatArray:
            return -self.reserve(self.loaded.state(theta), rate)[None, :]

        values = -self.reserve(self.on_grid, rate)[None, :]
        return float(periodic_grid_maxima(rows, self.grid, values)[0][1])

    def softest(self, lo: float, hi: float, cap: float) -> float | None:
        """The softest spring rate in [lo, hi] whose smallest preload is at most ``cap`` (None: not
        even the stiffest) [N/mm or N·m/rad]."""
        def margin(rate: float) -> float:
            return cap - self.min_preload(rate)

        if margin(lo) >= 0:
            return lo
        if hi <= lo or margin(hi) < 0:
            return None
        return smallest_feasible(margin, lo, hi, SPRING_REL_TOL)

    def extremes(self, rate: float, preload: float, spec: CamSpec | None = None) -> tuple[float, float | None]:
        """The smallest contact force over the turn and the speeds [N], and the largest Hertz pressure
        [N/mm²] (None without roller materials), exact as :func:`camcore.profile.dynamics.follower_dynamics`
        finds its extremes (grid, then golden section between neighbours), at the cam ``spec`` (default
        the model's)."""
        self.exact_runs += 1
        loaded = self.loaded if spec is None else LoadedFollower(spec, self.loaded_load(), self.margin_n,
                                                                  self.load.roller)
        stress = self.load.roller is not None

        def rows(theta: FloatArray) -> FloatArray:
            st = loaded.state(theta)
            low = self.reserve(st, rate) + preload + self.margin_n * st.arm
            out = [-low / st.arm]
            if stress:
                out.append(loaded.stress(st, self.peak_force(st, rate, preload) / (st.arm * st.cos_phi)))
            return np.vstack(out)

        _at, best = refine_maxima(rows, check_grid(loaded.spec))
        return float(-best[0]), (float(best[1]) if stress else None)

    def loaded_load(self) -> TranslatingLoad | OscillatingLoad:
        """The unit-spring load the model was made with."""
        return follower_load(self.spec.follower.motion, self.load, 1.0, 0.0)

    def stress_margin(self, rate: float, preload: float, allowed_mpa: float) -> Callable[[CamSpec], float]:
        """``spec -> 1 − (max p0 / p_allowed)²`` at this spring, exact over the turn (−inf where the roller
        undercuts the cam: its stress is not defined there): a margin that grows with the base radius."""
        def margin(spec: CamSpec) -> float:
            kin = self.lift_grid.kinematics(spec)
            rr = spec.model.roller_radius_mm
            if not np.all(rr * (1.0 - rr * kin.kappa_pitch) > 0):
                return -math.inf
            stress = self.extremes(rate, preload, spec)[1]
            assert stress is not None
            return 1.0 - (stress / allowed_mpa) ** 2

        return margin
