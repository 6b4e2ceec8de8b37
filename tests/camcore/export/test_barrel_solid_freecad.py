"""The barrel cam's STEP file read by FreeCAD (``freecadcmd``, its own STEP import and its own
volume), a second program beside the kernel's reader in tests/camcore/export/test_barrel_solid.py:
one valid, closed solid whose volume is the blank's less the groove the roller sweeps."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from camcore.export import SOLID_FORMATS
from camcore.export.barrel_solid import BarrelSolid
from tests.camcore.export.test_barrel_solid import CAMS, extent, groove_volume, radii
from tests.freecad import read_step

pytestmark = pytest.mark.freecad



@pytest.mark.parametrize("name", list(CAMS))
def test_freecad_reads_one_valid_solid_of_the_right_volume(name: str, tmp_path: Path) -> None:
    cam = CAMS[name]
    tolerance, margin, bore = 0.01, 6.0, 20.0
    got = read_step(SOLID_FORMATS["step"].write(BarrelSolid(cam, tolerance, margin, bore)), tmp_path)
    assert (got["valid"], got["closed"], got["solids"]) == (True, True, 1)
    outer, bottom = radii(cam)
    z_min, z_max, walls = extent(cam)
    expected = math.pi * (outer**2 - (bore / 2) ** 2) * (z_max - z_min + 2 * margin) - groove_volume(cam)
    fitted = walls + 2 * math.pi * (bottom + outer) * (z_max - z_min + 2 * margin)
    # as the kernel's reader: every surface within the tolerance, so the volume within tolerance × their area
    assert abs(got["volume_mm3"] - expected) <= tolerance * fitted
