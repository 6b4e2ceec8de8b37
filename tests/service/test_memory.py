"""Memory as a promise (issue 34): the CAD kernel in a process of its own, which dies and
retires cleanly, and the byte budget of answers held for open downloads; against a live
``python -m service`` (tests/live_server.py). The soak that checks the stated ceiling is
tests/service/test_soak.py."""

from __future__ import annotations

import os
import signal
import socket
import threading
import time
from pathlib import Path

import httpx
import orjson
import pytest

from scripts.soak import SOLID_BODY, descendants, encode_request
from tests.live_server import running_service

pytestmark = pytest.mark.e2e

MIB = 1024 * 1024


def maps_kernel(pid: int) -> bool:
    """Whether the process maps OpenCASCADE's libraries (libTKernel, the OCP module)."""
    maps = Path(f"/proc/{pid}/maps").read_text()
    return "TKernel" in maps or "/OCP" in maps


def kernel_children(pid: int) -> list[int]:
    return [p for p in descendants(pid) if b"service.cad_child" in Path(f"/proc/{p}/cmdline").read_bytes()]


def wait_for(condition: object, seconds: float) -> bool:
    until = time.monotonic() + seconds
    while time.monotonic() < until:
        if condition():  # type: ignore[operator]
            return True
        time.sleep(0.05)
    return False


def test_solids_are_written_by_a_kernel_process_that_retires() -> None:
    """A STEP and an STL are answered as before, the worker never maps the kernel, its child
    does; after CAMCORE_CAD_MAX_TASKS solids the child is replaced, and idle it exits."""
    with running_service(cad_max_tasks="2", cad_idle_s="2") as (url, proc):
        first = httpx.post(f"{url}/v1/profiles.step", json=SOLID_BODY, timeout=30)
        assert first.status_code == 200 and first.content.startswith(b"ISO-10303-21;")
        children = kernel_children(proc.pid)
        assert len(children) == 1 and maps_kernel(children[0]) and not maps_kernel(proc.pid)
        stl = httpx.post(f"{url}/v1/profiles.stl", json=SOLID_BODY, timeout=30)
        assert stl.status_code == 200 and len(stl.content) == 84 + 50 * int.from_bytes(stl.content[80:84], "little")
        # two solids written: that child retires; the next solid starts another
        # (15 s: the retired child exits at once when idle; a loaded 2-core machine was seen
        # to take more than 5 s between the retirement and the reaping)
        assert wait_for(lambda: children[0] not in kernel_children(proc.pid), 15)
        again = httpx.post(f"{url}/v1/profiles.step", json=SOLID_BODY, timeout=30)
        # the same solid (the header's FILE_NAME carries the time of writing)
        assert again.content.split(b"ENDSEC;", 1)[1] == first.content.split(b"ENDSEC;", 1)[1]
        assert kernel_children(proc.pid) and kernel_children(proc.pid) != children
        # idle for CAMCORE_CAD_IDLE_S (2 s; the reaper looks every 0.5 s): no kernel process left,
        # 15 s allowed for the same reason as above
        assert wait_for(lambda: not kernel_children(proc.pid), 15)
        assert not maps_kernel(proc.pid)


def test_a_kernel_error_is_the_same_refusal_as_in_process() -> None:
    """An error the child raises on purpose comes back as the same answer: an STL over the
    facet limit is 413 naming the limit, from the estimate made in the child."""
    body = {**SOLID_BODY, "solid": {**SOLID_BODY["solid"], "tolerance_mm": 0.002}}
    with running_service(max_stl_triangles="1000") as (url, _proc):
        answer = httpx.post(f"{url}/v1/profiles.stl", json=body, timeout=30)
        assert answer.status_code == 413, answer.text
        assert orjson.loads(answer.content)["limit"]["name"] == "STL facets"
        assert orjson.loads(answer.content)["errors"][0]["loc"] == ["body", "solid", "tolerance_mm"]


def cpu_ticks(pid: int) -> int:
    """The process's user and system CPU time so far [clock ticks] (/proc/<pid>/stat, fields 14 and 15)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return int(fields[11]) + int(fields[12])


def test_a_dead_kernel_process_is_a_503_that_says_so_once() -> None:
    """A child killed under a solid (as the out-of-memory killer would) answers 503 with
    Retry-After and a sentence naming the signal, logged once; the next solid is answered."""
    body = {**SOLID_BODY, "solid": {**SOLID_BODY["solid"], "tolerance_mm": 0.0002}}  # ~0.3 s in all
    with running_service(log_level="error") as (url, proc):
        assert httpx.post(f"{url}/v1/profiles.step", json=SOLID_BODY, timeout=30).status_code == 200
        child = kernel_children(proc.pid)[0]
        idle = cpu_ticks(child)
        with httpx.Client(timeout=30) as client:
            answers: list[httpx.Response] = []
            sender = threading.Thread(target=lambda: answers.append(client.post(f"{url}/v1/profiles.stl", json=body)))
            sender.start()
            # killed once it works on the solid (its CPU time moves: the worker's fit of the contour comes first,
            # and how long that takes is no measure of when the child starts)
            deadline = time.monotonic() + 20
            while cpu_ticks(child) == idle and time.monotonic() < deadline:
                time.sleep(0.002)
            os.kill(child, signal.SIGKILL)
            sender.join()
        answer = answers[0]
        assert answer.status_code == 503 and answer.headers["retry-after"] == "1", answer.text
        assert "CAD kernel's process was killed by signal 9 (SIGKILL)" in answer.json()["detail"]
        assert httpx.post(f"{url}/v1/profiles.step", json=SOLID_BODY, timeout=30).status_code == 200
        proc.terminate()
        out = proc.communicate(timeout=10)[0].decode()
    assert out.count("was killed by signal 9") == 1, out


def test_answers_in_flight_are_held_within_the_budget() -> None:
    """With a 1 MiB budget, a client that does not read a 200 000-row table (~23 MB of CSV from
    ~3 MB of columns) holds it; a second large answer meanwhile is 503 naming the budget, a small
    one is answered, and once the first client leaves the same large answer is given."""
    large = {"curve": {"type": "named", "name": "MS"}, "samples": 200_000}
    with running_service(max_answer_bytes_in_flight=str(MIB), write_timeout_s="30") as (url, _proc):
        host = url.split("//", 1)[1]
        stalled = socket.create_connection((host.split(":")[0], int(host.split(":")[1])))
        stalled.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
        stalled.sendall(encode_request(host, "POST", "/v1/curves/table", large, None, {"Accept": "text/csv"}))
        assert stalled.recv(12) == b"HTTP/1.1 200"
        refused = httpx.post(f"{url}/v1/curves/table", json=large, timeout=30)
        assert refused.status_code == 503 and refused.headers["retry-after"] == "1"
        assert "CAMCORE_MAX_ANSWER_BYTES_IN_FLIGHT" in refused.json()["detail"]
        assert "budget for answers in flight is 1 MiB" in refused.json()["detail"]
        small = httpx.post(f"{url}/v1/curves/table", json={**large, "samples": 101}, timeout=30)
        assert small.status_code == 503  # the budget is used up: refused before it computes
        stalled.close()
        assert wait_for(lambda: httpx.post(f"{url}/v1/curves/table", json={**large, "samples": 101},
                                           timeout=30).status_code == 200, 10)
        whole = httpx.post(f"{url}/v1/curves/table", json=large, headers={"Accept": "text/csv"}, timeout=30)
        assert whole.status_code == 200 and whole.content.count(b"\n") == 200_001
