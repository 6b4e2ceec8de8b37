"""The Dockerfile read as instructions (for the container and deployment tests)."""

from __future__ import annotations

import json
import shlex
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOCKERFILE = ROOT / "Dockerfile"


def instructions(path: Path = DOCKERFILE) -> list[tuple[str, str]]:
    """(INSTRUCTION, arguments) in order; comments dropped, backslash continuations joined."""
    result: list[tuple[str, str]] = []
    pending = ""
    for line in path.read_text(encoding="utf-8").splitlines():
        stripped = line.strip()
        if not pending and (not stripped or stripped.startswith("#")):
            continue
        if stripped.endswith("\\"):
            pending += stripped[:-1] + " "
            continue
        full = (pending + stripped).strip()
        pending = ""
        keyword, _, args = full.partition(" ")
        result.append((keyword.upper(), args.strip()))
    assert not pending, "Dockerfile ends inside a continued line"
    return result


def arguments(keyword: str, path: Path = DOCKERFILE) -> list[str]:
    """The arguments of every ``keyword`` instruction, in order."""
    return [args for kw, args in instructions(path) if kw == keyword]


def env(path: Path = DOCKERFILE) -> dict[str, str]:
    """The variables the image sets (ENV KEY=VALUE ..., the only form this Dockerfile uses)."""
    variables: dict[str, str] = {}
    for args in arguments("ENV", path):
        for item in shlex.split(args):
            key, sep, value = item.partition("=")
            assert sep, f"ENV {item!r}: use KEY=VALUE"
            variables[key] = value
    return variables


def exec_form(args: str) -> list[str]:
    """A CMD/HEALTHCHECK command in exec form (a JSON array); the shell form is not accepted."""
    command = json.loads(args)
    assert isinstance(command, list) and all(isinstance(a, str) for a in command), args
    return command


def cmd(path: Path = DOCKERFILE) -> list[str]:
    (args,) = arguments("CMD", path)
    return exec_form(args)


def healthcheck(path: Path = DOCKERFILE) -> tuple[dict[str, str], list[str]]:
    """HEALTHCHECK options (``--interval`` -> ``interval``) and its command."""
    (args,) = arguments("HEALTHCHECK", path)
    options_text, sep, command = args.partition(" CMD ")
    assert sep, "HEALTHCHECK needs a CMD"
    options = {}
    for option in options_text.split():
        name, _, value = option.removeprefix("--").partition("=")
        options[name] = value
    return options, exec_form(command)


def exposed_ports(path: Path = DOCKERFILE) -> list[int]:
    return [int(p.split("/")[0]) for args in arguments("EXPOSE", path) for p in args.split()]
