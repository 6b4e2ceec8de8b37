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
from collections.abc import Sequence
from dataclasses import dataclass, field, fields
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .catalog import named_curve
from .curve import Curve
from .errors import InvalidParameterError, StrokeRangeError

FloatArray = NDArray[np.float64]

#: standard gravity [m/s²] (CGPM 1901), used for friction torque μ·m·g·R.
G = 9.80665



_SHAPES = ("disc", "ring", "block", "point")


# --------------------------------------------------------------------------- helpers
def _finite(name: str, value: Any) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InvalidParameterError(f"{name} must be a number, not {value!r}.") from None
    if not math.isfinite(x):
        raise InvalidParameterError(f"{name} must be a finite number, not {x!r}.")
    return x


def _positive(name: str, value: Any) -> float:
    x = _finite(name, value)
    if not x > 0:
        raise InvalidParameterError(f"{name} must be greater than 0, got {x!r}.")
    return x


def _non_negative(name: str, value: Any) -> float:
    x = _finite(name, value)
    if x < 0:
        raise InvalidParameterError(f"{name} must be 0 or more, got {x!r}.")
    return x


def _count(name: str, value: Any) -> int:
    if isinstance(value, bool):
        raise InvalidParameterError(f"{name} must be a whole number ≥ 1, not {value!r}.")
    x = _finite(name, value)
    if not x.is_integer() or x < 1:
        raise InvalidParameterError(f"{name} must be a whole number ≥ 1, got {value!r}.")
    return int(x)


def accuracy_mm(arc_seconds: ArrayLike, radius_mm: ArrayLike) -> Any:
    """Angular indexing accuracy converted to a length at a radius.

    Parameters
    ----------
    arc_seconds : float or array_like
        Angular error θ (may be signed, ±) [arcsec].
    radius_mm : float or array_like
        Radius r at which the error is measured (≥ 0) [mm].

    Returns
    -------
    float or ndarray
        Arc length x = 2π·r·θ/(360·60·60) [mm]; a float for scalar input.

    References
    ----------
    INDEXMAN technical guide, 计算分度精度 (last table): x = 2πr·θ/(360×60×60)
    = 0.00000485·r·θ; e.g. 90″ at 300 mm → 0.131 mm.
    """
    theta = np.asarray(arc_seconds, dtype=np.float64)
    r = np.asarray(radius_mm, dtype=np.float64)
    if not (np.all(np.isfinite(theta)) and np.all(np.isfinite(r))):
        raise InvalidParameterError("arc_seconds and radius_mm must be finite numbers.")
    if np.any(r < 0):
        raise InvalidParameterError("radius_mm must be 0 or more.")
    x = 2.0 * math.pi * r * theta / (360.0 * 3600.0)
    return float(x) if x.ndim == 0 else x


def _as_dict(obj: Any) -> dict[str, Any]:
    """Dataclass fields as plain Python values (floats, lists) for JSON."""
    out: dict[str, Any] = {}
    for f in fields(obj):
        val = getattr(obj, f.name)
        if isinstance(val, np.ndarray):
            out[f.name] = val.tolist()
        elif isinstance(val, np.generic):
            out[f.name] = val.item()
        else:
            out[f.name] = val
    return out


