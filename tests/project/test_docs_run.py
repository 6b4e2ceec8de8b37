"""Every code block of README.md and docs/*.md runs (issue 33, "Docs that run").

tests/docs_blocks.py finds the blocks and their kinds; each is one test here (id = file:line), run
as a user would paste it, with the service's address (``HOST:8000``, ``127.0.0.1:8000``) made a
live server's:

- ``sh``: bash in a folder of its own per page (the repository's top-level entries linked into it,
  so ``openapi/openapi.json`` resolves and downloads land in the folder), with ``set -e``; curl fails
  on an HTTP error status, and ``pip install NAME==VERSION`` checks that .venv holds that version
  instead of installing;
- ``console``: each ``$`` command with .venv's python first on PATH, its output compared line by line;
- ``python``: .venv's python, line numbers the page's; a one-line expression whose comment shows a
  number (``ms.characteristics.vm.value  # 1.7596…``) must round to it. A block importing the
  generated client runs after the page's ``openapi-python-client generate`` block, in its folder;
- ``typescript``: compiled (strict) and run with node in the project tests/clients/test_typescript_client.py
  builds (types generated from the app's document), ``// 0.17789`` comments checked the same way;
- ``formula``: every formula block in one headless LibreOffice Calc session, one sheet per block,
  typed into cells as a user types them (en-US), in a file loaded with links updated: each must give
  a number or text, no error; whole URLs must answer 200; ``→ number`` says what the cell shows;
- ``linked``: the named test exists and holds each key the marker names, as the block does;
- ``not-run`` and ``not-code``: the marker gives its reason.

A block with no kind fails, naming the markers: a new block cannot go unrun unnoticed.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import httpx
import pytest

from tests.clients.test_typescript_client import node_modules, project, run, tool, tsc  # noqa: F401 (fixtures)
from tests.docs_blocks import (
    ROOT,
    Block,
    all_blocks,
    formulas,
    input_cells,
    link_keys,
    python_with_checks,
    shown_value_matches,
    typescript_with_checks,
    url_literals,
)
from tests.libreoffice import UPDATE_LINKS_ALWAYS, configure, run_basic, trusted_location

BLOCKS = all_blocks()
VENV_BIN = Path(sys.executable).parent
#: what `openapi-python-client generate` writes, and so what a block using the generated client needs
CLIENT_PACKAGE = "camcore_client"
#: a shell block's commands, seconds each at most (a chart, a solid, a soffice start)
SH_TIMEOUT_S = 300

#: curl as the docs write it, but a 4xx or 5xx answer fails the block (curl alone exits 0 on those);
#: pip never reaches the network: the version a block pins must be the one the tests run with
SH_PRELUDE = r"""set -e -o pipefail
curl() { command curl --fail-with-body --silent --show-error "$@"; }
pip() {
  [ "$1" = install ] || { echo "docs run: only 'pip install NAME==VERSION' is checked, not pip $1" >&2; return 2; }
  shift
  for req in "$@"; do
    case $req in *==*) ;; *) echo "docs run: pip install $req: pin a version (NAME==VERSION)" >&2; return 2;; esac
    have=$(python -c 'import importlib.metadata, sys; print(importlib.metadata.version(sys.argv[1]))' "${req%%==*}")
    [ "$have" = "${req#*==}" ] || { echo "docs run: pip install $req, but the tests use $have" >&2; return 1; }
  done
}
"""

#: runs one python block: its code compiled under the page's name, checks of shown numbers builtin
PY_RUNNER = r"""import builtins, sys

def __doc_check__(value, shown, line):
    decimals = len(shown.partition(".")[2])
    got = f"{float(value):.{decimals}f}"
    if got != shown:
        raise AssertionError(f"{sys.argv[1]}:{line}: the value is {value!r}, {got} to the digits the docs show {shown}")
    return value

builtins.__doc_check__ = __doc_check__
with open(sys.argv[2], encoding="utf-8") as f:
    exec(compile(f.read(), sys.argv[1], "exec"), {"__name__": "__main__"})
