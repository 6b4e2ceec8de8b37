"""The sine-family evaluation: sin/cos through tan(θ/2), and the two evaluation paths.

``camcore.curves.sections`` computes sin θ = 2q, cos θ = 1 − 2r and 1 − cos θ = 2r from one vectorised tan(θ/2)
(numpy's float64 tan is SIMD, its sin and cos are not). These tests hold those identities
to a 60-digit mpmath reference, and hold the sorted-table path (per-section slices, one
workspace) to the any-order path (coefficients gathered per point): same numbers.
"""

from __future__ import annotations

import mpmath
import numpy as np
import pytest

import camcore
from camcore.curves.catalog import CATALOG
from camcore.curves.reverse import ReturnCurve
from camcore.curves.sections import SectionCurve, half_angle_bases

EPS = float(np.finfo(np.float64).eps)


def _angles() -> np.ndarray:
    rng = np.random.default_rng(20261122)
    return np.concatenate([
        rng.uniform(0.0, 2.0 * np.pi, 2000),            # every angle a section can sweep
        np.pi + rng.uniform(-1e-9, 1e-9, 100),          # tan(θ/2) near its pole
        0.5 * np.pi + rng.uniform(-1e-9, 1e-9, 100),    # cos θ near 0 (u near 1)
        rng.uniform(0.0, 1e-6, 100),                     # small θ: 1 − cos θ ≈ θ²/2
        [0.0, np.pi / 2, np.pi, 2.0 * np.pi],
    ])


def test_sin_cos_from_half_angle_against_mpmath() -> None:
    theta = _angles()
    q, r = half_angle_bases(0.5 * theta)
    sn, cs, omc = 2.0 * q, 1.0 - 2.0 * r, 2.0 * r
    with mpmath.workdps(60):
        exact = [(mpmath.sin(mpmath.mpf(x)), mpmath.cos(mpmath.mpf(x))) for x in theta.tolist()]
        err_sin = max(abs(mpmath.mpf(a) - s) for a, (s, _) in zip(sn.tolist(), exact))
        err_cos = max(abs(mpmath.mpf(a) - c) for a, (_, c) in zip(cs.tolist(), exact))
        err_omc = max(abs(mpmath.mpf(a) - (1 - c)) for a, (_, c) in zip(omc.tolist(), exact))
        # relative error of 1 − cos θ for small θ, where 1 − cos(θ) in float64 loses all digits
        small = [(a, 1 - mpmath.cos(mpmath.mpf(x))) for a, x in zip(omc.tolist(), theta.tolist()) if 0 < x < 1e-6]
        rel_omc_small = max(abs((mpmath.mpf(a) - r) / r) for a, r in small)
    # measured: sin 0.88 eps, cos 1.41 eps, 1 − cos 1.41 eps (absolute), 1.8 eps relative at
    # small θ. tan is within 0.52 ulp and each of u², 1 + u², the quotient and 1 − 2r rounds
    # once: 4 eps bounds that chain with room for another platform's tan.
    assert float(err_sin) <= 4 * EPS
    assert float(err_cos) <= 4 * EPS
    assert float(err_omc) <= 4 * EPS
    assert float(rel_omc_small) <= 4 * EPS
    # exact where the identities are exact
    assert sn[-4] == 0.0 and cs[-4] == 1.0 and omc[-4] == 0.0


@pytest.mark.parametrize("name", sorted(CATALOG))
def test_sorted_table_and_any_order_give_the_same_numbers(name: str) -> None:
    curve = camcore.named_curve(name)
    # a large table crosses block boundaries inside pieces; end points and break points included
    t = np.unique(np.concatenate([np.linspace(curve.t_start, curve.t_end, 40_001), curve.break_points,
                                  [curve.t_start - 0.1, curve.t_end + 0.1]]))
    table = curve.derivatives(t, 4)
    order = np.random.default_rng(3).permutation(t.size)
    shuffled = curve.derivatives(t[order], 4)
    for k, (a, b) in enumerate(zip(table, shuffled)):
        assert np.array_equal(a[order], b), f"{name}: derivative {k} differs between the sorted and gathered paths"


@pytest.mark.parametrize("name", sorted(CATALOG))
def test_a_returns_sorted_table_is_its_gathered_numbers_to_the_bit(name: str) -> None:
    """A return (Makino's INIT = 2) evaluates a table with its rise's own piece path, run backwards over
    the mirrored times: every number, −0.0 apart from +0.0, is the gathered path's."""
    curve = ReturnCurve(camcore.named_curve(name))
    t = np.unique(np.concatenate([np.linspace(curve.t_start, curve.t_end, 40_001), curve.break_points,
                                  np.nextafter(curve.piece_starts, -np.inf)]))
    t = t[(t >= curve.t_start) & (t <= curve.t_end)]
    gathered = curve._derivatives_gathered(t, 4)
    for k, (a, b) in enumerate(zip(curve.derivatives(t, 4), gathered)):
        assert a.view(np.int64).tolist() == b.view(np.int64).tolist(), f"{name}: derivative {k}"


def test_section_curves_use_the_sliced_path_for_tables() -> None:
    """The identity above is only a check if the table really takes the sorted path."""
    curve = camcore.named_curve("MS")
    assert isinstance(curve, SectionCurve)
    calls: list[int] = []
    original = curve.eval_piece

    def spy(t, k, order, out, work=None):  # type: ignore[no-untyped-def]
        calls.append(k)
        original(t, k, order, out, work)

    curve.eval_piece = spy  # type: ignore[method-assign]
    try:
        curve.derivatives(np.linspace(0.0, 1.0, 50_000), 3)
    finally:
        del curve.eval_piece
    # 4 sections, the middle ones spanning more than one block of camcore.curves.base._BLOCK
    assert sorted(set(calls)) == [0, 1, 2, 3] and len(calls) > 4
