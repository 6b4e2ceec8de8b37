"""The root refinement behind characteristic values and torque peaks (camcore._solvers.illinois_roots).

Known roots, found to within 4 ulp, in far fewer evaluations than bisection's ~45 from a
1/256-wide bracket (the bracket width Curve.critical_points starts from).
"""

from __future__ import annotations

import math

import numpy as np

from camcore._solvers import illinois_roots as _refine_roots


def _solve(f, lo: list[float], hi: list[float]) -> tuple[np.ndarray, np.ndarray, int]:
    """Refine brackets of f(t, i) (i: the bracket's index); returns lo, hi and the call count."""
    calls = [0]

    def counted(t: np.ndarray, index: np.ndarray) -> np.ndarray:
        calls[0] += 1
        return f(t, index)

    a, b = np.array(lo), np.array(hi)
    index = np.arange(a.size)
    _refine_roots(counted, a, b, f(a, index), f(b, index), index)
    return a, b, calls[0]


def test_roots_of_smooth_functions_to_ulps_in_few_steps() -> None:
    # cos t = c has the root acos c; brackets 1/256 wide with the root anywhere inside
    c = np.linspace(-0.9, 0.9, 37)
    roots = np.arccos(c)
    left = roots - np.linspace(0.05, 0.95, c.size) / 256
    a, b, calls = _solve(lambda t, i: np.cos(t) - c[i], list(left), list(left + 1 / 256))
    ulps = 4 * np.spacing(roots)
    assert np.all(b - a <= ulps)
    assert np.all((a <= roots + ulps) & (roots - ulps <= b))
    # measured: 5 evaluations; bisection would take ~45
    assert calls <= 15, f"{calls} evaluations: the refinement has degraded to bisection"


def test_root_next_to_an_end_and_an_exact_zero() -> None:
    # the root 1e-13 from the bracket's left end: the chord keeps landing by that end
    root = 0.3 + 1e-13
    a, b, calls = _solve(lambda t, i: (t - root) * (1 + t * t), [0.3], [0.3 + 1 / 256])
    assert b[0] - a[0] <= 4 * math.ulp(0.3) and a[0] <= root <= b[0]
    assert calls <= 15, f"{calls} evaluations"  # measured: 2
    # a linear function: the first chord lands on the root exactly (f = 0) and both ends take it
    a, b, calls = _solve(lambda t, i: t - 0.5, [0.25], [0.75])
    assert a[0] == b[0] == 0.5 and calls == 1
