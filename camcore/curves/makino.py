"""Makino's named curves: his special curves 1, 2, 4, 36 and the break points of table 2.

References
----------
.. [1] Makino (1977), table 2 (classification numbers), §5.1 (curve 4), §5.2 and eqs.
   (13)-(14) (curve 36, trapecloid II), §5.3 and eqs. (15)-(16) (curves 1 and 2),
   subroutine CURVE.
"""

from __future__ import annotations

from collections.abc import Callable, Collection
from dataclasses import dataclass

from .._checks import finite
from ..errors import InvalidParameterError
from .targets import solve_targets
from .universal import PI, UniversalCurve, universal_curve


# --------------------------------------------------------------------------- special curves
def rapid_feed(z: float) -> UniversalCurve:
    """Makino curve 1: cutting-unit rapid feed, accelerating and decelerating 1 : z.

    T3 = 1/(1+z), T1 = T2 = T3/4, T4 = T3, T5 = T6 = (3+T3)/4, m = 1 (eqs. 15-16,
    CURVE lines 30-41). The end velocity V7 = (1 − z)·V3 is a result.

    Parameters
    ----------
    z : float
        Deceleration period over acceleration period, 0 < z ≤ 1 [-].

    Returns
    -------
    UniversalCurve

    References
    ----------
    Makino (1977), §5.3, eqs. (15)-(16); subroutine CURVE, lines 30-41.
    """
    z = finite("z", z)
    if not 0 < z <= 1:
        raise InvalidParameterError(f"z must satisfy 0 < z ≤ 1 (the feed decelerates to (1 − z)·Vm), got {z!r}.")
    t3 = 1.0 / (1.0 + z)
    t1 = t3 / 4.0
    t5 = (3.0 + t3) / 4.0
    return universal_curve((0.0, t1, t1, t3, t3, t5, t5, 1.0), m=1.0)


def cutting_feed(t4: float) -> UniversalCurve:
    """Makino curve 2: cutting feed, constant velocity V0 then a quarter-sine stop.

    T1 = T2 = T3 = 0, T5 = T6 = T7 = 1; Amp = 0,
    Amm = π / (4(1−T4)²/π + 2(1−T4)T4), V0 = 2(1−T4)·Amm/π (CURVE lines 42-55).

    Parameters
    ----------
    t4 : float
        End of the constant-velocity stretch, 0 ≤ T4 < 1 [-].

    Returns
    -------
    UniversalCurve

    References
    ----------
    Makino (1977), §5.3; subroutine CURVE, lines 42-55.
    """
    t4 = finite("T4", t4)
    if not 0 <= t4 < 1:
        raise InvalidParameterError(f"T4 must satisfy 0 ≤ T4 < 1, got {t4!r}.")
    v0, amm = cutting_feed_ends(t4)
    # the feed stops: S7 = 1 and V7 = 0 by construction
    return UniversalCurve((0.0, 0.0, 0.0, 0.0, t4, 1.0, 1.0, 1.0), amp=0.0, amm=amm, v0=v0, s7=1.0, v7=0.0)


def cutting_feed_ends(t4: float) -> tuple[float, float]:
    """Curve 2's start velocity V0 and its stopping acceleration Amm, without building the curve.

    The curve runs at V0 from T = 0 (A = 0) to T4, then stops by a quarter sine, ending at S = 1,
    V = 0, A = −Amm: these are its ends, so a motion program solving T4 for a continuous
    acceleration (:mod:`camcore.motion.resolve`) needs only them, not a curve per trial T4.

    Parameters
    ----------
    t4 : float
        End of the constant-velocity stretch, 0 ≤ T4 < 1 [-].

    Returns
    -------
    (float, float)
        V0 = 2(1−T4)·Amm/π and Amm = π / (4(1−T4)²/π + 2(1−T4)T4) [-].

    References
    ----------
    Makino (1977), §5.3; subroutine CURVE, lines 42-55.
    """
    amm = PI / (4.0 * (1.0 - t4) ** 2 / PI + 2.0 * (1.0 - t4) * t4)
    return 2.0 * (1.0 - t4) * amm / PI, amm