# --------------------------------------------------------------------------- results
@dataclass(frozen=True)
class MotionSummary:
    """Times and exact peaks of one index (field names as in API.md, /v1/indexers/motion).

    Peaks come from the curve's closed-form characteristic values, not from a sampled
    table; ``*_input_angle_deg`` [deg] and ``*_time_s`` [s] say where (from the start of
    the index) each first occurs.
    """

    indexing_time_s: float  #: th = (θh/360)·(60/N) [s]
    cycle_time_s: float  #: unit cycle time t0 = 60/(N·z) [s]
    dwell_time_s: float  #: t2 = t0 − th [s]
    machine_cycle_time_s: float  #: tm = t0 + ts [s]
    displacement_deg: float  #: h = 360/n or ψ [deg]
    stops: float  #: n (360/ψ for oscillating units, may be fractional)
    indexing_angle_deg: float  #: θh [deg]
    total_indexing_angle_deg: float  #: θt = θh·z [deg]
    dwell_angle_deg: float  #: input angle of one dwell, 360/z − θh [deg]
    dwells: int  #: z
    speed_rpm: float  #: N [rpm]
    omega_rad_s: float  #: largest |ω| [rad/s]
    omega_input_angle_deg: float
    omega_time_s: float
    alpha_rad_s2: float  #: largest |α| [rad/s²]
    alpha_pos_rad_s2: float  #: largest α [rad/s²]
    alpha_pos_input_angle_deg: float
    alpha_pos_time_s: float
    alpha_neg_rad_s2: float  #: most negative α (signed) [rad/s²]
    alpha_neg_input_angle_deg: float
    alpha_neg_time_s: float
    jerk_rad_s3: float  #: largest |jerk| [rad/s³]
    jerk_pos_rad_s3: float
    jerk_pos_input_angle_deg: float
    jerk_pos_time_s: float
    jerk_neg_rad_s3: float
    jerk_neg_input_angle_deg: float
    jerk_neg_time_s: float

    def as_dict(self) -> dict[str, Any]:
        return _as_dict(self)


@dataclass(frozen=True)
class MotionTable:
    """Output motion over the input angle (columns of equal length).

    ``dout_din`` = dθout/dθin [-] and ``d2out_din2_per_rad`` = d²θout/dθin² [1/rad] are
    the motion over input angle (independent of speed); the rest is over time.
    """

    input_angle_deg: FloatArray  #: from the start of the index [deg]
    time_s: FloatArray  #: from the start of the index [s]
    output_angle_deg: FloatArray  #: from the start position [deg]
    omega_rad_s: FloatArray
    alpha_rad_s2: FloatArray
    jerk_rad_s3: FloatArray
    dout_din: FloatArray
    d2out_din2_per_rad: FloatArray

    def columns(self) -> dict[str, FloatArray]:
        return {f.name: getattr(self, f.name) for f in fields(self)}


@dataclass(frozen=True)
class IndexerMotion:
    """Result of :meth:`Indexer.motion`: the ``summary`` and the ``table``."""

    summary: MotionSummary
    table: MotionTable


@dataclass(frozen=True)
class IndexerPosition:
    """Result of :meth:`Indexer.position` (field names as in API.md, /v1/indexers/position).

    ``t``, ``v``, ``a`` are the curve's dimensionless T, V, A at each output angle (as
    found by the chosen method; for the table method they are interpolated).
    """

    output_angle_deg: FloatArray
    input_angle_deg: FloatArray  #: θh·u [deg]
    time_s: FloatArray  #: th·u [s]
    omega_rad_s: FloatArray  #: (h/th)·V' [rad/s]
    alpha_rad_s2: FloatArray  #: (h/th²)·A' [rad/s²]
    t: FloatArray
    v: FloatArray
    a: FloatArray
    method: str

    def columns(self) -> dict[str, FloatArray]:
        return {f.name: getattr(self, f.name) for f in fields(self) if f.name != "method"}


