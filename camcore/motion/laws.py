"""A segment's law in real units, and what a program may leave out of a law.

A law runs normalised from N = 0 to 1 over T = 0 … 1 of its segment:
N(T) = (S(τ) − S0)/(S7 − S0), τ = T0 + (T7 − T0)·T, so that a return (the rise played
backwards, :class:`camcore.curves.reverse.ReturnCurve`) gives N(T) = 1 − S(1 − T). On a
segment of span β [deg] from position s_a, a law placed with gain g gives

    s(x) = s_a + g·(S(τ) − S0),   dᵏs/dxᵏ = g·((T7 − T0)/β)ᵏ·dᵏS/dτᵏ,

with g = h/(S7 − S0) for a stroke h. A polynomial matched to its neighbours is built in
these units directly (g = h, or a reference length when h = 0: an out-and-back move).

What a program may leave out (the law's *role*):

- ``polynomial`` without ``name`` and without ``start`` and/or ``end``: the omitted end
  meets its neighbour (s, v, a; j too with ``match: jerk``) — :mod:`camcore.motion.polynomials`;
- ``universal`` without ``v0`` (or ``v7``, when ``m`` is omitted too): that end takes its
  neighbour's velocity (for a return, ``v7`` is the segment's start and ``v0`` its end);
- ``makino`` curve 2 without ``t4`` (:data:`SOLVED_PARAMETERS`): T4 makes the acceleration
  continuous at its end (Makino 1977, §5.3).

References
----------
.. [1] Makino (1977), eqs. (1)-(12), subroutine CURVE (INIT = 2) and §5.3.
.. [2] VDI 2143 Blatt 1 (1980): dimensioned motion s = h·N(x/β), v = h/β·N′, a = h/β²·N″.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..curves.base import FloatArray
from ..curves.catalog import lookup
from ..curves.curve import Curve
from ..curves.universal import check_break_points
from ..errors import InvalidParameterError
from .spec import Law

#: a function that builds the curve of a law (the service passes its cached builder)
Build = Callable[[Law], Curve]

#: Makino curve numbers whose parameter a program may leave out to be solved, and that
#: parameter's range [lo, hi) (Makino 1977, §5.3: curve 2's T4, 0 ≤ T4 < 1)
SOLVED_PARAMETERS: dict[int, tuple[str, float, float]] = {2: ("t4", 0.0, 1.0)}

#: the segment's conditions at an end, by derivative order: 1 v, 2 a, 3 j
ORDER_KEYS = {1: "v", 2: "a", 3: "j"}


@dataclass(frozen=True)
class PlacedLaw:
    """A law on its segment, in real units (module notes): s = s_a + gain·(S(τ) − S0).

    ``curve`` None is a dwell at s_a. ``x_a`` and ``span`` are the segment's start and
    span [deg]; ``s_a`` its start position and ``gain`` the law's scale [mm or deg].
    """

    curve: Curve | None
    x_a: float
    span: float
    s_a: float
    gain: float

    @property
    def rate(self) -> float:
        """dτ/dx: the law's time per degree of master angle [1/deg]."""
        c = self.curve
        return 0.0 if c is None else (c.t_end - c.t_start) / self.span

    def at(self, u: ArrayLike, order: int = 3) -> list[FloatArray]:
        """s and its derivatives over x up to ``order`` at fractions u ∈ [0, 1] of the segment.

        At u = 0 the law's first piece answers (right limit), at u = 1 its last (left
        limit): the values on each side of a join.
        """
        u_arr = np.asarray(u, dtype=np.float64)
        c = self.curve
        if c is None:
            return [np.full(u_arr.shape, self.s_a)] + [np.zeros(u_arr.shape) for _ in range(order)]
        # clipped: T7 − T0 + T0 may round past T7, where the curve runs on at constant V7
        tau = np.clip(c.t_start + (c.t_end - c.t_start) * u_arr, c.t_start, c.t_end)
        vals = c.derivatives(tau, order)
        rate = self.rate
        out = [self.s_a + self.gain * (vals[0] - c.s_start)]
        out += [self.gain * rate**k * vals[k] for k in range(1, order + 1)]
        return out

    def ends(self) -> tuple[list[float], list[float]]:
        """[s, v, a, j] at the start (right limit) and at the end (left limit) [mm or deg per deg^k]."""
        vals = self.at(np.array([0.0, 1.0]), 3)
        return [float(v[0]) for v in vals], [float(v[1]) for v in vals]


