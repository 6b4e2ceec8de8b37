"""Servers and load for the bench's HTTP figures: ``python -m service`` on a free loopback port,
pinned with taskset, and wrk runs against it."""

from __future__ import annotations

import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path
from typing import Self

import httpx

ROOT = Path(__file__).resolve().parent.parent

WRK_MISSING = "wrk not installed: apt-get install wrk"
PINNING = ("2 cores: the server runs under `taskset -c 0` with 1 worker and `taskset -c 0,1` with 2 "
           "workers; wrk runs with 1 thread under `taskset -c 1` (it shares core 1 with the second worker)")


def have_wrk() -> bool:
    return shutil.which("wrk") is not None


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])


class Server:
    """``python -m service`` on 127.0.0.1 and a free port, pinned with taskset; stopped on exit.
    ``bare``: a bare FastAPI app with one route (bench/bare_app.py) under uvicorn instead, the
    floor for start-up times."""

    def __init__(self, workers: int, cpus: str, bare: bool = False, **settings: str):
        self.port = _free_port()
        self.started = time.perf_counter()
        # the figures time computation and HTTP, not admission: no computation is turned away
        # for its wait (with the default 0.5 s, 32 connections of uncached tables shed some)
        env = {**os.environ, "CAMCORE_HOST": "127.0.0.1", "CAMCORE_PORT": str(self.port),
               "CAMCORE_WORKERS": str(workers), "CAMCORE_LOG_LEVEL": "warning", "CAMCORE_MAX_QUEUE_WAIT_S": "60",
               **settings}
        cmd = [sys.executable, "-m", "service"]
        if bare:
            cmd = [sys.executable, "-m", "uvicorn", "bench.bare_app:app", "--host", "127.0.0.1", "--port",
                   str(self.port), "--log-level", "warning", "--loop", "uvloop", "--http", "httptools"]
        if shutil.which("taskset"):
            cmd = ["taskset", "-c", cpus, *cmd]
        self.proc = subprocess.Popen(cmd, cwd=ROOT, env=env, start_new_session=True,
                                     stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        self.url = f"http://127.0.0.1:{self.port}"

    def __enter__(self) -> Self:
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            if self.proc.poll() is not None:
                raise RuntimeError(f"server exited: {self.proc.stderr.read().decode()[-2000:]}")  # type: ignore[union-attr]
            try:
                if httpx.get(self.url + "/health", timeout=1).status_code == 200:
                    self.first_answer_s = time.perf_counter() - self.started
                    return self
            except httpx.HTTPError:
                pass
            time.sleep(0.01)
        self.__exit__()
        raise RuntimeError("server did not answer /health within 60 s")

    def __exit__(self, *_exc: object) -> None:
        if self.proc.poll() is None:
            os.killpg(self.proc.pid, signal.SIGTERM)  # the server's own session: it and its workers
            try:
                self.proc.wait(timeout=15)
            except subprocess.TimeoutExpired:
                os.killpg(self.proc.pid, signal.SIGKILL)
                self.proc.wait(timeout=5)


_UNITS = {"us": 1e-3, "ms": 1.0, "s": 1e3}


def wrk(url: str, seconds: int, lua: str | None = None) -> dict[str, float]:
    """One wrk run (1 thread, 32 connections, pinned to core 1): req/s and p99 latency [ms]."""
    cmd = ["wrk", "-t1", "-c32", f"-d{seconds}s", "--latency"]
    if lua:
        cmd += ["-s", lua]
    if shutil.which("taskset"):
        cmd = ["taskset", "-c", "1", *cmd]
    out = subprocess.run([*cmd, url], capture_output=True, text=True, timeout=seconds + 60, check=False).stdout
    rps = re.search(r"Requests/sec:\s*([\d.]+)", out)
    p99 = re.search(r"^\s*99%\s+([\d.]+)(us|ms|s)\s*$", out, re.MULTILINE)
    errors = re.search(r"Non-2xx or 3xx responses:\s*(\d+)", out)
    if not rps or not p99:
        raise RuntimeError(f"could not read wrk output:\n{out}")
    if errors:
        script = Path(lua).read_text() if lua else None
        raise RuntimeError(f"wrk saw error responses:\n{out}\n{script}")
    return {"rps": float(rps.group(1)), "p99_ms": float(p99.group(1)) * _UNITS[p99.group(2)]}


