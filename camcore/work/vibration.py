"""Residual vibration: the follower's response over τ."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from ..curves.kinds import LawCost
from .estimate import Field, WorkEstimate, WorkTerm

#: residual vibration (camcore.dynamics), measured over catalog, spline and Bezier curves at
#: τ = 0.001-1000 (1 to 3 000 values), best of 3 on a busy machine, ×1.5: one node of one
#: subcell at one τ value, 55-140 ns with the peak deviation (the integrals to every node, the
#: deviation, the peak's candidates), 14-60 ns for the residual amplitude alone. Measured again
#: against the whole estimate, over catalog, spline and Bezier curves at τ 0.001-1000 with 11 to
#: 2001 values, one run at a time: 1.6-16.5 times the run with the peak (kept: with two runs at
#: once a 96-value spectrum took 1.3 times as long, the margin it needs), 3.4-28 times without
#: (30 ns kept, still 1.7 times the run); per τ value,
#: the peak's refinement (Newton's iteration on at most 32 intervals), ~10 µs; per band of τ
#: (its Ω within a factor 2), cutting the subcells and the batches, ~1 ms; building the smooth
#: cells of the acceleration, the curve at 17 nodes per cell about twice over
VIBRATION_NODE_S = 1.5 * 1.4e-7
VIBRATION_RESIDUAL_NODE_S = 1.5 * 3e-8
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




#: columns of a spectrum (tau, residual_amplitude, peak_deviation) and of an indexer's table
SPECTRUM_COLUMNS = 3
INDEXER_TABLE_COLUMNS = 2
#: smooth cells of a closed-form curve's acceleration, at most: one per piece (camcore's catalog
#: and Makino's curves have ≤ 7), each a polynomial of degree 16 to rounding (measured)
CLOSED_FORM_CELLS = 8
#: a Bezier curve of degree d: 2·d + 8 cells (measured at most 35 over 300 random curves of
#: degree ≤ 20; a near-vertical tangent needs more, which the deadline stops)
BEZIER_CELLS_PER_DEGREE = 2
#: the indexer's table: one row is X from the Chebyshev series of its subcell (33 terms,
#: Clenshaw, one column gathered at a time), measured 0.15 µs per row at 2e5 rows, ×1.5
VIBRATION_ROW_S = 1.5 * 2e-7


def estimated_cells(kind: str, parameters: Mapping[str, Any]) -> int:
    """The smooth cells of a law's acceleration, before its curve is built [-].

    Parameters
    ----------
    kind : str
        A key of camcore.curves.kinds.CURVE_KINDS.
    parameters : mapping
        The kind's parameters.

    Returns
    -------
    int
        Cells [-].

    References
    ----------
    The measurements beside :data:`CLOSED_FORM_CELLS` and :data:`BEZIER_CELLS_PER_DEGREE`.
    """
    if kind == "points":
        return max(1, len(parameters["t"]) - 1)
    if kind == "bezier":
        return BEZIER_CELLS_PER_DEGREE * (len(parameters["control_points"]) - 1) + CLOSED_FORM_CELLS
    return CLOSED_FORM_CELLS
