"""Motion programs: their laws built, their parameters solved, their rows."""

from __future__ import annotations

from collections.abc import Sequence

from ..curves.kinds import LawCost
from .estimate import Field, WorkEstimate, WorkTerm, per_item_work

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




#: columns of a motion table: x_deg, s, v, a, j, and with a speed time_s, v_per_s, a_per_s2, j_per_s3
MOTION_TABLE_COLUMNS = 5
MOTION_TIME_COLUMNS = 4
