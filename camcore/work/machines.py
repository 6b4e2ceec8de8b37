"""The cost of a machine: per axis and camshaft speed, the rules, the motor's limit searches.

A machine's work beyond building its axes and their own checks (each counted as its own operation
counts it) is evaluating every axis's camshaft torque over the quadrature cells and the peak grid at
each speed (the summary: mean, ΔE, RMS, peaks), each axis's torque figures and speed limit once, a rule's two condition
sets on the 0.05° crossing grid, and the motor's limits (a root search over speed, each step a
refined peak or an RMS). The constants are measured on the reference machine (see each) and
carry the package's safety factor.
"""

from __future__ import annotations

from collections.abc import Sequence

from .estimate import WorkEstimate, WorkTerm

#: the margin over the figures measured below (2026-11-27, the reference machine, best of 7), as the
#: profiles' constants carry
SAFETY = 1.5
#: one axis's share of one speed's summary (mean, ΔE, RMS, refined peaks) [s], by kind: measured
#: 10.1 ms (the README's roller plate cam), 6.4 ms (a barrel cam), 4.1 ms (a 6-stop MS indexer),
#: 8.9 ms (a 4-segment motion program)
AXIS_SPEED_S = {"plate_cam": 0.0101, "barrel_cam": 0.0064, "indexer": 0.0041, "motion": 0.0089}
#: one axis's torque figures (refined peak, mean, RMS) and its speed limit at the machine's speed [s], its own
#: checks left out (its own operation's estimate counts them): measured 15 ms (plate cam, the jump speed 6.7 of
#: it), 5.8 (barrel cam), 2.8 (indexer), 6.8 (motion program)
AXIS_FIGURES_S = {"plate_cam": 0.015, "barrel_cam": 0.0058, "indexer": 0.0028, "motion": 0.0068}
#: one rule: two condition sets, each axis's position on the 0.05° crossing grid: measured 1.7 ms
RULE_S = 0.0017
#: one motor limit search over speed, per axis: ~20 speeds tried, each the total on ~6 500 angles:
#: measured 48 ms per search per axis (two searches over a plate cam and an indexer: 0.19 s)
MOTOR_SEARCH_S_PER_AXIS = 0.048
#: one row of the timing and torque tables, per axis: measured 0.8 ms for 3 601 rows of one axis
ROW_S_PER_AXIS = 2.2e-7


def machine_work(kinds: Sequence[str], speeds: int, rules: int, motor_searches: int, rows: int) -> WorkEstimate:
    """The machine's own work (its axes built: their operations' estimates).

    Parameters
    ----------
    kinds : sequence of str
        Each axis's mechanism (plate_cam, barrel_cam, indexer, motion).
    speeds : int
        Summaries computed: the machine's speed and the sweep's [-].
    rules : int
        Timing rules [-].
    motor_searches : int
        The motor's limit searches (peak and RMS: 2 with a drive) [-].
    rows : int
        Rows of the timing and torque tables [-].

    Returns
    -------
    WorkEstimate
        Terms at the request fields that drive them.

    References
    ----------
    M. Nygard, *Release It!*, 2nd ed. (2018), ch. 5: bounded work, refused before it starts.
    """
    per_speed = sum(AXIS_SPEED_S[k] for k in kinds) * SAFETY
    figures = sum(AXIS_FIGURES_S[k] for k in kinds) * SAFETY
    n = len(kinds)
    return WorkEstimate((
        WorkTerm(("speeds_rpm",), f"{speeds} speeds × {n} axes summed over the turn", speeds * per_speed),
        WorkTerm(("axes",), f"{n} axes' torque figures and speed limits", figures),
        WorkTerm(("rules",), f"{rules} timing rules", rules * RULE_S * SAFETY),
        WorkTerm(("drive",), f"{motor_searches} motor limit searches", motor_searches * n * MOTOR_SEARCH_S_PER_AXIS
                 * SAFETY),
        WorkTerm(("samples",), f"{rows} rows × {n} axes", rows * n * ROW_S_PER_AXIS * SAFETY),
    ))
