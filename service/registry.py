"""Every operation of the service, from each domain's declarations (service.operations).

The app's routes, its OpenAPI document and the tests that run over every operation read this one
tuple; a domain's new operation is one declaration in its own module, listed here.
"""

from __future__ import annotations

from service import health
from service.cams import barrel, barrel_toolpath, parallel, parallel_toolpath, roller_gear
from service.curves import operations as curves
from service.curves import sweep as characteristics_sweep
from service.curves import vibration as curve_vibration
from service.indexers import design as indexer_design
from service.indexers import operations as indexers
from service.indexers import sweep as sizing_sweep
from service.indexers import vibration as indexer_vibration
from service.machines import operations as machines
from service.motions import operations as motions
from service.operations import Operation
from service.profiles import design as profile_design
from service.profiles import dynamics, toolpath
from service.profiles import operations as profiles

OPERATIONS: tuple[Operation, ...] = (
    *health.OPERATIONS,
    *curves.OPERATIONS, *characteristics_sweep.OPERATIONS, *curve_vibration.OPERATIONS,
    *indexers.OPERATIONS, *sizing_sweep.OPERATIONS, *indexer_vibration.OPERATIONS, *indexer_design.OPERATIONS,
    *motions.OPERATIONS,
    *profiles.OPERATIONS, *toolpath.OPERATIONS, *dynamics.OPERATIONS, *profile_design.OPERATIONS,
    *barrel.OPERATIONS, *barrel_toolpath.OPERATIONS, *parallel.OPERATIONS, *parallel_toolpath.OPERATIONS,
    *roller_gear.OPERATIONS,
    *machines.OPERATIONS,
)


def operation(operation_id: str) -> Operation:
    """The operation of that id (KeyError: none)."""
    for op in OPERATIONS:
        if op.id == operation_id:
            return op
    raise KeyError(operation_id)
