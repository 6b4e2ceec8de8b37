"""The table of every operation id, written into docs/api.md from the registry, and the list of
every operation id by tag, written into README.md from the app's document.

Usage: ``python -m scripts.operation_table`` (or ``--check`` to fail when either drifted).
The table sits between the markers ``<!-- operations: begin -->`` and ``<!-- operations: end -->``:
each operation with its formats, then its file twins, then the older paths kept as deprecated
aliases. The list sits between ``<!-- operation-ids: begin -->`` and ``<!-- operation-ids: end -->``:
the list the document's header ends with (service.openapi_layout.operation_list), every operation
that is not deprecated.
"""

from __future__ import annotations

import sys
from pathlib import Path

from service.app import create_app
from service.openapi_layout import operation_list
from service.operations import cells
from service.operations.factory import routes_of
from service.registry import OPERATIONS

ROOT = Path(__file__).resolve().parent.parent
TARGET = ROOT / "docs" / "api.md"
BEGIN, END = "<!-- operations: begin -->", "<!-- operations: end -->"
README = ROOT / "README.md"
LIST_BEGIN, LIST_END = "<!-- operation-ids: begin -->", "<!-- operation-ids: end -->"


def render() -> str:
    """The table, as markdown."""
    rows = ["| operation id | method and path | answers |", "|---|---|---|"]
    for operation in OPERATIONS:
        for route in routes_of(operation):
            where = f"{operation.method} `{route.path}`"
            if route.kind == "operation":
                answers = ", ".join(fmt.name for fmt in route.formats)
            elif route.kind == "twin":
                answers = f"{route.formats[0].name} (`{operation.id}` with `?format={route.formats[0].name}`)"
            else:
                answers = (f"{route.formats[0].name}; deprecated, the same as "
                           f"`{operation.twin_id(route.formats[0])}`")
            rows.append(f"| `{route.id}` | {where} | {answers} |")
    rows.append(f"| `{cells.OPERATION_ID}` | GET `{cells.PATH}` | text: one field of any POST computation's answer, "
                "for a spreadsheet cell |")
    return "\n".join(rows) + "\n"


def render_list() -> str:
    """The list of every operation id by tag, as markdown (the app's document's header's)."""
    app = create_app()
    return operation_list(app.openapi(), app.route_kinds) + "\n"


def updated(text: str, begin: str = BEGIN, end: str = END, made: str | None = None) -> str:
    """A text with what sits between the markers made anew (default: docs/api.md's table)."""
    head, rest = text.split(begin, 1)
    _, tail = rest.split(end, 1)
    return f"{head}{begin}\n{render() if made is None else made}{end}{tail}"


def main(argv: list[str]) -> int:
    targets = [(TARGET, updated(TARGET.read_text(encoding="utf-8"))),
               (README, updated(README.read_text(encoding="utf-8"), LIST_BEGIN, LIST_END, render_list()))]
    drifted = [path for path, new in targets if new != path.read_text(encoding="utf-8")]
    if "--check" in argv:
        for path in drifted:
            print(f"{path} lists other operations than the service: run python -m scripts.operation_table",
                  file=sys.stderr)
        return 1 if drifted else 0
    for path, new in targets:
        path.write_text(new, encoding="utf-8")
    print(f"wrote the operation table of {TARGET} and the operation list of {README}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