def modified_constant_velocity(t1: float, t3: float) -> UniversalCurve:
    """Makino curve 4: non-standard modified constant velocity.

    T2 = T1, T4 = 1 − T3, T5 = T6 = 1 − T1; m from equal areas (CURVE lines 56-65).
    Curve 27 (MCV50) is T1 = 1/16, T3 = 1/4; the catalog's MCV25 is T1 = 3/32, T3 = 3/8.

    Parameters
    ----------
    t1 : float
        End of the first quarter-sine, 0 < T1 ≤ T3 [-].
    t3 : float
        Start of the constant velocity, T3 ≤ 0.5 [-].

    Returns
    -------
    UniversalCurve

    References
    ----------
    Makino (1977), §5.1; subroutine CURVE, lines 56-65; INDEXMAN technical guide, section 5
    (MCV25: T1 = 3/32, T3 = 3/8).
    """
    t1 = finite("T1", t1)
    t3 = finite("T3", t3)
    if not 0 < t1 <= t3 <= 0.5:
        raise InvalidParameterError(f"curve 4 needs 0 < T1 ≤ T3 ≤ 0.5, got T1 = {t1!r}, T3 = {t3!r}.")
    return universal_curve((0.0, t1, t1, t3, 1.0 - t3, 1.0 - t1, 1.0 - t1, 1.0))


def trapecloid_2(t1: float = 0.125) -> UniversalCurve:
    """Makino curve 36: trapecloid II (eq. 13).

    T2 = (2 − 6T1 + πT1)/(2 + π), T3 = T4 = T2 + T1, T5 = T6 = 1 − T1, T7 = 1.
    The OCR of eq. (13) reads T6 = T3, which puts T6 before T5; T6 = T5 (section VI
    empty) is the reading that gives the printed eq. (14) values Vm = 1.85,
    Am = 5.22, Jm = 65.6, Qmp = 7.75, Qmm = −5.34 (checked in the tests). The T2
    formula makes Amp = Amm, whatever T5 is, as long as section VI is empty.

    Parameters
    ----------
    t1 : float
        Length T1 of the quarter-sine sections [-] (default 1/8; the caller checks the range,
        see :data:`MAKINO_SPECIAL`).

    Returns
    -------
    UniversalCurve

    References
    ----------
    Makino (1977), §5.2, eqs. (13)-(14) (curve 36, trapecloid II).
    """
    t2 = (2 - 6 * t1 + PI * t1) / (2 + PI)
    t3 = t2 + t1
    return universal_curve((0.0, t1, t2, t3, t3, 1 - t1, 1 - t1, 1.0))


# --------------------------------------------------------------------------- table 2
#: Open break points of table 2, each from the curve's defining condition with
#: V7 = V0 (equal areas: Amp·(C1+C2+C3) = Amm·(C5+C6+C7)) and the stated m.
#: 35 (trapecloid, m = 1), T = (0, 1/8, A, A+1/8, A+1/8, A+1/4, A+1/4, 1):
#:     A − 1/8 + 1/(2π) = (7/4 − 2A)/π  →  A = (10 + π) / (8(2 + π)) = 0.30171…,
#:     the catalog's Tb = (2 − 6Ta + πTa)/(2 + π) with Ta = 1/8 (INDEXMAN TR).
TRAPECLOID_A = (10 + PI) / (8 * (2 + PI))
#: 45 (one-dwell modified trapezoid, m = 1), T = (0, 1/8, B, B+1/8, B+1/8, B+1/4, 1, 1):
#:     B − 1/8 + 1/(2π) = 1/(4π) + 3/4 − B  →  B = 7/16 − 1/(8π) = 0.39771…
ONE_DWELL_MT_B = 7 / 16 - 1 / (8 * PI)
#: 47 (one-dwell modified trapezoid, m = 2/3), T = (0, 1/8, C, C+1/8, C+1/8, C+5/24, 1, 1):
#:     C − 1/8 + 1/(2π) = (2/3)(1/(6π) + 19/24 − C)  →  C = 47/120 − 7/(30π) = 0.31738…
ONE_DWELL_MT_C = 47 / 120 - 7 / (30 * PI)
#: 49 (one-dwell trapecloid, T1 = 1/8, m = 1 as every trapecloid),
#:     T = (0, 1/8, D, D+1/8, D+1/8, 1, 1, 1): C5 = 2(7/8 − D)/π gives the same
#:     equation as curve 35, so D = A.
ONE_DWELL_TR_D = TRAPECLOID_A

