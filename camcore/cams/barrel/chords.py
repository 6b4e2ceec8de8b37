"""The cutter axis's path on a cylinder about the barrel cam's axis, developed, and its fit by
chords: the straight moves in (A, X) of :mod:`camcore.cams.barrel.toolpath` (whose module notes
give the path, the machine and why the fit is measured where it is).

References
----------
.. [1] Meek and Walton (1992): fitting within a tolerance measured against the curve.
.. [2] Kiefer (1953): golden-section search.
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from ..._maxima import golden_max
from ...curves.base import FloatArray
from ...deadline import checkpoint
from ...errors import GeometryError
from ...profile.lift import TWO_PI
from ...toolpath.fit import Budget
from ...toolpath.geometry import Element
from ...toolpath.measure import Span, measure
from .geometry import BarrelCam

#: greedy grid: cam angles per turn (finer where a span misses: 8 times, then again)
GRID_STEPS = 4096
#: the greedy search aims at this share of the tolerance (the measurement sees between the grid points)
AIM = 0.8
#: refits of a chord that misses the tolerance, each from a grid 8 times finer aiming half as high
REFITS = 8
#: points per chord where its deviation is sampled before the largest is refined
CHORD_SAMPLES = 16


class DevelopedPath:
    """Where the cutter's axis crosses the cylinder of ``radius_mm``, developed: P(θ) = (ρ·A(θ), X(θ)).

    Parameters
    ----------
    cam : BarrelCam
        A translating follower's cam.
    offset_mm : float
        d along the developed normal at the pitch radius [mm].
    radius_mm : float
        ρ, the cylinder's radius [mm].
    """

    def __init__(self, cam: BarrelCam, offset_mm: float, radius_mm: float):
        self.cam = cam
        self.offset_mm = float(offset_mm)
        self.radius_mm = float(radius_mm)

    def machine(self, theta: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """A [rad], X [mm], s' [mm/rad] and k = 1 − d·R·s''/w³ [-] at cam angles θ [rad]."""
        h, h1, h2 = self.cam.lift.derivatives(theta, 2)
        r, d = self.cam.pitch_radius_mm, self.offset_mm
        w = np.hypot(r, h1)
        return np.asarray(theta) - d * h1 / (r * w), h + d * r / w, h1, 1.0 - d * r * h2 / w**3

    def points(self, theta: FloatArray) -> tuple[FloatArray, FloatArray]:
        """ρ·A and X [mm]."""
        a, x, _, _ = self.machine(theta)
        return self.radius_mm * a, x

    def sample(self, theta: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
        """ρ·A, X, the unit direction of (ρ, s') and the signed speed k·|(ρ, s')| (dP/dθ = speed·direction)."""
        a, x, h1, k = self.machine(theta)
        speed = np.hypot(self.radius_mm, h1)
        return self.radius_mm * a, x, self.radius_mm / speed, h1 / speed, k * speed


def chords(curve: DevelopedPath, nodes: FloatArray) -> list[Span]:
    """The straight moves between consecutive nodes, as spans of one line each.

    Parameters
    ----------
    curve : DevelopedPath
        The path (its cylinder's developed plane).
    nodes : ndarray
        Cam angles of the nodes, in order [rad].

    Returns
    -------
    list of Span
        One line from each node's point to the next's [mm].

    References
    ----------
    The module notes of :mod:`camcore.cams.barrel.toolpath` (a move in (A, X) is a line in (ρ·A, X)).
    """
    px, py = curve.points(nodes)
    return [Span(float(nodes[i]), float(nodes[i + 1]),
                 (Element((float(px[i]), float(py[i])), (float(px[i + 1]), float(py[i + 1])), None, True,
                          float(nodes[i]), float(nodes[i + 1])),))
            for i in range(len(nodes) - 1)]


def fit_path(curve: DevelopedPath, bounds: list[float], tol: float, budget: Budget) -> tuple[list[Span], float]:
    """Chords within a tolerance of the exact path, stretch by stretch between the lift's breaks.

    Parameters
    ----------
    curve : DevelopedPath
        The exact path.
    bounds : list of float
        The stretches' ends, increasing, no break of the lift inside a stretch [rad].
    tol : float
        The largest deviation, both ways [mm].
    budget : Budget
        The count of moves and its limit.

    Returns
    -------
    (list of Span, float)
        The chords in order and their largest measured deviation [mm].

    Raises
    ------
    GeometryError
        Still over the tolerance after :data:`REFITS` refits.

    References
    ----------
    Meek and Walton (1992), fitting within a tolerance; :func:`chord_deviation` (all chords
    measured together: each evaluation of the lift costs most in its fixed part).
    """
    spans: list[Span] = []
    for a, b in itertools.pairwise(bounds):
        spans += _greedy(curve, a, b, AIM * tol, TWO_PI / GRID_STEPS, budget)
    for tighter in range(1, REFITS + 1):
        deviation = chord_deviation(curve, spans)
        worst = float(deviation.max(initial=0.0))
        if worst <= tol:
            return spans, worst
        checkpoint()
        refitted: list[Span] = []
        for span, dev in zip(spans, deviation):
            if dev <= tol:
                refitted.append(span)
                continue
            budget.add(-1)
            refitted += _greedy(curve, span.theta0, span.theta1, AIM * tol * 0.5**tighter,
                                (span.theta1 - span.theta0) / 8, budget)
        spans = refitted
    at = spans[int(np.argmax(chord_deviation(curve, spans)))]
    raise GeometryError(f"the path could not be fitted within {tol!r} mm between cam angles "
                        f"{math.degrees(at.theta0)!r}° and {math.degrees(at.theta1)!r}°.", field=("tolerance_mm",))


def chord_deviation(curve: DevelopedPath, spans: list[Span]) -> FloatArray:
    """The deviation of each chord from the exact path it stands for, both ways.

    Where the path's tangent keeps a positive component along the chord over the span (checked
    at :data:`CHORD_SAMPLES` points), the arc is a graph over the chord: each point of either has
    a partner on the other at its distance f from the chord's line, so the deviation both ways
    is max |f|, found at the samples and refined by golden section. A span where the check fails
    is measured by the general route (:func:`camcore.toolpath.measure.measure`).

    Parameters
    ----------
    curve : DevelopedPath
        The exact path.
    spans : list of Span
        One line each, its ends on the path at the span's θ0 and θ1.

    Returns
    -------
    ndarray
        The deviation of each span [mm].

    References
    ----------
    Kiefer (1953), golden section; camcore.toolpath.measure (the general measure, both ways).
    """
    checkpoint()
    t0 = np.array([s.theta0 for s in spans])
    t1 = np.array([s.theta1 for s in spans])
    sx = np.array([s.elements[0].start[0] for s in spans])
    sy = np.array([s.elements[0].start[1] for s in spans])
    dx = np.array([s.elements[0].end[0] for s in spans]) - sx
    dy = np.array([s.elements[0].end[1] for s in spans]) - sy
    length = np.hypot(dx, dy)
    cx, cy = dx / length, dy / length
    m = CHORD_SAMPLES
    # inside the span: at its ends a break's other side has another tangent
    frac = np.linspace(0.0, 1.0, m) * (1.0 - 2e-9) + 1e-9
    theta = (t0[:, None] + (t1 - t0)[:, None] * frac[None, :]).reshape(-1)
    lanes = np.repeat(np.arange(len(spans)), m)
    x, y, tx, ty, speed = curve.sample(theta)
    along = ((tx * cx[lanes] + ty * cy[lanes]) * np.sign(speed)).reshape(len(spans), m)

    def off(t: FloatArray, lane: np.ndarray) -> FloatArray:
        px, py = curve.points(t)
        return np.abs((px - sx[lane]) * cy[lane] - (py - sy[lane]) * cx[lane])

    samples = np.abs((x - sx[lanes]) * cy[lanes] - (y - sy[lanes]) * cx[lanes]).reshape(len(spans), m)
    best = np.argmax(samples, axis=1)
    rows = np.arange(len(spans))
    grid = theta.reshape(len(spans), m)
    a, b = grid[rows, np.maximum(best - 1, 0)], grid[rows, np.minimum(best + 1, m - 1)]
    _, refined = golden_max(lambda t: off(t, rows), a, b, width=1e-12)
    out = np.maximum(samples.max(axis=1), refined)
    general = np.nonzero(along.min(axis=1) <= 0.0)[0]
    if general.size:
        out[general] = measure(curve, [spans[k] for k in general])  # type: ignore[arg-type]
    return out


def _greedy(curve: DevelopedPath, theta0: float, theta1: float, aim_mm: float, step_rad: float,
            budget: Budget) -> list[Span]:
    """From each node, the farthest grid angle whose chord keeps every grid point between within
    ``aim_mm`` (grown by doubling, then bisected)."""
    n = max(2, math.ceil((theta1 - theta0) / step_rad))
    theta = np.linspace(theta0, theta1, n + 1)
    px, py = curve.points(theta)

    def fits(i: int, j: int) -> bool:
        sx, sy, dx, dy = px[i], py[i], px[j] - px[i], py[j] - py[i]
        length2 = dx * dx + dy * dy
        xs, ys = px[i:j + 1] - sx, py[i:j + 1] - sy
        u = np.clip((xs * dx + ys * dy) / length2, 0.0, 1.0) if length2 > 0 else np.zeros_like(xs)
        return bool(np.hypot(xs - u * dx, ys - u * dy).max() <= aim_mm)

    nodes = [0]
    i, guess = 0, 8
    while i < n:
        checkpoint()
        good, bad = i + 1, n + 1  # one grid step is the shortest chord
        j = min(n, i + guess)
        if fits(i, j):
            good = j
            while good < n:
                j = min(n, i + 2 * (good - i))
                if not fits(i, j):
                    bad = j
                    break
                good = j
        else:
            bad = j
        while bad <= n and bad - good > 1:
            j = (good + bad) // 2
            if fits(i, j):
                good = j
            else:
                bad = j
        nodes.append(good)
        budget.add(1)
        guess = max(1, good - i)
        i = good
    return chords(curve, theta[nodes])
