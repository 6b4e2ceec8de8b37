"""A resolved motion program: evaluation over the master angle, joins, characteristic values.

Every segment's law is placed (:class:`~camcore.motion.laws.PlacedLaw`): s and its
derivatives over the master angle x come from the law's closed form by the chain rule.
Within [0, period] a master angle is evaluated as it is; a segment's start belongs to it
(the right limit, as a curve's break points do) and x = period to the last segment (as
T7 to a curve's last piece). Outside, x wraps: s(x + k·P) = s(x) + k·Δ, with Δ the
program's advance per cycle (0 when it closes, 360/n for an indexer's output).

With a speed N [rpm] the master angle turns at ω = 6N deg/s: t = x/ω and
dᵏs/dtᵏ = ωᵏ·dᵏs/dxᵏ.

References
----------
.. [1] VDI 2143 Blatt 1 (1980): motion programs, continuity at the joins.
.. [2] Makino (1977), subroutine CURVE: characteristic values of each section.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from functools import cached_property

import numpy as np
from numpy.typing import ArrayLike

from ..curves.base import FloatArray
from ..errors import InvalidParameterError
from .laws import PlacedLaw
from .results import Join, MotionCharacteristics, MotionTable, ResolvedSegment

#: a join is continuous in a quantity when its jump is at most this fraction of the
#: program's scale of that quantity (range of s, peak |v|, |a|, |j|): a law's end values carry
#: rounding of ~1e-15 of its peaks, a real jump of a designed motion is far above 1e-9
CONTINUITY_TOLERANCE = 1e-9
#: degrees of master angle per second at 1 rpm
DEG_PER_S_PER_RPM = 6.0


class MotionProgram:
    """One machine cycle, resolved: positions and their derivatives over the master angle.

    Build it with :func:`camcore.motion.resolve.resolve_motion`.
    """

    def __init__(self, placed: Sequence[PlacedLaw], segments: Sequence[ResolvedSegment], period_deg: float,
                 start: float, unit: str):
        self.placed = tuple(placed)
        self.segments = tuple(segments)
        self.period_deg = float(period_deg)
        self.start = float(start)
        self.unit = unit
        self._starts = np.array([p.x_a for p in self.placed])
        self.advance = float(self.segments[-1].to) - self.start

    # ---------------------------------------------------------------- evaluation
    def derivatives(self, x_deg: ArrayLike, order: int = 3) -> list[FloatArray]:
        """s and its derivatives over the master angle up to ``order`` (≤ 4).

        Parameters
        ----------
        x_deg : array_like
            Master angles [deg], any real values (wrapped as in the module notes).
        order : int
            Highest derivative [-].

        Returns
        -------
        list of ndarray
            [s, ds/dx, d²s/dx², …][: order + 1], shaped like x [unit/deg^k].
        """
        x = np.asarray(x_deg, dtype=np.float64)
        flat = x.reshape(-1)
        period = self.period_deg
        turns = np.floor(flat / period)
        turns[(flat >= 0) & (flat <= period)] = 0.0
        local = flat - turns * period
        seg = np.clip(np.searchsorted(self._starts, local, side="right") - 1, 0, len(self.placed) - 1)
        if np.all(seg[1:] >= seg[:-1]):
            order_idx = None
            grouped = seg
        else:
            order_idx = np.argsort(seg, kind="stable")
            grouped = seg[order_idx]
        bounds = np.searchsorted(grouped, np.arange(len(self.placed) + 1), side="left")
        out = [np.empty_like(flat) for _ in range(order + 1)]
        for k, law in enumerate(self.placed):
            lo, hi = int(bounds[k]), int(bounds[k + 1])
            if lo == hi:
                continue
            where = slice(lo, hi) if order_idx is None else order_idx[lo:hi]
            vals = law.at((local[where] - law.x_a) / law.span, order)
            for o, v in zip(out, vals):
                o[where] = v
        out[0] += turns * self.advance
        return [o.reshape(x.shape) for o in out]

    def sample_angles(self, samples: int) -> FloatArray:
        """``samples`` master angles evenly over [0, period], both ends included [deg]."""
        return np.linspace(0.0, self.period_deg, samples)

    def table(self, x_deg: ArrayLike, speed_rpm: float | None = None) -> MotionTable:
        """The columns at master angles x: s, v, a, j, and with a speed the time columns.

        Parameters
        ----------
        x_deg : array_like
            Master angles [deg].
        speed_rpm : float, optional
            Speed of the master shaft [rpm] (> 0).

        Returns
        -------
        MotionTable
            Per degree (v, a, j) and, with the speed, per second (ω = 6·N deg/s).
        """
        x = np.asarray(x_deg, dtype=np.float64)
        s, v, a, j = self.derivatives(x, 3)
        if speed_rpm is None:
            return MotionTable(x, s, v, a, j)
        if not (math.isfinite(speed_rpm) and speed_rpm > 0):
            raise InvalidParameterError(f"speed_rpm must be a positive number, got {speed_rpm!r}.", field=("speed_rpm",))
        omega = DEG_PER_S_PER_RPM * float(speed_rpm)
        return MotionTable(x, s, v, a, j, time_s=x / omega, v_per_s=v * omega, a_per_s2=a * omega**2,
                           j_per_s3=j * omega**3)

    @cached_property
    def breaks_deg(self) -> FloatArray:
        """Master angles in [0, period) where a derivative may jump: the segments' starts and
        their laws' inner break points [deg]."""
        points: list[float] = []
        for law in self.placed:
            points.append(law.x_a)
            c = law.curve
            if c is not None:
                inner = np.asarray(c.break_points[1:-1], dtype=np.float64)
                points.extend((law.x_a + law.span * (inner - c.t_start) / (c.t_end - c.t_start)).tolist())
        return np.unique(np.mod(np.asarray(points), self.period_deg))

    # ---------------------------------------------------------------- joins
    @cached_property
    def scales(self) -> tuple[float, float, float, float]:
        """The program's scale of s, v, a, j for continuity classes: the range of s and the
        peak |v|, |a|, |j| over the cycle [unit/deg^k]."""
        ch = self.characteristics
        return (ch.s_max - ch.s_min, ch.v_peak, max(abs(ch.a_max), abs(ch.a_min)),
                max(abs(ch.j_max), abs(ch.j_min)))

    @cached_property
    def joins(self) -> tuple[Join, ...]:
        """Every join, the wrap-around at period_deg last: jumps (after − before) and the
        continuity class (:data:`CONTINUITY_TOLERANCE` of :attr:`scales`)."""
        n = len(self.placed)
        ends = [law.ends() for law in self.placed]
        out = []
        for k in [*range(1, n), 0]:
            before, after = (k - 1) % n, k
            left, right = ends[before][1], ends[after][0]
            jumps = [r - lo for r, lo in zip(right, left)]
            at = self.period_deg if k == 0 else self.placed[k].x_a
            ds, dv, da, dj = jumps
            out.append(Join(at, before, after, ds, dv, da, dj, continuity=self._continuity(jumps)))
        return tuple(out)

    def _continuity(self, jumps: Sequence[float]) -> str:
        level = -1
        for jump, scale in zip(jumps, self.scales):
            if abs(jump) > CONTINUITY_TOLERANCE * scale:
                break
            level += 1
        return "none" if level < 0 else f"C{level}"

    # ---------------------------------------------------------------- characteristics
    @cached_property
    def characteristics(self) -> MotionCharacteristics:
        """Exact extremes over the cycle: each law's own characteristic values (section-wise
        extrema of its closed form, :mod:`camcore.curves.extrema`) in real units."""
        best: dict[str, tuple[float, float]] = {}

        def offer(name: str, value: float, at: float, larger: bool) -> None:
            old = best.get(name)
            if old is None or (value > old[0] if larger else value < old[0]):
                best[name] = (value, at)

        for law in self.placed:
            c = law.curve
            if c is None:
                for q in "svaj":
                    value = law.s_a if q == "s" else 0.0
                    offer(f"{q}_max", value, law.x_a, True)
                    offer(f"{q}_min", value, law.x_a, False)
                continue
            ch = c.characteristics
            pairs = {"s": (ch.s_max, ch.s_min), "v": (ch.v_max, ch.v_min), "a": (ch.am_pos, ch.am_neg),
                     "j": (ch.jm_pos, ch.jm_neg)}
            for k, q in enumerate("svaj"):
                for ext in pairs[q]:
                    value = law.gain * law.rate**k * ext.value if k else law.s_a + law.gain * (ext.value - c.s_start)
                    at = law.x_a + law.span * (ext.t - c.t_start) / (c.t_end - c.t_start)
                    offer(f"{q}_max", float(value), float(at), True)
                    offer(f"{q}_min", float(value), float(at), False)
        v_max, v_min = best["v_max"], best["v_min"]
        peak = v_max if abs(v_max[0]) > abs(v_min[0]) or (abs(v_max[0]) == abs(v_min[0]) and v_max[1] <= v_min[1]) \
            else v_min
        values = {name: pair[0] for name, pair in best.items()} | {f"{n}_at_deg": pair[1] for n, pair in best.items()}
        return MotionCharacteristics(v_peak=abs(peak[0]), v_peak_at_deg=peak[1], **values)
