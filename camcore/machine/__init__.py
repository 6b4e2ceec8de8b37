"""Machines: several axes on one camshaft (plate cams, barrel cams, indexers, motion programs),
their timing, summed torque, flywheel, motor, speed limits and timing rules.

Map: :mod:`.axes` (each mechanism as the machine sees it), :mod:`.rules` (timing rules, their
violations and phase slack), :mod:`.compute` (the machine at a speed, the flywheel, the motor,
the speed limits), :mod:`.results` (what it answers).
"""

from .axes import DrivenLoad, IndexerAxis, LiftLoadAxis, MachineAxis, PlateCamAxis, SpeedLimit
from .compute import Drive, Flywheel, Machine
from .results import AxisLimit, AxisReport, MachineResult, MachineSummary, MotorFigures, SpeedLimits
from .rules import Condition, Rule, RuleResult, Violation

__all__ = [
    "AxisLimit", "AxisReport", "Condition", "Drive", "DrivenLoad", "Flywheel", "IndexerAxis", "LiftLoadAxis",
    "Machine", "MachineAxis", "MachineResult", "MachineSummary", "MotorFigures", "PlateCamAxis", "Rule", "RuleResult",
    "SpeedLimit", "SpeedLimits", "Violation",
]