def normalised_ends(curve: Curve) -> tuple[list[float], list[float]]:
    """N and its derivatives over T at both ends of a law normalised to run from 0 to 1.

    Parameters
    ----------
    curve : Curve
        The law.

    Returns
    -------
    (list of float, list of float)
        [N, N′, N″, N‴] at T = 0 (first piece) and at T = 1 (last piece) [-].

    Raises
    ------
    InvalidParameterError
        The law ends where it starts (S7 = S0): it has no stroke to normalise.

    References
    ----------
    VDI 2143 Blatt 1 (1980): the normalised law N(T), 0 ≤ T ≤ 1, N(0) = 0, N(1) = 1.
    """
    rise = curve.s_end - curve.s_start
    if rise == 0:
        raise InvalidParameterError("the law ends where it starts (S7 = S0): it has no stroke to scale to the "
                                    "segment's, so its own end conditions contradict the segment's.")
    span = curve.t_end - curve.t_start
    first = curve.eval_pieces(np.array([curve.t_start]), np.array([0]), 3)
    last = curve.eval_pieces(np.array([curve.t_end]), np.array([curve.n_pieces - 1]), 3)
    start = [0.0] + [float(first[k][0]) * span**k / rise for k in range(1, 4)]
    end = [1.0] + [float(last[k][0]) * span**k / rise for k in range(1, 4)]
    return start, end


def law_role(law: Law) -> str:
    """What a program does with a law: ``fixed`` (as given), ``polynomial`` or ``universal``
    (matched to its neighbours), ``solved`` (Makino curve 2 without T4).

    Parameters
    ----------
    law : Law
        The segment's law.

    Returns
    -------
    str
        The role.

    References
    ----------
    Makino (1977), §5.3 (curve 2's T4 chosen for continuity); VDI 2143 Blatt 1 (1980)
    (transitions meeting the neighbouring motion tasks).
    """
    p = law.parameters
    if law.kind == "polynomial" and p.get("name") is None and (p.get("start") is None or p.get("end") is None):
        return "polynomial"
    if law.kind == "universal" and (p.get("v0") is None or (p.get("v7") is None and p.get("m") is None)):
        return "universal"
    number = p.get("number")
    if law.kind == "makino" and number in SOLVED_PARAMETERS and p.get(SOLVED_PARAMETERS[int(number)][0]) is None:
        return "solved"
    return "fixed"


def matched_sides(law: Law) -> tuple[bool, bool]:
    """Whether the segment's start and its end take their conditions from the neighbours.

    Parameters
    ----------
    law : Law
        The segment's law.

    Returns
    -------
    (bool, bool)
        (start, end): a polynomial's omitted ``start``/``end``; a universal curve's omitted
        ``v0``/``v7`` (``v7`` only when ``m`` is omitted too), swapped for a return.

    References
    ----------
    Makino (1977), §5.3 and subroutine CURVE (V0, V7 free end velocities; INIT = 2).
    """
    p = law.parameters
    role = law_role(law)
    if role == "polynomial":
        return p.get("start") is None, p.get("end") is None
    if role == "universal":
        first, last = p.get("v0") is None, p.get("v7") is None and p.get("m") is None
        return (first, last) if law.direction == "rise" else (last, first)
    return False, False


def law_id(law: Law | None) -> str:
    """The id a resolved segment reports for its law.

    Parameters
    ----------
    law : Law or None
        The law (None: a dwell).

    Returns
    -------
    str
        ``dwell``; a catalog curve's id (``cycloid``, ``MS``); ``makino 2``; ``universal``;
        a polynomial's name or ``polynomial``; ``bezier``; ``points``.

    References
    ----------
    Makino (1977), table 2 (classification numbers); INDEXMAN technical guide, section 5.
    """
    if law is None:
        return "dwell"
    p = law.parameters
    if law.kind == "named":
        return lookup(str(p.get("name"))).id
    if law.kind == "makino":
        return f"makino {p.get('number')}"
    if law.kind == "polynomial" and p.get("name") is not None:
        return str(p["name"])
    return law.kind


