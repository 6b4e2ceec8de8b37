"""The shape docs/architecture.md promises: no import cycle in camcore/ or service/, no module
over 500 lines, and a core that imports nothing of the web stack.

Imports are read from the source (ast), every one of them, those under ``TYPE_CHECKING``
and inside functions included: a cycle hidden in a function is still a cycle.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ("camcore", "service")
MAX_LINES = 500


def modules() -> dict[str, Path]:
    out = {}
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            name = ".".join(path.relative_to(ROOT).with_suffix("").parts).removesuffix(".__init__")
            out[name] = path
    return out


MODULES = modules()


def imports_of(name: str, path: Path) -> set[str]:
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            found |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join(parts + ([base] if base else []))
            found.add(base)
            found |= {f"{base}.{alias.name}" for alias in node.names}
    return found


def graph() -> dict[str, set[str]]:
    # a package's __init__ re-exports its children by design: edges into a package are left out
    packages = {name for name, path in MODULES.items() if path.name == "__init__.py"}
    return {name: {m for m in imports_of(name, path) if m in MODULES and m != name and m not in packages}
            for name, path in MODULES.items() if name not in packages}


def cycles(edges: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    found: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        for w in edges.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in edges:
        if v not in index:
            visit(v)
    return found


def test_the_checker_finds_a_cycle() -> None:
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert cycles({"a": {"b"}, "b": set()}) == []


def test_no_import_cycle() -> None:
    assert len(MODULES) > 40  # the packages were found
    assert cycles(graph()) == []


def test_no_module_over_500_lines() -> None:
    sizes = {name: len(path.read_text(encoding="utf-8").splitlines()) for name, path in MODULES.items()}
    assert {name: n for name, n in sizes.items() if n > MAX_LINES} == {}


def test_camcore_imports_no_web_stack() -> None:
    web = ("fastapi", "starlette", "uvicorn", "pydantic", "service", "httpx")
    offenders = {name: sorted(m for m in imports_of(name, path) if m.split(".")[0] in web)
                 for name, path in MODULES.items() if name.startswith("camcore")}
    assert {name: found for name, found in offenders.items() if found} == {}


def test_the_architecture_names_every_module() -> None:
    """docs/architecture.md draws the map: every module of both packages is on it (a package's
    ``__init__`` by its folder)."""
    text = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    missing = [str(path.relative_to(ROOT)) for path in MODULES.values()
               if (f"{path.parent.name}/" if path.name == "__init__.py" else path.name) not in text]
    assert missing == []
