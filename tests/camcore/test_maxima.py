"""The maxima refinement that dynamics and the toolpath's measurement use (camcore._maxima.polished_grid_max:
shrinking local grids to 1e-5, then one parabolic step, Brent 1973, ch. 5), against golden section to 1e-13
(Kiefer 1953) and against maxima known in closed form."""

from __future__ import annotations

import math

import numpy as np

from camcore._maxima import golden_max, polished_grid_max


class SmoothCases:
    """f_i(x) = cos(k_i (x − c_i)) + 0.3 sin(3 k_i (x − c_i)) near its maximum, on intervals like a 0.25°
    grid's two cells (8.7e-3 rad) with the maximum anywhere inside: known in closed form by Newton on f'.
    ``values`` evaluates them (lane i at row i; a 2-D x holds a row of points per lane) and counts its calls."""

    def __init__(self) -> None:
        rng = np.random.default_rng(7)
        self.k = rng.uniform(0.5, 20.0, 400)
        self.c = rng.uniform(-1.0, 1.0, 400)
        # the maximum of cos u + 0.3 sin 3u near u = 0: f'(u) = −sin u + 0.9 cos 3u = 0, by Newton in u
        u = 0.0
        for _ in range(50):
            u -= (-math.sin(u) + 0.9 * math.cos(3 * u)) / (-math.cos(u) - 2.7 * math.sin(3 * u))
        self.peak = math.cos(u) + 0.3 * math.sin(3 * u)
        self.where = self.c + u / self.k
        self.a = self.where - rng.uniform(0.0, 8.7e-3, 400)
        self.b = self.where + rng.uniform(0.0, 8.7e-3, 400)
        self.calls = 0

    def values(self, x: np.ndarray) -> np.ndarray:
        self.calls += 1
        k, c = (self.k, self.c) if x.ndim == 1 else (self.k[:, None], self.c[:, None])
        u = k * (x - c)
        return np.cos(u) + 0.3 * np.sin(3 * u)


def test_grid_polish_to_rounding_in_fewer_calls() -> None:
    # each row of a call one interval's points (the toolpath's measurement: a call evaluates the exact
    # curve afresh, so calls count, not points)
    cases = SmoothCases()
    x, v = polished_grid_max(cases.values, cases.a, cases.b, width=1e-5, points=9)
    grid_calls, cases.calls = cases.calls, 0
    _, vg = golden_max(cases.values, cases.a, cases.b, width=1e-13)
    # the value to rounding (4 ulp of values near 1.2), never below golden section's to 1e-13 by more
    assert np.abs(v - cases.peak).max() <= 4 * np.spacing(cases.peak)
    assert np.all(v >= vg - 4 * np.spacing(cases.peak))
    # the place to the value's own conditioning: √(2 ulp/|f''|) ≈ 1e-8/k rad
    assert np.all(np.abs(x - cases.where) <= 3e-8 / cases.k)
    # 1.7e-2 → 1e-5 by quarters: 7 grids (the 7th finds every interval narrower), then 2 calls for the
    # parabola (its two points in one call, its vertex in another); golden section alone 56 to 1e-13
    assert grid_calls == 9 and cases.calls == 56


def test_grid_polish_evaluates_a_maximum_at_an_end_there() -> None:
    # a kink: f = 2t − t² rises to the first interval's right end and falls from the second's left end
    # (the maximum of a piece of the turn at a break point): each found at the end itself, exactly
    a, b = np.array([0.0, 1.0]), np.array([0.004, 1.002])
    x, v = polished_grid_max(lambda t: 2.0 * t - t * t, a, b, width=1e-5)
    assert x.tolist() == [0.004, 1.0] and v.tolist() == [2.0 * 0.004 - 0.004**2, 1.0]


def test_lanes_without_a_value_keep_minus_infinity() -> None:
    # dynamics counts a NaN as −inf (a point where a function is not defined never wins): no warning, no value
    x, v = polished_grid_max(lambda t: np.where(t > 5.0, -np.inf, -(t - 0.3) ** 2), np.array([0.0, 6.0]),
                             np.array([1.0, 7.0]), width=1e-5)
    assert v[0] == 0.0 and abs(x[0] - 0.3) < 1e-8 and v[1] == -np.inf
