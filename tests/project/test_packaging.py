"""The project as an installable library, and its two pinned requirement files.

requirements.lock pins what the library and the service need at run time (the container
installs it alone); requirements-dev.lock adds the development and test tools on top of it
(`-r requirements.lock`); make installs the latter and then this project, editable.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tomllib
import zipfile
from importlib import metadata
from pathlib import Path

from packaging.requirements import Requirement

from tests.requirements_files import normalise, pins, requirement_name

ROOT = Path(__file__).resolve().parents[2]
PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
RUNTIME = {requirement_name(r) for r in PROJECT["dependencies"]}
DEV_TOOLS = {requirement_name(r) for r in PROJECT["optional-dependencies"]["dev"]}
RUNTIME_LOCK = pins(ROOT / "requirements.lock")
DEV_LOCK_OWN = pins(ROOT / "requirements-dev.lock", follow=False)


def closure(names: set[str]) -> set[str]:
    """The installed distributions ``names`` need, transitively (markers evaluated, no extras)."""
    seen: set[str] = set()
    todo = list(names)
    while todo:
        name = todo.pop()
        if name in seen:
            continue
        seen.add(name)
        for text in metadata.requires(name) or []:
            req = Requirement(text)
            if req.marker is None or req.marker.evaluate({"extra": ""}):
                todo.append(normalise(req.name))
    return seen


def test_import_camcore_outside_the_repository(tmp_path: Path) -> None:
    # the venv's python, started from a folder with nothing of the project in it
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    code = "import camcore, service.settings; print(camcore.__file__, camcore.named_curve('MS').characteristics.vm.value)"
    proc = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=env, capture_output=True, text=True, timeout=60, check=False)
    assert proc.returncode == 0, proc.stderr
    where, vm = proc.stdout.split()
    assert Path(where) == ROOT / "camcore" / "__init__.py", "the editable install points at this repository"
    # and it computes: MS Vm is printed 1.76 (2 decimals) in the INDEXMAN guide's characteristic-value table
    assert round(float(vm), 2) == 1.76


def test_wheel_requires_the_runtime_dependencies_only(tmp_path: Path) -> None:
    # build from a copy holding only what the wheel is made of, so no build files land in the repository
    src = tmp_path / "src"
    src.mkdir()
    for name in ("pyproject.toml", "README.md"):
        shutil.copy2(ROOT / name, src / name)
    for package in ("camcore", "service"):
        shutil.copytree(ROOT / package, src / package, ignore=shutil.ignore_patterns("__pycache__"))
    # setuptools is pinned in requirements-dev.lock: no build isolation, no index, no network
    proc = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "--no-index",
                           "-w", str(tmp_path / "dist"), str(src)],
                          capture_output=True, text=True, timeout=300, check=False)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    (wheel,) = (tmp_path / "dist").glob("camcore-*.whl")
    with zipfile.ZipFile(wheel) as zf:
        names = zf.namelist()
        meta_name = next(n for n in names if n.endswith(".dist-info/METADATA"))
        meta = zf.read(meta_name).decode()
    requires = [Requirement(line.split(":", 1)[1]) for line in meta.splitlines() if line.startswith("Requires-Dist:")]
    always = {normalise(r.name) for r in requires if r.marker is None}
    extra_dev = {normalise(r.name) for r in requires if r.marker is not None and "extra" in str(r.marker)}
    assert always == RUNTIME, f"installing the wheel pulls in {always ^ RUNTIME} unexpectedly"
    assert extra_dev == DEV_TOOLS
    assert not always & DEV_TOOLS
    assert {"pytest", "hypothesis", "schemathesis", "ruff", "mpmath", "httpx", "openapi-python-client"} <= DEV_TOOLS
    top = {n.split("/")[0] for n in names if not n.split("/")[0].endswith(".dist-info")}
    assert top == {"camcore", "service"}, top


def test_runtime_lock_is_exactly_the_runtime_closure() -> None:
    # every pinned name is needed by a runtime dependency, and every dependency is pinned
    assert RUNTIME <= set(RUNTIME_LOCK)
    assert closure(RUNTIME) == set(RUNTIME_LOCK)
    assert not set(RUNTIME_LOCK) & DEV_TOOLS


def test_dev_lock_builds_on_the_runtime_lock() -> None:
    lines = (ROOT / "requirements-dev.lock").read_text(encoding="utf-8").splitlines()
    assert "-r requirements.lock" in lines
    # the dev file pins only what the runtime file does not, so a runtime pin has one place
    assert not set(DEV_LOCK_OWN) & set(RUNTIME_LOCK)
    everything = pins(ROOT / "requirements-dev.lock")
    assert set(RUNTIME_LOCK) <= set(everything)
    # the tools and all they need are pinned; setuptools is the build backend (no isolation)
    assert closure(DEV_TOOLS) | closure(RUNTIME) | {"setuptools"} == set(everything)


def test_venv_matches_the_pins() -> None:
    # make built this venv from the two files: what is installed is what they pin
    for name, version in pins(ROOT / "requirements-dev.lock").items():
        assert metadata.version(name) == version, name
