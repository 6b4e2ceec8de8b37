"""Drives: the input torque over the whole machine cycle, its RMS, and the motor check.

Over one machine cycle the input shaft carries, with fc the service factor and Tᵢ the unit's
internal friction on the input shaft (the maker's figure; it acts while the input turns):

- while the output indexes: fc·T_load(x) + Tᵢ, T_load = (dθout/dθin)·T_out (lossless, the
  power balance of :mod:`.sizing`);
- while the output dwells: Tᵢ (the cam holds the output, so the dwell torque loads the cam,
  not the input);
- while the input stands still (ts per index): 0.

An oscillating unit's cycle is its out stroke and its back stroke: the back stroke, the same
law from h down to 0, needs T_in(T) = (−h·V)·(−I·h·A·k − T_r) = the out stroke's, so both
strokes give the same torque at the same fraction of the index. The RMS is
√(∫T² dt / t_cycle), integrated exactly: Gauss–Legendre on each smooth piece of each law, split
where the torque changes sign (the motor's efficiency applies to driving torque only).
At the motor (reduction ratio i, motor turns per input turn, efficiency η_r; the unit's η):
T_m = T/(i·η·η_r) where the motor drives, T·η·η_r/i where the load drives it back.

References
----------
.. [1] INDEXMAN technical guide, section 3 (t0 = t1 + t2, tm = t0 + ts) and section 5.
.. [2] Power balance of a drive with losses: P_motor = P_load/η when driving, P_load·η when braking.
.. [3] Golub and Welsch (1969): Gauss quadrature nodes (numpy.polynomial.legendre.leggauss).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from .._checks import finite, positive
from .._solvers import illinois_roots
from ..curves.base import FloatArray
from ..curves.curve import Curve
from ..errors import InvalidParameterError
from ..results import doc, table_columns

#: Gauss–Legendre nodes per smooth stretch: exact for polynomials of degree 63; the laws'
#: trigonometric pieces converge far faster than 1e-15 at this order
GAUSS_NODES = 32
_GL_X, _GL_W = np.polynomial.legendre.leggauss(GAUSS_NODES)


@dataclass(frozen=True, kw_only=True)
class Motor:
    """A motor to check against the cycle (field names as docs/api.md ``motor``).

    Parameters
    ----------
    rated_torque_nm, peak_torque_nm : float
        Continuous and peak torque (> 0) [N·m].
    rotor_inertia_kgm2 : float
        Rotor inertia (> 0) [kg·m²].
    max_speed_rpm : float
        Highest speed (> 0) [rpm].
    reduction_ratio : float
        i, motor turns per input-shaft turn (> 0). Default 1.
    reduction_efficiency : float
        η_r of the reduction, 0 < η_r ≤ 1. Default 1.
    """

    rated_torque_nm: float
    peak_torque_nm: float
    rotor_inertia_kgm2: float
    max_speed_rpm: float
    reduction_ratio: float = 1.0
    reduction_efficiency: float = 1.0

    def __post_init__(self) -> None:
        for name in ("rated_torque_nm", "peak_torque_nm", "rotor_inertia_kgm2", "max_speed_rpm", "reduction_ratio"):
            object.__setattr__(self, name, positive(name, getattr(self, name)))
        eta = finite("reduction_efficiency", self.reduction_efficiency)
        if not 0 < eta <= 1:
            raise InvalidParameterError(f"reduction_efficiency must satisfy 0 < η ≤ 1, got {eta!r}.",
                                        field=("reduction_efficiency",))


@dataclass(frozen=True)
class TorqueTable:
    """The input torque over one machine cycle (columns of equal length; a jump is two rows)."""

    input_angle_deg: FloatArray = field(metadata=doc("input angle from the start of the cycle [deg]"))
    time_s: FloatArray = field(metadata=doc("from the start of the cycle [s]"))
    input_torque_nm: FloatArray = field(metadata=doc("fc·T_load + internal friction; 0 while the input stands [N·m]"))

    def columns(self) -> dict[str, FloatArray]:
        return table_columns(self)


@dataclass(frozen=True)
class TorqueLaw:
    """The load torque over one stretch of the cycle: f = c1·V·A + c2·|V| (or c2·V) of a curve
    between input angles x_a and x_a + span [deg]."""

    curve: Curve
    c1: float
    c2: float
    x_a: float
    span: float
    signed_friction: bool  # True: c2·|V| (resists both ways), False: c2·V

    def at_t(self, t: FloatArray, piece: np.ndarray | None = None) -> FloatArray:
        """f at curve times t (on the given pieces, or found) [N·m]."""
        c = self.curve
        vals = c.derivatives(t, 2) if piece is None else c.eval_pieces(t, piece, 2)
        v, a = vals[1], vals[2]
        return np.asarray(self.c1 * v * a + self.c2 * (np.abs(v) if self.signed_friction else v), dtype=np.float64)

    def t_of_x(self, x: FloatArray) -> FloatArray:
        c = self.curve
        return np.asarray(c.t_start + (c.t_end - c.t_start) * (x - self.x_a) / self.span, dtype=np.float64)


@dataclass(frozen=True)
class Cycle:
    """One machine cycle: where the output moves (torque laws), how long it lasts.

    ``turn_deg``: input angle of the cycle; ``stop_s``: total input stop time in it; ``rpm``:
    input speed; ``repeats``: how many times the laws' stretch of ``turn_deg`` is run in one
    cycle (2 for the out and back strokes of an oscillating unit, with equal torques).
    """

    laws: Sequence[TorqueLaw]
    turn_deg: float
    stop_s: float
    rpm: float
    repeats: int = 1

    @property
    def seconds_per_deg(self) -> float:
        return 1.0 / (6.0 * self.rpm)

    @property
    def cycle_s(self) -> float:
        """The machine cycle [s]."""
        return self.repeats * (self.turn_deg * self.seconds_per_deg + self.stop_s)


#: grid per smooth piece that brackets the zeros where the integrand may kink
_SCAN = np.linspace(0.0, 1.0, 129)


def _kinks(law: TorqueLaw, fc: float, internal_nm: float, lo: FloatArray, hi: FloatArray,
           pieces: np.ndarray, at_zero_torque: bool) -> tuple[FloatArray, np.ndarray]:
    """Curve times (and their pieces) inside the given pieces where, with ``at_zero_torque``,
    the input torque fc·f + Tᵢ is zero (a motor's scale kinks there: driving and braking
    differ) or, with friction c2·|V|, where V is zero (f kinks there); all pieces bracketed
    on one grid and refined together."""
    c = law.curve
    n = lo.size
    grid = lo[:, None] + (hi - lo)[:, None] * _SCAN[None, :]
    _, v, a = (d.reshape(n, _SCAN.size) for d in c.eval_pieces(grid.ravel(), np.repeat(pieces, _SCAN.size), 2))
    rows = [fc * (law.c1 * v * a + law.c2 * (np.abs(v) if law.signed_friction else v)) + internal_nm
            if at_zero_torque else None, v if law.signed_friction else None]
    found_t, found_k = [np.empty(0)], [np.empty(0, dtype=np.intp)]
    for r, g in enumerate(rows):
        if g is None:
            continue
        sign = np.sign(g)
        k_idx, i_idx = np.nonzero(sign[:, :-1] * sign[:, 1:] < 0)
        if k_idx.size:
            b_lo, b_hi = grid[k_idx, i_idx].copy(), grid[k_idx, i_idx + 1].copy()
            f_lo, f_hi = g[k_idx, i_idx].copy(), g[k_idx, i_idx + 1].copy()

            def row_r(t: FloatArray, label: np.ndarray, r: int = r) -> FloatArray:
                _, vv, aa = c.eval_pieces(t, pieces[label], 2)
                if r == 1:
                    return vv
                friction = np.abs(vv) if law.signed_friction else vv
                return np.asarray(fc * (law.c1 * vv * aa + law.c2 * friction) + internal_nm, dtype=np.float64)

            illinois_roots(row_r, b_lo, b_hi, f_lo, f_hi, k_idx)
            found_t.append(0.5 * (b_lo + b_hi))
            found_k.append(k_idx)
        zk, zi = np.nonzero(g == 0.0)
        found_t.append(grid[zk, zi])
        found_k.append(zk)
    return np.concatenate(found_t), np.concatenate(found_k)


def _integral(law: TorqueLaw, fc: float, internal_nm: float, fn: Callable[[FloatArray], FloatArray],
              fn_kinks_at_zero: bool) -> float:
    """∫ fn(fc·f + Tᵢ) dx over the law's stretch [deg·…]: Gauss–Legendre on every smooth piece,
    split where the integrand may kink (:func:`_kinks`; at zero torque only if ``fn`` kinks
    there), every node of every stretch in one evaluation."""
    c = law.curve
    starts = c.piece_starts
    ends = np.append(starts[1:], c.t_end)
    pieces = np.nonzero(ends > starts)[0]
    lo, hi = starts[pieces], ends[pieces]
    kink_t, kink_k = _kinks(law, fc, internal_nm, lo, hi, pieces, fn_kinks_at_zero)
    inside = (kink_t > lo[kink_k]) & (kink_t < hi[kink_k])
    # every piece's edges and kinks, ordered by piece then time: stretches join neighbours
    edge_k = np.concatenate([np.arange(pieces.size), np.arange(pieces.size), kink_k[inside]])
    edge_t = np.concatenate([lo, hi, kink_t[inside]])
    order = np.lexsort((edge_t, edge_k))
    edge_k, edge_t = edge_k[order], edge_t[order]
    same = edge_k[1:] == edge_k[:-1]
    a, b, k = edge_t[:-1][same], edge_t[1:][same], pieces[edge_k[:-1][same]]
    nodes = 0.5 * (a + b)[:, None] + 0.5 * (b - a)[:, None] * _GL_X[None, :]
    _, v, acc = c.eval_pieces(nodes.ravel(), np.repeat(k, _GL_X.size), 2)
    friction = np.abs(v) if law.signed_friction else v
    values = fn(fc * (law.c1 * v * acc + law.c2 * friction) + internal_nm).reshape(nodes.shape)
    dx_dt = law.span / (c.t_end - c.t_start)
    return float(np.dot(0.5 * (b - a), values @ _GL_W)) * dx_dt


def cycle_rms(cycle: Cycle, fc: float, internal_nm: float,
              scale: Callable[[FloatArray], FloatArray] | None = None) -> float:
    """RMS over the machine cycle of scale(fc·T_load + Tᵢ) (Tᵢ alone in the dwells, 0 while stopped).

    Parameters
    ----------
    cycle : Cycle
        The machine cycle.
    fc : float
        Service factor [-].
    internal_nm : float
        Internal friction on the input shaft [N·m].
    scale : callable, optional
        Maps input-shaft torque to the torque whose RMS is wanted (a motor's, which may kink
        at zero torque: driving and braking differ); None: the input torque itself.

    Returns
    -------
    float
        √(∫ T² dt / t_cycle) [N·m].

    References
    ----------
    INDEXMAN technical guide, section 3 (tm = t0 + ts); Golub and Welsch (1969).
    """
    moving = 0.0
    square = 0.0
    def squared(torque: FloatArray) -> FloatArray:
        return (torque if scale is None else scale(torque)) ** 2

    for law in cycle.laws:
        moving += law.span
        square += _integral(law, fc, internal_nm, squared, scale is not None)
    dwell_deg = cycle.turn_deg - moving
    square += float(squared(np.array([internal_nm]))[0]) * dwell_deg
    seconds = cycle.repeats * square * cycle.seconds_per_deg
    return math.sqrt(seconds / cycle.cycle_s)


def torque_table(cycle: Cycle, fc: float, internal_nm: float, samples: int) -> TorqueTable:
    """The input torque at ``samples`` angles over each moving stretch, the dwells' and the stops' ends.

    Parameters
    ----------
    cycle : Cycle
        The machine cycle.
    fc : float
        Service factor [-].
    internal_nm : float
        Internal friction on the input shaft [N·m].
    samples : int
        Rows over each moving stretch (≥ 2) [-].

    Returns
    -------
    TorqueTable
        Over the whole machine cycle (an oscillating unit's two strokes one after the other).

    References
    ----------
    INDEXMAN technical guide, section 3 (t0 = t1 + t2, tm = t0 + ts).
    """
    x_rows: list[FloatArray] = []
    torque_rows: list[FloatArray] = []
    for law in sorted(cycle.laws, key=lambda item: item.x_a):
        x = np.linspace(law.x_a, law.x_a + law.span, samples)
        x_rows.append(x)
        torque_rows.append(fc * law.at_t(law.t_of_x(x)) + internal_nm)
        x_rows.append(np.array([law.x_a + law.span]))  # the dwell side of the index's end
        torque_rows.append(np.array([internal_nm]))
    # the cycle's ends, where no law starts or ends there: the dwell's torque
    if not any(law.x_a == 0.0 for law in cycle.laws):
        x_rows.insert(0, np.array([0.0]))
        torque_rows.insert(0, np.array([internal_nm]))
    if not any(law.x_a + law.span >= cycle.turn_deg for law in cycle.laws):
        x_rows.append(np.array([cycle.turn_deg]))
        torque_rows.append(np.array([internal_nm]))
    x_all, t_all = np.concatenate(x_rows), np.concatenate(torque_rows)
    order = np.argsort(x_all, kind="stable")
    x_all, t_all = x_all[order], t_all[order]
    time = x_all * cycle.seconds_per_deg
    turn_s = cycle.turn_deg * cycle.seconds_per_deg
    if cycle.stop_s > 0:  # the input stands still: no torque
        x_all = np.concatenate([x_all, [cycle.turn_deg, cycle.turn_deg]])
        time = np.concatenate([time, [turn_s, turn_s + cycle.stop_s]])
        t_all = np.concatenate([t_all, [0.0, 0.0]])
    if cycle.repeats > 1:
        span_s = turn_s + cycle.stop_s
        x_all = np.concatenate([x_all + k * cycle.turn_deg for k in range(cycle.repeats)])
        time = np.concatenate([time + k * span_s for k in range(cycle.repeats)])
        t_all = np.tile(t_all, cycle.repeats)
    return TorqueTable(input_angle_deg=x_all, time_s=time, input_torque_nm=t_all)


def motor_scale(motor: Motor, efficiency: float) -> Callable[[FloatArray], FloatArray]:
    """Input-shaft torque → motor torque: T/(i·η·η_r) driving, T·η·η_r/i braking.

    Parameters
    ----------
    motor : Motor
        Reduction ratio i and efficiency η_r.
    efficiency : float
        η of the unit [-].

    Returns
    -------
    callable
        The map, vectorised [N·m → N·m].

    References
    ----------
    Power balance with losses: P_motor = P_load/η driving, P_load·η braking.
    """
    losses = efficiency * motor.reduction_efficiency
    i = motor.reduction_ratio

    def scale(torque: FloatArray) -> FloatArray:
        t = np.asarray(torque, dtype=np.float64)
        return np.where(t >= 0, t / (i * losses), t * losses / i)

    return scale
