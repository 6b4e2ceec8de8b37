"""The Dockerfile cannot be built here (no Docker engine), so check what can be checked:
its install step is the Makefile's (which CI runs), and its CMD serves the app."""

from __future__ import annotations

import json
import os
import re
import socket
import subprocess
import sys
import time
from pathlib import Path

import httpx

ROOT = Path(__file__).resolve().parents[2]
DOCKERFILE = (ROOT / "Dockerfile").read_text(encoding="utf-8")
MAKEFILE = (ROOT / "Makefile").read_text(encoding="utf-8")


def test_install_step_is_the_one_ci_runs() -> None:
    run_lines = [line for line in DOCKERFILE.splitlines() if line.startswith("RUN ") and "pip install" in line]
    assert run_lines == ["RUN python3 -m venv .venv && .venv/bin/pip install -r requirements.lock"]
    assert "python3 -m venv $(VENV)" in MAKEFILE and "$(VENV)/bin/pip install -r requirements.lock" in MAKEFILE
    assert (ROOT / ".ci" / "run").read_text(encoding="utf-8").strip().endswith("make test")


def test_image_rules() -> None:
    assert DOCKERFILE.startswith("#") and "FROM python:3.11-slim" in DOCKERFILE
    assert "PYTHONUNBUFFERED=1" in DOCKERFILE
    assert re.search(r"^USER (?!root)\w+", DOCKERFILE, re.M), "must not run as root"
    assert DOCKERFILE.index("COPY requirements.lock") < DOCKERFILE.index("COPY camcore"), "deps before code"
    assert "HEALTHCHECK" in DOCKERFILE and "/health" in DOCKERFILE


def test_cmd_serves_the_app() -> None:
    cmd_line = next(line for line in DOCKERFILE.splitlines() if line.startswith("CMD "))
    cmd = json.loads(cmd_line[4:])  # exec form: a JSON array
    assert cmd[0] == "/app/.venv/bin/python" and cmd[1:4] == ["-m", "uvicorn", "service.main:app"]
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    args = [sys.executable, *cmd[1:]]
    args[args.index("--host") + 1] = "127.0.0.1"  # loopback only in tests
    args[args.index("--port") + 1] = str(port)
    proc = subprocess.Popen(args, cwd=ROOT, env={**os.environ}, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 30
        while True:
            try:
                r = httpx.get(f"http://127.0.0.1:{port}/health", timeout=1)
                break
            except httpx.TransportError:
                if proc.poll() is not None or time.monotonic() > deadline:
                    raise
                time.sleep(0.1)
        assert r.status_code == 200 and r.json()["status"] == "ok"
    finally:
        proc.terminate()
        proc.wait(timeout=10)
