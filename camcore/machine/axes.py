"""The axes of a machine: each mechanism on the camshaft as the machine sees it.

An axis turns with the camshaft (the master) at its phase φ: at master angle x its own angle is
θ = (x − φ) mod 360°. Every axis answers, at its own angles, its position (mm or deg), the
position normalised to 0…1, where it dwells, where its derivatives may jump, and its torque on
the camshaft at a camshaft speed ω, by virtual work from its own forces:

* a plate cam with a force-closed follower: T = Q·q' (:class:`~camcore.profile.dynamics.LoadedFollower`,
  the same numbers :func:`~camcore.profile.dynamics.follower_dynamics` gives);
* a lift driving a load (a barrel cam's follower in its groove, a motion program's slave):
  Q = M·q''·ω² + C·q'·ω + Q_ext and T = Q·q'/η where the cam drives, Q·q'·η where the load drives
  the cam back;
* an indexer geared to the camshaft, r input turns per master turn: T = r·T_in(r·θ), T_in its input
  torque over the cycle as its sizing gives it (service factor and internal friction included).

References
----------
.. [1] Norton, *Cam Design and Manufacturing Handbook*: camshaft torque by the power balance T·ω = F·v.
.. [2] Power balance of a drive with losses: P_in = P_out/η driving, P_out·η braking.
.. [3] INDEXMAN technical guide, sections 3 and 5 (the indexer's input torque over the cycle).
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._checks import finite, positive
from ..curves.base import FloatArray
from ..errors import InvalidParameterError
from ..indexer import Indexer, Load, TimedIndexer, origin_shift_deg, size, to_origin
from ..indexer.drive import Cycle
from ..indexer.sizing import machine_cycle
from ..profile.cam import CamSpec
from ..profile.checks import check_grid, lift_check_grid, profile_checks
from ..profile.dynamics import FollowerLoad, LoadedFollower, RollerMaterials, follower_dynamics
from ..profile.dynamics._extremes import refine_maxima
from ..profile.lift import TWO_PI, Lift
from ..results import as_dict

#: a piece of a lift is a dwell when its velocity at these fractions of the piece is zero
DWELL_PROBES = np.array([0.125, 0.375, 0.5, 0.625, 0.875])
#: |velocity| at or below this share of the stroke per radian counts as zero (a dwell's is exactly 0)
DWELL_TOLERANCE = 1e-12


@dataclass(frozen=True)
class SpeedLimit:
    """The camshaft speed at which an axis (or the drive) first fails, and why."""

    speed_rpm: float | None
    reason: str
    at_deg: float | None = None  # master angle where it fails first


def _efficiency_applied(power_torque: FloatArray, efficiency: float) -> FloatArray:
    """T/η where the torque drives (T > 0), T·η where it brakes [N·m]."""
    if efficiency == 1.0:
        return power_torque
    return np.where(power_torque > 0, power_torque / efficiency, power_torque * efficiency)


class MachineAxis(ABC):
    """One mechanism on the camshaft (see the module notes); angles are its own, in radians."""

    name: str
    phase_deg: float
    kind: str
    unit: str

    def own(self, master_rad: FloatArray) -> FloatArray:
        """θ = x − φ, brought into [0, 2π] (x itself at φ = 0, so a one-axis machine samples its
        axis at exactly the angles of the axis's own operation) [rad]."""
        own = np.asarray(master_rad, dtype=np.float64) - math.radians(self.phase_deg)
        return np.where(own < 0, own + TWO_PI, own)

    @abstractmethod
    def position(self, own: FloatArray) -> FloatArray:
        """Position [mm or deg]."""

    @abstractmethod
    def derivatives_per_deg(self, own: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Position [unit], its slope [unit/deg] and curvature [unit/deg²] over the own angle (a cam table's)."""

    @abstractmethod
    def normalised(self, own: FloatArray) -> FloatArray:
        """Position normalised to 0…1 [-]."""

    @abstractmethod
    def breaks(self) -> FloatArray:
        """Own angles in [0, 2π) where a derivative may jump [rad]."""

    @abstractmethod
    def dwells(self) -> list[tuple[float, float]]:
        """Own-angle stretches [a, b] (0 ≤ a < b ≤ 2π) where the axis stands still [rad]."""

    @abstractmethod
    def torque(self, own: FloatArray, omega: float) -> FloatArray:
        """Torque on the camshaft at camshaft speed ω [rad/s] [N·m]."""

    @abstractmethod
    def checks(self, speed_rpm: float) -> dict[str, Any]:
        """The axis's own operation's figures at the camshaft speed (plain data)."""

    @abstractmethod
    def speed_limit(self) -> SpeedLimit:
        """The first failure speed of the axis itself [rpm] (None: none of its own)."""


# ----------------------------------------------------------------------------- lifts
def lift_dwells(lift: Lift) -> list[tuple[float, float]]:
    """Where a lift stands still: the pieces between its break points whose velocity is zero.

    Parameters
    ----------
    lift : Lift
        A lift over one turn (a plate cam's, a barrel cam's, a motion program's).

    Returns
    -------
    list of (float, float)
        Stretches [a, b] of the cam angle, merged where they touch [rad].

    References
    ----------
    VDI 2143 Blatt 1 (1980): a dwell (rest) is a stretch of zero velocity between motion laws.
    """
    breaks = np.unique(np.mod(np.asarray(lift.breaks_rad, dtype=np.float64), TWO_PI))
    edges = np.concatenate([[0.0], breaks[breaks > 0], [TWO_PI]])
    lo, hi = edges[:-1], edges[1:]
    keep = hi > lo
    lo, hi = lo[keep], hi[keep]
    probes = (lo[:, None] + (hi - lo)[:, None] * DWELL_PROBES[None, :]).ravel()
    h, h1 = lift.derivatives(probes, 1)
    scale = max(float(np.max(np.abs(h))), 1.0)
    still = np.all(np.abs(h1).reshape(lo.size, -1) <= DWELL_TOLERANCE * scale, axis=1)
    return merge_spans([(float(a), float(b)) for a, b, s in zip(lo, hi, still, strict=True) if s])


def merge_spans(spans: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """Stretches joined where they touch or overlap.

    Parameters
    ----------
    spans : list of (float, float)
        Stretches [a, b] of an angle, in any order [rad or deg].

    Returns
    -------
    list of (float, float)
        Disjoint stretches, in order, in the unit given [rad or deg].

    References
    ----------
    Interval union by a sweep over the sorted starts.
    """
    out: list[tuple[float, float]] = []
    for a, b in sorted(spans):
        if out and a <= out[-1][1]:
            out[-1] = (out[-1][0], max(out[-1][1], b))
        else:
            out.append((a, b))
    return out


class _LiftAxis(MachineAxis):
    """An axis whose position is a lift over its own angle (mm or deg)."""

    lift: Lift

    def __init__(self, name: str, phase_deg: float, lift: Lift, unit: str):
        self.name, self.phase_deg, self.lift, self.unit = name, float(phase_deg), lift, unit
        grid = lift_check_grid(lift)
        _, (top, neg_bottom) = refine_maxima(lambda t: np.vstack([p := lift.derivatives(t, 0)[0], -p]), grid)
        self.low, self.high = float(-neg_bottom), float(top)

    @property
    def stroke(self) -> float:
        return self.high - self.low

    def position(self, own: FloatArray) -> FloatArray:
        return self.lift.derivatives(own, 0)[0]

    def derivatives_per_deg(self, own: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        h, h1, h2 = self.lift.derivatives(own, 2)
        per_deg = math.pi / 180.0
        return h, h1 * per_deg, h2 * per_deg**2

    def normalised(self, own: FloatArray) -> FloatArray:
        span = self.stroke
        return (self.position(own) - self.low) / span if span > 0 else np.zeros_like(own)

    def breaks(self) -> FloatArray:
        return np.unique(np.mod(np.asarray(self.lift.breaks_rad, dtype=np.float64), TWO_PI))

    def dwells(self) -> list[tuple[float, float]]:
        return lift_dwells(self.lift)


class PlateCamAxis(_LiftAxis):
    """A plate cam with a force-closed follower (spring, preload, mass, damping)."""

    kind = "plate_cam"

    def __init__(self, name: str, phase_deg: float, cam: CamSpec, load: FollowerLoad, *, safety_margin_n: float = 0.0,
                 roller: RollerMaterials | None = None, allowed_stress_mpa: float | None = None):
        super().__init__(name, phase_deg, cam.lift, cam.lift.unit)
        self.cam, self.load, self.margin, self.roller = cam, load, float(safety_margin_n), roller
        self.allowed_stress_mpa = allowed_stress_mpa
        if allowed_stress_mpa is not None and roller is None:
            raise InvalidParameterError("allowed_stress_mpa needs the roller's width and materials (roller).",
                                        field=("allowed_stress_mpa",))
        self.follower = LoadedFollower(cam, load, self.margin, roller)

    def torque(self, own: FloatArray, omega: float) -> FloatArray:
        return self.follower.torque(self.follower.state(own), omega)

    def checks(self, speed_rpm: float) -> dict[str, Any]:
        dynamics = follower_dynamics(self.cam, self.load, speed_rpm, 2, safety_margin_n=self.margin, roller=self.roller)
        return {"dynamics": as_dict(dynamics.summary), "profile": as_dict(profile_checks(self.cam))}

    def speed_limit(self) -> SpeedLimit:
        """The jump speed (contact force down to the safety margin) or the speed at which the Hertz
        pressure reaches the allowed stress, whichever is lower; exact over the turn."""
        f = self.follower
        rows = [lambda st: -f.jump_omega(st)]
        if self.allowed_stress_mpa is not None:
            allowed = float(self.allowed_stress_mpa)
            rows.append(lambda st: -f.stress_omega(st, allowed))
        at, best = refine_maxima(lambda t: np.vstack([row(f.state(t)) for row in rows]), check_grid(self.cam))
        speeds = -best * 60.0 / TWO_PI
        i = int(np.argmin(speeds))
        if not math.isfinite(speeds[i]):
            return SpeedLimit(None, "the follower keeps its contact at every speed (a lift without motion)")
        at_deg = float(np.mod(np.degrees(at[i]) + self.phase_deg, 360.0))
        if i == 0:
            why = (f"follower jump: the contact force falls to the safety margin {self.margin:g} N"
                   if self.margin > 0 else "follower jump: the contact force falls to zero")
        else:
            why = f"Hertz stress reaches the allowed {self.allowed_stress_mpa:g} MPa"
        return SpeedLimit(float(speeds[i]), why, at_deg)


@dataclass(frozen=True)
class DrivenLoad:
    """What a lift drives: M, C, Q_ext in the follower's SI coordinate (m or rad) and the efficiency.

    ``mass`` [kg or kg·m²], ``damping`` [N·s/m or N·m·s/rad], ``external`` [N or N·m] (positive
    resisting the positive motion), ``efficiency`` η (0 < η ≤ 1) of the mechanism in between.
    """

    mass: float
    damping: float = 0.0
    external: float = 0.0
    efficiency: float = 1.0

    def __post_init__(self) -> None:
        finite("mass", self.mass)
        if self.mass < 0:
            raise InvalidParameterError("a driven load's mass must be ≥ 0.", field=("mass_kg",))
        finite("external", self.external)
        eta = finite("efficiency", self.efficiency)
        if not 0 < eta <= 1:
            raise InvalidParameterError(f"efficiency must satisfy 0 < η ≤ 1, got {eta!r}.", field=("efficiency",))


class LiftLoadAxis(_LiftAxis):
    """A lift driving a load through a positive drive: a barrel cam's groove, a motion program's slave."""

    def __init__(self, name: str, phase_deg: float, lift: Lift, unit: str, load: DrivenLoad, kind: str,
                 checks: dict[str, Any]):
        super().__init__(name, phase_deg, lift, unit)
        self.load, self.kind, self._checks = load, kind, checks
        self.to_si = math.radians(1.0) if unit == "deg" else 1e-3

    def torque(self, own: FloatArray, omega: float) -> FloatArray:
        _, h1, h2 = self.lift.derivatives(own, 2)
        q1, q2 = self.to_si * h1, self.to_si * h2
        load = self.load
        pivot = load.mass * q2 * omega**2 + load.damping * q1 * omega + load.external
        return _efficiency_applied(pivot * q1, load.efficiency)

    def checks(self, speed_rpm: float) -> dict[str, Any]:
        return self._checks

    def speed_limit(self) -> SpeedLimit:
        return SpeedLimit(None, "positive drive (the load is held both ways): no jump")


# ----------------------------------------------------------------------------- indexers
class IndexerAxis(MachineAxis):
    """An indexer whose input shaft turns ``ratio`` (a whole number) times per camshaft turn.

    Its position is the output angle from its position at master angle φ [deg]; normalised, the
    progress of the current index (0 at a station, 1 at the end of the index); a closed timing chart
    (an oscillating unit) normalised over its swing instead.
    """

    kind = "indexer"
    unit = "deg"

    def __init__(self, name: str, phase_deg: float, unit: Indexer | TimedIndexer, load: Load, *, ratio: int = 1,
                 internal_friction_torque_nm: float = 0.0, rated_output_torque_nm: float | None = None,
                 input_angle_origin: str = "index-start"):
        self.name, self.phase_deg, self.load = name, float(phase_deg), load
        #: where the sizing's input angles start (the indexer's own answer's origin)
        self.origin_shift_deg = origin_shift_deg(unit, input_angle_origin)
        if isinstance(ratio, bool) or not isinstance(ratio, int | np.integer) or ratio < 1:
            raise InvalidParameterError(
                f"ratio must be a whole number ≥ 1 of input turns per camshaft turn, so the indexer's cycle repeats "
                f"every camshaft turn; got {ratio!r}.", field=("ratio",))
        if unit.input_stop_time_s:
            raise InvalidParameterError(
                "an indexer geared to the camshaft turns with it: its input cannot stand still "
                "(input_stop_time_s must be 0).", field=("indexer", "input_stop_time_s"))
        self.ratio = int(ratio)
        self.unit_at = unit
        self.internal = float(internal_friction_torque_nm)
        self.rated_output_torque_nm = None if rated_output_torque_nm is None else positive(
            "rated_output_torque_nm", rated_output_torque_nm)
        self.timed = isinstance(unit, TimedIndexer)
        if isinstance(unit, Indexer) and unit.swing_angle_deg is not None and (self.ratio * unit.dwells) % 2:
            raise InvalidParameterError(
                f"an oscillating unit swings out and back: ratio × dwells = {self.ratio * unit.dwells} strokes per "
                "camshaft turn must be even, or the machine's cycle does not close.", field=("ratio",))
        if self.timed:
            program = unit.program  # type: ignore[union-attr]
            self.advance = float(program.advance)
            grid = np.linspace(0.0, 360.0, 2049)
            values = program.derivatives(grid, 0)[0]
            self.low, self.high = float(values.min()), float(values.max())
        self._cycles: dict[float, Cycle] = {}

    # ------------------------------------------------------------------ angles
    def _input_deg(self, own: FloatArray) -> FloatArray:
        """The input angle over the ratio's turns, 0 ≤ x_in ≤ 360·r [deg]."""
        return np.degrees(own) * self.ratio

    def _at_speed(self, master_rpm: float) -> Indexer | TimedIndexer:
        u = self.unit_at
        rpm = master_rpm * self.ratio
        if isinstance(u, TimedIndexer):
            return TimedIndexer(program=u.program, speed_rpm=rpm)
        return Indexer(indexing_angle_deg=u.indexing_angle_deg, stops=u.stops, swing_angle_deg=u.swing_angle_deg,
                       dwells=u.dwells, speed_rpm=rpm, curve=u.curve)

    def position(self, own: FloatArray) -> FloatArray:
        x = self._input_deg(own)
        u = self.unit_at
        if isinstance(u, TimedIndexer):
            turns = np.floor(x / 360.0)
            inside = np.where(turns >= self.ratio, 360.0, x - 360.0 * np.minimum(turns, self.ratio - 1))
            p = u.program.derivatives(inside, 0)[0] + self.advance * np.minimum(turns, self.ratio - 1)
            return np.mod(p, 360.0) if self.advance else p
        cycle = 360.0 / u.dwells
        k = np.minimum(np.floor(x / cycle), self.ratio * u.dwells - 1)
        out = u.motion_at(x - k * cycle).output_angle_deg
        h = u.displacement_deg
        if u.swing_angle_deg is not None:
            return np.where(np.mod(k, 2) == 0, out, h - out)
        return np.mod(k * h + out, 360.0)

    def derivatives_per_deg(self, own: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """The output over the camshaft angle: d/dθ = r·d/dx_in."""
        x = self._input_deg(own)
        u, r = self.unit_at, self.ratio
        if isinstance(u, TimedIndexer):
            turns = np.minimum(np.floor(x / 360.0), r - 1)
            _, v, a = u.program.derivatives(x - 360.0 * turns, 2)
            return self.position(own), r * v, r * r * a
        cycle = 360.0 / u.dwells
        k = np.minimum(np.floor(x / cycle), r * u.dwells - 1)
        table = u.motion_at(x - k * cycle)
        sign = np.where((u.swing_angle_deg is not None) & (np.mod(k, 2) == 1), -1.0, 1.0)
        return (self.position(own), sign * r * table.dout_din,
                sign * r * r * table.d2out_din2_per_rad * (math.pi / 180.0))

    def normalised(self, own: FloatArray) -> FloatArray:
        x = self._input_deg(own)
        u = self.unit_at
        if isinstance(u, TimedIndexer):
            inside = np.where(x >= 360.0 * self.ratio, 360.0, np.mod(x, 360.0))
            if not self.advance:
                return (u.program.derivatives(inside, 0)[0] - self.low) / (self.high - self.low)
            out = np.zeros_like(x)
            for law in u.program.placed:
                if law.curve is None:
                    continue
                a, b = law.x_a, law.x_a + law.span
                ends = u.program.derivatives(np.array([a, b]), 0)[0]
                here = (inside >= a) & (inside < b)
                out = np.where(here, (u.program.derivatives(inside, 0)[0] - ends[0]) / (ends[1] - ends[0]), out)
            return out
        if u.swing_angle_deg is not None:
            return self.position(own) / u.displacement_deg
        within = np.mod(x, 360.0 / u.dwells)
        moving = within < u.indexing_angle_deg
        progress = u.motion_at(np.where(moving, within, 0.0)).output_angle_deg / u.displacement_deg
        return np.where(moving, progress, 0.0)

    def _input_spans(self) -> tuple[list[tuple[float, float]], list[float]]:
        """Moving stretches and break points over one input turn [deg]."""
        u = self.unit_at
        if isinstance(u, TimedIndexer):
            moving = [(law.x_a, law.x_a + law.span) for law in u.program.placed if law.curve is not None]
            return moving, [float(b) for b in u.program.breaks_deg]
        cycle = 360.0 / u.dwells
        c = u.curve
        inner = [u.indexing_angle_deg * (t - c.t_start) / (c.t_end - c.t_start) for t in c.piece_starts.tolist()]
        moving = [(k * cycle, k * cycle + u.indexing_angle_deg) for k in range(u.dwells)]
        breaks = [k * cycle + b for k in range(u.dwells) for b in [*inner, u.indexing_angle_deg]]
        return moving, breaks

    def _to_own(self, input_deg: float, turn: int) -> float:
        return math.radians((360.0 * turn + input_deg) / self.ratio)

    def breaks(self) -> FloatArray:
        _, breaks = self._input_spans()
        own = [self._to_own(b, j) for j in range(self.ratio) for b in breaks]
        return np.unique(np.mod(np.asarray(own, dtype=np.float64), TWO_PI))

    def dwells(self) -> list[tuple[float, float]]:
        moving, _ = self._input_spans()
        spans: list[tuple[float, float]] = []
        for j in range(self.ratio):
            edge = 0.0
            for a, b in sorted(moving):
                if a > edge:
                    spans.append((self._to_own(edge, j), self._to_own(a, j)))
                edge = max(edge, b)
            if edge < 360.0:
                spans.append((self._to_own(edge, j), self._to_own(360.0, j)))
        return merge_spans(spans)

    # ------------------------------------------------------------------ torque
    def _cycle(self, omega: float) -> Cycle:
        key = float(omega)
        if key not in self._cycles:
            if len(self._cycles) > 64:
                self._cycles.clear()
            self._cycles[key] = machine_cycle(self._at_speed(omega * 60.0 / TWO_PI), self.load)
        return self._cycles[key]

    def torque(self, own: FloatArray, omega: float) -> FloatArray:
        cycle = self._cycle(omega)
        x = np.mod(self._input_deg(own), cycle.turn_deg)
        fc = float(self.load.service_factor)
        out = np.full(x.shape, self.internal)
        for law in cycle.laws:
            here = (x >= law.x_a) & (x < law.x_a + law.span)
            if here.any():
                out[here] = fc * law.at_t(law.t_of_x(x[here])) + self.internal
        return self.ratio * out

    def checks(self, speed_rpm: float) -> dict[str, Any]:
        unit = self._at_speed(speed_rpm)
        sized = size(unit, self.load, internal_friction_torque_nm=self.internal, table_samples=2)
        sizing = as_dict(to_origin(sized, self.origin_shift_deg, 360.0 / unit.dwells))
        sizing.pop("input_torque_table", None)
        return {"sizing": sizing}

    def speed_limit(self) -> SpeedLimit:
        """The speed at which the design output torque fc·(I·α_max + Tf + Tw) reaches the unit's rated
        output torque: α_max grows with the speed squared, so N = N0·√((T_rated/fc − Tf − Tw)/Ti(N0))."""
        if self.rated_output_torque_nm is None:
            return SpeedLimit(None, "no rated output torque given")
        reference = 60.0 / self.ratio  # any camshaft speed: the inertia torque scales with its square
        s = size(self._at_speed(reference), self.load, table_samples=2)
        room = self.rated_output_torque_nm / s.service_factor - s.friction_torque_nm - s.work_torque_nm
        why = f"the design output torque reaches the rated {self.rated_output_torque_nm:g} N·m"
        if room <= 0:
            return SpeedLimit(0.0, why + " at rest (friction and work torque alone)")
        if s.inertia_torque_nm <= 0:
            return SpeedLimit(None, "no inertia: the output torque does not grow with speed")
        return SpeedLimit(reference * math.sqrt(room / s.inertia_torque_nm), why)
