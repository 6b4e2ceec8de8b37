"""Every catalog curve starts and ends exactly where its law says: no float noise at T0, T7.

A table's first and last rows are what a designer reads first (a spreadsheet shows
``V = 2.8e-16`` at T = 1 as a non-zero velocity). The law's end conditions come from
the catalog's own definition of each curve, not from the implementation: a universal
curve (Makino 1977, eqs. (1)-(11)) of the catalog rises from S = 0 to S = 1 with
V0 = V7 = 0 (equal areas), and its acceleration starts at rest when section I is a
quarter sine from zero (T1 > T0) and ends at rest when section VII is a quarter cosine
down to zero (T7 > T6); a polynomial S = Σ cₖTᵏ has S, V, A at 0 and 1 from its integer
coefficients. Equality is exact (==), as the laws' end values are.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

import camcore
from camcore.curves.catalog import CatalogEntry

ENTRIES = list(camcore.CATALOG.values())


def law_ends(entry: CatalogEntry) -> dict[str, tuple[float, float] | tuple[float | None, float | None]]:
    """(value at T0, value at T7) of S, V and A by the catalog's definition; None where the
    law's A at that end is not zero (then A is not checked: it is a peak, not a rest)."""
    params = entry.parameters
    if "coefficients" in params:
        c = [Fraction(x) for x in params["coefficients"]]  # type: ignore[union-attr]
        s = (c[0], sum(c))
        v = (c[1] if len(c) > 1 else Fraction(0), sum(k * x for k, x in enumerate(c)))
        a = (2 * c[2] if len(c) > 2 else Fraction(0), sum(k * (k - 1) * x for k, x in enumerate(c)))
        return {"s": (float(s[0]), float(s[1])), "v": (float(v[0]), float(v[1])),
                "a": (0.0 if a[0] == 0 else None, 0.0 if a[1] == 0 else None)}
    t = params["t"]
    assert "m" not in params, "a catalog curve with a given m ends at a computed V7; extend this test"
    return {"s": (0.0, 1.0), "v": (0.0, 0.0),
            "a": (0.0 if t[1] > t[0] else None, 0.0 if t[7] > t[6] else None)}  # type: ignore[index]


def check_ends(curve: camcore.Curve, ends: dict[str, tuple[float | None, float | None]], label: str) -> None:
    t0, t7 = curve.t_start, curve.t_end
    # both evaluation paths: a few points (coefficients gathered per point) and a long sorted
    # table (each section on its contiguous slice)
    few = curve.derivatives(np.array([t0, t7]), 2)
    table = curve.derivatives(np.linspace(t0, t7, 20_001), 2)
    for k, name in enumerate("sva"):
        for end, want in enumerate(ends[name]):
            if want is None:
                continue
            got = (float(few[k][0]), float(few[k][-1]))[end], (float(table[k][0]), float(table[k][-1]))[end]
            assert got == (want, want), f"{label}: {name.upper()} at T{7 * end} is {got}, the law says {want}"
            # +0, not −0: a CSV cell or JSON number reads "0.0", never "-0.0"
            assert not any(np.signbit(g) and g == 0 for g in got), f"{label}: {name.upper()} at T{7 * end} is −0"


@pytest.mark.parametrize("entry", ENTRIES, ids=[e.id for e in ENTRIES])
def test_catalog_rise_ends_exactly_at_the_law(entry: CatalogEntry) -> None:
    check_ends(entry.build(), law_ends(entry), entry.id)


@pytest.mark.parametrize("entry", ENTRIES, ids=[e.id for e in ENTRIES])
def test_catalog_return_ends_exactly_at_the_law(entry: CatalogEntry) -> None:
    # the return plays the rise backwards: S and A keep their values, V changes sign
    rise = law_ends(entry)
    ret = {"s": rise["s"][::-1],
           "v": tuple(None if x is None else 0.0 - x for x in rise["v"][::-1]),
           "a": rise["a"][::-1]}
    check_ends(camcore.ReturnCurve(entry.build()), ret, f"{entry.id} return")  # type: ignore[arg-type]


@pytest.mark.parametrize(("v0", "v7", "s0", "s7"), [(0.0, 0.0, 0.0, 1.0), (0.25, 0.75, -0.5, 2.0), (1.0, 0.0, 0.0, 1.0)])
def test_universal_curve_ends_at_its_targets(v0: float, v7: float, s0: float, s7: float) -> None:
    # solved for both S7 and V7 (m omitted), the curve ends on the targets themselves
    curve = camcore.universal_curve([0, 0.125, 0.125, 0.5, 0.5, 0.875, 0.875, 1], v0=v0, v7=v7, s0=s0, s7=s7)
    s, v, a = curve.derivatives(np.array([0.0, 1.0]), 2)
    assert (s[0], s[1], v[0], v[1], a[0], a[1]) == (s0, s7, v0, v7, 0.0, 0.0)


def test_cutting_feed_stops_exactly() -> None:
    # Makino curve 2 decelerates from V0 to rest at S = 1 (CURVE lines 42-55)
    curve = camcore.makino_curve(2, t4=0.4)
    s, v = curve.derivatives(np.array([1.0]), 1)
    assert (s[0], v[0]) == (1.0, 0.0)
