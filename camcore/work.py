"""How much work a computation is, known before it runs: the cost model.

Every estimate is in seconds on the reference machine (2 cores, x86-64, Python 3.11,
numpy 2, one computation at a time), built from measured kernels times a safety factor
for a busy machine: a curve's cost comes from its kind (:data:`camcore.curves.kinds.CURVE_KINDS`,
``LawCost``), a contour file's from its format (:data:`camcore.export.FORMATS`), a
profile's checks and base-circle sizing from the constants below. An estimate keeps its
terms with the request field that drives each, so a caller that refuses the work can say
what to reduce. ``bench/cost_model.py`` measures every estimate against the real run.

References
----------
.. [1] M. Nygard, *Release It!*, 2nd ed. (2018), ch. 5: bounded work, fail fast, load shedding.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from .curves.kinds import CLOSED_FORM_COST, CURVE_KINDS, LawCost

Field = tuple[str | int, ...]

#: profile checks (largest pressure angle, smallest radius of curvature; every extreme refined
#: by the same local grids): measured 3.2 ms for 4 MS segments, 8.0 ms for 36, 48 ms for 360
#: (a per-segment step in every evaluation of the lift), 35 ms for 36 Bezier segments of degree
#: 20 and 0.24 s for 360; fitted as 2.5 ms + 0.12 ms per segment + the law evaluations below, ×1.5
CHECKS_FIXED_S = 1.5 * 0.0025
CHECKS_PER_SEGMENT_S = 1.5 * 0.00012
#: law evaluations of one check per segment (its share of the local-grid rounds) and in all
#: (the 7 200-point grid once)
CHECKS_SAMPLES_PER_SEGMENT = 350
CHECKS_SAMPLES = 7_000
#: one sampled profile angle: lift, kinematics and the columns (0.5 µs measured), ×1.5
PROFILE_SAMPLE_S = 1.5 * 5e-7
#: profile checks per base-circle limit: the solver's evaluations (bracket, then Illinois
#: regula falsi to 1e-10) over 36 extreme cases (pressure-angle limits 0.01°-89.9999°,
#: curvature limits 0-1e6 mm, starting radii 1-1e4 mm): median 15, 90th percentile 24, up
#: to 49 where a limit never binds and the radius falls to the geometric floor. The typical
#: count is estimated; the deadline (work_deadline_s) stops what runs far longer
CHECKS_PER_LIMIT = 16


@dataclass(frozen=True)
class WorkTerm:
    """One part of an estimate: the request field that drives it, what it is, its cost [s]."""

    field: Field
    what: str
    seconds: float


@dataclass(frozen=True)
class WorkEstimate:
    """The estimated seconds of a computation, as a sum of terms."""

    terms: tuple[WorkTerm, ...] = ()

    @property
    def seconds(self) -> float:
        """The estimate [s]."""
        return sum(term.seconds for term in self.terms)

    def __add__(self, other: WorkEstimate) -> WorkEstimate:
        return WorkEstimate(self.terms + other.terms)

    def largest(self) -> WorkTerm:
        """The term that costs most (what to reduce first)."""
        return max(self.terms, key=lambda term: term.seconds)


def law_cost(kind: str, parameters: Mapping[str, Any]) -> LawCost:
    """The cost of one curve of a kind with these parameters, before it is built.

    Parameters
    ----------
    kind : str
        A key of :data:`camcore.curves.kinds.CURVE_KINDS`.
    parameters : mapping
        The kind's parameters (sizes are read from them: control points, points).

    Returns
    -------
    LawCost
        Seconds to build it (with characteristic values and inverse start tables) and
        per evaluated time [s].

    References
    ----------
    camcore.curves.kinds, the measurements beside each kind's cost.
    """
    return CURVE_KINDS[kind].cost(parameters)


def curve_work(law: LawCost, field: Field, values_only: bool = False) -> WorkEstimate:
    """Building one curve.

    Parameters
    ----------
    law : LawCost
        The curve's cost (:func:`law_cost`).
    field : tuple
        The request field of the curve spec.
    values_only : bool
        Only the curve and its characteristic values, not its inverse's tables
        (:attr:`LawCost.values_s`) [-].

    Returns
    -------
    WorkEstimate
        One term [s].

    References
    ----------
    camcore.curves.kinds (LawCost).
    """
    if values_only:
        return WorkEstimate((WorkTerm(field, "building the curve and its characteristic values", law.values_s),))
    return WorkEstimate((WorkTerm(field, "building the curve", law.build_s),))


def per_item_work(count: int, seconds_each: float, field: Field, what: str) -> WorkEstimate:
    """``count`` items of equal cost, e.g. the rows of a table.

    Parameters
    ----------
    count : int
        Number of items [-].
    seconds_each : float
        Cost of one item [s].
    field : tuple
        The request field that sets the count.
    what : str
        What the items are, for the caller's message.

    Returns
    -------
    WorkEstimate
        One term [s].

    References
    ----------
    camcore.work, module notes.
    """
    return WorkEstimate((WorkTerm(field, what, count * seconds_each),))


def checks_work(laws: Sequence[LawCost | None], field: Field) -> WorkEstimate:
    """One run of the profile checks over a cam of these segments.

    Parameters
    ----------
    laws : sequence of LawCost or None
        Each segment's law (None: a dwell or the default cycloid).
    field : tuple
        The request field of the segments (what to reduce).

    Returns
    -------
    WorkEstimate
        One term [s].

    References
    ----------
    camcore.profile.checks; the measurements beside :data:`CHECKS_FIXED_S`.
    """
    costs = [(law or CLOSED_FORM_COST).sample_s for law in laws] or [CLOSED_FORM_COST.sample_s]
    seconds = (CHECKS_FIXED_S + CHECKS_PER_SEGMENT_S * len(costs)
               + 1.5 * (CHECKS_SAMPLES_PER_SEGMENT * sum(costs) + CHECKS_SAMPLES * max(costs)))
    return WorkEstimate((WorkTerm(field, f"the profile checks of {len(costs)} segments", seconds),))


def _dynamics_extremes_s(laws: Sequence[LawCost | None]) -> float:
    """The extremes of the follower dynamics over the turn [s] (golden-section searches, see
    :data:`DYNAMICS_PER_CHECKS`)."""
    costs = [(law or CLOSED_FORM_COST).sample_s for law in laws] or [CLOSED_FORM_COST.sample_s]
    checks = (DYNAMICS_CHECKS_FIXED_S + DYNAMICS_CHECKS_PER_SEGMENT_S * len(costs)
              + 1.5 * (DYNAMICS_CHECKS_SAMPLES_PER_SEGMENT * sum(costs) + DYNAMICS_CHECKS_SAMPLES * max(costs)))
    return DYNAMICS_PER_CHECKS * checks


def profile_work(laws: Sequence[LawCost | None], samples: int, segments_field: Field,
                 samples_field: Field) -> WorkEstimate:
    """A sampled plate-cam profile with its checks (the curves built apart).

    Parameters
    ----------
    laws : sequence of LawCost or None
        Each segment's law (None: a dwell or the default cycloid).
    samples : int
        Cam angles sampled [-].
    segments_field, samples_field : tuple
        The request fields of the segments and of the sample count.

    Returns
    -------
    WorkEstimate
        Checks and samples [s].

    References
    ----------
    camcore.profile.compute; the measurements beside :data:`PROFILE_SAMPLE_S`.
    """
    slowest = max((law.sample_s for law in laws if law is not None), default=CLOSED_FORM_COST.sample_s)
    return checks_work(laws, segments_field) + per_item_work(
        samples, PROFILE_SAMPLE_S + slowest, samples_field, f"{samples} profile samples")


def base_circle_work(laws: Sequence[LawCost | None], limits: int, segments_field: Field) -> WorkEstimate:
    """Base-circle sizing: per limit :data:`CHECKS_PER_LIMIT` profile checks, one more at the end.

    Parameters
    ----------
    laws : sequence of LawCost or None
        Each segment's law (None: a dwell or the default cycloid).
    limits : int
        Limits solved for (pressure angle, radius of curvature) [-].
    segments_field : tuple
        The request field of the segments.

    Returns
    -------
    WorkEstimate
        One term [s].

    References
    ----------
    camcore.profile.base_circle; the measurements beside :data:`CHECKS_PER_LIMIT`.
    """
    one = checks_work(laws, segments_field).seconds
    runs = CHECKS_PER_LIMIT * max(limits, 1) + 1
    return WorkEstimate((WorkTerm(segments_field, f"{runs} profile checks of {max(len(laws), 1)} segments",
                                  runs * one),))


#: Makino curve 2's T4 solved in a motion program: ~190 trial curves (the scan
#: camcore.motion.resolve.T4_GRID and its Illinois refinement), measured 21-36 ms; ×1.5
MOTION_SOLVE_S = 1.5 * 0.035
#: one master angle of a motion table: segment lookup, the chain rule, the time columns
#: (measured 0.07-0.11 µs per row at 2e5 rows, 4-100 segments); ×1.5
MOTION_ROW_S = 1.5 * 1.1e-7


def motion_work(laws: Sequence[LawCost | None], solved: int, rows: int, segments_field: Field,
                rows_field: Field) -> WorkEstimate:
    """A motion program resolved and sampled (the answer's encoding apart).

    Parameters
    ----------
    laws : sequence of LawCost or None
        The law each segment builds (its kind's cost, :data:`CURVE_KINDS`: the curve with its
        characteristic values); None where nothing is built (a dwell, a curve already built).
        Matched and solved laws are built afresh, so they always count.
    solved : int
        Parameters solved by scanning trial curves (Makino curve 2's T4) [-].
    rows : int
        Master angles sampled [-].
    segments_field, rows_field : tuple
        The request fields of the segments and of the sample count.

    Returns
    -------
    WorkEstimate
        Building the laws, solving, and the rows [s].

    References
    ----------
    camcore.motion.resolve; the measurements beside :data:`MOTION_SOLVE_S` and :data:`MOTION_ROW_S`.
    """
    built = [law for law in laws if law is not None]
    work = WorkEstimate((WorkTerm(segments_field, f"building the laws of {len(built)} segments",
                                  sum(law.build_s for law in built)),))
    if solved:
        work += WorkEstimate((WorkTerm(segments_field, f"solving {solved} parameters", solved * MOTION_SOLVE_S),))
    slowest = max((law.sample_s for law in built), default=5e-8)
    return work + per_item_work(rows, MOTION_ROW_S + slowest, rows_field, f"{rows} motion rows")


#: follower dynamics (camcore.profile.dynamics): one grid over the turn, one golden-section search
#: for every extreme at once, and the RMS quadrature; measured 0.6-2.1 times the golden-section
#: checks' estimate below (the checks before they moved to local grids) of the same cam (4-360
#: cycloid or degree-20 Bezier segments), ×1.2
DYNAMICS_PER_CHECKS = 2.5
DYNAMICS_CHECKS_FIXED_S = 1.5 * 0.010
DYNAMICS_CHECKS_PER_SEGMENT_S = 1.5 * 0.0007
DYNAMICS_CHECKS_SAMPLES_PER_SEGMENT = 800
DYNAMICS_CHECKS_SAMPLES = 25_000


def dynamics_work(laws: Sequence[LawCost | None], samples: int, segments_field: Field,
                  samples_field: Field) -> WorkEstimate:
    """The dynamics of a follower on a cam of these segments, with its table (the curves built apart).

    Parameters
    ----------
    laws : sequence of LawCost or None
        Each segment's law (None: a dwell or the default cycloid).
    samples : int
        Rows of the table [-].
    segments_field, samples_field : tuple
        The request fields of the segments and of the row count.

    Returns
    -------
    WorkEstimate
        The extremes over the turn and the rows [s].

    References
    ----------
    camcore.profile.dynamics; the measurements beside :data:`DYNAMICS_PER_CHECKS`.
    """
    extremes = _dynamics_extremes_s(laws)
    slowest = max((law.sample_s for law in laws if law is not None), default=CLOSED_FORM_COST.sample_s)
    return WorkEstimate((WorkTerm(segments_field, f"the follower dynamics of {max(len(laws), 1)} segments",
                                  extremes),)) + per_item_work(samples, PROFILE_SAMPLE_S + slowest, samples_field,
                                                               f"{samples} dynamics rows")


#: residual vibration (camcore.dynamics), measured over catalog, spline and Bezier curves at
#: τ = 0.001-1000 (1 to 3 000 values), best of 3 on a busy machine, ×1.5: one node of one
#: subcell at one τ value, 55-140 ns with the peak deviation (the integrals to every node, the
#: deviation, the peak's candidates), 14-60 ns for the residual amplitude alone; per τ value,
#: the peak's refinement (Newton's iteration on at most 32 intervals), ~10 µs; per band of τ
#: (its Ω within a factor 2), cutting the subcells and the batches, ~1 ms; building the smooth
#: cells of the acceleration, the curve at 17 nodes per cell about twice over
VIBRATION_NODE_S = 1.5 * 1.4e-7
VIBRATION_RESIDUAL_NODE_S = 1.5 * 6e-8
VIBRATION_TAU_S = 1.5 * 1e-5
VIBRATION_BAND_S = 1.5 * 1e-3
VIBRATION_CELL_SAMPLES = 2 * 17
#: nodes per subcell (camcore.dynamics._chebyshev.NODES)
VIBRATION_NODES = 32


def vibration_work(law: LawCost, cells: int, tau: Sequence[float], field: Field, peak: bool = True) -> WorkEstimate:
    """The residual vibration of one curve at each τ (camcore.dynamics.residual_vibration).

    The τ values fall into bands whose Ω = 2πτ lie within a factor 2 (as camcore groups them);
    a band's subcells are the curve's cells cut so that Ω·length ≤ 4 at its largest τ, at most
    ``cells`` + π·τ/2 of them, with 32 nodes each, at which the curve is evaluated once per band
    and the response computed once per τ value.

    Parameters
    ----------
    law : LawCost
        The curve's cost (:func:`law_cost`): its ``sample_s`` prices each node's acceleration.
    cells : int
        Smooth cells of its acceleration, as estimated before it is built (a piece each for
        closed forms, a spline interval each) [-].
    tau : sequence of float
        The τ values [-].
    field : tuple
        The request field of the τ values.
    peak : bool
        With the peak deviation (residual_vibration), or the residual amplitude alone
        (residual_amplitude).

    Returns
    -------
    WorkEstimate
        One term [s].

    References
    ----------
    camcore.dynamics._response (the subcells); the measurements beside :data:`VIBRATION_NODE_S`.
    """
    bands: dict[int, tuple[float, int]] = {}
    for t in tau:
        band = max(0, math.floor(math.log2(2 * math.pi * t)))
        largest, count = bands.get(band, (0.0, 0))
        bands[band] = (max(largest, t), count + 1)
    nodes = sampled = 0.0
    for largest, count in bands.values():
        subcells = cells + math.pi * largest / 2
        nodes += count * subcells
        sampled += subcells
    per_node = VIBRATION_NODE_S if peak else VIBRATION_RESIDUAL_NODE_S
    seconds = (VIBRATION_NODES * (nodes * per_node + 1.5 * sampled * law.sample_s)
               + 1.5 * VIBRATION_CELL_SAMPLES * cells * law.sample_s + len(bands) * VIBRATION_BAND_S
               + (len(tau) * VIBRATION_TAU_S if peak else 0.0))
    return WorkEstimate((WorkTerm(field, f"the response at {len(tau)} values of τ", seconds),))


#: a fitted path (camcore.toolpath): elements per moving segment ≈ FIT_ELEMENTS_PER_STROKE ·
#: (stroke/tolerance)^(1/3) (a biarc's error grows as the cube of its length: measured 25-34
#: elements a path for two 20 mm strokes at 1e-3 mm and 1e-4 mm → ×2, 0.8 per stroke-root for
#: 5 mm strokes over 90° and 30°), plus FIT_ELEMENTS_PER_SEGMENT at each segment's ends and
#: FIT_ELEMENTS_FIXED per path; the factor is set a little above what was measured
FIT_ELEMENTS_PER_STROKE = 0.9
FIT_ELEMENTS_PER_SEGMENT = 4
FIT_ELEMENTS_FIXED = 8
#: one path: its curvature and cusp scans and the measurement passes (measured 30-40 ms, one
#: computation at a time); one element: the greedy search's trials and its measurement both
#: ways (0.5-0.6 ms with closed-form laws, 4 to 12 segments: ~900 points of the exact curve
#: evaluated per element, FIT_POINTS_PER_ELEMENT counts them for a slower law); ×1.5
FIT_PATH_S = 1.5 * 0.04
FIT_ELEMENT_S = 1.5 * 6e-4
FIT_POINTS_PER_ELEMENT = 1000


def fit_elements_estimate(strokes_mm: Sequence[float], segments: int, tolerance_mm: float) -> int:
    """How many lines and arcs a path fitted within a tolerance will have, before fitting.

    Parameters
    ----------
    strokes_mm : sequence of float
        The stroke of each moving segment of the lift (a swing as the arc the follower
        point runs) [mm].
    segments : int
        Segments of the lift, dwells included [-].
    tolerance_mm : float
        The fitting tolerance [mm].

    Returns
    -------
    int
        The estimated element count of one path [-].

    References
    ----------
    Meek and Walton (1992): a biarc's deviation grows as the cube of its length; the
    measurements beside :data:`FIT_ELEMENTS_PER_STROKE`.
    """
    per_stroke = sum((abs(s) / tolerance_mm) ** (1.0 / 3.0) for s in strokes_mm)
    return int(FIT_ELEMENTS_FIXED + FIT_ELEMENTS_PER_SEGMENT * segments + FIT_ELEMENTS_PER_STROKE * per_stroke)


def fit_work(laws: Sequence[LawCost | None], elements: int, paths: int, segments_field: Field,
             tolerance_field: Field) -> WorkEstimate:
    """Fitting paths of lines and arcs to a cam (camcore.toolpath), the curves built apart.

    Parameters
    ----------
    laws : sequence of LawCost or None
        Each segment's law (None: a dwell or the default cycloid).
    elements : int
        Estimated elements of all paths together (:func:`fit_elements_estimate`) [-].
    paths : int
        Paths fitted (walls), each with its checks of the whole turn [-].
    segments_field, tolerance_field : tuple
        The request fields of the segments and of the tolerance.

    Returns
    -------
    WorkEstimate
        The checks of each path, and the elements [s].

    References
    ----------
    camcore.toolpath.fit; the measurements beside :data:`FIT_ELEMENT_S`.
    """
    slowest = max((law.sample_s for law in laws if law is not None), default=CLOSED_FORM_COST.sample_s)
    checks = checks_work(laws, segments_field).seconds
    return WorkEstimate((
        WorkTerm(segments_field, f"the curvature checks of {paths} paths", paths * (checks + FIT_PATH_S)),
        WorkTerm(tolerance_field, f"fitting about {elements} lines and arcs",
                 elements * (FIT_ELEMENT_S + 1.5 * FIT_POINTS_PER_ELEMENT
                             * max(0.0, slowest - CLOSED_FORM_COST.sample_s)))))
