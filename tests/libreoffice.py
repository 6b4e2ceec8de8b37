"""Headless LibreOffice for the tests: a second, independent reader of what the service writes.

Each call runs ``soffice --headless`` with its own user profile (a folder under the test's
tmp_path), so runs never share state with each other, with a desktop LibreOffice, or with
a parallel test. ``configure`` seeds a profile's settings (registrymodifications.xcu) before its first
start; ``run_basic`` runs a macro of the profile's own Basic library.
"""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path
from xml.sax.saxutils import escape, quoteattr

from tests.processes import run_bounded

#: a cold start with a new profile takes ~1–3 s here; a hung office must not hang the suite
TIMEOUT_S = 120

#: the settings a user changes so that a spreadsheet's WEBSERVICE() cells fetch when the
#: file opens (see docs/ecosystem.md): Tools ▸ Options ▸ LibreOffice Calc ▸ General ▸
#: "Update links when opening: Always" (0) ...
UPDATE_LINKS_ALWAYS = {("/org.openoffice.Office.Calc/Content/Update", "Link"): 0}


def trusted_location(folder: Path) -> dict[tuple[str, str], list[str]]:
    """... and the file's folder among Tools ▸ Options ▸ Security ▸ Macro Security ▸
    Trusted Sources ▸ Trusted File Locations (links update automatically only there)."""
    return {("/org.openoffice.Office.Common/Security/Scripting", "SecureURL"): [folder.resolve().as_uri()]}


def soffice() -> str:
    path = shutil.which("soffice") or shutil.which("libreoffice")
    assert path, "LibreOffice (soffice) is needed by this test: install libreoffice-draw and libreoffice-calc"
    return path


def configure(profile: Path, settings: dict[tuple[str, str], int | str | list[str]]) -> None:
    """Write ``{(node path, property): value}`` into a new profile's registrymodifications.xcu."""
    items = []
    for (node, prop), value in settings.items():
        text = "".join(f"<it>{escape(v)}</it>" for v in value) if isinstance(value, list) else escape(str(value))
        items.append(f"<item oor:path={quoteattr(node)}><prop oor:name={quoteattr(prop)} oor:op=\"fuse\">"
                     f"<value>{text}</value></prop></item>")
    user = profile / "user"
    user.mkdir(parents=True, exist_ok=True)
    (user / "registrymodifications.xcu").write_text(
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        '<oor:items xmlns:oor="http://openoffice.org/2001/registry" xmlns:xs="http://www.w3.org/2001/XMLSchema" '
        'xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">\n' + "\n".join(items) + "\n</oor:items>\n",
        encoding="utf-8")


def _run(profile: Path, args: list[str]) -> subprocess.CompletedProcess[str]:
    """soffice with these arguments, bounded in time (tests.processes)."""
    return run_bounded([soffice(), f"-env:UserInstallation={profile.resolve().as_uri()}", "--headless", "--norestore",
                        "--nolockcheck", *args], TIMEOUT_S)


def convert(source: str | Path, to: str, outdir: Path, profile: Path, infilter: str | None = None) -> Path:
    """``soffice --headless --convert-to <to>`` of ``source`` (a file or a URL) into ``outdir``.

    Returns the written file; fails with LibreOffice's own output when there is none.
    """
    outdir.mkdir(parents=True, exist_ok=True)
    args = [] if infilter is None else [f"--infilter={infilter}"]
    before = set(outdir.iterdir())
    run = _run(profile, [*args, "--convert-to", to, "--outdir", str(outdir), str(source)])
    made = sorted(set(outdir.iterdir()) - before)
    assert run.returncode == 0 and len(made) == 1, (
        f"soffice wrote {made} (exit {run.returncode}): {run.stdout} {run.stderr}")
    return made[0]


def run_basic(profile: Path, body: str) -> None:
    """Run ``Sub Main`` with this body (LibreOffice Basic) in a headless office on ``profile``.

    The macro is the profile's own (My Macros ▸ Standard ▸ Module1), which LibreOffice runs
    without asking; what it should write the caller checks. A Basic error would open a
    message box that nobody closes: the macro writes it to ``basic-error.txt`` instead.
    """
    module = profile / "user" / "basic" / "Standard" / "Module1.xba"
    error = profile / "basic-error.txt"
    if not module.exists():
        # a first start fills a new profile's Basic folder from LibreOffice's presets,
        # over anything written there before; settings written before it are kept
        first = _run(profile, ["--terminate_after_init"])
        assert first.returncode == 0 and module.exists(), f"no new profile: {first.stdout} {first.stderr}"
    module.write_text(
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        '<!DOCTYPE script:module PUBLIC "-//OpenOffice.org//DTD OfficeDocument 1.0//EN" "module.dtd">\n'
        '<script:module xmlns:script="http://openoffice.org/2000/script" script:name="Module1" '
        f'script:language="StarBasic">{escape(_with_error_file(body, error))}\n</script:module>\n',
        encoding="utf-8")
    error.unlink(missing_ok=True)
    run = _run(profile, ["macro:///Standard.Module1.Main"])
    assert run.returncode == 0, f"soffice exit {run.returncode}: {run.stdout} {run.stderr}"
    assert not error.exists(), f"the macro failed: {error.read_text(encoding='utf-8')}"


def _with_error_file(body: str, error: Path) -> str:
    return f"""Sub Main
  On Error GoTo Failed
{body}
  Exit Sub
Failed:
  f = FreeFile
  Open "{error}" For Output As #f
  Print #f, "Basic error " & Err & " at line " & Erl & ": " & Error$
  Close #f
End Sub"""
