"""Memory soak (issue 34): mixed traffic, STEP and STL exports and clients that stall, against a
real ``python -m service`` for a bounded time, with every serving process's RSS polled.

    python -m scripts.soak                       # 75 s, one worker, the default settings
    python -m scripts.soak --seconds 600         # the 10-minute soak
    python -m scripts.soak --workers 2           # two workers (compose.yaml's setup)

The traffic, all at once for ``--seconds``:

- ``--connections`` keep-alive connections of scripts/loadtest.py's mix (tables, inverses,
  characteristics, profiles, base circles, 50 001-row CSV tables), a 503 followed at once by
  the next request;
- ``--exporters`` connections asking, one after the other, for the plate cam as STEP and STL
  solids at tolerances from 0.05 mm down to 0.002 mm (contours of tens to thousands of edges);
- ``--stallers`` connections that each ask for a large answer (a 200 000-row CSV or JSON
  table, a 200 000-sample profile, an STL of ~100 000 facets) with a 4 KiB receive buffer and
  then read nothing: the server holds the answer until its write timeout cuts the connection
  (``CAMCORE_WRITE_TIMEOUT_S``); then the staller opens a new connection and asks again.

RSS (VmRSS, /proc/<pid>/status) of each worker and of each worker's children (the CAD
kernel's process) is read every 0.1 s; the report gives each one's peak, the peak of a
worker with its children together (what one worker costs its pod or container), and the
peak of everything (what the container's memory limit sees, the supervisor of several
workers included). Exit status 1 when ``--ceiling-mib`` is given and a worker with its
children went over it, or when an answer was neither 200, a 503 nor a 413/422 refusal.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import os
import random
import socket
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import httpx

from scripts.loadtest import PROFILE, Server, encoded, free_port, request_pool
from scripts.rawhttp import Connection, encode_request

#: the plate cam of the exports: the README's roller cam
SOLID_BODY = {"profile": PROFILE, "solid": {"thickness_mm": 12, "bore_diameter_mm": 20}}
TOLERANCES_MM = (0.05, 0.02, 0.01, 0.005, 0.002)
#: the large answers a staller asks for and never reads
LARGE: tuple[tuple[str, str, Any, dict[str, str]], ...] = (
    ("POST", "/v1/curves/table", {"curve": {"type": "named", "name": "MS"}, "samples": 200_000},
     {"Accept": "text/csv"}),
    ("POST", "/v1/curves/table", {"curve": {"type": "named", "name": "MCV50"}, "samples": 200_000}, {}),
    ("POST", "/v1/profiles", {"profile": PROFILE, "samples": 200_000}, {}),
    ("POST", "/v1/profiles.stl", {"profile": PROFILE, "solid": {"thickness_mm": 12, "bore_diameter_mm": 20,
                                                                "tolerance_mm": 0.002}}, {}),
)


def descendants(pid: int) -> list[int]:
    """Every process below ``pid`` (children, their children, ...)."""
    found: list[int] = []
    todo = [pid]
    while todo:
        parent = todo.pop()
        kids = sorted(_direct_children(parent))
        found += kids
        todo += kids
    return found


def rss_kib(pid: int) -> int:
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    except OSError:
        pass
    return 0


def rss_parts_mib(pid: int) -> dict[str, float]:
    """RssAnon, RssFile and RssShmem of ``pid`` [MiB]: what the process wrote, and the files
    (libraries) it maps, which the kernel can drop and read again."""
    parts: dict[str, float] = {}
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith(("RssAnon:", "RssFile:", "RssShmem:")):
                parts[line.split(":")[0]] = round(int(line.split()[1]) / 1024, 1)
    except OSError:
        pass
    return parts


def process_name(pid: int) -> str:
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace").strip()
    except OSError:
        return "?"


@dataclass
class Memory:
    """Peaks of RSS [KiB], polled."""

    worker_kib: dict[int, int] = field(default_factory=dict)  # worker pid: its own peak
    children_kib: dict[int, int] = field(default_factory=dict)  # worker pid: peak of its children's sum
    with_children_kib: dict[int, int] = field(default_factory=dict)  # worker pid: peak of itself + children
    total_kib: int = 0  # every process of the server at once
    child_pids: set[int] = field(default_factory=set)  # CAD processes seen (a recycled one is new)
    samples: int = 0

    def poll(self, server_pid: int, workers: int) -> None:
        workers_pids = [server_pid] if workers == 1 else [p for p in descendants(server_pid)
                                                          if p in _direct_children(server_pid)]
        total = rss_kib(server_pid) if workers > 1 else 0
        for w in workers_pids:
            own = rss_kib(w)
            kids = descendants(w)
            self.child_pids.update(kids)
            theirs = sum(rss_kib(k) for k in kids)
            self.worker_kib[w] = max(self.worker_kib.get(w, 0), own)
            self.children_kib[w] = max(self.children_kib.get(w, 0), theirs)
            self.with_children_kib[w] = max(self.with_children_kib.get(w, 0), own + theirs)
            total += own + theirs
        self.total_kib = max(self.total_kib, total)
        self.samples += 1


def _direct_children(pid: int) -> set[int]:
    """Children of every thread of ``pid`` (a child started from a worker thread is listed
    under that thread only)."""
    kids: set[int] = set()
    try:
        tasks = list(Path(f"/proc/{pid}/task").iterdir())
    except OSError:
        return kids
    for task in tasks:
        try:
            kids.update(int(c) for c in (task / "children").read_text().split())
        except OSError:
            pass
    return kids


@dataclass
class Tally:
    statuses: dict[str, int] = field(default_factory=dict)
    unexpected: dict[str, int] = field(default_factory=dict)
    stalls: int = 0

    def count(self, kind: str, status: int | str) -> None:
        key = f"{kind} {status}"
        self.statuses[key] = self.statuses.get(key, 0) + 1
        if status not in (200, 503, 413, 422):
            self.unexpected[key] = self.unexpected.get(key, 0) + 1


async def mixed(url: str, raw: list[bytes], kinds: list[str], until: float, tally: Tally, seed: int) -> None:
    rng = random.Random(seed)
    connection = Connection(url)
    try:
        while time.monotonic() < until:
            i = rng.randrange(len(raw))
            try:
                answer = await asyncio.wait_for(connection.request(raw[i]), 60.0)
            except (OSError, asyncio.IncompleteReadError, asyncio.LimitOverrunError, TimeoutError) as exc:
                await connection.close()
                tally.count(kinds[i], type(exc).__name__)
                continue
            tally.count(kinds[i], answer.status)
    finally:
        await connection.close()


async def exporter(url: str, until: float, tally: Tally, seed: int) -> None:
    rng = random.Random(seed)
    connection = Connection(url)
    host = url.split("//", 1)[1]
    try:
        while time.monotonic() < until:
            fmt = rng.choice(("step", "stl"))
            body = {**SOLID_BODY, "solid": {**SOLID_BODY["solid"], "tolerance_mm": rng.choice(TOLERANCES_MM)}}
            raw = encode_request(host, "POST", f"/v1/profiles.{fmt}", body)
            try:
                answer = await asyncio.wait_for(connection.request(raw), 60.0)
            except (OSError, asyncio.IncompleteReadError, asyncio.LimitOverrunError, TimeoutError) as exc:
                await connection.close()
                tally.count(fmt, type(exc).__name__)
                continue
            tally.count(fmt, answer.status)
            if answer.status == 503:
                await asyncio.sleep(float(answer.headers.get("retry-after", "1")))
    finally:
        await connection.close()


async def staller(url: str, until: float, tally: Tally, index: int, stall_s: float) -> None:
    """Ask for a large answer over a socket with a small receive buffer and read nothing for
    ``stall_s``; then drop the connection and ask again."""
    host = url.split("//", 1)[1]
    address = (host.split(":")[0], int(host.split(":")[1]))
    loop = asyncio.get_running_loop()
    n = index
    while time.monotonic() < until:
        method, path, body, headers = LARGE[n % len(LARGE)]
        n += 1
        sock = socket.socket()
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
        sock.setblocking(False)
        try:
            await loop.sock_connect(sock, address)
            await loop.sock_sendall(sock, encode_request(host, method, path, body, None, headers))
            # the status line only (it tells a 503 from an answer under way), then nothing
            head = await asyncio.wait_for(loop.sock_recv(sock, 12), 30.0)
            status = head[9:12].decode(errors="replace") if head.startswith(b"HTTP/1.1 ") else "none"
            tally.count(f"stall {path}", int(status) if status.isdigit() else status)
            tally.stalls += 1
            await asyncio.sleep(min(stall_s, max(0.0, until - time.monotonic())) if status == "200" else 1.0)
        except (OSError, TimeoutError) as exc:
            tally.count(f"stall {path}", type(exc).__name__)
            await asyncio.sleep(0.5)
        finally:
            sock.close()


async def soak(url: str, pid: int, workers: int, seconds: float, connections: int, exporters: int,
               stallers: int, stall_s: float, seed: int) -> tuple[Memory, Tally]:
    pool = request_pool(seed, 2000)
    raw, kinds = [encoded(req, url) for req in pool], [req.kind for req in pool]
    memory, tally = Memory(), Tally()
    until = time.monotonic() + seconds
    done = asyncio.Event()

    async def poll() -> None:
        while not done.is_set():
            memory.poll(pid, workers)
            await asyncio.sleep(0.1)

    poller = asyncio.ensure_future(poll())
    try:
        await asyncio.gather(*(mixed(url, raw, kinds, until, tally, seed * 1000 + i) for i in range(connections)),
                             *(exporter(url, until, tally, seed * 2000 + i) for i in range(exporters)),
                             *(staller(url, until, tally, i, stall_s) for i in range(stallers)))
    finally:
        done.set()
        await poller
    return memory, tally


def mib(kib: int) -> float:
    return round(kib / 1024, 1)


def report(memory: Memory, tally: Tally, seconds: float, settled: dict[int, tuple[int, int]]) -> dict[str, Any]:
    return {
        "seconds": seconds, "rss_samples": memory.samples,
        "worker_peak_mib": {w: mib(k) for w, k in memory.worker_kib.items()},
        "children_peak_mib": {w: mib(k) for w, k in memory.children_kib.items()},
        "worker_with_children_peak_mib": {w: mib(k) for w, k in memory.with_children_kib.items()},
        "total_peak_mib": mib(memory.total_kib),
        "child_processes_seen": len(memory.child_pids),
        "settled_mib": {w: [mib(own), mib(kids)] for w, (own, kids) in settled.items()},
        "statuses": dict(sorted(tally.statuses.items())), "unexpected": tally.unexpected, "stalls": tally.stalls,
    }


def run(seconds: float = 75.0, workers: int = 1, connections: int = 32, exporters: int = 4, stallers: int = 32,
        stall_s: float = 40.0, seed: int = 1, env: dict[str, str] | None = None,
        cwd: Path | None = None) -> dict[str, Any]:
    """One soak against a server this function starts (and stops); the report."""
    server = _server_in(cwd, env, workers)
    try:
        server.wait_ready(60.0)
        primed = prime_kernel(server.url)
        memory, tally = asyncio.run(soak(server.url, server.proc.pid, workers, seconds, connections, exporters,
                                         stallers, stall_s, seed))
        settled = {w: (rss_kib(w), sum(rss_kib(k) for k in descendants(w))) for w in memory.worker_kib}
        figures = report(memory, tally, seconds, settled)
        figures["primed_solid_status"] = primed
        figures["settled_parts_mib"] = {f"{p} {process_name(p)[-40:]}": rss_parts_mib(p)
                                        for w in memory.worker_kib for p in (w, *descendants(w))}
        return figures
    finally:
        server.stop()


def prime_kernel(url: str) -> int:
    """Write one STEP solid before the soak so the CAD kernel's process is up (and its memory
    counted) throughout: on one busy worker the exporters' own solids may all be refused busy
    (503), as a CI run saw. The answer's status."""
    return httpx.post(f"{url}/v1/profiles.step", json=SOLID_BODY, timeout=120).status_code


