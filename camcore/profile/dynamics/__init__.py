"""Dynamics of a force-closed follower on a plate cam: contact force, follower jump, the
smallest preload, camshaft torque and the Hertz stress of a roller.

Map: :mod:`.load` (what holds the follower: mass, spring, preload, external force, damping;
a roller's materials), :mod:`.hertz` (line contact of a roller on the cam surface),
:mod:`.compute` (the table over the cam angle and the exact figures over the turn),
:mod:`.results` (what it answers).
"""

from .compute import LoadedFollower, follower_dynamics
from .hertz import effective_modulus_mpa, line_contact_pressure_mpa, roller_contact_radius_mm
from .load import Coefficients, FollowerLoad, OscillatingLoad, RollerMaterials, TranslatingLoad
from .results import DynamicsSummary, DynamicsTable, FollowerDynamics

__all__ = [
    "Coefficients", "DynamicsSummary", "DynamicsTable", "FollowerDynamics", "FollowerLoad", "LoadedFollower", "OscillatingLoad",
    "RollerMaterials", "TranslatingLoad", "effective_modulus_mpa", "follower_dynamics", "line_contact_pressure_mpa",
    "roller_contact_radius_mm",
]
