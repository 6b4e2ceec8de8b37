"""The curve catalog: one place that knows every named curve.

Each entry has an id, aliases (Makino's classification number among them), a name,
a family, the source document and the parameters that define it. Lookup is
case-insensitive and ignores spaces, underscores and hyphens.

Sources
-------
- Makino (1977), table 2 and subroutine CURVE: the classification numbers.
- INDEXMAN technical guide, section 5: MS, MC = MCV50, MCV25, MT, TR, with their
  constants (Ta, Tb, Tc) — all reproduced as universal curves:
  MS = 26 (Ta = 1/8); MCV50 = 27 (Ta = 1/16, Tb = 1/4); MCV25 = curve 4 with
  T3 = Tb = 3/8, T1 = Ta = T3/4 = 3/32 (the MCV family follows T1 = T3/4);
  MT = 25 (Ta = 1/8); TR = 35 (Ta = 1/8, Tb = (2 − 6Ta + πTa)/(2 + π),
  Tc = Tb + 2Ta).
"""

from __future__ import annotations

import difflib
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import lru_cache

from ..errors import UnknownCurveError
from .curve import Curve
from .makino import MAKINO_BREAK_POINTS, makino_curve, modified_constant_velocity, trapecloid_2
from .polynomial import NAMED_POLYNOMIALS, PolynomialCurve

MAKINO = "Makino 1977, table 2"
INDEXMAN = "INDEXMAN technical guide, section 5"


@dataclass(frozen=True)
class CatalogEntry:
    """A named curve: identity, provenance and how to build it."""

    id: str
    name: str
    family: str
    source: str
    factory: Callable[[], Curve]
    aliases: tuple[str, ...] = ()
    makino_number: int | None = None
    parameters: dict[str, object] = field(default_factory=dict)

    def build(self) -> Curve:
        return _build(self.id)


def _makino(number: int) -> Callable[[], Curve]:
    return lambda: makino_curve(number)


def _polynomial(name: str) -> Callable[[], Curve]:
    return lambda: PolynomialCurve(NAMED_POLYNOMIALS[name])


def _tp(number: int) -> dict[str, object]:
    pts, m = MAKINO_BREAK_POINTS[number]
    out: dict[str, object] = {"t": [float(x) for x in pts]}
    if m is not None:
        out["m"] = m
    return out


_ENTRIES: list[CatalogEntry] = [
    CatalogEntry("MS", "modified sine", "symmetric", f"{INDEXMAN}; {MAKINO} No. 26", _makino(26),
                 ("26", "modified-sine"), 26, _tp(26)),
    CatalogEntry("MCV50", "modified constant velocity, 50 % constant", "symmetric",
                 f"{INDEXMAN} (MC); {MAKINO} No. 27", _makino(27),
                 ("MC", "27", "modified-constant-velocity"), 27, _tp(27)),
    CatalogEntry("MCV25", "modified constant velocity, 25 % constant", "symmetric", INDEXMAN,
                 lambda: modified_constant_velocity(3 / 32, 3 / 8), (),
                 None, {"t": [0.0, 3 / 32, 3 / 32, 3 / 8, 5 / 8, 29 / 32, 29 / 32, 1.0]}),
    CatalogEntry("MT", "modified trapezoid", "symmetric", f"{INDEXMAN}; {MAKINO} No. 25", _makino(25),
                 ("25", "modified-trapezoid"), 25, _tp(25)),
    CatalogEntry("TR", "trapecloid", "asymmetric", f"{INDEXMAN}; {MAKINO} No. 35", _makino(35),
                 ("35", "trapecloid"), 35, _tp(35)),
    CatalogEntry("constant-acceleration", "constant acceleration (parabolic)", "basic", f"{MAKINO} No. 11",
                 _makino(11), ("11", "parabolic"), 11, _tp(11)),
    CatalogEntry("simple-harmonic", "simple harmonic", "discontinuous", f"{MAKINO} No. 12", _makino(12),
                 ("12", "harmonic"), 12, _tp(12)),
    CatalogEntry("cycloid", "cycloid", "symmetric", f"{MAKINO} No. 22", _makino(22), ("22",), 22, _tp(22)),
    CatalogEntry("asymmetric-cycloid", "asymmetric cycloid", "asymmetric", f"{MAKINO} No. 33",
                 _makino(33), ("33",), 33, _tp(33)),
    CatalogEntry("asymmetric-modified-trapezoid", "asymmetric modified trapezoid", "asymmetric",
                 f"{MAKINO} No. 34", _makino(34), ("34",), 34, _tp(34)),
    CatalogEntry("trapecloid-2", "trapecloid II", "special", "Makino 1977, eqs. (13)-(14), No. 36",
                 lambda: trapecloid_2(), ("36", "trapecloid-ii"), 36,
                 {"t1": 0.125, "t": [float(x) for x in trapecloid_2().t]}),
    CatalogEntry("one-dwell-cycloid", "one-dwell cycloid, m = 1", "one-dwell", f"{MAKINO} No. 43",
                 _makino(43), ("43",), 43, _tp(43)),
    CatalogEntry("one-dwell-cycloid-m2-3", "one-dwell cycloid, m = 2/3", "one-dwell", f"{MAKINO} No. 44",
                 _makino(44), ("44",), 44, _tp(44)),
    CatalogEntry("one-dwell-modified-trapezoid", "one-dwell modified trapezoid, m = 1", "one-dwell",
                 f"{MAKINO} No. 45", _makino(45), ("45",), 45, _tp(45)),
    CatalogEntry("one-dwell-modified-trapezoid-ferguson", "one-dwell modified trapezoid (Ferguson)",
                 "one-dwell", f"{MAKINO} No. 46", _makino(46), ("46",), 46, _tp(46)),
    CatalogEntry("one-dwell-modified-trapezoid-m2-3", "one-dwell modified trapezoid, m = 2/3", "one-dwell",
                 f"{MAKINO} No. 47", _makino(47), ("47",), 47, _tp(47)),
    CatalogEntry("one-dwell-modified-sine", "one-dwell modified sine, T1 = 1/8", "one-dwell",
                 f"{MAKINO} No. 48", _makino(48), ("48",), 48, _tp(48)),
    CatalogEntry("one-dwell-trapecloid", "one-dwell trapecloid, T1 = 1/8", "one-dwell", f"{MAKINO} No. 49",
                 _makino(49), ("49",), 49, _tp(49)),
    CatalogEntry("no-dwell-simple-harmonic", "no-dwell simple harmonic", "no-dwell", f"{MAKINO} No. 50",
                 _makino(50), ("50",), 50, _tp(50)),
    CatalogEntry("no-dwell-modified-trapezoid", "no-dwell modified trapezoid", "no-dwell", f"{MAKINO} No. 51",
                 _makino(51), ("51",), 51, _tp(51)),
    CatalogEntry("no-dwell-modified-constant-velocity", "no-dwell modified constant velocity", "no-dwell",
                 f"{MAKINO} No. 52", _makino(52), ("52",), 52, _tp(52)),
    CatalogEntry("constant-velocity", "constant velocity", "polynomial", "S = T", _polynomial("constant-velocity"),
                 ("uniform", "straight-line"), None, {"coefficients": list(NAMED_POLYNOMIALS["constant-velocity"])}),
    CatalogEntry("3-4-5", "3-4-5 polynomial", "polynomial", "S = 10T³ − 15T⁴ + 6T⁵", _polynomial("3-4-5"),
                 ("345", "quintic"), None, {"coefficients": list(NAMED_POLYNOMIALS["3-4-5"])}),
    CatalogEntry("4-5-6-7", "4-5-6-7 polynomial", "polynomial", "S = 35T⁴ − 84T⁵ + 70T⁶ − 20T⁷",
                 _polynomial("4-5-6-7"), ("4567", "septic"), None,
                 {"coefficients": list(NAMED_POLYNOMIALS["4-5-6-7"])}),
]

