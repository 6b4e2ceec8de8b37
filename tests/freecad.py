"""Headless FreeCAD for the tests (``freecadcmd``, Debian's freecad-python3): runs a macro or script with
its settings in the environment, time-bound, with a home folder of its own (FreeCAD writes its user
settings there), and measures a saved document with tests/freecad_measure.py."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path
from typing import Any

from tests.processes import run_bounded

#: a FreeCAD start is ~0.3 s and the three cams build in ~1 s here; a hung kernel must not hang the suite
TIMEOUT_S = 120
MEASURE = Path(__file__).with_name("freecad_measure.py")


def freecadcmd() -> str:
    path = shutil.which("freecadcmd")
    assert path, "FreeCAD (freecadcmd) is needed by this test: install freecad-python3"
    return path


def run(script: Path, home: Path, **env: str) -> subprocess.CompletedProcess[str]:
    """``freecadcmd script`` with ``env`` added; on a timeout its whole process group is ended.
    freecadcmd exits 0 even when the script raises, so callers check what the script wrote."""
    home.mkdir(parents=True, exist_ok=True)
    return run_bounded([freecadcmd(), str(script)], TIMEOUT_S, env={**os.environ, "HOME": str(home), **env},
                       merge_stderr=True)


def measure(document: Path, home: Path) -> dict[str, Any]:
    """Every solid of a saved document and every roller's contact (tests/freecad_measure.py)."""
    out = document.with_suffix(".measured.json")
    ran = run(MEASURE, home, CAMCORE_MEASURE_DOC=str(document), CAMCORE_MEASURE_OUT=str(out))
    assert ran.returncode == 0 and out.exists(), f"the measuring script wrote nothing for {document}: {ran.stdout}"
    result: dict[str, Any] = json.loads(out.read_text(encoding="utf-8"))
    return result


#: what FreeCAD's own STEP reader makes of a file: its volume, validity, closure, solids and area
READ_STEP = """import json, os
import Part
shape = Part.Shape()
shape.read(os.environ["CAMCORE_STEP"])
print("camcore:", json.dumps({"volume_mm3": shape.Volume, "valid": shape.isValid(), "closed": shape.isClosed(),
                              "solids": len(shape.Solids), "area_mm2": shape.Area}))
"""


def read_step(content: bytes, folder: Path) -> dict[str, Any]:
    """A STEP file read by FreeCAD (an independent reader): volume_mm3, valid, closed, solids, area_mm2."""
    step, script = folder / "solid.step", folder / "read_step.py"
    step.write_bytes(content)
    script.write_text(READ_STEP, encoding="utf-8")
    ran = run(script, folder / "home", CAMCORE_STEP=str(step))
    assert "camcore: " in ran.stdout, ran.stdout
    result: dict[str, Any] = json.loads(ran.stdout.split("camcore: ", 1)[1].splitlines()[0])
    return result
