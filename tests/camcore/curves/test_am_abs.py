"""``am_abs``: the largest |A| with the T where it first occurs, like every other extreme.

``am`` stays the bare number that normalises Q; ``am_abs`` adds its T. Where the law makes
Amp = Amm (m = 1: MS, MT, TR, cycloid) the two peaks tie and the earlier one is reported.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import camcore

ENTRIES = list(camcore.CATALOG.values())


@pytest.mark.parametrize("entry", ENTRIES, ids=[e.id for e in ENTRIES])
@pytest.mark.parametrize("direction", ["rise", "return"])
def test_am_abs_is_am_with_its_time(entry: camcore.CatalogEntry, direction: str) -> None:
    curve = entry.build() if direction == "rise" else camcore.ReturnCurve(entry.build())
    ch = curve.characteristics
    assert ch.am_abs.value == ch.am == max(ch.am_pos.value, -ch.am_neg.value)
    assert ch.am_abs.t in (ch.am_pos.t, ch.am_neg.t)
    if ch.am == 0:
        return
    # |A| reaches Am at that T, from one side or the other (at a break point the table takes the
    # right limit, the peak may be the left one); 1e-12 is a few hundred ulps of rounding in A
    eps = 1e-12 * ch.am
    left, right = curve.derivatives(np.array([ch.am_abs.t - 1e-13, ch.am_abs.t]), 2)[2]
    assert max(abs(left), abs(right)) == pytest.approx(ch.am, abs=1e3 * eps)
    # and nowhere earlier: a fine grid before that T stays below Am by more than rounding
    before = np.linspace(curve.t_start, ch.am_abs.t, 4001)[:-2]
    before = before[before < ch.am_abs.t]
    if before.size:
        assert np.abs(curve.derivatives(before, 2)[2]).max() < ch.am - eps


@pytest.mark.parametrize(("name", "t_am"), [
    ("MS", 1 / 8),        # INDEXMAN MS: quarter sine up to Amp at Ta = 1/8
    ("TR", 1 / 8),        # trapecloid: Amp reached at T1 = 1/8, held to Tb (ties Amm)
    ("MT", 1 / 8),        # modified trapezoid: Amp from T1 = 1/8 to T2 = 3/8
    ("cycloid", 1 / 4),   # A = 2π sin 2πT peaks at T = 1/4
    ("one-dwell-cycloid", 1 / 4),
])
def test_am_abs_time_of_known_laws(name: str, t_am: float) -> None:
    ch = camcore.named_curve(name).characteristics
    # the T comes from the break points themselves or a root refined to machine precision
    assert math.isclose(ch.am_abs.t, t_am, abs_tol=1e-12), ch.am_abs
