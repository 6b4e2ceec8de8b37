"""Resolving a motion program: positions, solved strokes, matched and solved laws.

What depends on what, and in which order it is resolved:

1. Positions. A segment starts where the previous one ends (``start`` for the first); its
   stroke is ``stroke``, ``to`` − start, 0 for a dwell, or solved (``to: null``).
2. A solved stroke (``to: null``) makes the velocity continuous at the segment's start:
   h·N′(0)/β = v at the end of the previous segment, so that segment must be resolved
   first and the law's N′(0) must not be 0.
3. Makino curve 2 without ``t4``: T4 makes the acceleration continuous at its end,
   h(T4)·N″(1; T4)/β² = a at the start of the next segment, whose stroke may depend on
   h (an absolute ``to``). With ``to: null`` as well, h(T4) = β·v_prev/N′(0; T4): Makino's
   two conditions, velocity at the start and acceleration at the end (1977, §5.3). T4 is
   found by scanning [0, 1) and refining each sign change (Illinois); exactly one root is
   accepted.
4. A universal curve with omitted ``v0``/``v7`` takes the velocity of its resolved
   neighbour; a matched polynomial takes s, v, a (and j) of its resolved neighbour, and
   consecutive matched polynomials are solved together (:mod:`camcore.motion.polynomials`).

Each step runs as soon as what it needs is known; the passes repeat until every segment
is placed. A join where *both* sides take their conditions from the other (a matched end
next to a solved stroke, a solved T4 next to a matched start, …) has no rule and is refused
before anything is computed; so are dependencies that run in a circle (a solved stroke of
the first segment that needs the end velocity of the last, whose position needs that
stroke). Every refusal is an :class:`InvalidParameterError` naming the segment.

References
----------
.. [1] Makino (1977), §5.3, Fig. 6-9: the cutting-unit feed cam (curves 1, 2 and 48).
.. [2] VDI 2143 Blatt 1 (1980): motion tasks at the joins (rest, constant velocity,
   reversal, motion) and transitions that meet them.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._solvers import scan_roots
from ..curves.curve import Curve
from ..curves.kinds import build_curve
from ..curves.makino import cutting_feed_ends
from ..curves.universal import MIN_SECTION
from ..errors import CamError, InvalidParameterError
from ._segment import Segment, describe_adaptive
from .laws import (
    ORDER_KEYS,
    SOLVED_PARAMETERS,
    Build,
    PlacedLaw,
    given_conditions,
    law_id,
    law_role,
    matched_sides,
    normalised_ends,
    universal_matched,
    with_parameter,
)
from .polynomials import Member, matched_polynomial, solve_chain
from .program import MotionProgram
from .results import ResolvedSegment
from .spec import CYCLOID, MATCH_ORDERS, SOLVE, MotionSpec, check_program

#: T4 is scanned on k/128 (k = 0 … 127) and 1 − 2⁻ᵏ (k = 8 … 29): curve 2's end acceleration
#: −Amm(T4) grows without bound as T4 → 1, so the fine steps near 1 keep up with it; they stop
#: at 1 − 2⁻²⁹ ≈ 1 − 1.9e-9 because the universal curve merges sections shorter than
#: MIN_SECTION = 1e-9 (camcore.curves.universal), which would remove curve 2's last section. The two
#: sets share no value (127/128 < 1 − 2⁻⁸), so sorting makes the grid (np.unique would import numpy.ma
#: at start-up: ~20 ms)
T4_GRID = np.sort(np.concatenate([np.arange(128) / 128.0, 1.0 - 2.0 ** -np.arange(8, 30)]))


@contextmanager
def _at_segment(index: int, *field: str) -> Iterator[None]:
    """Errors raised inside are about segment ``index`` (and its ``field``): the message
    names the segment, the error's field is prefixed with it."""
    try:
        yield
    except CamError as exc:
        if exc.field[:1] != ("segments",):
            exc.field = ("segments", index, *field, *exc.field)
        text = str(exc)
        if not text.startswith("segments["):
            exc.args = (f"segments[{index}]: {text}",)
        raise


