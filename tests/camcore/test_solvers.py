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


def test_one_bracket_in_floats_equals_the_array_newton() -> None:
    """camcore._solvers.newton_root (one bracket, Python floats) takes newton_roots' steps: the
    same root to the bit, for rising and falling functions, a zero slope (it bisects) and a
    root at a bracket's end; and the root is acos(c) to 4 ulp."""
    from camcore._solvers import newton_root, newton_roots

    c = np.linspace(-0.95, 0.95, 41)
    roots = np.arccos(c)
    lo = roots - np.linspace(0.02, 0.98, c.size) / 64
    hi = lo + 1 / 64
    lo[0], hi[1] = roots[0], roots[1]  # f = 0 at the left end of one bracket, the right of another
    # cos t − c falls; (cos t − c)³ has a zero slope at its root; 2·(c − cos t) rises
    cases = [(lambda t, i: (np.cos(t) - c[i], -np.sin(t))),
             (lambda t, i: ((np.cos(t) - c[i]) ** 3, -3 * (np.cos(t) - c[i]) ** 2 * np.sin(t))),
             (lambda t, i: (2 * (c[i] - np.cos(t)), 2 * np.sin(t)))]
    for n_case, f in enumerate(cases):
        index = np.arange(c.size)
        f_lo, f_hi = f(lo, index)[0], f(hi, index)[0]
        together = newton_roots(f, lo.copy(), hi.copy(), f_lo, f_hi, index)
        for i in range(c.size):
            one = newton_root(lambda t, i=i: tuple(float(x) for x in f(np.float64(t), i)),  # noqa: B023
                              float(lo[i]), float(hi[i]), float(f_lo[i]), float(f_hi[i]))
            assert one == together[i], (i, one, together[i])
        if n_case == 0:
            # f itself rounds: cos t and c are within an ulp of 1 (2.2e-16) each, which moves the
            # root by that over |f'| = sin t (0.31 at c = ±0.95); plus the root's own 4 ulp
            eps = np.finfo(float).eps
            assert np.all(np.abs(together - roots) <= 2 * eps / np.sin(roots) + 4 * np.spacing(roots))