"""


def _marks(block: Block) -> list[pytest.MarkDecorator]:
    """What a block needs: a live server (e2e), LibreOffice, node, the generator. Only python on the
    library stays in make test-fast: every other block runs programs (docs), which a new block may
    name without a marker of their own (freecadcmd, soffice...)."""
    kind, text = block.kind, block.text
    marks = []
    if block.uses_server() and kind in {"sh", "console", "python", "typescript", "formula"}:
        marks.append(pytest.mark.e2e)
    if kind in {"sh", "console", "typescript", "formula"} or (kind == "python" and block.uses_server()):
        marks.append(pytest.mark.docs)
    if kind == "formula" or (kind == "sh" and "soffice" in text):
        marks.append(pytest.mark.libreoffice)
    if kind == "typescript" or (kind == "sh" and re.search(r"\b(npm|node)\b", text)):
        marks.append(pytest.mark.node)
    if kind in {"sh", "python"} and ("openapi-python-client" in text or CLIENT_PACKAGE in text):
        marks.append(pytest.mark.generator)
    return marks


def _params() -> list[object]:
    return [pytest.param(block, id=block.id, marks=_marks(block)) for block in BLOCKS]


def _fail(block: Block, what: str, proc: subprocess.CompletedProcess[str]) -> str:
    return f"{block.id}: {what} (exit {proc.returncode})\n--- stdout\n{proc.stdout[-3000:]}\n--- stderr\n{proc.stderr[-3000:]}"


# -- the folders a page's blocks run in, and what ran there ------------------------------------------

class Pages:
    """One folder per page, as a user follows it: the repository's top-level entries linked in."""

    def __init__(self, root: Path) -> None:
        self.root = root
        self.ran: dict[str, subprocess.CompletedProcess[str]] = {}

    def folder(self, block: Block) -> Path:
        folder = self.root / str(block.path).replace("/", "_")
        if not folder.exists():
            folder.mkdir(parents=True)
            (folder / "home").mkdir()
            for entry in ROOT.iterdir():
                if not entry.name.startswith("."):
                    (folder / entry.name).symlink_to(entry)
        return folder

    def env(self, block: Block) -> dict[str, str]:
        # HOME in the folder: soffice's profile and npm's cache stay out of the user's
        return {**os.environ, "PATH": f"{VENV_BIN}{os.pathsep}{os.environ['PATH']}",
                "HOME": str(self.folder(block) / "home")}

    def sh(self, block: Block, request: pytest.FixtureRequest) -> subprocess.CompletedProcess[str]:
        """The block run once (a later block of the page may need what it made)."""
        if block.id not in self.ran:
            folder = self.folder(block)
            script = folder / f"block-{block.line}.sh"
            script.write_text(SH_PRELUDE + _text(block, request), encoding="utf-8")
            self.ran[block.id] = subprocess.run(["bash", script.name], check=False, cwd=folder, env=self.env(block),
                                                capture_output=True, text=True, timeout=SH_TIMEOUT_S)
        return self.ran[block.id]


@pytest.fixture(scope="module")
def pages(tmp_path_factory: pytest.TempPathFactory) -> Pages:
    return Pages(tmp_path_factory.mktemp("pages"))


def _text(block: Block, request: pytest.FixtureRequest) -> str:
    """The block's text, with a live server's address if it names the service's."""
    return block.live(request.getfixturevalue("base_url")) if block.uses_server() else block.text


# -- the blocks ------------------------------------------------------------------------------------

@pytest.mark.parametrize("block", _params())
def test_block_runs(block: Block, request: pytest.FixtureRequest) -> None:
    kind = block.kind
    assert kind is not None, (
        f"{block.id}: a ```{block.language} block this test cannot run. Give it a language it runs (sh, console, "
        "python, ts), write spreadsheet formulas one per line starting with =, or put a marker on the line "
        "before the fence: <!-- not-run: why it cannot run here -->, <!-- not-code: what it is (an answer, "
        'a listing) -->, or <!-- run: tests/<file>.py "key" … --> when a test runs it already')
    {"sh": _sh, "console": _console, "python": _python, "typescript": _typescript, "formula": _formula,
     "linked": _linked, "not-run": _reason, "not-code": _reason}[kind](block, request)


def _reason(block: Block, request: pytest.FixtureRequest) -> None:
    reason = block.markers.get("not-run", block.markers.get("not-code", ""))
    assert len(reason.split()) >= 2, f"{block.id}: say why in the marker (<!-- not-run: why -->), not {reason!r}"


def _linked(block: Block, request: pytest.FixtureRequest) -> None:
    path, keys = link_keys(block.markers["run"])
    test = ROOT / path
    assert test.is_file() and re.match(r"tests/.+/test_\w+\.py$", path), f"{block.id}: no test module {path}"
    source = test.read_text(encoding="utf-8")
    assert re.search(r"^def test_", source, re.MULTILINE), f"{block.id}: {path} has no test"
    assert keys, f'{block.id}: name the block\'s key lines that {path} holds: <!-- run: {path} "key" … -->'
    assert [k for k in keys if k not in block.text] == [], f"{block.id}: keys not in the block"
    assert [k for k in keys if k not in source] == [], f"{block.id}: keys {path} does not hold"


def _sh(block: Block, request: pytest.FixtureRequest) -> None:
    proc = request.getfixturevalue("pages").sh(block, request)
    assert proc.returncode == 0, _fail(block, "the shell block failed", proc)


