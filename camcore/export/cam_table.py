"""A motion program as a servo drive's cam table: CSV of master position at a fixed step,
slave position, velocity and acceleration.

Electronic-cam editors of servo drives and motion controllers take a cam as a table of
master/slave points; the plainest form they import is CSV: one header row, then one row per
master position, ``.`` as decimal mark, the columns mapped in the import dialog (no vendor's
own file layout is claimed here). The columns:

``master_deg``
    master (drive shaft) position, from 0 to the period at a fixed step, both ends [deg];
``slave_<unit>``
    slave position [mm or deg, the program's unit];
``velocity_<unit>_per_deg``
    d(slave)/d(master) [unit/deg], the slope a drive multiplies by the master's speed;
``acceleration_<unit>_per_deg2``
    d²(slave)/d(master)² [unit/deg²].

The derivatives are taken with respect to the master position, not time, so one table
serves every machine speed (a drive gets slave velocity = slope × master velocity).

References
----------
.. [1] VDI 2143 Blatt 1 (1980): motion laws over the master angle, their derivatives.
.. [2] RFC 4180: CSV with a header row.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..curves.base import FloatArray
from .registry import FileFormat


@dataclass(frozen=True)
class CamTable:
    """The columns of a cam table over the master angle (a motion program sampled at a fixed step).

    Attributes
    ----------
    master_deg : numpy.ndarray
        Master positions [deg].
    slave : numpy.ndarray
        Slave positions [unit].
    velocity, acceleration : numpy.ndarray
        ds/dx [unit/deg] and d²s/dx² [unit/deg²].
    unit : str
        ``mm`` or ``deg``.
    """

    master_deg: FloatArray
    slave: FloatArray
    velocity: FloatArray
    acceleration: FloatArray
    unit: str


def cam_table_csv(table: CamTable) -> str:
    """The cam table as CSV (module notes for the columns).

    Parameters
    ----------
    table : CamTable
        Master positions [deg], slave positions [unit], velocity [unit/deg] and
        acceleration [unit/deg²].

    Returns
    -------
    str
        Header and one row per master position, full float precision (``repr``), ``\\n`` line ends.

    References
    ----------
    RFC 4180 (header row, comma separators); VDI 2143 Blatt 1 (the derivatives over the master angle).
    """
    u = table.unit
    lines = [f"master_deg,slave_{u},velocity_{u}_per_deg,acceleration_{u}_per_deg2"]
    for row in zip(table.master_deg.tolist(), table.slave.tolist(), table.velocity.tolist(),
                   table.acceleration.tolist()):
        lines.append(",".join(repr(float(v)) for v in row))
    return "\n".join(lines) + "\n"


def _write_cam_table(table: CamTable) -> bytes:
    return cam_table_csv(table).encode()


#: motion-program downloads, by name; ``cost(rows)`` (measured ~2.2 µs a row, ×1.5)
MOTION_FORMATS: dict[str, FileFormat[CamTable]] = {f.name: f for f in (
    FileFormat("cam-table", "text/csv; charset=utf-8", "cam_table.csv",
               "servo cam table: CSV of master_deg (fixed step), slave, velocity and acceleration per degree of master",
               _write_cam_table, lambda rows: 1.5 * 2.2e-6 * rows),
)}