# --------------------------------------------------------------------------- indexer
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
        if (self.stops is None) == (self.swing_angle_deg is None):
            raise InvalidParameterError(
                "give exactly one of stops (n, stops per output turn) and swing_angle_deg "
                "(ψ, for oscillating units)."
            )
        if self.stops is not None:
            put(self, "stops", _count("stops", self.stops))
        else:
            psi = _positive("swing_angle_deg", self.swing_angle_deg)
            if psi > 360:
                raise InvalidParameterError(f"swing_angle_deg must satisfy 0 < ψ ≤ 360, got {psi!r}.")
            put(self, "swing_angle_deg", psi)
        theta_h = _finite("indexing_angle_deg", self.indexing_angle_deg)
        if not 0 < theta_h <= 360:
            raise InvalidParameterError(f"indexing_angle_deg must satisfy 0 < θh ≤ 360, got {theta_h!r}.")
        put(self, "indexing_angle_deg", theta_h)
        z = _count("dwells", self.dwells)
        put(self, "dwells", z)
        if theta_h * z > 360 * (1 + 1e-12):
            raise InvalidParameterError(
                f"the total indexing angle θt = θh·z must not exceed 360°, but "
                f"indexing_angle_deg × dwells = {theta_h!r} × {z} = {theta_h * z!r}."
            )
        if (self.speed_rpm is None) == (self.cycle_time_s is None):
            raise InvalidParameterError(
                "give exactly one of speed_rpm (N, input speed) and cycle_time_s (t0 = 60/(N·z))."
            )
        if self.speed_rpm is not None:
            put(self, "speed_rpm", _positive("speed_rpm", self.speed_rpm))
        else:
            put(self, "cycle_time_s", _positive("cycle_time_s", self.cycle_time_s))
        put(self, "input_stop_time_s", _non_negative("input_stop_time_s", self.input_stop_time_s))
        c = self.curve
        d_t = c.t_end - c.t_start
        d_s = c.s_end - c.s_start
        if not (math.isfinite(d_s) and d_s != 0 and d_t > 0):
            raise InvalidParameterError(
                "the curve must move (S at T7 different from S at T0) to drive an index."
            )

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
        return self.indexing_angle_deg / 360.0 * 60.0 / self.rpm

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
    def _spans(self) -> tuple[float, float]:
        c = self.curve
        return c.t_end - c.t_start, c.s_end - c.s_start

    @property
    def _scales(self) -> tuple[float, float, float]:
        """Factors from the curve's V, A, J to ω [rad/s], α [rad/s²], jerk [rad/s³]."""
        d_t, d_s = self._spans
        h = self.displacement_rad
        th = self.indexing_time_s
        return h / th * d_t / d_s, h / th**2 * d_t**2 / d_s, h / th**3 * d_t**3 / d_s

    def _angle_of_t(self, t: Any) -> Any:
        d_t, _ = self._spans
        return self.indexing_angle_deg * (np.asarray(t, dtype=np.float64) - self.curve.t_start) / d_t

    def _time_of_t(self, t: Any) -> Any:
        d_t, _ = self._spans
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
        kv, ka, kj = self._scales
        pos_a, neg_a = (ch.am_pos, ch.am_neg) if ka > 0 else (ch.am_neg, ch.am_pos)
        pos_j, neg_j = (ch.jm_pos, ch.jm_neg) if kj > 0 else (ch.jm_neg, ch.jm_pos)
        ang, tim = self._angle_of_t, self._time_of_t

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
        d_t, d_s = self._spans
        theta_h = self.indexing_angle_deg
        u = np.minimum(theta / theta_h, 1.0)
        t = c.t_start + d_t * u
        s, v, a, j = c.derivatives(t, 3)
        dwell = theta > theta_h
        kv, ka, kj = self._scales
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
            Number of rows (≥ 2), both ends of the index included.
        """
        n = _count("samples", samples)
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
        d_t, d_s = self._spans
        lo, hi = sorted((c.s_start, c.s_end))
        s_goal = np.clip(c.s_start + d_s * flat / h, lo, hi)
        if method == "exact":
            t = c.inverse(s_goal)
            _, v, a = c.derivatives(t, 2)
        elif method == "table":
            step = _positive("table_step", table_step)
            if step > d_t:
                raise InvalidParameterError(f"table_step must not exceed the curve's duration {d_t!r}, got {step!r}.")
            if table_decimals is not None:
                table_decimals = int(_non_negative("table_decimals", table_decimals))
            tab = c.inverse_table(s_goal, step, table_decimals)
            t, v, a = tab.t, tab.v, tab.a
        else:
            raise InvalidParameterError(f"method must be 'exact' or 'table', not {method!r}.")
        kv, ka, _ = self._scales
        shape = x.shape
        return IndexerPosition(
            output_angle_deg=x,
            input_angle_deg=np.asarray(self._angle_of_t(t)).reshape(shape),
            time_s=np.asarray(self._time_of_t(t)).reshape(shape),
            omega_rad_s=(kv * np.asarray(v)).reshape(shape),
            alpha_rad_s2=(ka * np.asarray(a)).reshape(shape),
            t=np.asarray(t).reshape(shape),
            v=np.asarray(v).reshape(shape),
            a=np.asarray(a).reshape(shape),
            method=method,
        )


# --------------------------------------------------------------------------- loads
@dataclass(frozen=True, kw_only=True)
class LoadPart:
    """One rigid part (or ``count`` equal parts) turning with the output.

    Parameters
    ----------
    shape : {"disc", "ring", "block", "point"}
        disc: solid cylinder of diameter D; ring: hollow cylinder D, d; block: a × b
        rectangle (the sides perpendicular to the axis); point: a point mass.
    mass_kg : float
        Mass of one part (≥ 0) [kg].
    diameter_mm, inner_diameter_mm : float
        D (disc, ring) and d ≤ D (ring) [mm].
    a_mm, b_mm : float
        Block sides perpendicular to the axis [mm].
    offset_mm : float
        Distance of the part's own axis (centre of mass) from the output axis (≥ 0) [mm].
    count : int
        Number of equal parts (e.g. fixtures on a pitch circle), ≥ 1.

    References
    ----------
    Standard rigid-body moments of inertia about the centroid axis: disc m·D²/8,
    ring m·(D² + d²)/8, block m·(a² + b²)/12, point 0; parallel-axis (Steiner)
    rule I = I_c + m·r².
    """

    shape: str
    mass_kg: float
    diameter_mm: float | None = None
    inner_diameter_mm: float | None = None
    a_mm: float | None = None
    b_mm: float | None = None
    offset_mm: float = 0.0
    count: int = 1

    def __post_init__(self) -> None:
        put = object.__setattr__
        shape = str(self.shape).strip().lower()
        if shape not in _SHAPES:
            raise InvalidParameterError(f"shape must be one of {', '.join(_SHAPES)}, not {self.shape!r}.")
        put(self, "shape", shape)
        put(self, "mass_kg", _non_negative("mass_kg", self.mass_kg))
        put(self, "offset_mm", _non_negative("offset_mm", self.offset_mm))
        put(self, "count", _count("count", self.count))
        needs = {"disc": ("diameter_mm",), "ring": ("diameter_mm", "inner_diameter_mm"),
                 "block": ("a_mm", "b_mm"), "point": ()}[shape]
        for name in needs:
            if getattr(self, name) is None:
                raise InvalidParameterError(f"a {shape} part needs {name}.")
        for name in ("diameter_mm", "inner_diameter_mm", "a_mm", "b_mm"):
            if getattr(self, name) is not None:
                put(self, name, _non_negative(name, getattr(self, name)))
        if shape == "ring" and self.inner_diameter_mm > self.diameter_mm:  # type: ignore[operator]
            raise InvalidParameterError(
                f"a ring needs inner_diameter_mm ≤ diameter_mm, got {self.inner_diameter_mm!r} > {self.diameter_mm!r}."
            )

    @property
    def total_mass_kg(self) -> float:
        """count·m [kg]."""
        return self.count * self.mass_kg

    @property
    def own_inertia_kgm2(self) -> float:
        """Inertia of one part about its own axis [kg·m²]."""
        m = self.mass_kg
        if self.shape == "disc":
            return m * (self.diameter_mm * 1e-3) ** 2 / 8.0  # type: ignore[operator]
        if self.shape == "ring":
            d_out, d_in = float(self.diameter_mm or 0.0), float(self.inner_diameter_mm or 0.0)
            return m * ((d_out * 1e-3) ** 2 + (d_in * 1e-3) ** 2) / 8.0
        if self.shape == "block":
            return m * ((self.a_mm * 1e-3) ** 2 + (self.b_mm * 1e-3) ** 2) / 12.0  # type: ignore[operator]
        return 0.0

    @property
    def inertia_kgm2(self) -> float:
        """count·(I_own + m·r²) about the output axis [kg·m²]."""
        return self.count * (self.own_inertia_kgm2 + self.mass_kg * (self.offset_mm * 1e-3) ** 2)


@dataclass(frozen=True, kw_only=True)
class Load:
    """What the output drives (field names as API.md ``LoadSpec``).

    Parameters
    ----------
    inertia_kgm2 : float
        Inertia given directly (≥ 0), added to the parts' [kg·m²].
    parts : sequence of LoadPart
        Parts summed with the parallel-axis rule.
    friction_coefficient : float, optional
        μ (≥ 0); with ``friction_radius_mm`` gives Tf = μ·(Σm)·g·R over the parts' masses.
    friction_radius_mm : float, optional
        R, radius at which the friction acts (≥ 0) [mm].
    friction_torque_nm : float, optional
        Tf given directly (≥ 0) [N·m]; not together with ``friction_coefficient``.
    work_torque_nm : float
        Tw, torque the process needs while indexing (≥ 0) [N·m]. Default 0.
    service_factor : float
        fc ≥ 1. Default 1.5.
    efficiency : float
        η of the drive to the input shaft, 0 < η ≤ 1. Default 1.
    """

    inertia_kgm2: float = 0.0
    parts: Sequence[LoadPart] = ()
    friction_coefficient: float | None = None
    friction_radius_mm: float | None = None
    friction_torque_nm: float | None = None
    work_torque_nm: float = 0.0
    service_factor: float = 1.5
    efficiency: float = 1.0

    def __post_init__(self) -> None:
        put = object.__setattr__
        put(self, "inertia_kgm2", _non_negative("inertia_kgm2", self.inertia_kgm2))
        parts = tuple(self.parts)
        for i, p in enumerate(parts):
            if not isinstance(p, LoadPart):
                raise InvalidParameterError(f"parts[{i}] must be a LoadPart, not {type(p).__name__}.")
        put(self, "parts", parts)
        if self.friction_coefficient is not None:
            if self.friction_torque_nm is not None:
                raise InvalidParameterError(
                    "give friction_coefficient (with friction_radius_mm) or friction_torque_nm, not both."
                )
            put(self, "friction_coefficient", _non_negative("friction_coefficient", self.friction_coefficient))
            if self.friction_radius_mm is None:
                raise InvalidParameterError("friction_coefficient needs friction_radius_mm (friction torque μ·m·g·R).")
            if not parts:
                raise InvalidParameterError(
                    "friction_coefficient needs parts with mass_kg (friction torque μ·m·g·R uses the parts' "
                    "masses); give friction_torque_nm directly instead."
                )
        elif self.friction_radius_mm is not None:
            raise InvalidParameterError("friction_radius_mm needs friction_coefficient (friction torque μ·m·g·R).")
        if self.friction_radius_mm is not None:
            put(self, "friction_radius_mm", _non_negative("friction_radius_mm", self.friction_radius_mm))
        if self.friction_torque_nm is not None:
            put(self, "friction_torque_nm", _non_negative("friction_torque_nm", self.friction_torque_nm))
        put(self, "work_torque_nm", _non_negative("work_torque_nm", self.work_torque_nm))
        fc = _finite("service_factor", self.service_factor)
        if fc < 1:
            raise InvalidParameterError(f"service_factor must be at least 1, got {fc!r}.")
        put(self, "service_factor", fc)
        eta = _finite("efficiency", self.efficiency)
        if not 0 < eta <= 1:
            raise InvalidParameterError(f"efficiency must satisfy 0 < η ≤ 1, got {eta!r}.")
        put(self, "efficiency", eta)

    @property
    def mass_kg(self) -> float:
        """Σ count·m over the parts [kg]."""
        return float(sum(p.total_mass_kg for p in self.parts))

    @property
    def total_inertia_kgm2(self) -> float:
        """inertia_kgm2 + Σ parts [kg·m²]."""
        return self.inertia_kgm2 + float(sum(p.inertia_kgm2 for p in self.parts))

    @property
    def total_friction_torque_nm(self) -> float:
        """Tf: given, or μ·(Σm)·g·R [N·m]; 0 when neither is given."""
        if self.friction_torque_nm is not None:
            return float(self.friction_torque_nm)
        if self.friction_coefficient is not None:
            radius_m = float(self.friction_radius_mm or 0.0) * 1e-3
            return self.friction_coefficient * self.mass_kg * G * radius_m
        return 0.0


@dataclass(frozen=True)
class Sizing:
    """Result of :func:`size` (field names as in API.md, /v1/indexers/sizing).

    Torques [N·m], power [kW], inertia [kg·m²], α [rad/s²]. ``input_torque_nm`` is the
    service-factored peak of |T_in| over the index (the larger of the driving peak
    ``input_torque_pos_nm`` and the braking peak ``input_torque_neg_nm``, signed; a tie
    within 1e-12 relative goes to the driving peak); ``input_torque_t`` is the curve's T
    where it occurs (for the catalog curves, T = the fraction of the index).
    """

    inertia_kgm2: float
    mass_kg: float
    alpha_max_rad_s2: float
    omega_max_rad_s: float
    inertia_torque_nm: float
    friction_torque_nm: float
    work_torque_nm: float
    output_torque_nm: float
    design_output_torque_nm: float
    service_factor: float
    efficiency: float
    input_torque_nm: float
    input_torque_t: float
    input_torque_input_angle_deg: float
    input_torque_time_s: float
    input_torque_pos_nm: float
    input_torque_pos_t: float
    input_torque_neg_nm: float
    input_torque_neg_t: float
    input_torque_catalog_nm: float
    qm: float
    input_power_kw: float
    input_power_catalog_kw: float
    speed_rpm: float
    accuracy_mm: float | None = None

    def as_dict(self) -> dict[str, Any]:
        return _as_dict(self)


def _power_balance_peaks(curve: Curve, c1: float, c2: float) -> tuple[float, float, float, float]:
    """Exact max and min over [T0, T7] of f(T) = c1·V·A + c2·V, with the T of each.

    Candidates are each piece's ends (one-sided) and the roots of
    f' = c1·(J·V + A²) + c2·A, from :meth:`Curve.critical_points`. Ties: earliest T.
    """
    # f' = c1·(J·V + A²) + c2·A: its roots and the piece ends are where f can peak
    t_all, k_all = curve.critical_points(lambda d: c1 * (d[3] * d[1] + d[2] * d[2]) + c2 * d[2])
    _, v, a = curve._eval_pieces(t_all, k_all, 2)
    f_all = np.asarray(c1 * v * a + c2 * v, dtype=np.float64)
    order = np.argsort(t_all, kind="stable")
    t_all, f_all = t_all[order], f_all[order]
    i_max, i_min = int(np.argmax(f_all)), int(np.argmin(f_all))
    return float(f_all[i_max]), float(t_all[i_max]), float(f_all[i_min]), float(t_all[i_min])


def size(
    indexer: Indexer,
    load: Load,
    accuracy_arc_seconds: float | None = None,
    accuracy_radius_mm: float | None = None,
) -> Sizing:
    """Output and input torque and input power needed to index a load.

    Parameters
    ----------
    indexer : Indexer
    load : Load
    accuracy_arc_seconds, accuracy_radius_mm : float, optional
        If both are given, ``accuracy_mm`` = :func:`accuracy_mm` of them [arcsec, mm].

    Returns
    -------
    Sizing
        - ``alpha_max_rad_s2`` = (h/th²)·Am (h in rad, Am = max|A|)
        - ``inertia_torque_nm`` Ti = I·α_max; ``output_torque_nm`` Tt = Ti + Tf + Tw;
          ``design_output_torque_nm`` = fc·Tt
        - ``input_torque_nm`` = fc·max over T of |(h/θh)·V'(T)·[I·(h/th²)·A'(T) + Tf + Tw]|,
          the exact peak of the power balance T_in·ω_in = T_out·ω_out (h/θh is the
          output/input angle ratio), with its T, input angle and time
        - ``input_torque_catalog_nm`` = 360/(n·θh)·Qm·fc·Tt (catalog short form,
          Qm = the curve's Qm+)
        - ``input_power_kw`` = 2π·N·T_in/60/η/1000; ``input_power_catalog_kw`` the same
          with the catalog torque.

    Notes
    -----
    With Tf = Tw = 0 the exact peak is fc·(h/θh)·I·(h/th²)·max(V·A) = fc·(h/θh)·Ti·Qm,
    which is the catalog form: the two agree. Friction and work torque act at the
    velocity peak (V up to Vm ≈ 1.76 for MS) while the catalog weights them with Qm
    (≈ 0.99), so with large Tf or Tw the catalog form underestimates.

    References
    ----------
    INDEXMAN technical guide, section 5 (a = (h/th²)·A, characteristic values Qm, Am);
    section 2 (n = 360/ψ); 计算分度精度 (accuracy). Power balance of a lossless drive.
    """
    if not isinstance(indexer, Indexer):
        raise InvalidParameterError("size() needs an Indexer as its first argument.")
    if not isinstance(load, Load):
        raise InvalidParameterError("size() needs a Load as its second argument.")
    c = indexer.curve
    ch = c.characteristics
    d_t, d_s = indexer._spans
    kv, ka, _ = indexer._scales
    inertia = load.total_inertia_kgm2
    alpha_max = abs(ka) * ch.am
    ti = inertia * alpha_max
    tf = load.total_friction_torque_nm
    tw = float(load.work_torque_nm)
    tt = ti + tf + tw
    fc = float(load.service_factor)
    eta = float(load.efficiency)
    ratio = indexer.displacement_rad / math.radians(indexer.indexing_angle_deg)  # h/θh, output/input angle
    # f(T) = ratio·V'·[I·(h/th²)·A' + Tf + Tw], with V' = V·ΔT/ΔS, I·(h/th²)·A' = I·ka·A
    c1 = ratio * d_t / d_s * inertia * ka
    c2 = ratio * d_t / d_s * (tf + tw)
    f_max, t_max, f_min, t_min = _power_balance_peaks(c, c1, c2)
    # the driving peak governs unless the braking peak is larger by more than rounding
    # (for a symmetric curve without friction the two are equal up to the last bits)
    braking = abs(f_min) > abs(f_max) * (1.0 + 1e-12)
    t_peak = t_min if braking else t_max
    t_in = fc * (abs(f_min) if braking else abs(f_max))
    qm = ch.qm_pos.value * d_t / abs(d_s)
    t_cat = 360.0 / (indexer.n * indexer.indexing_angle_deg) * qm * fc * tt
    w_in = indexer.input_speed_rad_s
    acc = None
    if accuracy_arc_seconds is not None and accuracy_radius_mm is not None:
        acc = float(accuracy_mm(accuracy_arc_seconds, accuracy_radius_mm))
    return Sizing(
        inertia_kgm2=inertia,
        mass_kg=load.mass_kg,
        alpha_max_rad_s2=alpha_max,
        omega_max_rad_s=abs(kv) * ch.vm.value,
        inertia_torque_nm=ti,
        friction_torque_nm=tf,
        work_torque_nm=tw,
        output_torque_nm=tt,
        design_output_torque_nm=fc * tt,
        service_factor=fc,
        efficiency=eta,
        input_torque_nm=t_in,
        input_torque_t=t_peak,
        input_torque_input_angle_deg=float(indexer._angle_of_t(t_peak)),
        input_torque_time_s=float(indexer._time_of_t(t_peak)),
        input_torque_pos_nm=fc * f_max,
        input_torque_pos_t=t_max,
        input_torque_neg_nm=fc * f_min,
        input_torque_neg_t=t_min,
        input_torque_catalog_nm=t_cat,
        qm=qm,
        input_power_kw=w_in * t_in / eta / 1000.0,
        input_power_catalog_kw=w_in * t_cat / eta / 1000.0,
        speed_rpm=indexer.rpm,
        accuracy_mm=acc,
    )


__all__ = [
    "G", "Indexer", "IndexerMotion", "IndexerPosition", "Load", "LoadPart", "MotionSummary",
    "MotionTable", "Sizing", "accuracy_mm", "size",
]