CATALOG: dict[str, CatalogEntry] = {entry.id: entry for entry in _ENTRIES}


def _key(name: str) -> str:
    return re.sub(r"[\s_\-/]+", "", name.strip().lower())


_INDEX: dict[str, str] = {}
for _entry in _ENTRIES:
    for _name in (_entry.id, *_entry.aliases):
        _INDEX[_key(_name)] = _entry.id


def lookup(name: str) -> CatalogEntry:
    """The catalog entry for an id, alias or Makino number (case-insensitive).

    Parameters
    ----------
    name : str
        An entry's id (``MS``), an alias (``modified-sine``) or Makino's number (``26``);
        case, spaces, underscores, hyphens and slashes are ignored.

    Returns
    -------
    CatalogEntry

    Raises
    ------
    UnknownCurveError
        No entry has this name; the error lists up to five close matches.

    References
    ----------
    Makino (1977), table 2 (the classification numbers); INDEXMAN technical guide,
    section 5 (the names MS, MC = MCV50, MCV25, MT, TR).
    """
    key = _key(str(name))
    if key in _INDEX:
        return CATALOG[_INDEX[key]]
    by_key = {_key(n): n for e in _ENTRIES for n in (e.id, *e.aliases)}
    close = [by_key[k] for k in difflib.get_close_matches(key, list(by_key), n=5, cutoff=0.6)]
    close += [n for k, n in by_key.items() if key and len(key) > 2 and key in k and n not in close]
    raise UnknownCurveError(str(name), close[:5])


@lru_cache(maxsize=len(_ENTRIES))
def _build(entry_id: str) -> Curve:
    # a fixed, small key set: one immutable curve per catalog entry
    return CATALOG[entry_id].factory()


def named_curve(name: str) -> Curve:
    """Build (once) the catalog curve with this id, alias or Makino number.

    Parameters
    ----------
    name : str
        As for :func:`lookup`.

    Returns
    -------
    Curve
        The entry's curve; built on first use and shared afterwards (curves are immutable).

    Raises
    ------
    UnknownCurveError
        No entry has this name.

    References
    ----------
    Makino (1977), table 2 and subroutine CURVE; INDEXMAN technical guide, section 5
    (MS = No. 26, MCV50 = No. 27, MCV25, MT = No. 25, TR = No. 35).
    """
    return lookup(name).build()
