"""The one-variable solves of the design's search, for many candidates at once: the smallest base radius
where a margin that grows with it is met (Illinois), a point where a unimodal margin is met (golden
section), and the range of base radii an oscillating arm can be assembled at.

References
----------
.. [1] Dowell and Jarratt (1971), the Illinois method.
.. [2] Kiefer (1953), golden-section search.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from ...curves.base import FloatArray
from ...deadline import checkpoint
from ...errors import GeometryError

IndexArray = NDArray[np.intp]
#: golden-section steps of the search for a point meeting a margin that falls again towards the upper end
#: (0.618^16 ≈ 5e-4 of the bracket: a window of feasible radii narrower than that is missed by the search,
#: not by the exact solve at the design found)
PEAK_STEPS = 16
GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0
#: the search's base radius is solved to this relative width (it ranks candidates; the answer is solved
#: again to 1e-10 by the exact solves)
ROOT_REL_TOL = 1e-9


def feasible_points(margin: Callable[[IndexArray, FloatArray], FloatArray], a: FloatArray, b: FloatArray
                    ) -> tuple[FloatArray, FloatArray]:
    """For each lane a point of (a, b) where a unimodal margin is ≥ 0.

    Parameters
    ----------
    margin : callable
        ``(lanes, x) -> margins``: the margin of each of these lanes at its own x [-].
    a, b : ndarray
        Each lane's interval [mm]; overwritten.

    Returns
    -------
    (ndarray, ndarray)
        The point [mm] and the margin there [-]: golden section towards the margin's maximum, a lane stopping
        at its first point that meets it, or after :data:`PEAK_STEPS` with the best it found (< 0).

    References
    ----------
    Kiefer (1953), golden-section search.
    """
    g = GOLDEN
    x1, x2 = b - g * (b - a), a + g * (b - a)
    lanes = np.arange(a.size)
    f1, f2 = margin(lanes, x1), margin(lanes, x2)
    best_x, best_f = np.where(f1 >= f2, x1, x2), np.maximum(f1, f2)
    active = lanes[best_f < 0]
    for _ in range(PEAK_STEPS):
        checkpoint()
        if active.size == 0:
            break
        right = f1[active] < f2[active]  # the maximum lies in [x1, b]
        a[active] = np.where(right, x1[active], a[active])
        b[active] = np.where(right, b[active], x2[active])
        new = np.where(right, a[active] + g * (b[active] - a[active]), b[active] - g * (b[active] - a[active]))
        f_new = margin(active, new)
        x1[active], x2[active] = np.where(right, x2[active], new), np.where(right, new, x1[active])
        f1[active], f2[active] = np.where(right, f2[active], f_new), np.where(right, f_new, f1[active])
        better = f_new > best_f[active]
        best_x[active] = np.where(better, new, best_x[active])
        best_f[active] = np.where(better, f_new, best_f[active])
        active = active[best_f[active] < 0]
    return best_x, best_f





def illinois(margin: Callable[[IndexArray, FloatArray], FloatArray], a: FloatArray, b: FloatArray, f_a: FloatArray,
             f_b: FloatArray) -> FloatArray:
    """The smallest x in (a, b] with margin ≥ 0 for every lane, margins growing with x.

    Parameters
    ----------
    margin : callable
        ``(lanes, x) -> margins``: the margin of each of these lanes at its own x [-].
    a, b : ndarray
        Each lane's bracket [mm]; overwritten.
    f_a, f_b : ndarray
        The margins there, f_a < 0 ≤ f_b [-]; overwritten.

    Returns
    -------
    ndarray
        The brackets' feasible ends after Illinois regula falsi on all open lanes together, each closed to
        :data:`ROOT_REL_TOL` of max(1, x) [mm]; one lane is solved in Python floats (:func:`illinois_one`).

    References
    ----------
    Dowell and Jarratt (1971), the Illinois method.
    """
    if a.size == 1:
        first = np.zeros(1, dtype=np.intp)
        return np.array([illinois_one(lambda x: float(margin(first, np.array([x]))[0]),
                                       float(a[0]), float(b[0]), float(f_a[0]), float(f_b[0]))])
    side = np.zeros(a.size, dtype=np.int8)  # +1: b moved last time, −1: a moved last time
    active = np.arange(a.size)
    for _ in range(200):
        checkpoint()
        active = active[(b[active] - a[active] > ROOT_REL_TOL * np.maximum(1.0, b[active])) & (f_b[active] != 0)]
        if active.size == 0:
            break
        lo, hi, flo, fhi = a[active], b[active], f_a[active], f_b[active]
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            chord = hi - fhi * (hi - lo) / (fhi - flo)
        mid = np.where(np.isfinite(chord) & (chord > lo) & (chord < hi), chord, 0.5 * (lo + hi))
        f_mid = margin(active, mid)
        ok = f_mid >= 0
        stale = side[active]
        b[active] = np.where(ok, mid, hi)
        f_b[active] = np.where(ok, f_mid, np.where(stale == -1, 0.5 * fhi, fhi))
        a[active] = np.where(ok, lo, mid)
        f_a[active] = np.where(ok, np.where(stale == 1, 0.5 * flo, flo), f_mid)
        side[active] = np.where(ok, 1, -1)
    return b


def illinois_one(margin: Callable[[float], float], a: float, b: float, f_a: float, f_b: float) -> float:
    """:func:`illinois` for one lane, in Python floats (an array operation's fixed cost is most of one step).

    Parameters
    ----------
    margin : callable
        ``x -> margin`` [-].
    a, b : float
        The bracket [mm].
    f_a, f_b : float
        The margins there, f_a < 0 ≤ f_b [-].

    Returns
    -------
    float
        The bracket's feasible end, closed to :data:`ROOT_REL_TOL` of max(1, x) [mm].

    References
    ----------
    Dowell and Jarratt (1971), the Illinois method.
    """
    side = 0
    for _ in range(200):
        checkpoint()
        if not (b - a > ROOT_REL_TOL * max(1.0, b) and f_b != 0):
            break
        chord = b - f_b * (b - a) / (f_b - f_a) if math.isfinite(f_a) and f_b != f_a else math.nan
        mid = chord if math.isfinite(chord) and a < chord < b else 0.5 * (a + b)
        f_mid = margin(mid)
        if f_mid >= 0:
            b, f_b = mid, f_mid
            f_a = 0.5 * f_a if side == 1 else f_a
            side = 1
        else:
            a, f_a = mid, f_mid
            f_b = 0.5 * f_b if side == -1 else f_b
            side = -1
    return b


def assembly_range(model: object, lift: FloatArray, floor: float, rb_hi: float) -> tuple[float, float]:
    """The base radii within [floor, rb_hi] at which a follower can be assembled and swung through the lift.

    Parameters
    ----------
    model : FollowerModel
        The follower (its ``check`` and ``check_swing``).
    lift : ndarray
        The lift sampled over the turn [mm or deg].
    floor : float
        The smallest base radius worth considering [mm].
    rb_hi : float
        The largest [mm].

    Returns
    -------
    (float, float)
        The range (lo, hi) [mm]: an oscillating arm reaches the base circle only between |d − L| − Rr and
        d + L − Rr and must not swing through the line of centres, so hi may lie below ``rb_hi`` (found by
        bisection to 1e-12 relative); (inf, inf) where no radius works.

    References
    ----------
    Shinzato and Kunigami (1988), fig. 1 (the follower's geometry); camcore.profile.followers (the checks).
    """
    def ok(rb: float) -> bool:
        try:
            model.check(rb)  # type: ignore[attr-defined]
            model.check_swing(rb, lift)  # type: ignore[attr-defined]
        except GeometryError:
            return False
        return True

    lo = max(floor, float(model.min_base_radius_mm()) * (1.0 + 1e-12) + 1e-12)  # type: ignore[attr-defined]
    if lo > rb_hi or not ok(lo):
        return math.inf, math.inf
    if ok(rb_hi):
        return lo, rb_hi
    good, bad = lo, rb_hi
    while bad - good > 1e-12 * bad:
        mid = 0.5 * (good + bad)
        good, bad = (mid, bad) if ok(mid) else (good, mid)
    return lo, good
