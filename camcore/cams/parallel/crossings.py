"""Where envelopes and paths meet: a point's least distance from a roller's path, two envelopes'
crossing, a point's foot on an envelope (the solvers of :mod:`.trace`).

References
----------
.. [1] J. Nocedal, S. J. Wright, *Numerical Optimization*, 2nd ed. (2006), ch. 11 (Newton's
   method for nonlinear equations).
.. [2] M. Dowell, P. Jarratt, "A modified regula falsi method for computing the root of an
   equation", BIT 11 (1971) 168-174 (the Illinois method).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ..._solvers import illinois_roots
from ...curves.base import FloatArray
from .envelope import centres, track
from .geometry import ParallelCam

#: ε: a point is covered when a roller comes nearer than Rr − ε (:mod:`.trace`), a share of the
#: centre distance: far above the rounding of 100 mm coordinates (1e-14 mm), far below any
#: machining (1e-5 mm at C = 100 mm); a point's foot within 2ε of it is a hand-over between two
#: envelopes that run together, so 2ε is also the largest gap the contour has there
COVER_SHARE = 1e-7
#: Newton steps of a distance minimum between two samples of a passage: each squares the error
#: of a start within a sample step (1e-2 rad at 1°): 1e-4, 1e-8, 1e-16 rad
DISTANCE_STEPS = 4
#: Newton steps of a crossing (2 × 2) or a foot, started within a sample step: 4-6 where the
#: convergence is quadratic; the rest for shallow crossings, whose first steps are held to a step
CROSSING_STEPS = 16
#: a foot's Gauss-Newton step under this share of a sample step has the iteration converging
FAR_STEP_SHARE = 1e-3
#: a point whose gap from the envelope, less this many times the last step's length along it, is still
#: over 2ε is off the envelope: the steps left add up to less than twice the last (gap·κ ≤ ½)
FAR_MARGIN = 4.0
#: a crossing is solved when the two envelope points are this close, as a share of C (1e-9 mm
#: at C = 100 mm: the rounding of a cam angle, ~1e-16 rad, times the paths' speed, ×1e4)
CROSSING_SHARE = 1e-11


def distance_minima(cam: ParallelCam, alpha0: FloatArray, qx: FloatArray, qy: FloatArray, tau0: FloatArray,
                     lo: FloatArray, hi: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The least distance of each point from its roller's path for τ in a bracket.

    Parameters
    ----------
    cam : ParallelCam
        The cam.
    alpha0 : ndarray
        Each roller's arm angle at τ = 0 [rad].
    qx, qy : ndarray
        The points [mm].
    tau0, lo, hi : ndarray
        The start and the bracket of each search [rad].

    Returns
    -------
    (ndarray, ndarray)
        The distance [mm] and the roller's cam angle there [rad].

    References
    ----------
    Nocedal and Wright (2006), ch. 11: Newton on (P − Q)·P′ = 0 with P″ exact, kept in the bracket.
    """
    t = tau0.copy()
    for _ in range(DISTANCE_STEPS):
        px, py, p1x, p1y, p2x, p2y = centres(cam, alpha0, t)
        dx, dy = px - qx, py - qy
        slope = dx * p1x + dy * p1y
        curve = p1x * p1x + p1y * p1y + dx * p2x + dy * p2y
        # past a maximum (curve ≤ 0) go downhill by a gradient step scaled by |P′|²
        scale = np.where(curve > 0, curve, p1x * p1x + p1y * p1y)
        moved = np.clip(t - slope / scale, lo, hi)
        if np.array_equal(moved, t):  # no angle moved: every later step would repeat this one, and
            return np.hypot(dx, dy), t  # the centres at t are at hand
        t = moved
    px, py, *_ = centres(cam, alpha0, t)
    return np.hypot(px - qx, py - qy), t


def crossings(cam: ParallelCam, alpha: FloatArray, sides: FloatArray, t0: FloatArray, lo: FloatArray,
               hi: FloatArray, u0: FloatArray, step: float) -> tuple[NDArray[np.bool_], FloatArray, FloatArray]:
    """Crossings of envelope A with envelope B near a start, A's cam angle kept in a bracket.

    Parameters
    ----------
    cam : ParallelCam
        The cam.
    alpha, sides : ndarray
        Arm angles at τ = 0 [rad] and sides (±1) [-]: n of A, then n of B.
    t0, lo, hi : ndarray
        A's start and bracket [rad].
    u0 : ndarray
        B's start [rad].
    step : float
        The largest Newton step [rad].

    Returns
    -------
    (ndarray of bool, ndarray, ndarray)
        Solved (the points within CROSSING_SHARE·C, A's angle in its bracket), A's and B's cam angles [rad].

    References
    ----------
    Nocedal and Wright (2006), ch. 11: Newton's method on A(t) − B(u) = 0 with exact tangents.
    """
    n = t0.size
    t, u = t0.copy(), u0.copy()
    tol = CROSSING_SHARE * cam.center_distance_mm
    for _ in range(CROSSING_STEPS):
        e = track(cam, alpha, sides, np.concatenate([t, u]))
        fx, fy = e.x[:n] - e.x[n:], e.y[:n] - e.y[n:]
        if np.all(np.hypot(fx, fy) <= tol):
            break
        ax, ay = e.stretch[:n] * e.tx[:n], e.stretch[:n] * e.ty[:n]
        bx, by = e.stretch[n:] * e.tx[n:], e.stretch[n:] * e.ty[n:]
        # [A′  −B′]·(dt, du) = −(A − B), by Cramer's rule
        det = bx * ay - ax * by
        with np.errstate(divide="ignore", invalid="ignore"):
            dt = (fx * by - fy * bx) / det
            du = (fx * ay - fy * ax) / det
        bad = ~(np.isfinite(dt) & np.isfinite(du))
        # A's cam angle stays in its bracket: nearly parallel envelopes may touch just outside it
        t = np.clip(t + np.where(bad, 0.0, np.clip(dt, -step, step)), lo, hi)
        u = u + np.where(bad, 0.0, np.clip(du, -step, step))
    e = track(cam, alpha, sides, np.concatenate([t, u]))
    solved = np.hypot(e.x[:n] - e.x[n:], e.y[:n] - e.y[n:]) <= tol
    # only a crossing between A's last free point and the first covered one counts
    return solved & (t >= lo - 1e-9 * step) & (t <= hi + 1e-9 * step), t, u


