"""Characteristic values of many curves at once (camcore.curves.batch) equal each curve's own.

The batch stacks the sections of many curves into one pass of the same bracketing grid and
the same refinement as a curve alone, so the values are not close but identical (``==``);
any difference would mean a root bracketed or refined differently.
"""

from __future__ import annotations

import numpy as np
import pytest

import camcore
from camcore.curves import build_curve
from camcore.curves.batch import _PIECES_PER_PASS, VALUES, characteristic_values
from camcore.curves.reverse import ReturnCurve
from camcore.curves.sections import SectionCurve


def _own(curves: list) -> dict[str, np.ndarray]:
    return {name: np.array([getattr(c.characteristics, name).value for c in curves]) for name in VALUES}


def _appendix_3_2_grid() -> list:
    """Makino's curve 4 over T3 = I/32, T1 = J/64 (appendix 3-2), the combinations it allows."""
    curves = []
    for i in range(1, 9):
        for j in range(1, 17):
            if j / 64 <= i / 32:
                curves.append(build_curve("makino", {"number": 4, "t1": j / 64, "t3": i / 32}))
    return curves


def test_appendix_grid_equals_each_curve() -> None:
    curves = _appendix_3_2_grid()
    assert len(curves) == 72
    found = characteristic_values(curves)
    own = _own(curves)
    for name in VALUES:
        assert np.array_equal(found[name], own[name]), name


def test_mixed_kinds_and_directions_in_order() -> None:
    """Section curves (catalog, universal, returns through their rise) beside curves done one by
    one (polynomial, Bézier, a return curve); each value lands in its own row."""
    curves = [
        build_curve("named", {"name": "MS"}),
        build_curve("polynomial", {"name": "3-4-5"}),
        build_curve("universal", {"t": [0, 0.1, 0.1, 0.3, 0.5, 0.75, 0.75, 1], "m": 0.5}),
        build_curve("named", {"name": "MCV50"}, "return"),
        build_curve("makino", {"number": 1, "z": 0.4}),
        build_curve("bezier", {"control_points": [[k / 7, h] for k, h in enumerate([0, 0, 0, 0.2, 0.8, 1, 1, 1])]}),
        build_curve("named", {"name": "cycloid"}),
    ]
    assert not all(isinstance(c, SectionCurve) for c in curves)
    found = characteristic_values(curves)
    own = _own(curves)
    for name in VALUES:
        assert np.array_equal(found[name], own[name]), name


def test_more_pieces_than_one_pass() -> None:
    """Enough curves for several passes (a pass holds 1020 pieces): the chunks join in order."""
    rng = np.random.default_rng(7)
    curves = []
    while sum(c.n_pieces for c in curves) < 2.5 * _PIECES_PER_PASS:
        t1, t3 = sorted(rng.uniform(0.01, 0.24, 2))
        curves.append(build_curve("makino", {"number": 4, "t1": float(t1), "t3": float(t3)}))
    found = characteristic_values(curves)
    own = _own(curves)
    for name in VALUES:
        assert np.array_equal(found[name], own[name]), name


def test_no_curves() -> None:
    assert all(v.size == 0 for v in characteristic_values([]).values())


@pytest.mark.parametrize("name, vm, am", [("MS", 1.76, 5.53), ("cycloid", 2.00, 6.28)])
def test_catalog_values(name: str, vm: float, am: float) -> None:
    """INDEXMAN guide, section 5, characteristic table: MS Vm 1.76, Am 5.53; cycloid 2.00, 6.28
    (printed to the hundredth: half a unit of the last digit)."""
    found = characteristic_values([build_curve("named", {"name": name})])
    assert found["vm"][0] == pytest.approx(vm, abs=0.005)
    assert found["am_pos"][0] == pytest.approx(am, abs=0.005)


