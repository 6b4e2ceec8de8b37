"""Plate cams: the profile checks, a sampled profile, base-circle sizing, follower dynamics, and
fitting a contour with lines and arcs (toolpaths and solids)."""

from __future__ import annotations

from collections.abc import Sequence

from ..curves.kinds import CLOSED_FORM_COST, LawCost
from .estimate import Field, WorkEstimate, WorkTerm, per_item_work

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


#: columns of a profile table (cam angle, lift, contact and pitch points, angles, radii…)
PROFILE_COLUMNS = 14
#: columns of the dynamics table: angle, time, lift, velocity, acceleration, spring, contact,
#: normal, torque, and stress (roller) or the pivot torque (oscillating)
DYNAMICS_COLUMNS = 11
#: numbers of one toolpath element in the JSON answer (ends, centre, radius)
ELEMENT_VALUES = 7