#: Makino table-2 break points T0..T7 (T0 = 0, T7 = 1). m is the stated ratio; None
#: means m comes from equal areas (V7 = V0). Source: Makino's characteristic table (Makino
#: (1976)) as quoted by a public implementation (docs/sources.md), open values derived above.
MAKINO_BREAK_POINTS: dict[int, tuple[tuple[float, ...], float | None]] = {
    11: ((0, 0, 0.5, 0.5, 0.5, 0.5, 1, 1), None),
    12: ((0, 0, 0, 0.5, 0.5, 1, 1, 1), None),
    22: ((0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1), None),
    25: ((0, 0.125, 0.375, 0.5, 0.5, 0.625, 0.875, 1), None),
    26: ((0, 0.125, 0.125, 0.5, 0.5, 0.875, 0.875, 1), None),
    27: ((0, 1 / 16, 1 / 16, 0.25, 0.75, 15 / 16, 15 / 16, 1), None),
    33: ((0, 0.2, 0.2, 0.4, 0.4, 0.7, 0.7, 1), None),
    34: ((0, 0.1, 0.3, 0.4, 0.4, 0.55, 0.85, 1), None),
    35: ((0, 0.125, TRAPECLOID_A, TRAPECLOID_A + 0.125, TRAPECLOID_A + 0.125,
          TRAPECLOID_A + 0.25, TRAPECLOID_A + 0.25, 1), None),
    43: ((0, 0.25, 0.25, 0.5, 0.5, 1, 1, 1), None),
    44: ((0, 0.2, 0.2, 0.4, 0.4, 1, 1, 1), None),
    45: ((0, 0.125, ONE_DWELL_MT_B, ONE_DWELL_MT_B + 0.125, ONE_DWELL_MT_B + 0.125,
          ONE_DWELL_MT_B + 0.25, 1, 1), None),
    # 46 (Ferguson): the copy reads T5 = .675, flagged doubtful; every transition of the
    # modified-trapezoid family is a 1/8 quarter wave, so T5 = T4 + 1/8 = .625 is used.
    46: ((0, 0.125, 0.375, 0.5, 0.5, 0.625, 1, 1), None),
    47: ((0, 0.125, ONE_DWELL_MT_C, ONE_DWELL_MT_C + 0.125, ONE_DWELL_MT_C + 0.125,
          ONE_DWELL_MT_C + 5 / 24, 1, 1), None),
    48: ((0, 0.125, 0.125, 0.5, 0.5, 1, 1, 1), None),
    49: ((0, 0.125, ONE_DWELL_TR_D, ONE_DWELL_TR_D + 0.125, ONE_DWELL_TR_D + 0.125, 1, 1, 1), None),
    # 50, no-dwell simple harmonic, is not in the copy: S = (1 − cos πT)/2 starts at
    # A = +Amp and ends at A = −Amm with V = 0 at both ends, which is exactly these
    # break points (the same law as 12; Makino lists it again in the no-dwell class).
    50: ((0, 0, 0, 0.5, 0.5, 1, 1, 1), None),
    51: ((0, 0, 0.25, 0.5, 0.5, 0.75, 1, 1), None),
    52: ((0, 0, 0, 0.25, 0.75, 1, 1, 1), None),
}


@dataclass(frozen=True)
class MakinoSpecial:
    """One of Makino's special (parametric) curves: its parameters and its builder."""

    number: int
    name: str
    parameters: tuple[str, ...]
    optional: tuple[str, ...]
    build: Callable[..., UniversalCurve]
    rule: str


def _trapecloid_2(t1: float | None = None) -> UniversalCurve:
    return trapecloid_2(0.125 if t1 is None else _check_t1_36(t1))


