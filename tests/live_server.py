"""A real ``python -m service`` on a loopback port, started as the README says."""

from __future__ import annotations

import os
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import httpx

ROOT = Path(__file__).resolve().parents[1]


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@contextmanager
def running_service(module: str = "service", **settings: str) -> Iterator[tuple[str, subprocess.Popen[bytes]]]:
    """``python -m service`` (or ``module``, a test's server started the same way) on a free
    loopback port, with ``CAMCORE_<NAME>`` set from ``settings`` over the environment; yields its
    URL and process, stops it afterwards."""
    port = free_port()
    env = {**os.environ, "CAMCORE_HOST": "127.0.0.1", "CAMCORE_PORT": str(port), "CAMCORE_LOG_LEVEL": "warning",
           **{f"CAMCORE_{name.upper()}": value for name, value in settings.items()}}
    proc = subprocess.Popen([sys.executable, "-m", module], cwd=ROOT, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    url = f"http://127.0.0.1:{port}"
    try:
        deadline = time.monotonic() + 30
        while True:
            try:
                if httpx.get(f"{url}/health", timeout=1).status_code == 200:
                    break
            except httpx.TransportError:
                pass
            if proc.poll() is not None or time.monotonic() > deadline:
                out = proc.stdout.read().decode() if proc.stdout else ""
                raise RuntimeError(f"server did not start: {out}")
            time.sleep(0.1)
        yield url, proc
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
        if proc.stdout:
            proc.stdout.close()
