"""The repository stands on its own: nothing tracked points outside it, and docs/api.md
documents every path the app serves.

A user who clones the repository has only what git tracks. A file that sends them to a
sibling folder of the repository, to an absolute path on the machine it was written on, or
to the background documents the project was specified from (the patterns are below) sends
them nowhere: the contract is docs/api.md, and the sources are cited by their keys in
docs/sources.md.
"""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

from service.app import create_app

ROOT = Path(__file__).resolve().parents[2]
API_DOC = ROOT / "docs" / "api.md"

# The patterns are assembled from pieces so that this file does not match itself.
_SHARED = re.escape("../" + "shared")
#: an absolute path under the work root (slash, "work", slash), not preceded by a path or word character
_WORK = r"(?<![\w.~/-])" + re.escape("/" + "work/")
#: the background documents, by file name (docs/api.md is lower case and is not matched)
_BACKGROUND = r"\b(?:" + "|".join(re.escape(n + ".md") for n in ("MISSION", "STYLE", "API")) + r")\b"
OUTSIDE_REFERENCE = re.compile(f"{_SHARED}|{_WORK}|{_BACKGROUND}")


def tracked_files() -> list[Path]:
    """Every file git tracks in this checkout (not a checkout: the test fails, it does not skip)."""
    out = subprocess.run(["git", "-C", str(ROOT), "ls-files", "-z"], check=True, capture_output=True).stdout
    return [ROOT / name for name in out.decode("utf-8").split("\0") if name]


def outside_references(paths: list[Path]) -> list[str]:
    """``path:line: text`` for each line of a text file that refers outside the repository.

    Binary files (a NUL byte in them) are skipped; text is read as UTF-8 with replacement,
    so a stray byte cannot hide a line.
    """
    found = []
    for path in paths:
        if not path.is_file():  # deleted in the work tree but still in the index
            continue
        data = path.read_bytes()
        if b"\0" in data:
            continue
        for number, line in enumerate(data.decode("utf-8", errors="replace").splitlines(), 1):
            if OUTSIDE_REFERENCE.search(line):
                shown = path.relative_to(ROOT) if path.is_relative_to(ROOT) else path
                found.append(f"{shown}:{number}: {line.strip()[:160]}")
    return found


def test_no_tracked_file_refers_outside_the_repository() -> None:
    files = tracked_files()
    assert len(files) > 50, f"git ls-files listed only {len(files)} files: is this the repository?"
    bad = outside_references(files)
    assert not bad, ("tracked files refer to files a clone does not have; cite docs/api.md or a key of "
                     "docs/sources.md instead:\n" + "\n".join(bad))


def test_the_detector_finds_each_kind_of_outside_reference(tmp_path: Path) -> None:
    # what the test above must catch, and what it must leave alone; built with "+" so that
    # this file itself holds none of them
    shared, work = "../" + "shared", "/" + "work/"
    lines = {
        f"see {shared}/reference/makino.txt": True,
        f"open {work}shared/notes.txt": True,
        f"({work}main/.venv/bin/python)": True,
        "as MISSION" + ".md says": True,
        "STYLE" + ".md": True,
        "the contract (API" + ".md)": True,
        "the contract (docs/api.md)": False,
        f"network{work}queue and homework/": False,
        "Makino (1977), eq. (11)": False,
    }
    text = tmp_path / "sample.txt"
    text.write_text("\n".join(lines), encoding="utf-8")
    found = outside_references([text])
    expected = [i for i, (_, bad) in enumerate(lines.items(), 1) if bad]
    assert [int(f.split(":")[1]) for f in found] == expected, found
    binary = tmp_path / "image.png"
    binary.write_bytes(b"\x89PNG\0" + shared.encode())
    assert outside_references([binary]) == []


def served_operations() -> list[tuple[str, str, str]]:
    """(method, path, operation id) of every operation the app serves under /v1 and /health.

    Read from the app's own OpenAPI document, which FastAPI builds from the app's routes
    (the routers are included lazily, so ``app.routes`` does not list them one by one);
    the only routes left out of it are the documentation pages and their assets.
    """
    ops = []
    for path, operations in create_app().openapi()["paths"].items():
        if path.startswith("/v1/") or path == "/health":
            for method, operation in operations.items():
                ops.append((method.upper(), path, operation["operationId"]))
    return sorted(ops)


def test_api_doc_covers_every_served_path() -> None:
    doc = API_DOC.read_text(encoding="utf-8")
    ops = served_operations()
    assert len(ops) >= 17, ops  # the app's routes were found
    # each operation has its own entry, "`METHOD /path`" (its file twins and older paths are in the
    # table: the same answer in one format), and every route a row in the operation-id table
    from service.registry import OPERATIONS

    operations = {(op.method, op.path) for op in OPERATIONS}
    missing_entry = [f"{m} {p}" for m, p, _ in ops if (m, p) in operations and f"`{m} {p}`" not in doc]
    missing_row = [f"{op_id}: {m} {p}" for m, p, op_id in ops if f"| `{op_id}` | {m} `{p}` |" not in doc]
    assert not missing_entry, f"docs/api.md has no entry for: {missing_entry}"
    assert not missing_row, f"docs/api.md's operation-id table lacks: {missing_row}"


def test_files_named_in_the_docs_exist() -> None:
    # docs/sources.md says where each source is used, by file (and test) name: modules that move
    # must take their citations along
    named = set()
    for doc in (API_DOC, ROOT / "docs" / "sources.md"):
        text = doc.read_text(encoding="utf-8")
        named |= set(re.findall(r"`((?:camcore|service|tests|scripts|bench)/[\w./]*?)(?:::\w+)?`", text))
    assert len(named) > 20, named  # the pattern found the file names
    missing = sorted(name for name in named if not (ROOT / name).exists())
    assert not missing, f"docs name files that do not exist: {missing}"


def test_every_setting_is_documented_with_its_default() -> None:
    from service.settings import Settings

    api = (ROOT / "docs" / "api.md").read_text(encoding="utf-8")
    rows = {line.split("|")[1].strip(" `"): line.split("|")[2] for line in api.splitlines()
            if line.startswith("| `CAMCORE_")}
    for name, field in Settings.model_fields.items():
        variable = f"CAMCORE_{name.upper()}"
        assert variable in rows, f"{variable} is not in docs/api.md's settings table"
        default = field.default
        if isinstance(default, (int, float)) and not isinstance(default, bool):
            shown = rows[variable].split("(")[0].strip(" `")
            assert float(shown) == float(default), (variable, shown, default)