def _console(block: Block, request: pytest.FixtureRequest) -> None:
    pages: Pages = request.getfixturevalue("pages")
    session = re.split(r"^\$ ", _text(block, request), flags=re.MULTILINE)
    assert session[0].strip() == "" and len(session) > 1, f"{block.id}: a console block starts with '$ '"
    for step in session[1:]:
        command, *shown = step.rstrip("\n").split("\n")
        proc = subprocess.run(["bash", "-c", command], check=False, cwd=pages.folder(block), env=pages.env(block),
                              capture_output=True, text=True, timeout=SH_TIMEOUT_S)
        assert (proc.stdout + proc.stderr).rstrip("\n").split("\n") == shown, _fail(block, f"$ {command}", proc)


def _python(block: Block, request: pytest.FixtureRequest) -> None:
    pages: Pages = request.getfixturevalue("pages")
    folder = pages.folder(block)
    if re.search(rf"^\s*(from|import) {CLIENT_PACKAGE}\b", block.text, re.MULTILINE):
        generate = [b for b in BLOCKS if b.path == block.path and b.kind == "sh"
                    and "openapi-python-client generate" in b.text]
        assert generate, f"{block.id} imports {CLIENT_PACKAGE}: its page has no block that generates it"
        proc = pages.sh(generate[0], request)
        assert proc.returncode == 0, _fail(generate[0], "the client's generation failed", proc)
    source = folder / f"block-{block.line}.py"
    source.write_text(python_with_checks("\n" * block.line + _text(block, request)), encoding="utf-8")
    (folder / "run_block.py").write_text(PY_RUNNER, encoding="utf-8")
    proc = subprocess.run([str(VENV_BIN / "python"), "run_block.py", str(block.path), source.name],
                          cwd=folder, env=pages.env(block), capture_output=True, text=True, timeout=SH_TIMEOUT_S,
                          check=False)
    assert proc.returncode == 0, _fail(block, "the python block failed", proc)


def _typescript(block: Block, request: pytest.FixtureRequest) -> None:
    folder: Path = request.getfixturevalue("project")
    name = f"doc_{block.path.stem}_{block.line}"
    text = block.live(request.getfixturevalue("base_url"))
    (folder / "src" / f"{name}.ts").write_text(typescript_with_checks(text), encoding="utf-8")
    proc = tsc(folder, "-p", ".")
    assert proc.returncode == 0, _fail(block, "tsc (strict) refused the block", proc)
    proc = run(tool("node"), folder / "dist" / f"{name}.js", cwd=folder, timeout=120)
    assert proc.returncode == 0, _fail(block, "node failed running the block", proc)


# -- formulas: every block in one LibreOffice Calc session -----------------------------------------

#: the column the formulas are typed into (Z: clear of the input cells a formula refers to)
FORMULA_COLUMN = 25
FORMULA_BLOCKS = [b for b in BLOCKS if b.kind == "formula"]


def _sheets(inputs: list[dict[str, float]]) -> str:
    """A flat-XML spreadsheet, one sheet per formula block holding its input cells."""
    tables = []
    for i, cells in enumerate(inputs):
        rows: dict[int, dict[int, float]] = {}
        for name, value in cells.items():
            col, row = re.fullmatch(r"([A-Y])(\d+)", name).groups()  # type: ignore[union-attr]
            rows.setdefault(int(row) - 1, {})[ord(col) - ord("A")] = value
        body = ""
        for r in range(max(rows, default=-1) + 1):
            cols = rows.get(r, {})
            body += "<table:table-row>" + "".join(
                f'<table:table-cell office:value-type="float" office:value="{cols[c]!r}"/>' if c in cols
                else "<table:table-cell/>" for c in range(max(cols, default=0) + 1)) + "</table:table-row>"
        tables.append(f'<table:table table:name="b{i}">{body or "<table:table-row><table:table-cell/></table:table-row>"}'
                      "</table:table>")
    return ('<?xml version="1.0" encoding="UTF-8"?>\n<office:document '
            'xmlns:office="urn:oasis:names:tc:opendocument:xmlns:office:1.0" '
            'xmlns:table="urn:oasis:names:tc:opendocument:xmlns:table:1.0" office:version="1.3" '
            'office:mimetype="application/vnd.oasis.opendocument.spreadsheet"><office:body><office:spreadsheet>'
            + "".join(tables) + "</office:spreadsheet></office:body></office:document>\n")


def _basic_string(text: str) -> str:
    return '"' + text.replace('"', '""') + '"'


