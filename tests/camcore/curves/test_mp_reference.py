"""camcore's float64 curves against a 40-digit mpmath reference.

The reference ``tests/data/mp_reference.csv`` is written by ``scripts/mpmath_reference.py``
(independent of camcore): a line-by-line port of Makino's subroutine CURVE (1977,
appendix 1, lines 75-124 and 146-221) for every table-2 curve, curve 36 (eq. 13) and
curves 1, 2, 4, and the INDEXMAN guide's displacement formulas for MS, MCV50, MCV25,
MT, TR. Rows: k/400, every interior break point (as a float) and the break points ± 1e-9.
"""

from __future__ import annotations

import csv
import importlib.util
from collections import defaultdict
from pathlib import Path

import numpy as np
import pytest

import camcore
from camcore import makino_curve

ROOT = Path(__file__).resolve().parents[3]
DATA = ROOT / "tests" / "data" / "mp_reference.csv"
SCRIPT = ROOT / "scripts" / "mpmath_reference.py"

#: 1e-13 of each quantity's peak on the curve. Why scaled: float64 evaluates each
#: quantity as a sum of terms as large as its peak (S ≤ 1, V ≤ 2.2, A ≤ 8, J ≤ 201),
#: so its absolute error is a few ulps of the peak, not of the value (J passes through
#: 0 with an error of ~eps·Jm, so a relative-to-value test would be meaningless there).
#: Measured worst case over the whole file: 1.4e-15 × peak (J of curve 4); 1e-13 leaves
#: a factor 70 for other platforms' libm and is still 10^8 below any formula error.
REL_TOL = 1e-13


def load() -> dict[str, np.ndarray]:
    by_curve: dict[str, list[list[float]]] = defaultdict(list)
    with DATA.open() as f:
        reader = csv.reader(f)
        header = next(reader)
        assert header == ["curve", "T", "S", "V", "A", "J"], header
        for r in reader:
            by_curve[r[0]].append([float(x) for x in r[1:]])
    return {k: np.array(v) for k, v in by_curve.items()}


REFERENCE = load()


def camcore_curve(curve_id: str) -> camcore.Curve:
    if curve_id.startswith("indexman-"):
        return camcore.named_curve(curve_id.removeprefix("indexman-"))
    special = {
        "makino-1-z0.9": lambda: makino_curve(1, z=0.9),
        "makino-2-t4-0.6": lambda: makino_curve(2, t4=0.6),
        "makino-4-t1-0.05-t3-0.2": lambda: makino_curve(4, t1=0.05, t3=0.2),
    }
    if curve_id in special:
        return special[curve_id]()
    return makino_curve(int(curve_id.removeprefix("makino-")))


@pytest.mark.parametrize("curve_id", sorted(REFERENCE))
def test_camcore_matches_mpmath_reference(curve_id: str) -> None:
    ref = REFERENCE[curve_id]
    t = ref[:, 0]
    got = camcore_curve(curve_id).derivatives(t, 3)
    for row, name in enumerate("SVAJ"):
        want = ref[:, row + 1]
        peak = max(1.0, float(np.max(np.abs(want))))
        err = np.abs(got[row] - want)
        k = int(np.argmax(err))
        assert err[k] <= REL_TOL * peak, (
            f"{curve_id} {name}: |camcore − mpmath| = {err[k]:.3e} (peak {peak:.4g}) at T = {t[k]!r}"
        )


def test_reference_covers_every_sine_family_catalog_curve() -> None:
    """Every catalog entry of the universal-curve family has reference rows."""
    covered = set()
    for curve_id in REFERENCE:
        if curve_id.startswith("indexman-"):
            covered.add(camcore.lookup(curve_id.removeprefix("indexman-")).id)
        elif curve_id.removeprefix("makino-").isdigit():
            covered.add(camcore.lookup(curve_id.removeprefix("makino-")).id)
    sine_family = {k for k, e in camcore.CATALOG.items() if e.family != "polynomial"}
    assert sine_family - covered == set(), f"no reference for {sorted(sine_family - covered)}"
    assert sum(len(v) for v in REFERENCE.values()) >= 5000
    assert all(len(v) >= 401 for v in REFERENCE.values())


def test_reference_file_is_what_the_script_writes() -> None:
    """Regenerate a few rows with the script and compare them to the committed file."""
    spec = importlib.util.spec_from_file_location("mpmath_reference", SCRIPT)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    cs = module.curves()
    with DATA.open() as f:
        lines = {(r[0], r[1]): r for r in csv.reader(f)}
    for curve_id, t in [("makino-27", 0.0), ("makino-35", 0.3), ("indexman-MS", 0.15), ("makino-36", 0.5)]:
        expected = module.row(curve_id, cs[curve_id], t)
        assert lines[(curve_id, repr(t))] == expected, f"{curve_id} T = {t}: file differs from the script"
    # the grid the script would write for one curve is the file's grid
    assert [float(x) for x in module.sample_times(cs["makino-26"])] == list(REFERENCE["makino-26"][:, 0])
