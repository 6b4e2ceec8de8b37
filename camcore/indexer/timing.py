"""Indexers driven by a timing chart: the output angle over one input turn as a motion program.

A timing chart is a :class:`~camcore.motion.MotionProgram` in degrees of output over
360° of input angle x: unequal indexing, special charts, an oscillating unit's out and
back. The input turns at N rpm, ω_in = 2πN/60 = (π/180)·6N rad/s, so with the chart's
s(x) [deg] and its derivatives over x [deg/deg^k]

    ω = ω_in·s′,   α = ω_in²·(180/π)·s″,   jerk = ω_in³·(180/π)²·s‴,

and dθout/dθin = s′. A chart that advances by Δ per input turn is a rotary unit; one that
closes (Δ = 0) an oscillating unit. Its summary follows the single-curve indexer's fields:
z is the number of dwells (separate stretches of dwell segments, the wrap-around joined),
and per-index values are averages over z (exact for equal indexing), so that a chart of z
equal indexes answers what the single-curve indexer with ``dwells = z`` answers.

References
----------
.. [1] INDEXMAN technical guide, sections 2-3 (n = 360/ψ, θh, z, t0 = 60/(N·z)), §4-5
   (timing charts of oscillating units: out, dwell, back, dwell).
.. [2] VDI 2143 Blatt 1 (1980): motion programs over the master angle.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from .._checks import non_negative, positive
from ..curves.base import FloatArray
from ..curves.extrema import peaks_of
from ..errors import InvalidParameterError, NonMonotoneError, StrokeRangeError
from ..motion import SPAN_TOLERANCE, MotionProgram, PlacedLaw
from .checks import check_speed_alternatives
from .results import IndexerMotion, IndexerPosition, MotionSummary, MotionTable

DEG_PER_RAD = 180.0 / math.pi
#: degrees of input angle per second at 1 rpm
DEG_PER_S_PER_RPM = 6.0


def check_timing_frame(unit: str, period_deg: float) -> None:
    """A timing chart is in degrees of output over one input turn (360°).

    Parameters
    ----------
    unit : str
        The chart's unit of position ("deg").
    period_deg : float
        Its master angle [deg] (360).

    Raises
    ------
    InvalidParameterError
        Another unit or period (the field names which).

    References
    ----------
    INDEXMAN technical guide, §4-5 (the timing chart spans one turn of the input shaft).
    """
    if unit != "deg":
        raise InvalidParameterError(f"a timing chart gives the output angle in 'deg', not {unit!r}.", field=("unit",))
    if abs(period_deg - 360.0) > SPAN_TOLERANCE * 360.0:
        raise InvalidParameterError(f"a timing chart spans one input turn: period_deg must be 360, not {period_deg!r}.",
                                    field=("period_deg",))


def check_timing(program: MotionProgram) -> None:
    """A timing chart is in degrees of output over one input turn, and moves the output.

    Parameters
    ----------
    program : MotionProgram
        The chart.

    Raises
    ------
    InvalidParameterError
        As :func:`check_timing_frame`, or an output that never moves (the field names the
        chart's part).

    References
    ----------
    INDEXMAN technical guide, §4-5 (the timing chart spans one turn of the input shaft).
    """
    check_timing_frame(program.unit, program.period_deg)
    ch = program.characteristics
    if not ch.s_max > ch.s_min:
        raise InvalidParameterError("the timing chart never moves the output.", field=("segments",))


def _dwell_count(program: MotionProgram) -> int:
    """Stretches of dwell segments in the cycle, the last joined to the first across the wrap-around [-]."""
    dwell = [law.curve is None for law in program.placed]
    starts = sum(1 for k, d in enumerate(dwell) if d and not dwell[k - 1])
    return starts if not all(dwell) else 1


@dataclass(frozen=True, kw_only=True)
class TimedIndexer:
    """An indexer (or oscillating unit) whose output follows a timing chart over one input turn.

    Parameters
    ----------
    program : MotionProgram
        The chart (:func:`check_timing`).
    speed_rpm : float, optional
        N, input speed [rpm].
    cycle_time_s : float, optional
        t0, unit cycle time [s]: N = 60/(t0·z). Give exactly one of the two.
    input_stop_time_s : float
        ts, time the input stands still each index [s]; tm = t0 + ts.

    References
    ----------
    INDEXMAN technical guide, sections 2-3 and §4-5.
    """

    program: MotionProgram
    speed_rpm: float | None = None
    cycle_time_s: float | None = None
    input_stop_time_s: float = 0.0
    dwells: int = field(init=False)

    def __post_init__(self) -> None:
        check_timing(self.program)
        check_speed_alternatives(self.speed_rpm, self.cycle_time_s)
        put = object.__setattr__
        if self.speed_rpm is not None:
            put(self, "speed_rpm", positive("speed_rpm", self.speed_rpm))
        else:
            put(self, "cycle_time_s", positive("cycle_time_s", self.cycle_time_s))
        put(self, "input_stop_time_s", non_negative("input_stop_time_s", self.input_stop_time_s))
        put(self, "dwells", _dwell_count(self.program))

    # ------------------------------------------------------------ derived values
    @property
    def per_index(self) -> int:
        """z for the per-index averages: the dwells, at least 1 (a chart without a dwell is one cycle) [-]."""
        return max(self.dwells, 1)

    @property
    def rpm(self) -> float:
        """Input speed N [rpm] (given, or 60/(t0·z))."""
        if self.speed_rpm is not None:
            return float(self.speed_rpm)
        return 60.0 / (float(self.cycle_time_s) * self.per_index)  # type: ignore[arg-type]

    @property
    def input_speed_rad_s(self) -> float:
        """ω_in = 2πN/60 [rad/s]."""
        return 2.0 * math.pi * self.rpm / 60.0

    @property
    def moving_angle_deg(self) -> float:
        """Input angle of the chart's moves over one turn [deg]."""
        return float(sum(law.span for law in self.program.placed if law.curve is not None))

    @property
    def displacement_deg(self) -> float:
        """h: the advance per index |Δ|/z of a rotary unit, the swing s_max − s_min of a closed chart [deg]."""
        advance = abs(self.program.advance)
        ch = self.program.characteristics
        return advance / self.per_index if advance > 0 else ch.s_max - ch.s_min

    @property
    def n(self) -> float:
        """Stops per output turn, 360/h (may be fractional) [-]."""
        return 360.0 / self.displacement_deg

    @property
    def indexing_angle_deg(self) -> float:
        """θh: input angle per index, the moving angle over z [deg]."""
        return self.moving_angle_deg / self.per_index

    @property
    def scales(self) -> tuple[float, float, float]:
        """Factors from the chart's s′, s″, s‴ [deg/deg^k] to ω [rad/s], α [rad/s²], jerk [rad/s³]."""
        w = self.input_speed_rad_s
        return w, w**2 * DEG_PER_RAD, w**3 * DEG_PER_RAD**2

    def time_of(self, x_deg: ArrayLike) -> FloatArray:
        """Time from the start of the chart at input angles x: x/(6N) [s]."""
        return np.asarray(x_deg, dtype=np.float64) / (DEG_PER_S_PER_RPM * self.rpm)

    # ------------------------------------------------------------ motion
    def summary(self) -> MotionSummary:
        """Times (per index on average over the z dwells) and the chart's exact peaks.

        Returns
        -------
        MotionSummary
            As the single-curve indexer's; angles and times of the peaks from the start of the chart.

        References
        ----------
        INDEXMAN technical guide, sections 2, 3 and 5; the peaks are the chart's exact
        characteristic values (:attr:`MotionProgram.characteristics`).
        """
        ch = self.program.characteristics
        kv, ka, kj = self.scales
        z = self.per_index
        moving = self.moving_angle_deg
        t0 = 60.0 / (self.rpm * z) if self.cycle_time_s is None else float(self.cycle_time_s)

        def when(x: float) -> float:
            return float(self.time_of(x))

        return MotionSummary(
            indexing_time_s=float(self.time_of(self.indexing_angle_deg)),
            cycle_time_s=t0,
            dwell_time_s=float(self.time_of((360.0 - moving) / z)),
            machine_cycle_time_s=t0 + float(self.input_stop_time_s),
            displacement_deg=self.displacement_deg,
            stops=self.n,
            indexing_angle_deg=self.indexing_angle_deg,
            total_indexing_angle_deg=moving,
            dwell_angle_deg=(360.0 - moving) / z,
            dwells=self.dwells,
            speed_rpm=self.rpm,
            omega_rad_s=kv * ch.v_peak, omega_input_angle_deg=ch.v_peak_at_deg, omega_time_s=when(ch.v_peak_at_deg),
            alpha_rad_s2=ka * max(abs(ch.a_max), abs(ch.a_min)),
            alpha_pos_rad_s2=ka * ch.a_max, alpha_pos_input_angle_deg=ch.a_max_at_deg,
            alpha_pos_time_s=when(ch.a_max_at_deg),
            alpha_neg_rad_s2=ka * ch.a_min, alpha_neg_input_angle_deg=ch.a_min_at_deg,
            alpha_neg_time_s=when(ch.a_min_at_deg),
            jerk_rad_s3=kj * max(abs(ch.j_max), abs(ch.j_min)),
            jerk_pos_rad_s3=kj * ch.j_max, jerk_pos_input_angle_deg=ch.j_max_at_deg,
            jerk_pos_time_s=when(ch.j_max_at_deg),
            jerk_neg_rad_s3=kj * ch.j_min, jerk_neg_input_angle_deg=ch.j_min_at_deg,
            jerk_neg_time_s=when(ch.j_min_at_deg),
        )

    def motion_at(self, input_angles_deg: ArrayLike) -> MotionTable:
        """Output motion at input angles over the chart's turn, 0 ≤ x ≤ 360 [deg].

        Parameters
        ----------
        input_angles_deg : array_like
            Input angles from the start of the chart [deg].

        Returns
        -------
        MotionTable
            Output angle [deg], ω, α, jerk [rad/s^k], dθout/dθin [-] and its derivative [1/rad].

        References
        ----------
        INDEXMAN technical guide, section 5 (ω, α, jerk from the motion over the input angle).
        """
        x = np.asarray(input_angles_deg, dtype=np.float64).reshape(-1)
        bad = ~np.isfinite(x) | (x < 0) | (x > 360.0)
        if bad.any():
            i = int(np.nonzero(bad)[0][0])
            raise InvalidParameterError(f"input_angle_deg[{i}] = {float(x[i])!r} must lie in the chart's turn, "
                                        "0 ≤ x ≤ 360°.")
        s, v, a, j = self.program.derivatives(x, 3)
        kv, ka, kj = self.scales
        return MotionTable(input_angle_deg=x, time_s=self.time_of(x), output_angle_deg=s, omega_rad_s=kv * v,
                           alpha_rad_s2=ka * a, jerk_rad_s3=kj * j, dout_din=v, d2out_din2_per_rad=a * DEG_PER_RAD)

    def motion(self, samples: int = 101) -> IndexerMotion:
        """Summary and a table at ``samples`` input angles evenly over the turn, both ends included.

        Parameters
        ----------
        samples : int
            Rows (≥ 2) [-].

        Returns
        -------
        IndexerMotion
            :meth:`summary` and :meth:`motion_at` of the rows.
        """
        if samples < 2:
            raise InvalidParameterError(f"samples must be at least 2, got {samples}.")
        return IndexerMotion(summary=self.summary(), table=self.motion_at(np.linspace(0.0, 360.0, samples)))

    # ------------------------------------------------------------ position lookup
    def position(self, output_angle_deg: ArrayLike) -> IndexerPosition:
        """The first input angle of the chart at which the output reaches each given angle.

        Parameters
        ----------
        output_angle_deg : array_like
            Output angles within the chart's range, s_min ≤ x ≤ s_max [deg].

        Returns
        -------
        IndexerPosition
            Input angle, time, ω and α there; ``t``, ``v``, ``a`` of the segment's law normalised
            to run from 0 to 1 (T, dN/dT, d²N/dT²; 0 on a dwell).

        Raises
        ------
        StrokeRangeError
            An angle outside the chart's range.
        NonMonotoneError
            The first segment that reaches an angle has a law that is not monotone.

        References
        ----------
        INDEXMAN technical guide, worked example before the characteristic-value table (the
        input angle at which the output reaches a position, solved exactly here per segment).
        """
        goal = np.asarray(output_angle_deg, dtype=np.float64)
        flat = goal.reshape(-1)
        ch = self.program.characteristics
        slack = 8 * float(np.spacing(max(abs(ch.s_max), abs(ch.s_min), 1.0)))
        bad = ~np.isfinite(flat) | (flat < ch.s_min - slack) | (flat > ch.s_max + slack)
        if bad.any():
            i = int(np.nonzero(bad)[0][0])
            raise StrokeRangeError(f"output_angle_deg[{i}] = {float(flat[i])!r} is outside the chart, which moves "
                                   f"the output between {ch.s_min!r}° and {ch.s_max!r}°.", field=("output_angle_deg", i))
        x, u, nv, na = (np.zeros_like(flat) for _ in range(4))
        todo = np.ones(flat.shape, dtype=bool)
        for k, law in enumerate(self.program.placed):
            lo, hi = _law_range(law)
            hit = todo & (flat >= lo - slack) & (flat <= hi + slack)
            if not hit.any():
                continue
            todo &= ~hit
            if law.curve is None:
                x[hit] = law.x_a
                continue
            x[hit], u[hit], nv[hit], na[hit] = _solve_in_law(k, law, flat[hit])
        _, v, a = self.program.derivatives(x, 2)
        kv, ka, _ = self.scales
        shape = goal.shape
        return IndexerPosition(output_angle_deg=goal, input_angle_deg=x.reshape(shape),
                               time_s=self.time_of(x).reshape(shape), omega_rad_s=(kv * v).reshape(shape),
                               alpha_rad_s2=(ka * a).reshape(shape), t=u.reshape(shape), v=nv.reshape(shape),
                               a=na.reshape(shape), method="exact")

    # ------------------------------------------------------------ sizing support
    def power_balance_peaks(self, c_inertia: float, c_resisting: float
                            ) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
        """Exact max and min over the turn of f(x) = s′·(c_inertia·s″ + c_resisting·sgn s′).

        Parameters
        ----------
        c_inertia : float
            Multiplies s′·s″ [N·m per deg/deg·deg/deg²].
        c_resisting : float
            A torque that resists the motion (friction, work), times |s′| [N·m].

        Returns
        -------
        ((float, float, float), (float, float, float))
            (value, input angle [deg], T of the segment's law) of the max and of the min; ties: earliest.

        References
        ----------
        Power balance of a lossless drive: T_in = (dθout/dθin)·T_out. Candidates: each law's
        piece ends, the roots of f′ on either sign of s′, and the roots of s′ (Makino 1977,
        characteristic values: section-wise extrema).
        """
        xs: list[FloatArray] = []
        us: list[FloatArray] = []
        fs: list[FloatArray] = []
        for law in self.program.placed:
            c = law.curve
            if c is None:
                continue
            g, r = law.gain, law.rate
            c1 = c_inertia * g * g * r**3  # s′·s″ = g²·r³·V·A
            c2 = c_resisting * abs(g) * r  # |s′| = |g|·r·|V|
            # f′ ∝ c1·(J·V + A²) ± c2·A on either sign of V, and the roots of V itself
            cand = [c.critical_points(_power_slope(c1, sign * c2)) for sign in (1.0, -1.0)]
            cand.append(c.critical_points(lambda d: d[1]))
            t_all = np.concatenate([t for t, _ in cand])
            k_all = np.concatenate([k for _, k in cand])
            _, v, a = c.eval_pieces(t_all, k_all, 2)
            fs.append(c1 * v * a + c2 * np.abs(v))
            u = (t_all - c.t_start) / (c.t_end - c.t_start)
            us.append(u)
            xs.append(law.x_a + law.span * u)
        x_all, f_all, u_all = np.concatenate(xs), np.concatenate(fs), np.concatenate(us)
        top, bottom = peaks_of(x_all, f_all)
        return ((top.value, top.t, float(u_all[x_all == top.t][0])),
                (bottom.value, bottom.t, float(u_all[x_all == bottom.t][0])))


def _power_slope(c1: float, c2: float) -> Callable[[list[FloatArray]], FloatArray]:
    """d/dT of c1·V·A + c2·V: c1·(J·V + A²) + c2·A."""
    return lambda d: c1 * (d[3] * d[1] + d[2] * d[2]) + c2 * d[2]


def _law_range(law: PlacedLaw) -> tuple[float, float]:
    """Smallest and largest output over a segment [deg] (the law's exact extremes)."""
    c = law.curve
    if c is None:
        return law.s_a, law.s_a
    ch = c.characteristics
    ends = (law.s_a + law.gain * (ch.s_min.value - c.s_start), law.s_a + law.gain * (ch.s_max.value - c.s_start))
    return min(ends), max(ends)


def _solve_in_law(k: int, law: PlacedLaw, goal: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Input angle, law time u and the normalised law's N′, N″ where a monotone law reaches ``goal``."""
    c = law.curve
    assert c is not None
    if c.monotone_direction == 0:
        raise NonMonotoneError(f"segment {k}'s law is not monotone, so the output angle does not determine the "
                               "input angle there; a position lookup needs laws that only rise or only fall.",
                               field=("segments", k, "curve"))
    lo, hi = sorted((c.s_start, c.s_end))
    s_goal = np.clip(c.s_start + (goal - law.s_a) / law.gain, lo, hi)
    t = c.inverse(s_goal)
    _, v, a = c.derivatives(t, 2)
    d_t, d_s = c.t_end - c.t_start, c.s_end - c.s_start
    u = (t - c.t_start) / d_t
    return law.x_a + law.span * u, u, v * d_t / d_s, a * d_t**2 / d_s