@pytest.fixture(scope="module")
def calc(base_url: str, tmp_path_factory: pytest.TempPathFactory) -> dict[str, list[tuple[int, int, str, str]]]:
    """Each formula block's cells after Calc computed them: (error code, result type, value, text).

    The file is loaded as a user opens it with links allowed (docs/ecosystem.md's two settings,
    UpdateDocMode according to them), then each formula is typed into its cell as en-US text
    (FormulaLocal: the function names and separators a user types) and the sheet recalculated."""
    runnable = FORMULA_BLOCKS
    tmp = tmp_path_factory.mktemp("calc")
    folder = tmp / "sheets"
    folder.mkdir()
    sheet = folder / "docs.fods"
    sheet.write_text(_sheets([input_cells(b.markers.get("cells", "")) for b in runnable]), encoding="utf-8")
    out = tmp / "cells.tsv"
    profile = tmp / "profile"
    configure(profile, UPDATE_LINKS_ALWAYS | trusted_location(folder))
    typed, read = [], []
    for i, block in enumerate(runnable):
        for row, (formula, _) in enumerate(formulas(block.live(base_url))):
            cell = f"doc.Sheets.getByIndex({i}).getCellByPosition({FORMULA_COLUMN}, {row})"
            typed.append(f"  {cell}.FormulaLocal = {_basic_string(formula)}")
            # one line per cell; line breaks and tabs of a text answer written as \\n, \\t
            read.append(f"  c = {cell}\n  Print #f, {i} & Chr(9) & c.getError() & Chr(9) & c.FormulaResultType2 & "
                        "Chr(9) & c.getValue() & Chr(9) & Replace(Replace(Replace(c.getString(), Chr(9), \"\\t\"), "
                        "Chr(10), \"\\n\"), Chr(13), \"\\r\")")
    run_basic(profile, f"""
  Dim load(1) As New com.sun.star.beans.PropertyValue
  load(0).Name = "Hidden" : load(0).Value = True
  load(1).Name = "UpdateDocMode" : load(1).Value = com.sun.star.document.UpdateDocMode.ACCORDING_TO_CONFIG
  doc = StarDesktop.loadComponentFromURL("{sheet.resolve().as_uri()}", "_blank", 0, load())
{chr(10).join(typed)}
  doc.calculateAll()
  f = FreeFile
  Open "{out}" For Output As #f
{chr(10).join(read)}
  Close #f
  doc.close(True)""")
    results: dict[str, list[tuple[int, int, str, str]]] = {b.id: [] for b in runnable}
    for line in out.read_text(encoding="utf-8").splitlines():
        index, error, result_type, value, text = line.split("\t", 4)
        results[runnable[int(index)].id].append((int(error), int(result_type), value, text))
    return results


#: com.sun.star.sheet.FormulaResult
VALUE, STRING = 1, 2


def _formula(block: Block, request: pytest.FixtureRequest) -> None:
    base_url = request.getfixturevalue("base_url")
    cells = request.getfixturevalue("calc")[block.id]
    lines = formulas(block.live(base_url))
    assert len(cells) == len(lines), f"{block.id}: Calc gave {len(cells)} cells for {len(lines)} formulas"
    for (formula, says), (error, result_type, value, text) in zip(lines, cells):
        assert error == 0 and result_type in {VALUE, STRING}, f"{block.id}: {formula} gives {text} (error {error})"
        assert not text.lstrip().startswith('{"detail"'), f"{block.id}: {formula} gives an error answer: {text}"
        for url in url_literals(formula):
            answer = httpx.get(url, timeout=30)
            assert answer.status_code == 200, f"{block.id}: {url} answers {answer.status_code}: {answer.text}"
        shown = re.match(r"(-?\d+(?:\.\d+)?)", says)
        if shown and "(text)" in says:  # the text of the answer, every digit
            assert (result_type, text) == (STRING, shown[1]), f"{block.id}: {formula} gives {text}, not {says}"
        elif shown:
            assert result_type == VALUE and shown_value_matches(float(value), shown[1]), (
                f"{block.id}: {formula} gives {value}, not {says}")


def test_formula_inputs_are_given() -> None:
    # a cell a formula refers to (outside its strings) holds a number the block's marker gives
    for block in FORMULA_BLOCKS:
        refs = {m for f, _ in formulas(block.text) for m in re.findall(r'(?<![\w"/?=&.])([A-Z]{1,2}\d+)\b',
                                                                          re.sub(r'"[^"]*"', '""', f))}
        given = set(input_cells(block.markers.get("cells", "")))
        assert refs <= given, f"{block.id} refers to {sorted(refs - given)}: give them <!-- cells: A2=0.1833 -->"


def test_every_page_is_read() -> None:
    # README.md and every docs/*.md page, and a block kind known for each of the languages in use
    assert {str(b.path) for b in BLOCKS} >= {"README.md", "docs/ecosystem.md"}
    assert {b.kind for b in BLOCKS} >= {"sh", "python", "typescript", "formula", "linked", "not-run", "not-code"}
