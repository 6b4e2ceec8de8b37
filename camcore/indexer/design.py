"""Designing an indexer for the user: every candidate sized, the feasible ones ranked.

For a number of stops, a load, the machine's cycle (one index and one dwell per input turn:
t0 = 60/N) and the dwell the process needs, each candidate indexing angle θh, curve and
(optionally) motor is sized exactly as :func:`camcore.indexer.size` sizes it. A candidate is
feasible when

* its dwell, t0·(1 − θh/360), is at least the dwell the process needs;
* its design output torque fc·Tt is within the unit's rated output torque, and its peak input
  torque within the allowed input torque, when those are given;
* with a motor, the motor carries it (peak, RMS and speed within its ratings, every efficiency
  applied: :mod:`.drive`).

The feasible candidates are ranked by the criterion (the smallest peak input torque, the smallest
RMS input torque, or with motors the smallest motor — by rated torque — that carries the design,
then its RMS use), ties kept in the order given. The search is exhaustive over the finite
candidate set, so the first is the optimum of that set, not of a continuous search.

References
----------
.. [1] INDEXMAN technical guide, sections 2, 3 and 5 (indexing time th = θh/360·t0, the dwell
   t0 − th, the torque and power sizing).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Literal

from .._checks import count, non_negative, positive
from ..curves.curve import Curve
from ..deadline import checkpoint
from ..errors import InvalidParameterError
from ..results import doc
from .drive import Motor
from .kinematics import Indexer
from .load import Load
from .sizing import size

Criterion = Literal["input_torque", "rms_input_torque", "motor"]
CRITERIA: tuple[Criterion, ...] = ("input_torque", "rms_input_torque", "motor")


@dataclass(frozen=True)
class NamedMotor:
    """A motor the user offers, with its name."""

    name: str
    motor: Motor


@dataclass(frozen=True)
class Candidate:
    """One candidate design, sized, with its verdict."""

    indexing_angle_deg: float = field(metadata=doc("θh [deg]"))
    curve: str = field(metadata=doc("the curve's name"))
    motor: str | None = field(metadata=doc("the motor's name; null without motors"))
    indexing_time_s: float = field(metadata=doc("th = θh/360·t0 [s]"))
    dwell_time_s: float = field(metadata=doc("t0 − th [s]"))
    input_torque_nm: float = field(metadata=doc("fc × the exact peak input torque (sizeIndexer's) [N·m]"))
    rms_input_torque_nm: float = field(metadata=doc("over the machine cycle, internal friction included [N·m]"))
    input_power_kw: float = field(metadata=doc("2πN·T_in/60/η [kW]"))
    design_output_torque_nm: float = field(metadata=doc("fc·(Ti + Tf + Tw) [N·m]"))
    alpha_max_rad_s2: float = field(metadata=doc("the output's peak angular acceleration [rad/s²]"))
    motor_peak_torque_nm: float | None = field(metadata=doc("with a motor: its peak torque [N·m]"))
    motor_rms_torque_nm: float | None = field(metadata=doc("with a motor: its RMS torque [N·m]"))
    peak_utilisation: float | None = field(metadata=doc("with a motor: peak torque / its peak rating"))
    rms_utilisation: float | None = field(metadata=doc("with a motor: RMS torque / its rated torque"))
    feasible: bool = field(metadata=doc("every requirement met"))
    reason: str | None = field(metadata=doc("what it misses, when infeasible"))
    missed: tuple[str, ...] = field(default=(), metadata={"internal": True})  # the requirements' request fields


@dataclass(frozen=True)
class IndexerDesign:
    """The ranked candidates: feasible ones first, best first; then the infeasible ones."""

    criterion: str = field(metadata=doc("how the feasible candidates are ranked"))
    speed_rpm: float = field(metadata=doc("N, the input speed: 60/t0 [rpm]"))
    cycle_time_s: float = field(metadata=doc("t0 [s]"))
    max_indexing_angle_deg: float = field(metadata=doc("the largest θh that leaves the dwell needed [deg]"))
    best: Candidate | None = field(metadata=doc("the first feasible candidate"))
    candidates: tuple[Candidate, ...] = field(metadata=doc("every candidate, ranked"))


def _key(c: Candidate, criterion: Criterion, motor_size: dict[str | None, float]) -> tuple[float, ...]:
    if criterion == "motor":
        return (motor_size.get(c.motor, 0.0), c.rms_utilisation or 0.0, c.input_torque_nm)
    if criterion == "rms_input_torque":
        return (c.rms_input_torque_nm, c.input_torque_nm)
    return (c.input_torque_nm, c.rms_input_torque_nm)


def design_indexer(stops: int, load: Load, speed_rpm: float, angles_deg: Sequence[float],
                   curves: Sequence[tuple[str, Curve]], *, min_dwell_s: float = 0.0,
                   motors: Sequence[NamedMotor] = (), internal_friction_torque_nm: float = 0.0,
                   rated_output_torque_nm: float | None = None, max_input_torque_nm: float | None = None,
                   criterion: Criterion | None = None) -> IndexerDesign:
    """Every candidate (angle × curve × motor) sized and ranked (module notes).

    Parameters
    ----------
    stops : int
        n, stops per output turn (≥ 1) [-].
    load : Load
        What the output drives.
    speed_rpm : float
        N, the input speed; one index per input turn, t0 = 60/N [rpm].
    angles_deg : sequence of float
        Candidate indexing angles θh, each 0 < θh ≤ 360 [deg].
    curves : sequence of (str, Curve)
        Candidate curves, by name.
    min_dwell_s : float
        The dwell the process needs (≥ 0) [s].
    motors : sequence of NamedMotor
        Candidate motors (empty: no motor check) [-].
    internal_friction_torque_nm : float
        The unit's own friction on the input shaft (≥ 0) [N·m].
    rated_output_torque_nm, max_input_torque_nm : float, optional
        The unit's rated output torque and the allowed peak input torque [N·m].
    criterion : {"input_torque", "rms_input_torque", "motor"}, optional
        How to rank; default ``motor`` with motors, else ``input_torque``.

    Returns
    -------
    IndexerDesign
        The ranked candidates and the best.

    References
    ----------
    INDEXMAN technical guide, sections 2, 3 and 5.
    """
    count("stops", stops)
    positive("speed_rpm", speed_rpm)
    non_negative("min_dwell_s", min_dwell_s)
    if not angles_deg:
        raise InvalidParameterError("give at least one candidate indexing angle.", field=("indexing_angles_deg",))
    if not curves:
        raise InvalidParameterError("give at least one candidate curve.", field=("curves",))
    chosen: Criterion = criterion or ("motor" if motors else "input_torque")
    if chosen == "motor" and not motors:
        raise InvalidParameterError("ranking by motor needs motors to choose from.", field=("criterion",))
    cycle_s = 60.0 / speed_rpm
    max_angle = 360.0 * (1.0 - min_dwell_s / cycle_s)
    if max_angle <= 0:
        raise InvalidParameterError(
            f"the dwell needed, {min_dwell_s:g} s, is the whole cycle t0 = {cycle_s:.6g} s or more: no indexing "
            "angle leaves it.", field=("min_dwell_s",))
    rows: list[Candidate] = []
    for angle in angles_deg:
        for name, curve in curves:
            for m in (motors or (None,)):
                checkpoint()
                unit = Indexer(stops=stops, indexing_angle_deg=angle, speed_rpm=speed_rpm, curve=curve)
                s = size(unit, load, internal_friction_torque_nm=internal_friction_torque_nm,
                         motor=None if m is None else m.motor, table_samples=2)
                reasons: dict[str, str] = {}
                dwell = cycle_s - unit.indexing_time_s
                # the dwell exactly at the need is met (1e-12: the rounding of t0·(1 − θh/360))
                if dwell < min_dwell_s * (1 - 1e-12):
                    reasons["min_dwell_s"] = f"the dwell {dwell:.4g} s is shorter than the {min_dwell_s:g} s needed"
                if rated_output_torque_nm is not None and s.design_output_torque_nm > rated_output_torque_nm:
                    reasons["rated_output_torque_nm"] = (f"the design output torque {s.design_output_torque_nm:.4g} "
                                                         f"N·m exceeds the rated {rated_output_torque_nm:g} N·m")
                if max_input_torque_nm is not None and s.input_torque_nm > max_input_torque_nm:
                    reasons["max_input_torque_nm"] = (f"the input torque {s.input_torque_nm:.4g} N·m exceeds the "
                                                      f"allowed {max_input_torque_nm:g} N·m")
                if m is not None and not s.motor_ok:
                    reasons["motors"] = f"motor {m.name}: {s.motor_reason}"
                rows.append(Candidate(
                    angle, name, None if m is None else m.name, unit.indexing_time_s, dwell, s.input_torque_nm,
                    s.rms_input_torque_nm, s.input_power_kw, s.design_output_torque_nm, s.alpha_max_rad_s2,
                    s.motor_peak_torque_nm, s.motor_rms_torque_nm, s.peak_utilisation, s.rms_utilisation,
                    not reasons, "; ".join(reasons.values()) or None, tuple(reasons)))
    motor_size: dict[str | None, float] = {m.name: m.motor.rated_torque_nm for m in motors}
    feasible = sorted((r for r in rows if r.feasible), key=lambda r: _key(r, chosen, motor_size))
    rest = [r for r in rows if not r.feasible]
    return IndexerDesign(chosen, float(speed_rpm), cycle_s, max_angle, feasible[0] if feasible else None,
                         (*feasible, *rest))
