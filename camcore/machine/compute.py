"""A machine: several axes on one camshaft, their summed torque, the flywheel, the motor, the speed limits.

At a camshaft speed ω the total torque is T(x) = Σ T_i(x) over the master angle x. Over the turn:

* the mean T̄ = (1/2π)∫T dx (the work per turn over 2π; the inertia parts average to zero), the RMS
  √((1/2π)∫T² dx), both by Gauss–Legendre on cells of at most 0.5° between every axis's break points,
  split where a kinked integrand changes branch (a torque through an efficiency at its zeros), so
  each cell holds a smooth function;
* the energy E(x) = ∫₀ˣ (T − T̄) dx at every cell edge, the zeros of T − T̄ among them, so its
  largest and smallest values, and ΔE = max E − min E, are exact (Norton, *Design of Machinery*,
  "Flywheels"); the system inertia on the camshaft for a coefficient of speed fluctuation Cs is
  I = ΔE/(Cs·ω²), and a given inertia leaves Cs = ΔE/(I·ω²);
* the peaks refined between grid points that hold every break (golden section);
* the motor through the gear (i motor turns per camshaft turn, efficiency η): T/(i·η) driving,
  T·η/i braking. With a flywheel the motor carries the mean plus what the flywheel does not absorb:
  the motor's torque falls with its speed by its slip s at the rated torque T_r, T_m = T̄ − c·Δω with
  c = i·T_r/(s·ω) on the camshaft, and I·ω·dΔω/dx = T_m − T; per harmonic k of the load torque the
  motor carries 1/(1 + i·k·λ) of it, λ = I·ω/c (the periodic solution, by FFT of T on 4096 angles).

References
----------
.. [1] Norton, *Design of Machinery*, chapter "Flywheels": E, ΔE, Cs = (ω_max − ω_min)/ω_avg,
   I_s = ΔE/(Cs·ω_avg²).
.. [2] Power balance of a drive with losses: P_motor = P_load/η driving, P_load·η braking.
.. [3] Golub and Welsch (1969): Gauss quadrature nodes (numpy.polynomial.legendre.leggauss).
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from .._checks import finite, positive
from .._solvers import NoFeasiblePointError, scan_roots, smallest_feasible
from ..curves.base import FloatArray
from ..deadline import checkpoint
from ..errors import InvalidParameterError
from ..indexer.drive import Motor, motor_scale
from ..profile.dynamics._extremes import refine_maxima
from ..profile.lift import TWO_PI
from .axes import MachineAxis
from .results import AxisLimit, AxisReport, MachineResult, MachineSummary, MotorFigures, SpeedLimits
from .rules import Rule, check_rule

#: widest quadrature cell [rad] and Gauss–Legendre nodes per cell: 8 nodes are exact for degree 15,
#: far below the torques' rounding on 0.5° cells of a smooth piece
CELL_RAD = math.radians(0.5)
GAUSS_NODES = 8
_GL_X, _GL_W = np.polynomial.legendre.leggauss(GAUSS_NODES)
#: angles of the motor-with-flywheel model's FFT (the motor's torque is a filtered load torque: its
#: harmonics fall as 1/k, so 4096 angles resolve it far below the motor's own data)
FFT_ANGLES = 4096
FFT_OVERSAMPLING = 8
#: the break points' left neighbours on the peak grid: no jump strictly inside a cell
LEFT = 1e-10


@dataclass(frozen=True)
class Flywheel:
    """Give one: the coefficient of speed fluctuation Cs to keep (0 < Cs < 1), or the flywheel's inertia."""

    speed_fluctuation: float | None = None
    inertia_kgm2: float | None = None

    def __post_init__(self) -> None:
        if (self.speed_fluctuation is None) == (self.inertia_kgm2 is None):
            raise InvalidParameterError("a flywheel gives exactly one of speed_fluctuation and inertia_kgm2.")
        if self.speed_fluctuation is not None and not 0 < finite("speed_fluctuation", self.speed_fluctuation) < 1:
            raise InvalidParameterError("speed_fluctuation must satisfy 0 < Cs < 1.", field=("speed_fluctuation",))
        if self.inertia_kgm2 is not None and finite("inertia_kgm2", self.inertia_kgm2) < 0:
            raise InvalidParameterError("inertia_kgm2 must be ≥ 0.", field=("inertia_kgm2",))


