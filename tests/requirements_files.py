"""Requirement files and names read the way pip reads them (for the packaging tests)."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def normalise(name: str) -> str:
    """A project name in PEP 503 normal form (``Fastapi_Offline`` -> ``fastapi-offline``)."""
    return re.sub(r"[-_.]+", "-", name).lower()


def requirement_name(requirement: str) -> str:
    """The project name of a requirement string (``numpy>=2.0`` -> ``numpy``)."""
    return normalise(re.split(r"[=<>!~;\[ (]", requirement.strip(), maxsplit=1)[0])


def pins(path: Path, follow: bool = True) -> dict[str, str]:
    """name -> pinned version in a requirements file; ``-r other`` lines followed when ``follow``."""
    result: dict[str, str] = {}
    for raw in path.read_text(encoding="utf-8").splitlines():
        line = raw.split("#")[0].strip()
        if not line:
            continue
        if line.startswith("-r "):
            if follow:
                result.update(pins(path.parent / line[3:].strip()))
            continue
        assert not line.startswith("-"), f"{path.name}: unexpected option {line!r}"
        name, sep, version = line.partition("==")
        assert sep and version, f"{path.name}: {line!r} is not pinned with =="
        result[normalise(name)] = version
    return result