#: Makino's special curves by number (1977, §5.1-5.3, eq. 13): the one place that
#: knows their parameters, used by :func:`makino_curve` and by the service's spec.
MAKINO_SPECIAL: dict[int, MakinoSpecial] = {
    1: MakinoSpecial(1, "rapid feed", ("z",), (), rapid_feed, "0 < z ≤ 1"),
    2: MakinoSpecial(2, "cutting feed", ("t4",), (), cutting_feed, "0 ≤ T4 < 1"),
    4: MakinoSpecial(4, "non-standard modified constant velocity", ("t1", "t3"), (), modified_constant_velocity,
                     "0 < T1 ≤ T3 ≤ 0.5"),
    36: MakinoSpecial(36, "trapecloid II", (), ("t1",), _trapecloid_2, "optional T1, default 1/8"),
}


def makino_curve(number: int, **params: float | None) -> UniversalCurve:
    """Makino's curve by its classification number (table 2 and special curves).

    Parameters
    ----------
    number : int
        Makino's classification number [-]: a table-2 curve (no parameters) or a special
        curve of :data:`MAKINO_SPECIAL`: 1 (``z``), 2 (``t4``), 4 (``t1``, ``t3``),
        36 (``t1``, default 1/8).
    **params : float or None
        The special curve's parameters [-] (dimensionless times and ratios); None means not given.
        Curve 4 may give the target ``vm`` (and ``t1_over_t3``, default 1/4) instead of
        ``t1``, ``t3``; curve 1 ``v_ratio`` (= V7/V3) instead of ``z``
        (:func:`camcore.curves.targets.solve_targets`).

    Returns
    -------
    UniversalCurve

    References
    ----------
    Makino (1977), table 2, eqs. (13)-(16), subroutine CURVE; §5.1 (curve 4 from Vm).
    """
    params = solve_targets(number, params)
    given = {k for k, v in params.items() if v is not None}
    check_makino_parameters(number, given)
    special = MAKINO_SPECIAL.get(number)
    if special is not None:
        return special.build(**{k: params[k] for k in given})
    pts, m = MAKINO_BREAK_POINTS[number]
    return universal_curve(pts, m=m)


def check_makino_parameters(number: int, given: Collection[str], solvable: Collection[str] = ()) -> None:
    """Makino's curve ``number`` exists and is given exactly its own parameters.

    Parameters
    ----------
    number : int
        Makino's classification number [-].
    given : collection of str
        The names of the parameters given.
    solvable : collection of str
        Parameters that may be left out, because the caller solves them (a motion program
        solves curve 2's t4).

    Raises
    ------
    InvalidParameterError
        A parameter the curve does not take, one it needs and was not given, or a number
        Makino does not define.

    References
    ----------
    Makino (1977), table 2 and §5 (the special curves 1, 2, 4, 36 and their parameters).
    """
    special = MAKINO_SPECIAL.get(number)
    allowed = set(special.parameters + special.optional) if special else set()
    extra = set(given) - allowed
    if extra:
        raise InvalidParameterError(
            f"Makino curve {number} takes no parameter {', '.join(sorted(extra))}"
            + (f"; it takes {', '.join(sorted(allowed))}." if allowed else ".")
        )
    if special is not None:
        missing = set(special.parameters) - set(given) - set(solvable)
        if missing:
            raise InvalidParameterError(f"Makino curve {number} needs {', '.join(sorted(missing))}.")
    elif number not in MAKINO_BREAK_POINTS:
        known = sorted([*MAKINO_SPECIAL, *MAKINO_BREAK_POINTS])
        raise InvalidParameterError(
            f"Makino curve number {number} is not one of {', '.join(map(str, known))}."
        )


def _check_t1_36(t1: float) -> float:
    t1 = finite("T1", t1)
    t2 = (2 - 6 * t1 + PI * t1) / (2 + PI)
    if not (0 < t1 and t2 >= t1 and t2 + t1 <= 1 - t1):
        raise InvalidParameterError(f"trapecloid II needs 0 < T1 ≤ 0.27 or so (T1 ≤ T2, T3 ≤ 1 − T1), got T1 = {t1!r}.")
    return t1

