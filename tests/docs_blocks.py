"""The fenced code blocks of README.md and docs/*.md, with their language, place and kind.

tests/project/test_docs_run.py runs each by its kind against a live server, so every block a user
would paste is checked (issue 33, "Docs that run"). A block's kind comes from, in this order:

1. a marker, an HTML comment on the lines right before its opening fence:
   ``<!-- not-run: why -->`` (code that cannot run here: Excel Power Query, a Google Sheets-only
   formula), ``<!-- not-code: what it is -->`` (an answer sample, a listing, a diagram) or
   ``<!-- run: tests/<file>.py "key" "key" … -->`` (run by that test already; every key is text the
   block and that test both hold). ``<!-- cells: A2=0.1833 -->`` gives the input cells a formula
   block refers to, beside its kind;
2. the fence's language: ``sh``/``bash``/``shell``, ``console`` (``$`` commands, each followed by
   what it prints), ``python``/``py``, ``ts``/``typescript``;
3. a block without a language whose every line starts with ``=``: spreadsheet formulas.

Anything else has no kind, and the test of that block fails saying how to mark it.
"""

from __future__ import annotations

import ast
import re
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: the Markdown files a user reads for recipes
DOCS = (ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md")))

LANGUAGES = {"sh": "sh", "bash": "sh", "shell": "sh", "console": "console", "python": "python", "py": "python",
             "ts": "typescript", "typescript": "typescript"}
MARKER_KINDS = {"run": "linked", "not-run": "not-run", "not-code": "not-code"}

_FENCE = re.compile(r"^(?P<indent>\s*)(?P<fence>`{3,}|~{3,})\s*(?P<info>[^`]*)$")
_MARKER = re.compile(r"^\s*<!--\s*(?P<name>[a-z-]+):\s*(?P<text>.*?)\s*-->\s*$")
#: the service's address in the docs: ``HOST`` in docs/ecosystem.md, the default port on loopback in the README
_ADDRESSES = ("HOST:8000", "127.0.0.1:8000")


@dataclass(frozen=True)
class Block:
    path: Path  #: relative to the repository root
    line: int  #: the opening fence's line, 1-based
    language: str  #: the fence's info word, lower case ('' when none)
    text: str  #: the lines between the fences, without the fence's indentation
    markers: dict[str, str] = field(default_factory=dict)  #: marker name → its text

    @property
    def id(self) -> str:
        return f"{self.path}:{self.line}"

    @property
    def kind(self) -> str | None:
        """linked, not-run, not-code, sh, console, python, typescript, formula; None when unknown."""
        for name, kind in MARKER_KINDS.items():
            if name in self.markers:
                return kind
        if self.language in LANGUAGES:
            return LANGUAGES[self.language]
        lines = [line for line in self.text.splitlines() if line.strip()]
        if not self.language and lines and all(line.lstrip().startswith("=") for line in lines):
            return "formula"
        return None

    def live(self, base_url: str) -> str:
        """The text with the service's address (``HOST:8000``, ``127.0.0.1:8000``) made the live server's."""
        host_port = base_url.split("://", 1)[1]
        text = self.text
        for address in _ADDRESSES:
            text = text.replace(address, host_port)
        return text

    def uses_server(self) -> bool:
        return any(address in self.text for address in _ADDRESSES)


def blocks(path: Path) -> list[Block]:
    """The fenced blocks of one Markdown file, in order."""
    lines = path.read_text(encoding="utf-8").splitlines()
    found = []
    i = 0
    while i < len(lines):
        opening = _FENCE.match(lines[i])
        if not opening:
            i += 1
            continue
        indent, fence = len(opening["indent"]), opening["fence"]
        closing = re.compile(rf"^\s{{0,{indent + 3}}}{re.escape(fence[0])}{{{len(fence)},}}\s*$")
        end = next((j for j in range(i + 1, len(lines)) if closing.match(lines[j])), len(lines))
        # the fence's indentation off each line (a line indented less loses what it has)
        body = [line[indent:] if not line[:indent].strip() else line.lstrip() for line in lines[i + 1:end]]
        markers = {}
        j = i - 1
        while j >= 0 and (marker := _MARKER.match(lines[j])):
            markers.setdefault(marker["name"], marker["text"])
            j -= 1
        found.append(Block(path.relative_to(ROOT), i + 1, opening["info"].split()[0].lower()
                           if opening["info"].strip() else "", "\n".join(body) + "\n", markers))
        i = end + 1
    return found


def all_blocks() -> list[Block]:
    return [block for path in DOCS for block in blocks(path)]


def link_keys(marker: str) -> tuple[str, list[str]]:
    """``tests/x.py "key" "key"`` → the test's path and the keys."""
    path, _, rest = marker.partition(" ")
    return path, re.findall(r'"([^"]+)"', rest)


def input_cells(marker: str) -> dict[str, float]:
    """``A2=0.1833, B3=1`` → {"A2": 0.1833, "B3": 1.0}."""
    cells = {}
    for item in filter(None, (part.strip() for part in marker.split(","))):
        name, _, value = item.partition("=")
        cells[name.strip().upper()] = float(value)
    return cells


#: a number a comment says a line gives: "# 1.7596…", "// 0.17789 (INDEXMAN MS table, T = 0.30)"
_SHOWN = r"(?P<shown>-?\d+(?:\.\d+)?)(?:…|\.\.\.)?(?:\s|\(|$)"


def shown_value_matches(value: float, shown: str) -> bool:
    """Whether ``value`` is ``shown`` to the decimals shown (the docs round: 1.7596… for 1.759603)."""
    decimals = len(shown.partition(".")[2])
    return f"{float(value):.{decimals}f}" == shown


def python_with_checks(source: str) -> str:
    """The source with each one-line expression statement whose comment shows a number
    (``ms.characteristics.vm.value  # 1.7596…``) made a call of ``__doc_check__(value, shown, line)``;
    lines keep their numbers."""
    lines = source.splitlines()
    for node in ast.walk(ast.parse(source)):
        if not (isinstance(node, ast.Expr) and node.lineno == node.end_lineno) or node.end_col_offset is None:
            continue
        line = lines[node.lineno - 1]
        comment = re.match(r"\s*#\s*" + _SHOWN, line[node.end_col_offset:])
        if comment:
            expression = line[node.col_offset:node.end_col_offset]
            lines[node.lineno - 1] = (line[:node.col_offset] + f"__doc_check__({expression}, {comment['shown']!r}, "
                                      f"{node.lineno})" + line[node.end_col_offset:])
    return "\n".join(lines) + "\n"


_TS_SHOWN = re.compile(r"^(?P<indent>\s*)(?P<expression>[\w$?.\[\]]+);\s*//\s*" + _SHOWN)


def typescript_with_checks(source: str) -> str:
    """The same for TypeScript: ``data?.s[30];  // 0.17789`` throws unless the value rounds to it."""
    out = []
    for line in source.splitlines():
        match = _TS_SHOWN.match(line)
        if match:
            shown = match["shown"]
            decimals = len(shown.partition(".")[2])
            line = (f"{match['indent']}if (Number({match['expression']}).toFixed({decimals}) !== {shown!r}) "
                    f"{{ throw new Error(`{match['expression']} is ${{{match['expression']}}}, the docs show {shown}`); }}")
        out.append(line)
    return "\n".join(out) + "\n"


#: a formula line, and what the docs say it gives after an arrow: ``=VALUE(…)   → 0.1778…``
_FORMULA = re.compile(r"^(?P<formula>=.*?)(?:\s+→\s*(?P<says>.*))?$")


def formulas(text: str) -> list[tuple[str, str]]:
    """The formulas of a formula block with what the docs say each gives ('' when nothing)."""
    found = []
    for line in text.splitlines():
        if line.strip():
            match = _FORMULA.match(line.strip())
            assert match, line
            found.append((match["formula"].rstrip(), (match["says"] or "").strip()))
    return found


def url_literals(formula: str) -> list[str]:
    """The whole URLs a formula fetches: string literals starting http not joined to anything with &."""
    return [m[1] for m in re.finditer(r'"(https?://[^"]*)"(?!\s*&)', formula)]