@dataclass(frozen=True)
class Drive:
    """The camshaft's drive: ``gear_ratio`` i (motor-side turns per camshaft turn, before the motor's own
    reduction), ``efficiency`` η of the gear, the ``motor`` and its ``slip`` s at rated torque (the
    fraction its speed drops from no load to rated torque, for the flywheel model)."""

    motor: Motor
    gear_ratio: float = 1.0
    efficiency: float = 1.0
    slip: float = 0.05

    def __post_init__(self) -> None:
        positive("gear_ratio", self.gear_ratio)
        if not 0 < finite("efficiency", self.efficiency) <= 1:
            raise InvalidParameterError("efficiency must satisfy 0 < η ≤ 1.", field=("efficiency",))
        if not 0 < finite("slip", self.slip) < 1:
            raise InvalidParameterError("slip must satisfy 0 < s < 1.", field=("slip",))

    @property
    def ratio(self) -> float:
        """Motor turns per camshaft turn, the gear's and the motor's reduction together [-]."""
        return self.gear_ratio * self.motor.reduction_ratio

    @property
    def scale(self) -> Callable[[FloatArray], FloatArray]:
        """Camshaft torque → motor torque (every efficiency applied)."""
        return motor_scale(dataclasses.replace(self.motor, reduction_ratio=self.ratio), self.efficiency)

    @property
    def reflected_rotor_inertia_kgm2(self) -> float:
        return self.motor.rotor_inertia_kgm2 * self.ratio**2


def _rpm(omega: float) -> float:
    return omega * 60.0 / TWO_PI


