"""The table of every operation id, written into docs/api.md from the registry.

Usage: ``python -m scripts.operation_table`` (or ``--check`` to fail when docs/api.md drifted).
The table sits between the markers ``<!-- operations: begin -->`` and ``<!-- operations: end -->``:
each operation with its formats, then its file twins, then the older paths kept as deprecated
aliases.
"""

from __future__ import annotations

import sys
from pathlib import Path

from service.operations import cells
from service.operations.factory import routes_of
from service.registry import OPERATIONS

TARGET = Path(__file__).resolve().parent.parent / "docs" / "api.md"
BEGIN, END = "<!-- operations: begin -->", "<!-- operations: end -->"


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


def updated(text: str) -> str:
    """docs/api.md's text with the table between the markers made anew."""
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    return f"{head}{BEGIN}\n{render()}{END}{tail}"


def main(argv: list[str]) -> int:
    text = TARGET.read_text(encoding="utf-8")
    new = updated(text)
    if "--check" in argv:
        if new != text:
            print(f"{TARGET} lists other operations than the registry: run python -m scripts.operation_table",
                  file=sys.stderr)
            return 1
        return 0
    TARGET.write_text(new, encoding="utf-8")
    print(f"wrote the operation table of {TARGET}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
