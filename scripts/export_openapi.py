"""Write openapi/openapi.json from ``app.openapi()`` (no server is started).

Usage: ``python -m scripts.export_openapi`` (or ``--check`` to fail when it drifted).

Keys are sorted (a stable, reviewable diff), except the media types of a ``content`` map,
which keep the app's order: JSON first where an operation also answers CSV or a file, because
some generators (openapi-python-client) read only the first media type they know.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

from service.app import create_app
from service.settings import Settings

TARGET = Path(__file__).resolve().parent.parent / "openapi" / "openapi.json"


def _ordered(node: Any, keep_order: bool = False) -> Any:
    """The document with every object's keys sorted, but a ``content`` map's kept in order."""
    if isinstance(node, dict):
        keys = list(node) if keep_order else sorted(node)
        return {k: _ordered(node[k], keep_order=k == "content" and not keep_order) for k in keys}
    if isinstance(node, list):
        return [_ordered(x) for x in node]
    return node


def render() -> str:
    spec = create_app(Settings()).openapi()
    return json.dumps(_ordered(spec), indent=2, ensure_ascii=False) + "\n"


def main(argv: list[str]) -> int:
    text = render()
    if "--check" in argv:
        if not TARGET.exists() or TARGET.read_text(encoding="utf-8") != text:
            print(f"{TARGET} is out of date: run python -m scripts.export_openapi", file=sys.stderr)
            return 1
        return 0
    TARGET.parent.mkdir(parents=True, exist_ok=True)
    TARGET.write_text(text, encoding="utf-8")
    print(f"wrote {TARGET}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