class Machine:
    """Axes on one camshaft (unique names), their timing rules, a flywheel and a drive."""

    def __init__(self, axes: Sequence[MachineAxis], rules: Sequence[Rule] = (), flywheel: Flywheel | None = None,
                 drive: Drive | None = None):
        self.axes = list(axes)
        self.by_name = {a.name: a for a in self.axes}
        if len(self.by_name) != len(self.axes):
            raise InvalidParameterError("axis names must be unique.", field=("axes",))
        for i, rule in enumerate(rules):
            for part, c in (("while", rule.when), ("require", rule.require)):
                if c.axis not in self.by_name:
                    raise InvalidParameterError(
                        f"rules[{i}].{part}.axis names {c.axis!r}, which is not an axis of this machine "
                        f"({', '.join(self.by_name)}).", field=("rules", i, part, "axis"))
        self.rules, self.flywheel, self.drive = list(rules), flywheel, drive
        breaks = [np.mod(a.breaks() + math.radians(a.phase_deg), TWO_PI) for a in self.axes]
        self.breaks = np.unique(np.concatenate([*breaks, [0.0]]))
        self.edges = self._cells(np.concatenate([self.breaks, [TWO_PI]]))
        self.peak_grid = np.unique(np.concatenate([self.edges[:-1], np.mod(self.breaks - LEFT, TWO_PI)]))

    @staticmethod
    def _cells(edges: FloatArray) -> FloatArray:
        """Every edge kept, the stretches between them cut into cells of at most CELL_RAD."""
        out = [edges[:1]]
        for a, b in itertools.pairwise(edges.tolist()):
            n = max(1, math.ceil((b - a) / CELL_RAD))
            out.append(np.linspace(a, b, n + 1)[1:])
        return np.unique(np.concatenate(out))

    # ------------------------------------------------------------------ torques
    def axis_torques(self, x: FloatArray, omega: float) -> FloatArray:
        """(axes, len(x)): each axis's camshaft torque at master angles x [rad] [N·m]."""
        checkpoint()
        return np.vstack([a.torque(a.own(x), omega) for a in self.axes])

    def total(self, x: FloatArray, omega: float) -> FloatArray:
        """The camshaft's total torque at master angles x [rad] [N·m]."""
        return np.asarray(self.axis_torques(x, omega).sum(axis=0), dtype=np.float64)

    def _split(self, fun: Callable[[FloatArray], FloatArray], edges: FloatArray) -> FloatArray:
        """The edges with the zeros of ``fun`` between them added."""
        roots, _ = scan_roots(fun, edges)
        return np.unique(np.concatenate([edges, roots]))

    def _cell_integrals(self, fun: Callable[[FloatArray], FloatArray], edges: FloatArray) -> FloatArray:
        """∫ fun over each cell between neighbouring edges (Gauss–Legendre)."""
        a, b = edges[:-1], edges[1:]
        nodes = 0.5 * (a + b)[:, None] + 0.5 * (b - a)[:, None] * _GL_X[None, :]
        values = fun(nodes.ravel()).reshape(nodes.shape)
        return np.asarray(0.5 * (b - a) * (values @ _GL_W), dtype=np.float64)

    def _kinked_edges(self, omega: float) -> FloatArray:
        """The cells, split where an axis's torque through an efficiency changes sign (it kinks there)."""
        edges = self.edges
        for axis in self.axes:
            load = getattr(axis, "load", None)
            if getattr(load, "efficiency", 1.0) != 1.0:
                def torque(x: FloatArray, axis: MachineAxis = axis) -> FloatArray:
                    return axis.torque(axis.own(x), omega)
                edges = self._split(torque, edges)
        return edges

    # ------------------------------------------------------------------ one speed
    def summary(self, speed_rpm: float) -> MachineSummary:
        """The totals, the flywheel and the motor at one speed."""
        speed_rpm = positive("speed_rpm", speed_rpm)
        omega = TWO_PI * speed_rpm / 60.0

        def total(x: FloatArray) -> FloatArray:
            return self.total(x, omega)

        edges = self._kinked_edges(omega)
        work = float(self._cell_integrals(total, edges).sum())
        mean = work / TWO_PI
        split = self._split(lambda x: total(x) - mean, edges)
        energy = np.concatenate([[0.0], np.cumsum(self._cell_integrals(lambda x: total(x) - mean, split))])
        i_max, i_min = int(np.argmax(energy)), int(np.argmin(energy))
        delta_e = float(energy[i_max] - energy[i_min])
        rms = math.sqrt(float(self._cell_integrals(lambda x: total(x) ** 2, edges).sum()) / TWO_PI)
        at, best = refine_maxima(lambda x: np.vstack([t := total(x), -t, np.abs(t)]), self.peak_grid)
        at_deg = np.degrees(at)
        inertia, flywheel, fluctuation = self._flywheel(delta_e, omega)
        motor = None if self.drive is None else self._motor(edges, total, mean, omega, inertia)
        summary = MachineSummary(
            speed_rpm=float(speed_rpm), cycle_time_s=60.0 / speed_rpm,
            peak_total_nm=float(best[2]), peak_total_at_deg=float(at_deg[2]),
            max_total_nm=float(best[0]), max_total_at_deg=float(at_deg[0]),
            min_total_nm=float(-best[1]), min_total_at_deg=float(at_deg[1]),
            rms_total_nm=rms, mean_total_nm=mean, work_per_cycle_j=work, energy_fluctuation_j=delta_e,
            energy_max_at_deg=float(np.degrees(split[i_max])), energy_min_at_deg=float(np.degrees(split[i_min])),
            system_inertia_kgm2=inertia, flywheel_inertia_kgm2=flywheel, speed_fluctuation=fluctuation, motor=motor)
        return summary

    def axis_reports(self, speed_rpm: float) -> tuple[AxisReport, ...]:
        """Each axis's camshaft torque figures and its own operation's checks at one speed."""
        omega = TWO_PI * speed_rpm / 60.0
        at, best = refine_maxima(lambda x: np.abs(self.axis_torques(x, omega)), self.peak_grid)
        edges = self._kinked_edges(omega)
        reports = []
        for k, axis in enumerate(self.axes):
            def one(x: FloatArray, axis: MachineAxis = axis) -> FloatArray:
                return axis.torque(axis.own(x), omega)
            mean = float(self._cell_integrals(one, edges).sum()) / TWO_PI
            rms = math.sqrt(float(self._cell_integrals(lambda x, f=one: f(x) ** 2,  # type: ignore[misc]
                                                       edges).sum()) / TWO_PI)
            reports.append(AxisReport(axis.name, axis.kind, axis.unit, axis.phase_deg, float(best[k]),
                                      float(np.degrees(at[k])), rms, mean, axis.checks(speed_rpm)))
        return tuple(reports)

    def _flywheel(self, delta_e: float, omega: float) -> tuple[float | None, float | None, float | None]:
        """(system inertia, the flywheel itself, Cs) from ΔE: I = ΔE/(Cs·ω²)."""
        rotor = 0.0 if self.drive is None else self.drive.reflected_rotor_inertia_kgm2
        fw = self.flywheel
        if fw is None:
            return None, None, None
        if fw.speed_fluctuation is not None:
            system = delta_e / (fw.speed_fluctuation * omega**2)
            return system, max(system - rotor, 0.0), fw.speed_fluctuation
        assert fw.inertia_kgm2 is not None
        system = fw.inertia_kgm2 + rotor
        return system, fw.inertia_kgm2, (delta_e / (system * omega**2) if system > 0 else None)

    def _motor(self, edges: FloatArray, total: Callable[[FloatArray], FloatArray], mean: float, omega: float,
               inertia: float | None) -> MotorFigures:
        drive = self.drive
        assert drive is not None
        scale, motor = drive.scale, drive.motor
        split = self._split(total, edges)
        rms = math.sqrt(float(self._cell_integrals(lambda x: scale(total(x)) ** 2, split).sum()) / TWO_PI)
        t_max, t_min = self._extremes(total)
        peak = float(np.abs(scale(np.array([t_max, t_min]))).max())
        peak_fw = rms_fw = cs_fw = None
        if inertia is not None and inertia > 0:
            _, carried, c = self.carried(total, mean, omega, inertia)
            at_motor = scale(carried)
            peak_fw = float(np.abs(at_motor).max())
            rms_fw = float(np.sqrt(np.mean(at_motor**2)))
            cs_fw = float((carried.max() - carried.min()) / (c * omega))
        speed = _rpm(omega) * drive.ratio
        use_peak, use_rms = (peak, rms) if peak_fw is None or rms_fw is None else (peak_fw, rms_fw)
        reasons = []
        if use_peak > motor.peak_torque_nm:
            reasons.append(f"the peak torque {use_peak:.4g} N·m exceeds the motor's peak torque "
                           f"{motor.peak_torque_nm:.4g} N·m")
        if use_rms > motor.rated_torque_nm:
            reasons.append(f"the RMS torque {use_rms:.4g} N·m exceeds the motor's rated torque "
                           f"{motor.rated_torque_nm:.4g} N·m")
        if speed > motor.max_speed_rpm:
            reasons.append(f"the motor speed {speed:.4g} rpm exceeds its maximum {motor.max_speed_rpm:.4g} rpm")
        return MotorFigures(speed, peak, rms, peak_fw, rms_fw, cs_fw, drive.reflected_rotor_inertia_kgm2,
                            not reasons, "; ".join(reasons) or None)

    def carried(self, total: Callable[[FloatArray], FloatArray], mean: float | None, omega: float, inertia: float
                ) -> tuple[FloatArray, FloatArray, float]:
        """The camshaft torque the motor carries with the flywheel (see the module notes): the angles
        [rad], the torque there [N·m] and the motor's slope c on the camshaft [N·m·s/rad]. ``mean``: T̄
        (None: the mean of the samples)."""
        drive = self.drive
        assert drive is not None
        x = np.arange(FFT_ANGLES, dtype=np.float64) * (TWO_PI / FFT_ANGLES)
        torque = total(x)
        mean = float(torque.mean()) if mean is None else mean
        ripple = np.fft.rfft(torque - mean)
        c = drive.ratio * drive.motor.rated_torque_nm / (drive.slip * omega)
        lam = inertia * omega / c
        # read back on 8× as many angles (the trigonometric interpolant): its peak within (π/32768)²/2 of the
        # series' own, where the 4096 angles alone would miss it by up to 3e-7 of the amplitude
        fine = FFT_ANGLES * FFT_OVERSAMPLING
        carried = mean + FFT_OVERSAMPLING * np.fft.irfft(ripple / (1.0 + 1j * np.arange(ripple.size) * lam), fine)
        x_fine = np.arange(fine, dtype=np.float64) * (TWO_PI / fine)
        return x_fine, np.asarray(carried, dtype=np.float64), c

    def _extremes(self, total: Callable[[FloatArray], FloatArray]) -> tuple[float, float]:
        _, best = refine_maxima(lambda x: np.vstack([t := total(x), -t]), self.peak_grid)
        return float(best[0]), float(-best[1])

    # ------------------------------------------------------------------ columns
    def timing(self, x_deg: FloatArray) -> dict[str, FloatArray]:
        """x_deg, then per axis its position (``<name>_<unit>``) and ``<name>_normalised``."""
        x = np.radians(x_deg)
        columns: dict[str, FloatArray] = {"x_deg": x_deg}
        for a in self.axes:
            own = a.own(x)
            columns[f"{a.name}_{a.unit}"] = a.position(own)
            columns[f"{a.name}_normalised"] = a.normalised(own)
        return columns

    def torque_columns(self, x_deg: FloatArray, speed_rpm: float, summary: MachineSummary | None = None
                       ) -> dict[str, FloatArray]:
        """x_deg, per axis ``<name>_nm``, ``total_nm``; with a drive ``motor_nm`` (at the motor, no flywheel)
        and, given the summary of a machine with a flywheel, ``carried_by_motor_nm`` (the camshaft torque the
        motor carries with it) and ``motor_with_flywheel_nm`` (at the motor), interpolated from the model's
        4096 angles [N·m]."""
        omega = TWO_PI * speed_rpm / 60.0
        each = self.axis_torques(np.radians(x_deg), omega)
        columns: dict[str, FloatArray] = {"x_deg": x_deg}
        for a, t in zip(self.axes, each, strict=True):
            columns[f"{a.name}_nm"] = t
        total = each.sum(axis=0)
        columns["total_nm"] = total
        if self.drive is not None:
            columns["motor_nm"] = self.drive.scale(total)
            inertia = None if summary is None else summary.system_inertia_kgm2
            if summary is not None and inertia:
                grid, carried, _ = self.carried(lambda x: self.total(x, omega), summary.mean_total_nm, omega, inertia)
                at = np.interp(np.radians(x_deg), np.append(grid, TWO_PI), np.append(carried, carried[0]))
                columns["carried_by_motor_nm"] = at
                columns["motor_with_flywheel_nm"] = self.drive.scale(at)
        return columns

    # ------------------------------------------------------------------ limits
    def speed_limits(self, speed_rpm: float, inertia: float | None = None) -> SpeedLimits:
        """Each axis's first failure speed, the drive's (motor speed; peak and RMS torque, with the flywheel of
        system inertia ``inertia`` [kg·m²] when given), and the smallest."""
        limits = []
        for a in self.axes:
            lim = a.speed_limit()
            limits.append(AxisLimit(a.name, lim.speed_rpm, lim.reason, lim.at_deg))
        if self.drive is not None:
            limits += self._drive_limits(speed_rpm, inertia)
        found = [lim for lim in limits if lim.speed_rpm is not None]
        if not found:
            return SpeedLimits(tuple(limits), None, None, None, True)
        first = min(found, key=lambda lim: float(lim.speed_rpm))  # type: ignore[arg-type]
        top = first.speed_rpm
        return SpeedLimits(tuple(limits), top, first.axis, first.reason, top is None or top >= speed_rpm)

    def _drive_limits(self, speed_rpm: float, inertia: float | None) -> list[AxisLimit]:
        """The motor's speed limit, and the speeds at which its peak and RMS torque reach its ratings: through a
        stiff drive, or with the machine's flywheel (its inertia at the machine's speed, as built) by the model of
        the module notes, as the motor check at the machine's speed takes them."""
        drive = self.drive
        assert drive is not None
        motor, scale = drive.motor, drive.scale
        top = motor.max_speed_rpm / drive.ratio
        out = [AxisLimit("drive", top, f"the motor reaches its maximum speed {motor.max_speed_rpm:g} rpm", None)]
        a, b = self.edges[:-1], self.edges[1:]
        nodes = np.concatenate([self.peak_grid, (0.5 * (a + b)[:, None] + 0.5 * (b - a)[:, None] * _GL_X).ravel()])
        flywheel = inertia is not None and inertia > 0

        def at_motor(rpm: float) -> FloatArray:
            omega = TWO_PI * rpm / 60.0
            if flywheel:
                assert inertia is not None
                return scale(self.carried(lambda x: self.total(x, omega), None, omega, inertia)[1])
            # the grid and every quadrature node (cells of 0.5°, 9 points each): the peak within
            # ½|T''|·(0.07°)² of the refined one, a relative 1e-6 of the speed for the torques here
            return scale(self.total(nodes, omega))

        def peak(rpm: float) -> float:
            return float(np.abs(at_motor(rpm)).max())

        def rms(rpm: float) -> float:
            if flywheel:
                return float(np.sqrt(np.mean(at_motor(rpm) ** 2)))
            omega = TWO_PI * rpm / 60.0

            def total(x: FloatArray) -> FloatArray:
                return self.total(x, omega)
            split = self._split(total, self._kinked_edges(omega))
            return math.sqrt(float(self._cell_integrals(lambda x: scale(total(x)) ** 2, split).sum()) / TWO_PI)

        how = " (with the flywheel)" if flywheel else " (stiff drive, no flywheel)"
        for figure, rating, words in ((peak, motor.peak_torque_nm, "peak torque"),
                                      (rms, motor.rated_torque_nm, "rated torque (RMS)")):
            if figure(top) < rating:
                continue  # within the rating up to the motor's top speed
            def margin(n: float, f: Callable[[float], float] = figure, r: float = rating) -> float:
                return f(n) - r if n > 0 else -math.inf
            try:
                rpm = smallest_feasible(margin, 0.0, min(speed_rpm, top), rel_tol=1e-9)
            except NoFeasiblePointError:
                continue
            at_rest = rpm <= 1e-6 * speed_rpm  # the friction and work torques alone exceed it
            out.append(AxisLimit("drive", 0.0 if at_rest else rpm, f"the motor's {words} {rating:g} N·m is reached"
                                 + (" at rest (friction and work alone)" if at_rest else how), None))
        return out

    # ------------------------------------------------------------------ everything
    def compute(self, speed_rpm: float, speeds_rpm: Sequence[float] = ()) -> MachineResult:
        """The summary, the axes, the speed limits and the rules at one speed, and the summary per swept speed."""
        rules = tuple(check_rule(rule, self.by_name) for rule in self.rules)
        sweep = tuple(self.summary(n) for n in speeds_rpm)
        summary = self.summary(speed_rpm)
        return MachineResult(summary, self.axis_reports(speed_rpm),
                             self.speed_limits(speed_rpm, summary.system_inertia_kgm2), rules, sweep)
