"""The roller-gear cam's STEP file read by FreeCAD (``freecadcmd``: its own STEP import and its own
volume), a program beside the kernel's reader of tests/camcore/export/test_roller_gear_solid.py: one
valid, closed solid whose volume is the hourglass body in closed form plus the rib meshed from exact
flank points (tests/roller_gear_reference.py)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from camcore.cams.roller_gear import make_roller_gear_cam
from camcore.export import SOLID_FORMATS
from camcore.export.roller_gear_solid import RollerGearSolid
from tests import roller_gear_reference as ref
from tests.freecad import read_step

pytestmark = pytest.mark.freecad



def test_freecad_reads_one_valid_solid_of_the_right_volume(tmp_path: Path) -> None:
    cam = make_roller_gear_cam(8, 100.0, 60.0, 10.0, 20.0, 120.0, "MS")
    tolerance, bore = 0.01, 20.0
    got = read_step(SOLID_FORMATS["step"].write(RollerGearSolid(cam, tolerance, bore)), tmp_path)
    assert (got["valid"], got["closed"], got["solids"]) == (True, True, 1)
    top, root = ref.top_radius(cam), math.hypot(cam.roller_ends_mm[1], cam.roller_radius_mm)
    rings = ref.rib_rings(cam, np.linspace(0.0, 2 * math.pi, 2881), top, root, 32)
    rib, _ = ref.ring_mesh_volume_area(rings)
    half = float(np.abs(rings[..., 2]).max()) + 0.5 * cam.roller_radius_mm
    expected = ref.body_volume(cam.center_distance_mm, root, half, bore) + rib
    # every surface within the tolerance: the volume within the tolerance times FreeCAD's own area of it
    # (the rib's mesh short of its limit by ~6 mm³ at this spacing, far inside)
    assert abs(got["volume_mm3"] - expected) <= tolerance * got["area_mm2"]