def universal_matched(law: Law, stroke: float, span_deg: float, v_start: float | None,
                      v_end: float | None) -> Law:
    """A universal law with its omitted end velocities taken from the neighbours.

    Parameters
    ----------
    law : Law
        The universal law (``v0`` and/or ``v7`` omitted).
    stroke : float
        The segment's stroke h [mm or deg] (not 0).
    span_deg : float
        The segment's span β [deg].
    v_start, v_end : float or None
        The neighbours' velocities at the segment's start and end [mm/deg or deg/deg]
        (None where the side is not matched).

    Returns
    -------
    Law
        The law with ``v0``/``v7`` set: V = v·β/h·(S7 − S0)/(T7 − T0), the real velocity in the
        law's own units (``v7`` at the start of a return, ``v0`` at its end).

    Raises
    ------
    InvalidParameterError
        A zero stroke (nothing to scale a velocity by), or break points out of order.

    References
    ----------
    Makino (1977), eqs. (1)-(11): V0, V7 of the universal curve; §5.3 (curves split at a
    joint of non-zero velocity).
    """
    p = dict(law.parameters)
    if stroke == 0:
        raise InvalidParameterError("a universal curve with omitted v0/v7 needs a stroke to scale its neighbours' "
                                    "velocities by; this segment's stroke is 0.")
    t = check_break_points(p["t"])
    s0 = float(p["s0"]) if p.get("s0") is not None else 0.0
    s7 = float(p["s7"]) if p.get("s7") is not None else 1.0
    per_real = span_deg / stroke * (s7 - s0) / (t[7] - t[0])
    first, last = ("v0", "v7") if law.direction == "rise" else ("v7", "v0")
    if v_start is not None:
        p[first] = v_start * per_real
    if v_end is not None:
        p[last] = v_end * per_real
    if not all(math.isfinite(float(p[k])) for k in ("v0", "v7") if p.get(k) is not None):
        raise InvalidParameterError("the neighbours' velocities scaled to this universal curve are not finite.")
    return Law(law.kind, p, law.direction)


def with_parameter(law: Law, name: str, value: float) -> Law:
    """The law with one parameter set (a solved T4).

    Parameters
    ----------
    law : Law
        The law.
    name : str
        The parameter.
    value : float
        Its value [-].

    Returns
    -------
    Law

    References
    ----------
    Makino (1977), §5.3 (T4 of curve 2).
    """
    params: dict[str, Any] = dict(law.parameters)
    params[name] = value
    return Law(law.kind, params, law.direction)


def given_conditions(law: Law, stroke: float, span_deg: float) -> tuple[dict[int, float] | None, dict[int, float] | None]:
    """The conditions a half-matched polynomial gives itself, in real units.

    Parameters
    ----------
    law : Law
        A polynomial with ``start`` or ``end`` given as normalised conditions ``{s, v, a, j}``
        (the law runs N = 0 → 1: ``s`` is 0 at the start and 1 at the end).
    stroke : float
        The segment's stroke h [mm or deg].
    span_deg : float
        The segment's span β [deg].

    Returns
    -------
    (dict or None, dict or None)
        Start and end conditions by derivative order (1 v, 2 a, 3 j) [mm or deg per deg^k]:
        dᵏs/dxᵏ = h/βᵏ·Nᵏ; None where the end is matched.

    Raises
    ------
    InvalidParameterError
        A given ``s`` other than 0 (start) or 1 (end): it contradicts the segment's own
        positions; or a zero stroke with given derivatives (nothing to scale them by).

    References
    ----------
    VDI 2143 Blatt 1 (1980): dimensioned motion from the normalised law.
    """
    out: list[dict[int, float] | None] = []
    for side, target in (("start", 0.0), ("end", 1.0)):
        cond: Mapping[str, Any] | None = law.parameters.get(side)
        if cond is None:
            out.append(None)
            continue
        if cond.get("s") is not None and float(cond["s"]) != target:
            raise InvalidParameterError(
                f"the polynomial's {side} gives s = {cond['s']!r}, but a law in a program runs from s = 0 to 1 (the "
                "positions come from the program): its own end conditions contradict the segment's.")
        given = {k: float(cond[key]) for k, key in ORDER_KEYS.items() if cond.get(key) is not None}
        if given and stroke == 0:
            raise InvalidParameterError(
                f"the polynomial's {side} conditions are normalised to the stroke, which is 0 here; omit them to "
                "match the neighbour, or give the segment a stroke.")
        out.append({k: stroke / span_deg**k * value for k, value in given.items()})
    return out[0], out[1]