def bracketed_crossings(cam: ParallelCam, alpha_a: float, side_a: float, t_free: float, t_covered: float,
                         alpha_b: FloatArray, u0: FloatArray, step: float
                         ) -> tuple[NDArray[np.bool_], FloatArray, FloatArray]:
    """Where envelope A enters each roller B's band between a free and a covered cam angle.

    The root of A's depth in the band, |A(t) − P_B| − Rr (its least distance from B's path, less
    Rr), by the Illinois method in the bracket; B's cam angle there is that point's foot on B's path.

    Parameters
    ----------
    cam : ParallelCam
        The cam.
    alpha_a, side_a : float
        A's arm angle at τ = 0 [rad] and side (±1) [-].
    t_free, t_covered : float
        A's cam angles where it is free and where B covers it [rad].
    alpha_b : ndarray
        Each B's arm angle at τ = 0 [rad].
    u0 : ndarray
        B's cam angle near the crossing [rad].
    step : float
        The sampled cam angles' step [rad].

    Returns
    -------
    (ndarray of bool, ndarray, ndarray)
        Found (the depth changes sign in the bracket), A's and B's cam angles there [rad].

    References
    ----------
    Dowell and Jarratt (1971), the Illinois method (:func:`camcore._solvers.illinois_roots`).
    """
    n = alpha_b.size
    lo = np.full(n, min(t_free, t_covered))
    hi = np.full(n, max(t_free, t_covered))
    foot = u0.copy()
    rr = cam.roller_radius_mm

    def depth(t: FloatArray, which: NDArray[np.intp]) -> FloatArray:
        a = track(cam, alpha_a, side_a, t)
        d, u = distance_minima(cam, alpha_b[which], a.x, a.y, foot[which], u0[which] - CROSSING_STEPS * step,
                                u0[which] + CROSSING_STEPS * step)
        foot[which] = u
        return d - rr

    f_lo, f_hi = depth(lo, np.arange(n)), depth(hi, np.arange(n))
    ok = np.sign(f_lo) != np.sign(f_hi)
    if ok.any():
        illinois_roots(depth, lo, hi, f_lo, f_hi, np.arange(n))
    t = np.where(np.abs(f_lo) <= np.abs(f_hi), lo, hi)
    depth(t, np.arange(n))
    return ok, t, foot


def feet(cam: ParallelCam, alpha: FloatArray, side: FloatArray, x: float, y: float, u0: FloatArray,
          step: float) -> FloatArray:
    """The cam angle of the foot of a point on each envelope near u0, where that foot is within 2ε of it.

    Parameters
    ----------
    cam : ParallelCam
        The cam.
    alpha, side : ndarray
        Each envelope's arm angle at τ = 0 [rad] and side (±1) [-].
    x, y : float
        The point [mm].
    u0 : ndarray
        The starts [rad].
    step : float
        The largest Newton step [rad].

    Returns
    -------
    ndarray
        The foot's cam angle, NaN where the point stands off that envelope by more than 2ε [rad].

    References
    ----------
    Nocedal and Wright (2006), ch. 10: Gauss-Newton on (E(u) − X)·E′(u) = 0.
    """
    u = u0.copy()
    eps2 = 2 * COVER_SHARE * cam.center_distance_mm
    for _ in range(CROSSING_STEPS):
        e = track(cam, alpha, side, u)
        with np.errstate(divide="ignore", invalid="ignore"):
            du = -((e.x - x) * e.tx + (e.y - y) * e.ty) / e.stretch
        du = np.where(np.isfinite(du), np.clip(du, -step, step), 0.0)
        # a lane whose foot is near (a step under FAR_STEP_SHARE of a sample step: the iteration
        # converges, each step shrinking the next by gap·κ ≪ ½) and whose point stays off the envelope
        # by more than 2ε even FAR_MARGIN steps' worth nearer is NaN however long it goes on
        gap = np.hypot(e.x - x, e.y - y)
        far = (np.abs(du) < FAR_STEP_SHARE * step) & (gap - FAR_MARGIN * np.abs(e.stretch * du) > eps2)
        u = u + du
        if np.all(far | (np.abs(du) <= 1e-15 * np.maximum(1.0, np.abs(u)))):
            break
    e = track(cam, alpha, side, u)
    gap = np.hypot(e.x - x, e.y - y)
    return np.where(gap <= eps2, u, np.nan)