def _server_in(cwd: Path | None, env: dict[str, str] | None, workers: int) -> Server:
    """scripts/loadtest.py's Server, or the same from another checkout (``cwd``: a before/after
    comparison runs the older code from an exported tree)."""
    if cwd is None:
        return Server(env, workers=workers)
    server = Server.__new__(Server)
    server.port = free_port()
    server.url = f"http://127.0.0.1:{server.port}"
    full = {**os.environ, "CAMCORE_HOST": "127.0.0.1", "CAMCORE_PORT": str(server.port),
            "CAMCORE_WORKERS": str(workers), "CAMCORE_LOG_LEVEL": "warning", **(env or {}),
            "PYTHONPATH": str(cwd)}
    server.proc = subprocess.Popen([sys.executable, "-m", "service"], cwd=cwd, env=full,
                                   stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    return server


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seconds", type=float, default=75.0)
    ap.add_argument("--workers", type=int, default=1)
    ap.add_argument("--connections", type=int, default=32)
    ap.add_argument("--exporters", type=int, default=4)
    ap.add_argument("--stallers", type=int, default=32)
    ap.add_argument("--stall-s", type=float, default=40.0)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--ceiling-mib", type=float, default=None)
    ap.add_argument("--cwd", type=Path, default=None, help="serve another checkout's code (before/after)")
    args = ap.parse_args(argv)
    figures = run(args.seconds, args.workers, args.connections, args.exporters, args.stallers, args.stall_s,
                  args.seed, cwd=args.cwd)
    print(json.dumps(figures, indent=1))
    over = args.ceiling_mib is not None and any(v > args.ceiling_mib
                                                for v in figures["worker_with_children_peak_mib"].values())
    return 1 if over or figures["unexpected"] else 0


if __name__ == "__main__":
    sys.exit(main())
