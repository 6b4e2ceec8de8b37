"""The barrel cam's STEP file read by FreeCAD (``freecadcmd``, its own STEP import and its own
volume), a second program beside the kernel's reader in tests/camcore/export/test_barrel_solid.py:
one valid, closed solid whose volume is the blank's less the groove the roller sweeps."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from camcore.export import SOLID_FORMATS
from camcore.export.barrel_solid import BarrelSolid
from tests.camcore.export.test_barrel_solid import CAMS, extent, groove_volume, radii
from tests.freecad import run

pytestmark = pytest.mark.freecad

SCRIPT = """import json, os
import Part
shape = Part.Shape()
shape.read(os.environ["CAMCORE_STEP"])
print("camcore:", json.dumps({"volume_mm3": shape.Volume, "valid": shape.isValid(), "closed": shape.isClosed(),
                              "solids": len(shape.Solids)}))
"""


@pytest.mark.parametrize("name", list(CAMS))
def test_freecad_reads_one_valid_solid_of_the_right_volume(name: str, tmp_path: Path) -> None:
    cam = CAMS[name]
    tolerance, margin, bore = 0.01, 6.0, 20.0
    step = tmp_path / "barrel.step"
    step.write_bytes(SOLID_FORMATS["step"].write(BarrelSolid(cam, tolerance, margin, bore)))
    script = tmp_path / "measure.py"
    script.write_text(SCRIPT, encoding="utf-8")
    ran = run(script, tmp_path / "home", CAMCORE_STEP=str(step))
    assert "camcore: " in ran.stdout, ran.stdout
    got = json.loads(ran.stdout.split("camcore: ", 1)[1].splitlines()[0])
    assert (got["valid"], got["closed"], got["solids"]) == (True, True, 1)
    outer, bottom = radii(cam)
    z_min, z_max, walls = extent(cam)
    expected = math.pi * (outer**2 - (bore / 2) ** 2) * (z_max - z_min + 2 * margin) - groove_volume(cam)
    fitted = walls + 2 * math.pi * (bottom + outer) * (z_max - z_min + 2 * margin)
    # as the kernel's reader: every surface within the tolerance, so the volume within tolerance × their area
    assert abs(got["volume_mm3"] - expected) <= tolerance * fitted
