"""Cam indexers: kinematics over the input angle, position lookup, torque and power sizing.

An indexer turns a constantly turning input shaft into an intermittent output: during
the indexing angle θh of the input the output moves by h (one index) along a cam curve,
during the rest of the input turn (the dwell) it stands still. With the curve's
dimensionless time T and displacement S, the input angle is θ = θh·T (the input turns at
constant speed, so dimensionless time = dimensionless input position) and the output
angle is h·S.

Quantities and units
--------------------
Angles the user gives or reads are in degrees [deg]; ω, α, jerk are in radians per
second (power) [rad/s, rad/s², rad/s³]; inertia [kg·m²]; torques [N·m]; power [kW];
lengths [mm]; g = 9.80665 m/s² (standard gravity).

Curves whose T does not run over 0..1 or whose S does not run from 0 to 1 (user curves,
return strokes) are normalised: u = (T − T0)/(T7 − T0) is the fraction of the index,
S' = (S − S(T0))/(S(T7) − S(T0)) the fraction of the displacement, so that
V' = V·ΔT/ΔS, A' = A·ΔT²/ΔS, J' = J·ΔT³/ΔS. For the catalog curves ΔT = ΔS = 1 and the
formulas are the guide's.

References
----------
.. [1] INDEXMAN technical guide, section 2 (分度数和分配角: n = 360/ψ, θh, z, θt = θh·z),
   section 3 (循环时间: t0 = t1 + t2 = 60/(N·z), tm = t0 + ts), section 5 (凸轮曲线:
   s = h·S, v = (h/th)·V, a = (h/th²)·A, j = (h/th³)·J; th = (θh/360)·(60/N)), the worked
   example before 凸轮曲线的特性值一览 (input angle θ = θh·T, ω = (h/th)·V·π/180), and the
   last table 计算分度精度 (x = 2π·r·θ/(360·60·60) = 0.00000485·r·θ).
.. [2] Power balance of a lossless cam drive: input torque × input speed = output torque ×
   output speed, so T_in = (dθout/dθin)·T_out = (h/θh)·V'(T)·T_out(T). The catalog short
   form replaces the peak of V'·A' by Qm·Am (Q = A·V/Am, section 5 characteristic table).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike

from .._checks import count, finite, non_negative, positive
from ..curves.catalog import named_curve
from ..curves.curve import Curve
from ..errors import InvalidParameterError, StrokeRangeError
from .checks import check_alternatives, check_curve_moves, check_total_indexing_angle
from .results import IndexerMotion, IndexerPosition, MotionSummary, MotionTable


def indexing_time_s(indexing_angle_deg: ArrayLike, speed_rpm: ArrayLike) -> Any:
    """th = (θh/360)·(60/N), the time of one index.

    Parameters
    ----------
    indexing_angle_deg : array_like
        θh [deg].
    speed_rpm : array_like
        N [rpm].

    Returns
    -------
    float or ndarray
        th [s].

    References
    ----------
    INDEXMAN technical guide, section 5 worked example (th = (θh/360)·(60/N)).
    """
    return np.asarray(indexing_angle_deg, dtype=np.float64) / 360.0 * 60.0 / np.asarray(speed_rpm, dtype=np.float64)


def index_scales(h_rad: ArrayLike, th_s: ArrayLike, d_t: float, d_s: float) -> tuple[Any, Any, Any]:
    """Factors from a curve's V, A, J to ω, α, jerk of an index.

    Parameters
    ----------
    h_rad : array_like
        h, the output's travel per index [rad].
    th_s : array_like
        th, the indexing time [s].
    d_t, d_s : float
        T7 − T0 and S(T7) − S(T0) of the curve [-].

    Returns
    -------
    (float or ndarray, …)
        (h/th)·ΔT/ΔS [rad/s], (h/th²)·ΔT²/ΔS [rad/s²], (h/th³)·ΔT³/ΔS [rad/s³].

    References
    ----------
    INDEXMAN technical guide, section 5: v = (h/th)·V, a = (h/th²)·A, j = (h/th³)·J.
    """
    h = np.asarray(h_rad, dtype=np.float64)
    th = np.asarray(th_s, dtype=np.float64)
    return h / th * d_t / d_s, h / th**2 * d_t**2 / d_s, h / th**3 * d_t**3 / d_s


@dataclass(frozen=True, kw_only=True)
class Indexer:
    """A cam indexer (or oscillating unit) running at constant input speed.

    Parameters
    ----------
    indexing_angle_deg : float
        θh, input-shaft angle per index, 0 < θh ≤ 360 [deg].
    stops : int, optional
        n, stops per output turn (≥ 1); the output moves h = 360/n per index.
    swing_angle_deg : float, optional
        ψ, output swing of an oscillating unit, 0 < ψ ≤ 360 [deg]; h = ψ, n = 360/ψ.
        Give exactly one of ``stops`` and ``swing_angle_deg``.
    dwells : int
        z, indexes per input turn (≥ 1, θh·z ≤ 360). Default 1.
    speed_rpm : float, optional
        N, input-shaft speed [rpm].
    cycle_time_s : float, optional
        t0, unit cycle time [s]; N = 60/(t0·z). Give exactly one of ``speed_rpm`` and
        ``cycle_time_s``.
    curve : Curve or str
        The cam curve (a :class:`camcore.Curve` or a catalog name). Default MS.
    input_stop_time_s : float
        ts, time the input shaft stands still each index (≥ 0) [s]; only changes the
        machine cycle time tm = t0 + ts. Default 0.

    Raises
    ------
    InvalidParameterError
        With a sentence naming the field and the rule it breaks.

    References
    ----------
    INDEXMAN technical guide, sections 2-1 to 2-4 (n = 360/ψ, θh, z, θt = θh·z),
    section 3 (t0 = t1 + t2 = 60/(N·z), tm = t0 + ts), section 5 worked example
    (th = (θh/360)·(60/N)).
    """

    indexing_angle_deg: float
    stops: int | None = None
    swing_angle_deg: float | None = None
    dwells: int = 1
    speed_rpm: float | None = None
    cycle_time_s: float | None = None
    curve: Curve = field(default_factory=lambda: named_curve("MS"))
    input_stop_time_s: float = 0.0

    def __post_init__(self) -> None:
        put = object.__setattr__
        if isinstance(self.curve, str):
            put(self, "curve", named_curve(self.curve))
        if not isinstance(self.curve, Curve):
            raise InvalidParameterError(f"curve must be a camcore Curve or a catalog name, not {self.curve!r}.")
        check_alternatives(self.stops, self.swing_angle_deg, self.speed_rpm, self.cycle_time_s)
        if self.stops is not None:
            put(self, "stops", count("stops", self.stops))
        else:
            psi = positive("swing_angle_deg", self.swing_angle_deg)
            if psi > 360:
                raise InvalidParameterError(f"swing_angle_deg must satisfy 0 < ψ ≤ 360, got {psi!r}.")
            put(self, "swing_angle_deg", psi)
        theta_h = finite("indexing_angle_deg", self.indexing_angle_deg)
        if not 0 < theta_h <= 360:
            raise InvalidParameterError(f"indexing_angle_deg must satisfy 0 < θh ≤ 360, got {theta_h!r}.")
        put(self, "indexing_angle_deg", theta_h)
        z = count("dwells", self.dwells)
        put(self, "dwells", z)
        check_total_indexing_angle(theta_h, z)
        if self.speed_rpm is not None:
            put(self, "speed_rpm", positive("speed_rpm", self.speed_rpm))
        else:
            put(self, "cycle_time_s", positive("cycle_time_s", self.cycle_time_s))
        put(self, "input_stop_time_s", non_negative("input_stop_time_s", self.input_stop_time_s))
        check_curve_moves(self.curve)

    # ------------------------------------------------------------ derived values
    @property
    def n(self) -> float:
        """Stops per output turn n (360/ψ for an oscillating unit) [-]."""
        if self.stops is not None:
            return float(self.stops)
        return 360.0 / float(self.swing_angle_deg or 0.0)

    @property
    def displacement_deg(self) -> float:
        """h, output displacement per index: 360/n, or ψ [deg]."""
        return 360.0 / self.stops if self.stops is not None else float(self.swing_angle_deg)  # type: ignore[arg-type]

    @property
    def displacement_rad(self) -> float:
        """h [rad]."""
        return math.radians(self.displacement_deg)

    @property
    def total_indexing_angle_deg(self) -> float:
        """θt = θh·z [deg]."""
        return self.indexing_angle_deg * self.dwells

    @property
    def rpm(self) -> float:
        """Input speed N [rpm] (given, or 60/(t0·z))."""
        if self.speed_rpm is not None:
            return float(self.speed_rpm)
        return 60.0 / (float(self.cycle_time_s) * self.dwells)  # type: ignore[arg-type]

    @property
    def unit_cycle_time_s(self) -> float:
        """t0 = 60/(N·z) [s] (given, or from N)."""
        if self.cycle_time_s is not None:
            return float(self.cycle_time_s)
        return 60.0 / (self.rpm * self.dwells)

    @property
    def indexing_time_s(self) -> float:
        """th = (θh/360)·(60/N) [s]."""
        return float(indexing_time_s(self.indexing_angle_deg, self.rpm))

    @property
    def dwell_time_s(self) -> float:
        """t2 = t0 − th [s] (computed as (360/z − θh)/(6N) to avoid cancellation)."""
        return max(0.0, 360.0 / self.dwells - self.indexing_angle_deg) / (6.0 * self.rpm)

    @property
    def machine_cycle_time_s(self) -> float:
        """tm = t0 + ts [s]."""
        return self.unit_cycle_time_s + float(self.input_stop_time_s)

    @property
    def input_speed_rad_s(self) -> float:
        """Input angular speed 2πN/60 [rad/s]."""
        return 2.0 * math.pi * self.rpm / 60.0

    # ------------------------------------------------------------ curve scaling
    @property
    def spans(self) -> tuple[float, float]:
        """ΔT = T7 − T0 and ΔS = S(T7) − S(T0) of the curve [-] (1 and 1 for catalog curves)."""
        c = self.curve
        return c.t_end - c.t_start, c.s_end - c.s_start

    @property
    def scales(self) -> tuple[float, float, float]:
        """Factors from the curve's V, A, J to ω [rad/s], α [rad/s²], jerk [rad/s³]."""
        d_t, d_s = self.spans
        kv, ka, kj = index_scales(self.displacement_rad, self.indexing_time_s, d_t, d_s)
        return float(kv), float(ka), float(kj)

    def angle_of_t(self, t: Any) -> Any:
        """Input angle θ = θh·(T − T0)/ΔT at the curve's times T [deg]."""
        d_t, _ = self.spans
        return self.indexing_angle_deg * (np.asarray(t, dtype=np.float64) - self.curve.t_start) / d_t

    def time_of_t(self, t: Any) -> Any:
        """Time th·(T − T0)/ΔT from the start of the index at the curve's times T [s]."""
        d_t, _ = self.spans
        return self.indexing_time_s * (np.asarray(t, dtype=np.float64) - self.curve.t_start) / d_t

    # ------------------------------------------------------------ motion
    def summary(self) -> MotionSummary:
        """Times and exact peaks of ω, α, jerk over one index.

        References
        ----------
        INDEXMAN technical guide, sections 2, 3 and 5 (v = (h/th)·V, a = (h/th²)·A,
        j = (h/th³)·J with h in radians); the peaks are the curve's exact
        characteristic values (Vm, Am±, Jm±).
        """
        ch = self.curve.characteristics
        kv, ka, kj = self.scales
        pos_a, neg_a = (ch.am_pos, ch.am_neg) if ka > 0 else (ch.am_neg, ch.am_pos)
        pos_j, neg_j = (ch.jm_pos, ch.jm_neg) if kj > 0 else (ch.jm_neg, ch.jm_pos)
        ang, tim = self.angle_of_t, self.time_of_t

        def where(t: float) -> tuple[float, float]:
            return float(ang(t)), float(tim(t))

        a_pos, a_neg = ka * pos_a.value, ka * neg_a.value
        j_pos, j_neg = kj * pos_j.value, kj * neg_j.value
        return MotionSummary(
            indexing_time_s=self.indexing_time_s,
            cycle_time_s=self.unit_cycle_time_s,
            dwell_time_s=self.dwell_time_s,
            machine_cycle_time_s=self.machine_cycle_time_s,
            displacement_deg=self.displacement_deg,
            stops=self.n,
            indexing_angle_deg=self.indexing_angle_deg,
            total_indexing_angle_deg=self.total_indexing_angle_deg,
            dwell_angle_deg=360.0 / self.dwells - self.indexing_angle_deg,
            dwells=self.dwells,
            speed_rpm=self.rpm,
            omega_rad_s=abs(kv) * ch.vm.value,
            omega_input_angle_deg=where(ch.vm.t)[0],
            omega_time_s=where(ch.vm.t)[1],
            alpha_rad_s2=max(abs(a_pos), abs(a_neg)),
            alpha_pos_rad_s2=a_pos,
            alpha_pos_input_angle_deg=where(pos_a.t)[0],
            alpha_pos_time_s=where(pos_a.t)[1],
            alpha_neg_rad_s2=a_neg,
            alpha_neg_input_angle_deg=where(neg_a.t)[0],
            alpha_neg_time_s=where(neg_a.t)[1],
            jerk_rad_s3=max(abs(j_pos), abs(j_neg)),
            jerk_pos_rad_s3=j_pos,
            jerk_pos_input_angle_deg=where(pos_j.t)[0],
            jerk_pos_time_s=where(pos_j.t)[1],
            jerk_neg_rad_s3=j_neg,
            jerk_neg_input_angle_deg=where(neg_j.t)[0],
            jerk_neg_time_s=where(neg_j.t)[1],
        )

    def motion_at(self, input_angles_deg: ArrayLike) -> MotionTable:
        """Output motion at given input angles over one cycle.

        Parameters
        ----------
        input_angles_deg : array_like
            Input angles from the start of the index, 0 ≤ θ ≤ 360/z [deg]. Angles in
            (θh, 360/z] are in the dwell: the output stands at h with ω = α = jerk = 0.

        Returns
        -------
        MotionTable
            ``time_s`` = θ/(6N) [s]; output angle h·S' [deg]; ω, α, jerk [rad/s, rad/s²,
            rad/s³]. At a break point the right-hand piece is used (the catalog's rule).

        References
        ----------
        INDEXMAN technical guide, section 5 (s = h·S, v = (h/th)·V, a = (h/th²)·A,
        j = (h/th³)·J) and worked example (dimensionless time = input position, θ = θh·T).
        """
        theta = np.asarray(input_angles_deg, dtype=np.float64).reshape(-1)
        cycle = 360.0 / self.dwells
        bad = ~np.isfinite(theta) | (theta < 0) | (theta > cycle)
        if bad.any():
            i = int(np.nonzero(bad)[0][0])
            raise InvalidParameterError(
                f"input_angle_deg[{i}] = {float(theta[i])!r} must lie in one cycle, 0 ≤ θ ≤ 360/z = {cycle!r}°."
            )
        c = self.curve
        d_t, d_s = self.spans
        theta_h = self.indexing_angle_deg
        u = np.minimum(theta / theta_h, 1.0)
        t = c.t_start + d_t * u
        s, v, a, j = c.derivatives(t, 3)
        dwell = theta > theta_h
        kv, ka, kj = self.scales
        h = self.displacement_deg
        out = h * (s - c.s_start) / d_s
        out = np.where(dwell, h, out)
        omega = np.where(dwell, 0.0, kv * v)
        alpha = np.where(dwell, 0.0, ka * a)
        jerk = np.where(dwell, 0.0, kj * j)
        h_rad, th_rad = self.displacement_rad, math.radians(theta_h)
        ratio = np.where(dwell, 0.0, h_rad / th_rad * v * d_t / d_s)
        ratio2 = np.where(dwell, 0.0, h_rad / th_rad**2 * a * d_t**2 / d_s)
        return MotionTable(
            input_angle_deg=theta,
            time_s=theta / (6.0 * self.rpm),
            output_angle_deg=out,
            omega_rad_s=omega,
            alpha_rad_s2=alpha,
            jerk_rad_s3=jerk,
            dout_din=ratio,
            d2out_din2_per_rad=ratio2,
        )

    def motion(self, samples: int = 101) -> IndexerMotion:
        """Summary and a table at ``samples`` input angles evenly over [0, θh].

        Parameters
        ----------
        samples : int
            Number of rows (≥ 2), both ends of the index included [-].

        Returns
        -------
        IndexerMotion
            :meth:`summary` and :meth:`motion_at` of the rows.
        """
        n = count("samples", samples)
        if n < 2:
            raise InvalidParameterError(f"samples must be at least 2, got {n}.")
        theta = np.linspace(0.0, self.indexing_angle_deg, n)
        return IndexerMotion(summary=self.summary(), table=self.motion_at(theta))

    # ------------------------------------------------------------ position lookup
    def position(
        self,
        output_angle_deg: ArrayLike,
        method: Literal["exact", "table"] = "exact",
        table_step: float = 0.01,
        table_decimals: int | None = None,
    ) -> IndexerPosition:
        """Input angle, time, ω and α at which the output reaches given angles.

        Parameters
        ----------
        output_angle_deg : array_like
            Output angles from the start of the index, 0 ≤ x ≤ h [deg].
        method : {"exact", "table"}
            ``exact`` solves S(T) = S to machine precision (:meth:`Curve.inverse`);
            ``table`` interpolates proportionally between rows of a ``table_step``
            table (:meth:`Curve.inverse_table`), as the catalog's worked example does.
        table_step : float
            Row spacing of the table in T (table method only) [-].
        table_decimals : int, optional
            Round the table to this many decimals first, as printed (the catalog prints 5).

        Returns
        -------
        IndexerPosition

        References
        ----------
        INDEXMAN technical guide, worked example before 凸轮曲线的特性值一览: n = 6,
        θh = 270°, MS, 60 rpm, 11° → S = 0.1833, T = 0.304, θ = 82.08°, V = 1.339,
        ω = 1.8696 rad/s.
        """
        x = np.asarray(output_angle_deg, dtype=np.float64)
        flat = x.reshape(-1)
        h = self.displacement_deg
        bad = ~np.isfinite(flat) | (flat < 0) | (flat > h)
        if bad.any():
            i = int(np.nonzero(bad)[0][0])
            raise StrokeRangeError(
                f"output_angle_deg[{i}] = {float(flat[i])!r} is outside the index, which moves the "
                f"output from 0 to h = {h!r}°.",
                field=("output_angle_deg", i),
            )
        c = self.curve
        d_t, d_s = self.spans
        lo, hi = sorted((c.s_start, c.s_end))
        s_goal = np.clip(c.s_start + d_s * flat / h, lo, hi)
        if method == "exact":
            t = c.inverse(s_goal)
            _, v, a = c.derivatives(t, 2)
        elif method == "table":
            step = positive("table_step", table_step)
            if step > d_t:
                raise InvalidParameterError(f"table_step must not exceed the curve's duration {d_t!r}, got {step!r}.")
            if table_decimals is not None:
                table_decimals = int(non_negative("table_decimals", table_decimals))
            tab = c.inverse_table(s_goal, step, table_decimals)
            t, v, a = tab.t, tab.v, tab.a
        else:
            raise InvalidParameterError(f"method must be 'exact' or 'table', not {method!r}.")
        kv, ka, _ = self.scales
        shape = x.shape
        return IndexerPosition(
            output_angle_deg=x,
            input_angle_deg=np.asarray(self.angle_of_t(t)).reshape(shape),
            time_s=np.asarray(self.time_of_t(t)).reshape(shape),
            omega_rad_s=(kv * np.asarray(v)).reshape(shape),
            alpha_rad_s2=(ka * np.asarray(a)).reshape(shape),
            t=np.asarray(t).reshape(shape),
            v=np.asarray(v).reshape(shape),
            a=np.asarray(a).reshape(shape),
            method=method,
        )