def resolve_motion(spec: MotionSpec, build: Build | None = None,
                   limits: Mapping[str, int] | None = None) -> MotionProgram:
    """Resolve a motion program: every stroke, solved parameter and matched law.

    Parameters
    ----------
    spec : MotionSpec
        The program.
    build : callable, optional
        Builds the curve of a law given in full (the service passes its cached builder);
        default :func:`camcore.curves.kinds.build_curve`. Laws that depend on the program
        (matched, solved) are always built afresh.
    limits : mapping, optional
        Size limits handed to :func:`build_curve` (``max_bezier_degree``, ``max_curve_points``).

    Returns
    -------
    MotionProgram

    Raises
    ------
    InvalidParameterError
        A broken rule or an unsolvable condition, naming the segment (``field`` starts with
        ``("segments", index)``).

    References
    ----------
    Makino (1977), §5.3 (T4 and the cutting stroke chosen for continuity); VDI 2143 Blatt 1
    (1980) (matching the neighbouring motion tasks).
    """
    check_program(spec)

    def fresh(law: Any) -> Curve:
        return build_curve(law.kind, law.parameters, law.direction, limits)

    return _Resolver(spec, build or fresh, fresh).run()


class _Resolver:
    def __init__(self, spec: MotionSpec, build: Build, fresh: Build):
        self.spec = spec
        self.fresh = fresh
        n = len(spec.segments)
        period = float(spec.period_deg)
        starts = np.concatenate([[0.0], np.cumsum([float(s.span_deg) for s in spec.segments])[:-1]])
        self.segs = []
        for i, segment in enumerate(spec.segments):
            end = period if i == n - 1 else float(starts[i + 1])
            law = None if segment.type == "dwell" else (segment.law or CYCLOID)
            if not end > float(starts[i]):
                raise InvalidParameterError(
                    f"segments[{i}]: span_deg = {segment.span_deg!r} vanishes against the master angle where the "
                    f"segment starts ({float(starts[i])!r}°); make it longer.", field=("segments", i, "span_deg"))
            self.segs.append(Segment(i, segment, law, float(starts[i]), end - float(starts[i])))
        for seg in self.segs:
            with _at_segment(seg.index):
                self._prepare(seg, build)
        for seg in self.segs:
            self._check_join(seg.index)
        self.chains = self._chains()
        self.chain_done = [False] * len(self.chains)

    # ---------------------------------------------------------------- preparation
    def _prepare(self, seg: Segment, build: Build) -> None:
        law = seg.law
        if law is None:
            seg.role = "dwell"
            return
        seg.role = law_role(law)
        seg.matched = matched_sides(law)
        if seg.role in ("polynomial", "solved") and law.direction != "rise":
            what = "a polynomial with omitted start/end takes its ends from the segment's own ends" \
                if seg.role == "polynomial" else "curve 2's T4 is solved for its stop at the segment's end"
            raise InvalidParameterError(f"{what}, so give it direction 'rise' (or give the law in full).",
                                        field=("curve", "direction"))
        if seg.segment.match != "acceleration" and seg.role != "polynomial":
            raise InvalidParameterError("match applies to a polynomial law with omitted start or end.",
                                        field=("match",))
        if seg.segment.to == SOLVE and seg.role not in ("fixed", "solved"):
            raise InvalidParameterError(
                "to: null solves the stroke from the law's start velocity, so the law must be given in full (not "
                "matched to its neighbours); give to or stroke.", field=("to",))
        if seg.role == "fixed":
            with _at_segment(seg.index, "curve"):
                seg.curve = build(law)
                seg.normal = normalised_ends(seg.curve)

    def _check_join(self, k: int) -> None:
        """Refuse a join where both sides take their conditions from the other (except two
        matched polynomials: a spline)."""
        n = len(self.segs)
        left, right = self.segs[(k - 1) % n], self.segs[k]
        left_kind = left.adaptive_end()
        right_kind = right.adaptive_start()
        if left_kind and right_kind and not (left_kind == right_kind == "polynomial"):
            raise InvalidParameterError(
                f"segments[{k}]: its start and the end of segments[{left.index}] each take their conditions from "
                f"the other ({describe_adaptive(right_kind)}; {describe_adaptive(left_kind)}), so neither is "
                "known; give one of them explicit conditions.", field=("segments", k))

    def _chains(self) -> list[list[int]]:
        """Consecutive matched polynomials joined end to start, each chain in order."""
        n = len(self.segs)

        def free(k: int) -> bool:  # join k, between segment k − 1 and k, has two matched polynomial sides
            left, right = self.segs[(k - 1) % n], self.segs[k]
            return left.role == right.role == "polynomial" and left.matched[1] and right.matched[0]

        polys = [s.index for s in self.segs if s.role == "polynomial"]
        if len(polys) == n and all(free(k) for k in range(n)):
            return [list(range(n))]
        chains = []
        for i in polys:
            if free(i):
                continue
            chain = [i]
            while free((chain[-1] + 1) % n):
                chain.append((chain[-1] + 1) % n)
            chains.append(chain)
        return chains

    # ---------------------------------------------------------------- passes
    def run(self) -> MotionProgram:
        while not all(seg.placed is not None for seg in self.segs):
            progress = False
            for seg in self.segs:
                with _at_segment(seg.index):
                    progress |= self._advance(seg)
            for c, chain in enumerate(self.chains):
                if not self.chain_done[c]:
                    with _at_segment(chain[0]):
                        progress |= self._advance_chain(c, chain)
            if not progress:
                raise self._stuck()
        placed = [seg.placed for seg in self.segs]
        assert all(p is not None for p in placed)
        return MotionProgram([p for p in placed if p is not None], [self._result(seg) for seg in self.segs],
                             self.spec.period_deg, self.spec.start, self.spec.unit)

    def _prev(self, seg: Segment) -> Segment:
        return self.segs[(seg.index - 1) % len(self.segs)]

    def _next(self, seg: Segment) -> Segment:
        return self.segs[(seg.index + 1) % len(self.segs)]

    def _advance(self, seg: Segment) -> bool:
        changed = False
        if seg.s_a is None:
            prev = self._prev(seg)
            if seg.index == 0:
                seg.s_a = float(self.spec.start)
            elif prev.s_a is not None and prev.stroke is not None:
                seg.s_a = prev.s_a + prev.stroke
            else:
                seg.waiting = f"the end position of segments[{prev.index}] for its start"
            changed |= seg.s_a is not None
        if seg.stroke is None:
            seg.stroke = self._stroke(seg)
            changed |= seg.stroke is not None
        if seg.placed is None and seg.role != "polynomial":
            changed |= self._place(seg)
        return changed

    def _stroke(self, seg: Segment) -> float | None:
        to, stroke = seg.segment.to, seg.segment.stroke
        if seg.role == "dwell":
            return 0.0
        if stroke is not None:
            return float(stroke)
        if to != SOLVE:
            assert to is not None  # check_segment: a move has to or stroke
            return None if seg.s_a is None else float(to) - seg.s_a
        if seg.role == "solved":
            return None  # with T4 (_solve_parameter)
        prev = self._prev(seg)
        if prev.placed is None:
            seg.waiting = f"the end velocity of segments[{prev.index}] for its solved stroke (to: null)"
            return None
        return self._solved_stroke(seg, seg.normal[0][1], prev.placed.ends()[1][1], prev.index)

    @staticmethod
    def _solved_stroke(seg: Segment, slope: float, v_prev: float, prev: int) -> float:
        """h with h·N′(0)/β = v_prev: the velocity continuous at the segment's start."""
        if slope == 0:
            raise InvalidParameterError(
                "to: null solves the stroke that makes the velocity continuous at the start, but this law starts at "
                "rest (N′(0) = 0), so no stroke does; give to or stroke.", field=("to",))
        if v_prev == 0:
            raise InvalidParameterError(
                f"to: null solves the stroke that makes the velocity continuous at the start, but segments[{prev}] "
                "ends at rest, so that stroke is 0; give to or stroke.", field=("to",))
        return v_prev * seg.span / slope

    def _check_stroke(self, seg: Segment, stroke: float) -> None:
        """A law that runs from 0 to 1 needs a stroke to scale it by."""
        assert seg.s_a is not None
        if abs(stroke) <= 16 * np.finfo(float).eps * max(abs(seg.s_a), abs(seg.s_a + stroke)):
            raise InvalidParameterError(
                f"a stroke of 0 with the law {law_id(seg.law)!r}: a law runs from 0 to 1 and needs a stroke; make the "
                "segment a dwell (type: dwell), or give it a stroke.", field=("to",) if seg.segment.to is not None
                else ("stroke",))

    def _place(self, seg: Segment) -> bool:
        if seg.s_a is None:
            return False
        if seg.role == "dwell":
            seg.placed = PlacedLaw(None, seg.x_a, seg.span, seg.s_a, 0.0)
            return True
        if seg.role == "solved":
            return self._solve_parameter(seg)
        if seg.stroke is None:
            return False
        self._check_stroke(seg, seg.stroke)
        if seg.role == "universal":
            prev, nxt = self._prev(seg), self._next(seg)
            needs = [other for other, side in ((prev, 0), (nxt, 1)) if seg.matched[side] and other.placed is None]
            if needs:
                seg.waiting = f"the velocity of segments[{needs[0].index}] for its matched end"
                return False
            v_start = self._ends(prev)[1][1] if seg.matched[0] else None
            v_end = self._ends(nxt)[0][1] if seg.matched[1] else None
            assert seg.law is not None
            law = universal_matched(seg.law, seg.stroke, seg.span, v_start, v_end)
            with _at_segment(seg.index, "curve"):
                seg.curve = self.fresh(law)
                seg.normal = normalised_ends(seg.curve)
            seg.solved.update({k: float(law.parameters[k]) for k in ("v0", "v7")
                               if law.parameters.get(k) is not None and seg.law.parameters.get(k) is None})
        assert seg.curve is not None
        seg.placed = PlacedLaw(seg.curve, seg.x_a, seg.span, seg.s_a, seg.stroke / (seg.curve.s_end - seg.curve.s_start))
        return True

    def _ends(self, seg: Segment) -> tuple[list[float], list[float]]:
        assert seg.placed is not None
        return seg.placed.ends()

    # ---------------------------------------------------------------- Makino's T4
    def _solve_parameter(self, seg: Segment) -> bool:
        """T4 of curve 2: the acceleration continuous at its end (Makino 1977, §5.3)."""
        assert seg.law is not None and seg.s_a is not None
        s_a = seg.s_a
        name, lo, hi = SOLVED_PARAMETERS[int(seg.law.parameters["number"])]
        prev, nxt = self._prev(seg), self._next(seg)
        if nxt is seg:
            raise InvalidParameterError(f"{name} of curve 2 makes the acceleration continuous at its end, where the "
                                        "program has no other segment; give it.", field=("curve", name))
        solving = seg.segment.to == SOLVE
        if solving and prev.placed is None:
            seg.waiting = f"the end velocity of segments[{prev.index}] for its solved stroke (to: null)"
            return False
        v_prev = prev.placed.ends()[1][1] if solving and prev.placed is not None else 0.0
        next_start = self._next_start(nxt, s_a)
        if next_start is None:
            seg.waiting = f"the start acceleration of segments[{nxt.index}] for its {name}"
            return False

        with _at_segment(seg.index, "curve"):  # a law that cannot be built at all says why (not "no root")
            self.fresh(with_parameter(seg.law, name, lo))

        def trial(value: float) -> tuple[float, float, float, float]:
            """(residual, stroke, end acceleration, next start acceleration) at a trial value, from the law's
            ends in closed form (:func:`cutting_feed_ends`: no curve built per trial). They equal the built
            curve's own ends (its N′(0) and N″(1)) bit for bit (tests/camcore/curves/test_makino.py) but where a
            piece of the curve is shorter than MIN_SECTION and merged into its neighbour (T4 within it of 0 or
            1): there the curve is built, as before."""
            if value < MIN_SECTION or 1.0 - value < MIN_SECTION:
                start, end = normalised_ends(self.fresh(with_parameter(seg.law, name, value)))  # type: ignore[arg-type]
                v_start, a_end_normal = start[1], end[2]
            else:
                v_start, amm = cutting_feed_ends(value)
                a_end_normal = -amm
            if solving:
                stroke = self._solved_stroke(seg, v_start, v_prev, prev.index)
            else:
                stroke = seg.stroke if seg.stroke is not None else float(seg.segment.to) - s_a  # type: ignore[arg-type]
            a_end, a_next = stroke * a_end_normal / seg.span**2, next_start(stroke)
            return a_end - a_next, stroke, a_end, a_next

        def residual(values: NDArray[np.float64]) -> NDArray[np.float64]:
            out = np.empty(values.shape)
            for i, value in enumerate(values.tolist()):
                try:
                    out[i] = trial(value)[0]
                except CamError:  # a value where the law cannot be built: no sign to bracket with
                    out[i] = math.nan
            return out

        grid = lo + (hi - lo) * T4_GRID
        roots, f = scan_roots(residual, grid)
        if not roots:
            finite = np.flatnonzero(np.isfinite(f))
            shown = ""
            if finite.size:
                _, _, a_end, a_next = trial(float(grid[finite[0]]))
                unit = f"{self.spec.unit}/deg²"
                shown = (f" (at {name} = {grid[finite[0]]:g} it ends at a = {a_end:.6g} {unit} and segments[{nxt.index}] "
                         f"starts at {a_next:.6g} {unit}; the difference keeps its sign up to {name} → {hi:g})")
            raise InvalidParameterError(
                f"no {name} in [{lo:g}, {hi:g}) makes the acceleration continuous at the end of this curve 2 and the "
                f"start of segments[{nxt.index}]{shown}; change the spans or strokes, or give {name}.",
                field=("curve", name))
        if len(roots) > 1:
            listed = ", ".join(f"{r:.9g}" for r in sorted(roots))
            raise InvalidParameterError(
                f"several values of {name} ({listed}) make the acceleration continuous at the end of this curve 2; "
                f"give the one you mean.", field=("curve", name))
        _, stroke, _, _ = trial(roots[0])
        with _at_segment(seg.index, "curve"):
            curve = self.fresh(with_parameter(seg.law, name, roots[0]))
        seg.stroke = stroke
        self._check_stroke(seg, stroke)
        seg.curve = curve
        seg.normal = normalised_ends(curve)
        seg.solved[name] = roots[0]
        if solving:
            seg.solved["stroke"] = stroke
        seg.placed = PlacedLaw(curve, seg.x_a, seg.span, s_a, stroke / (curve.s_end - curve.s_start))
        return True

    def _next_start(self, nxt: Segment, s_a: float) -> Callable[[float], float] | None:
        """The next segment's start acceleration as a function of this segment's stroke
        (its own stroke may be an absolute ``to`` minus where this one ends), or None
        while it is not known."""
        if nxt.placed is not None:
            a = nxt.placed.ends()[0][2]
            return lambda _stroke: a
        if nxt.role == "dwell":
            return lambda _stroke: 0.0
        if nxt.role != "fixed":
            return None
        if nxt.index == 0:  # the wrap-around: the first segment's stroke does not depend on this one's
            return None  # known at once (it starts at ``start``): placed on this pass or the next
        curvature, span, to, fixed = nxt.normal[0][2], nxt.span, nxt.segment.to, nxt.segment.stroke
        if fixed is not None:
            return lambda _stroke: float(fixed) * curvature / span**2
        assert to is not None and to != SOLVE  # a solved stroke next to a solved T4: refused by _check_join
        return lambda stroke: (float(to) - s_a - stroke) * curvature / span**2

    # ---------------------------------------------------------------- matched polynomials
    def _advance_chain(self, c: int, chain: list[int]) -> bool:
        segs = [self.segs[i] for i in chain]
        missing = [s for s in segs if s.s_a is None or s.stroke is None]
        if missing:
            return False
        periodic = len(chain) == len(self.segs) and all(s.matched == (True, True) for s in segs)
        first, last = segs[0], segs[-1]
        outside = []
        if not periodic:
            if first.matched[0]:
                outside.append(self._prev(first))
            if last.matched[1]:
                outside.append(self._next(last))
        waiting = [s for s in outside if s.placed is None]
        if waiting:
            first.waiting = f"the end conditions of segments[{waiting[0].index}] for its matched polynomial"
            return False
        members = []
        for p, seg in enumerate(segs):
            assert seg.law is not None and seg.s_a is not None and seg.stroke is not None
            order = MATCH_ORDERS[seg.segment.match]
            with _at_segment(seg.index, "curve"):
                given = given_conditions(seg.law, seg.stroke, seg.span)
            start: Mapping[int, float] | None = given[0]
            end: Mapping[int, float] | None = given[1]
            if seg.matched[0]:
                start = None if (periodic or p > 0) else {k: self._ends(self._prev(seg))[1][k] for k in range(1, order + 1)}
            if seg.matched[1]:
                end = None if (periodic or p < len(segs) - 1) else {k: self._ends(self._next(seg))[0][k]
                                                                  for k in range(1, order + 1)}
            members.append(Member(seg.span, seg.s_a, seg.stroke, order, start, end))
        for seg, member in zip(segs, members):
            with _at_segment(seg.index, "curve"):  # the pattern of conditions determines a polynomial
                matched_polynomial(member, {k: 0.0 for k in member.orders(0)}, {k: 0.0 for k in member.orders(1)})
        with _at_segment(chain[0]):
            conditions = solve_chain(members, periodic)
        for seg, member, (start_c, end_c) in zip(segs, members, conditions):
            with _at_segment(seg.index, "curve"):
                curve, gain = matched_polynomial(member, start_c, end_c)
            assert seg.s_a is not None
            seg.curve = curve
            seg.placed = PlacedLaw(curve, seg.x_a, seg.span, seg.s_a, gain)
            seg.solved["degree"] = float(len(getattr(curve, "coefficients", ())) - 1)
            for side, cond in (("start", start_c), ("end", end_c)):
                seg.solved.update({f"{ORDER_KEYS[k]}_{side}": float(v) for k, v in sorted(cond.items())})
        self.chain_done[c] = True
        return True

    # ---------------------------------------------------------------- results
    def _stuck(self) -> InvalidParameterError:
        seg = next(s for s in self.segs if s.placed is None)
        waits = seg.waiting or "the conditions of its neighbours"
        return InvalidParameterError(
            f"segments[{seg.index}]: it needs {waits}, which depends in turn on this segment (through the positions, "
            "the solved conditions or the wrap-around at period_deg), so the program cannot be resolved in order; give "
            "an explicit to or stroke, or explicit end conditions, to break the circle.", field=("segments", seg.index))

    def _result(self, seg: Segment) -> ResolvedSegment:
        assert seg.s_a is not None and seg.stroke is not None
        law = seg.law
        return ResolvedSegment(
            index=seg.index, type=seg.segment.type, start_deg=seg.x_a, end_deg=seg.x_a + seg.span,
            from_=seg.s_a, to=seg.s_a + seg.stroke, stroke=seg.stroke, curve=law_id(law),
            direction="rise" if law is None else law.direction, solved=dict(seg.solved))
