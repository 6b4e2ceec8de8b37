"""Headless LibreOffice for the tests: a second, independent reader of what the service writes.

Each call runs ``soffice --headless --convert-to`` with its own fresh user profile (a
folder under the test's tmp_path), so runs never share state with each other, with a
desktop LibreOffice, or with a parallel test; ``configure`` seeds that profile with
settings (registrymodifications.xcu) before the first start.
"""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path
from xml.sax.saxutils import escape

#: a cold start with a new profile takes ~1–3 s here; a hung office must not hang the suite
TIMEOUT_S = 120


def soffice() -> str:
    path = shutil.which("soffice") or shutil.which("libreoffice")
    assert path, "LibreOffice (soffice) is needed by this test: install libreoffice-draw and libreoffice-calc"
    return path


def configure(profile: Path, settings: dict[tuple[str, str], str | int | bool]) -> None:
    """Write ``{(node path, property): value}`` into a new profile's registrymodifications.xcu."""
    items = []
    for (node, prop), value in settings.items():
        text = str(value).lower() if isinstance(value, bool) else str(value)
        items.append(f'<item oor:path="{escape(node)}"><prop oor:name="{escape(prop)}" oor:op="fuse">'
                     f'<value>{escape(text)}</value></prop></item>')
    user = profile / "user"
    user.mkdir(parents=True, exist_ok=True)
    (user / "registrymodifications.xcu").write_text(
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        '<oor:items xmlns:oor="http://openoffice.org/2001/registry" xmlns:xs="http://www.w3.org/2001/XMLSchema" '
        'xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">\n' + "\n".join(items) + "\n</oor:items>\n",
        encoding="utf-8")


def convert(source: str | Path, to: str, outdir: Path, profile: Path, infilter: str | None = None) -> Path:
    """``soffice --headless --convert-to <to>`` of ``source`` (a file or a URL) into ``outdir``.

    Returns the written file; fails with LibreOffice's own output when there is none.
    """
    outdir.mkdir(parents=True, exist_ok=True)
    cmd = [soffice(), f"-env:UserInstallation={profile.resolve().as_uri()}", "--headless", "--norestore",
           "--nolockcheck"]
    if infilter is not None:
        cmd.append(f"--infilter={infilter}")
    cmd += ["--convert-to", to, "--outdir", str(outdir), str(source)]
    before = set(outdir.iterdir())
    run = subprocess.run(cmd, capture_output=True, text=True, timeout=TIMEOUT_S, check=False)
    made = sorted(set(outdir.iterdir()) - before)
    assert run.returncode == 0 and len(made) == 1, (
        f"soffice wrote {made} (exit {run.returncode}): {run.stdout} {run.stderr}")
    return made[0]