# ------------------------------------------------------------------ one curve's few roots, one by one
# A curve alone has a few Newton roots (two for MS-like universal curves); they are refined one
# by one on the section's scalar formulas (camcore.curves.sections.eval_section_point and
# camcore._solvers.newton_root) where the batch refines hundreds together on arrays. The batch
# rows above equal the single values only because both give the same numbers to the bit.
def _random_section_curves(count: int, seed: int) -> list:
    rng = np.random.default_rng(seed)
    curves = [build_curve("named", {"name": name}) for name in ("MS", "MCV50", "MT", "TR", "cycloid")]
    while len(curves) < count:
        t1, t2, t3 = sorted(rng.uniform(0.01, 0.99, 3))
        kind = rng.integers(3)
        if kind == 0:
            curves.append(build_curve("universal", {"t": [0, t1 / 2, t1, t2, t2, t3, t3, 1]}))
        elif kind == 1:
            curves.append(build_curve("universal", {"t": [0, t1, t1, t2, t2, t3, t3, 1], "m": float(rng.uniform(0.2, 0.8))}))
        else:
            curves.append(build_curve("makino", {"number": 4, "t1": float(t1 / 4), "t3": float(t1 / 2)}))
    return curves


def test_scalar_and_grid_formulas_equal_the_array_formulas_to_the_bit() -> None:
    """eval_point at random times on every piece, and at each piece's ends, equals eval_pieces;
    so does eval_grid (the bracketing grid: coefficients repeated per piece, not gathered)."""
    rng = np.random.default_rng(3)
    for curve in _random_section_curves(60, 11):
        assert curve.has_point_formulas
        grid = np.sort(rng.uniform(curve.piece_starts[:, None], curve.piece_ends[:, None], (curve.n_pieces, 9)))
        gathered = curve.eval_pieces(grid.reshape(-1), np.repeat(np.arange(curve.n_pieces), 9), 4)
        assert all(np.array_equal(a, b.reshape(grid.shape)) for a, b in zip(curve.eval_grid(grid, 4), gathered))
        for k in range(curve.n_pieces):
            a, b = float(curve.piece_starts[k]), float(curve.piece_ends[k])
            times = np.concatenate([[a, b], rng.uniform(a, b, 20)])
            arrays = curve.eval_pieces(times, np.full(times.size, k), 4)
            for i, t in enumerate(times.tolist()):
                assert curve.eval_point(t, k) == [float(row[i]) for row in arrays], (t, k)


def test_one_by_one_newton_equals_the_array_newton(monkeypatch: pytest.MonkeyPatch) -> None:
    """The candidates of 300 curves with their roots refined one by one equal those refined on
    arrays (the path a batch takes), and the one-by-one path was taken."""
    from camcore.curves import extrema

    taken = []
    real = extrema._point_root
    monkeypatch.setattr(extrema, "_point_root", lambda *args: taken.append(1) or real(*args))
    curves = _random_section_curves(300, 5)
    one_by_one = [extrema.characteristic_candidates(c) for c in curves]
    assert len(taken) > 300
    monkeypatch.setattr(extrema, "_POINT_NEWTON_MAX", -1)
    taken.clear()
    together = [extrema.characteristic_candidates(c) for c in curves]
    assert not taken
    for (t1, k1), (t2, k2) in zip(one_by_one, together):
        assert np.array_equal(t1, t2) and np.array_equal(k1, k2)


def test_a_few_times_evaluated_one_by_one_equal_the_arrays_to_the_bit() -> None:
    """Curve.derivatives of up to 8 times takes the scalar formulas (the tracing solvers ask for one or
    two at a time): the same bytes as the gathered arrays, at random times, break points, T0 and T7; with
    a time outside [T0, T7] the arrays' path answers (sections 0 and VIII). Their return strokes too
    (a plate cam's return segment), through the rise's scalar formulas at the mirrored time."""
    rng = np.random.default_rng(5)
    rises = [*_random_section_curves(30, 13), *(camcore.named_curve(n) for n in ("MS", "MCV50", "MT", "TR"))]
    curves = [*rises, *(ReturnCurve(c) for c in rises[::3])]
    for curve in curves:
        assert curve.has_point_formulas
        breaks = curve.break_points
        for size in (1, 2, 5, 8):
            for times in (rng.uniform(curve.t_start, curve.t_end, size), rng.choice(breaks, size),
                          np.append(rng.uniform(curve.t_start, curve.t_end, size - 1), curve.t_end + 0.1)):
                for order in (0, 2, 4):
                    fast = curve.derivatives(times, order)
                    arrays = curve._derivatives_gathered(np.asarray(times, dtype=np.float64), order)
                    assert [a.tobytes() for a in fast] == [b.tobytes() for b in arrays], (times, order)
