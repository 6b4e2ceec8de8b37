"""The CAD kernel's work in processes of its own (issue 34), whose memory goes back to the system.

One STEP export raised a worker from 138 to 375 MiB that it never gave back (OpenCASCADE:
+96 MiB anonymous, +150 MiB of mapped library). A worker now never imports the kernel: each
solid (STEP, STL) is written by a child process, ``python -m service.cad_child`` (started
with :class:`subprocess.Popen`, so it imports nothing of the service's web stack), and
:class:`CadPool` keeps at most ``cad_processes`` of them per worker. A child is retired
after ``cad_max_tasks`` solids (what the kernel keeps between solids goes with it) and after
``cad_idle_s`` without one (all of it goes: a worker that makes no solids holds no kernel).

Semantics are the in-process ones: the estimate and the budget are checked before, in the
worker (the contour's fit is part of the estimate); the computation runs in the WorkGate's
thread, which waits for a child and for its answer, checking the deadline and the client's
disconnect (camcore.deadline.checkpoint) every :data:`POLL_S`; a stopped computation answers
503 at once, and the child, which runs its own copy of the deadline for the fit, is given
:data:`GRACE_S` to finish before it is killed. Starting a child (~1.5 s, the kernel's load) is
the operation's ``warmup``, outside the budget and deadline, as the in-process load was.
A child that dies under a solid (killed by the kernel's out-of-memory killer, a crash in the
kernel) answers 503 with a sentence saying so, logged once, and the next solid starts a new
one; an error the child raised on purpose (a LimitExceededError, a GeometryError) is raised
in the worker as it was raised there.
"""

from __future__ import annotations

import importlib
import logging
import signal
import socket
import subprocess
import sys
import threading
import time
from multiprocessing.connection import Connection
from typing import Any

from camcore.deadline import checkpoint
from camcore.errors import WorkStoppedError
from service.errors import ServiceBusyError

logger = logging.getLogger("camcore.service")

#: how often a waiting thread checks its deadline and its client [s]
POLL_S = 0.02
#: a stopped computation's child may finish this long before it is killed [s]
GRACE_S = 0.5
#: a child must have loaded the kernel within this [s] (it takes ~1.5 s on the reference machine)
START_TIMEOUT_S = 30.0


class CadProcessError(ServiceBusyError):
    """The CAD kernel's process ended under a solid (503: the next solid gets a new one)."""


def _rebuilt(module: str, name: str, args: tuple[Any, ...], attributes: dict[str, Any]) -> Exception:
    """An exception the child raised, as it was: its class, ``args`` and attributes."""
    cls: Any = importlib.import_module(module)
    for part in name.split("."):
        cls = getattr(cls, part)
    if not (isinstance(cls, type) and issubclass(cls, Exception)):
        return RuntimeError(f"{module}.{name}: {args}")
    exc: Exception = cls.__new__(cls)
    Exception.__init__(exc, *args)
    exc.__dict__.update(attributes)
    return exc


def _ended(returncode: int | None) -> str:
    if returncode is None:
        return "stopped answering"
    if returncode < 0:
        try:
            return f"was killed by signal {-returncode} ({signal.Signals(-returncode).name})"
        except ValueError:
            return f"was killed by signal {-returncode}"
    return f"exited with status {returncode}"


class _Child:
    """One kernel process and its connection; ``tasks`` solids written so far."""

    def __init__(self) -> None:
        ours, theirs = socket.socketpair()
        try:
            self.proc = subprocess.Popen([sys.executable, "-m", "service.cad_child", str(theirs.fileno())],
                                         pass_fds=(theirs.fileno(),), stdin=subprocess.DEVNULL)
        finally:
            theirs.close()
        self.conn = Connection(ours.detach())
        self.tasks = 0
        self.last_used = time.monotonic()
        deadline = time.monotonic() + START_TIMEOUT_S
        while not self.conn.poll(POLL_S):
            if self.proc.poll() is not None or time.monotonic() > deadline:
                self.kill()
                raise CadProcessError(f"the CAD kernel's process {_ended(self.proc.returncode)} while it started; "
                                      "retry in a moment.")
        self.conn.recv()  # ("ready",)

    def kill(self) -> None:
        self.conn.close()
        if self.proc.poll() is None:
            self.proc.kill()
        self.proc.wait()

    def retire(self) -> None:
        """Close its connection (it exits at once) and reap it, in the background."""
        self.conn.close()
        threading.Thread(target=self._reap, daemon=True, name="cad-reap").start()

    def _reap(self) -> None:
        try:
            self.proc.wait(timeout=5.0)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()


class CadPool:
    """At most ``processes`` kernel processes for one worker's solids."""

    def __init__(self, processes: int, max_tasks: int, idle_s: float, deadline_s: float):
        self.processes = processes
        self.max_tasks = max_tasks
        self.idle_s = idle_s
        self.deadline_s = deadline_s
        self._cond = threading.Condition()
        self._free: list[_Child | None] = [None] * processes  # a free slot; None: no process in it yet
        self.started = 0  # processes started (the health answer, the tests)
        self.died = 0  # processes that ended under a solid
        self._reaper: threading.Thread | None = None

    # ------------------------------------------------------------------ slots
    def _take(self, checked: bool, timeout_s: float | None = None) -> _Child | None | bool:
        """A free slot (its child or None), waiting with the deadline checked; False when
        ``timeout_s`` passed first."""
        until = None if timeout_s is None else time.monotonic() + timeout_s
        with self._cond:
            while not self._free:
                self._cond.wait(POLL_S)
                if checked:
                    checkpoint()
                if until is not None and time.monotonic() > until:
                    return False
            return self._free.pop()

    def _give(self, child: _Child | None) -> None:
        if child is not None and child.tasks >= self.max_tasks:
            child.retire()
            child = None
        with self._cond:
            self._free.append(child)
            self._cond.notify()

    def _started(self) -> _Child:
        child = _Child()
        self.started += 1
        if self._reaper is None:
            self._reaper = threading.Thread(target=self._reap_idle, daemon=True, name="cad-idle")
            self._reaper.start()
        return child

    def _reap_idle(self) -> None:
        """Retire the children idle for ``idle_s`` (their memory goes back to the system)."""
        while True:
            time.sleep(min(1.0, self.idle_s / 4))
            now = time.monotonic()
            with self._cond:
                for i, child in enumerate(self._free):
                    if child is not None and now - child.last_used > self.idle_s:
                        child.retire()
                        self._free[i] = None

    # ------------------------------------------------------------------ the operation's hooks
    def warm(self) -> None:
        """A free slot's kernel process started, if it has none (the operation's warmup: in a
        thread, outside the budget and deadline). With every slot busy, those processes are
        running and nothing is done (after 10 s of waiting, nothing either)."""
        slot = self._take(checked=False, timeout_s=0.0 if self._any_started() else 10.0)
        if slot is False:
            return
        child = slot if isinstance(slot, _Child) else None
        try:
            if child is None:
                child = self._started()
        finally:
            self._give(child)

    def _any_started(self) -> bool:
        with self._cond:
            return len(self._free) < self.processes or any(c is not None for c in self._free)

    def write(self, fmt: str, solid: Any) -> bytes:
        """The solid's file (``camcore.export.SOLID_FORMATS[fmt].write(solid)``) from a kernel
        process; in the WorkGate's thread, under its deadline."""
        slot = self._take(checked=True)
        child = slot if isinstance(slot, _Child) else None
        give = True  # the slot goes back here (not when a stopped computation's child finishes later)
        try:
            if child is None:
                child = self._started()  # warm() had no free slot: the start counts against the deadline
            child.conn.send((fmt, solid, self.deadline_s))
            child.tasks += 1
            while not child.conn.poll(POLL_S):
                if child.proc.poll() is not None:
                    raise EOFError
                checkpoint()
            answer = child.conn.recv()
        except WorkStoppedError:
            give = False
            self._finish_later(child)
            raise
        except (EOFError, OSError):
            assert child is not None
            try:  # its connection closed: it has ended or is ending; its own status, not our kill's
                returncode: int | None = child.proc.wait(timeout=1.0)
            except subprocess.TimeoutExpired:
                returncode = None
            child.kill()
            child = None
            self.died += 1
            why = _ended(returncode)
            logger.error("the CAD kernel's process %s while it wrote a %s solid; a new one is started "
                         "for the next solid", why, fmt)
            raise CadProcessError(f"the CAD kernel's process {why} while it wrote this {fmt} solid "
                                  "(see the service's log); a new one is started: retry in a moment.") from None
        finally:
            if give:
                if child is not None:
                    child.last_used = time.monotonic()
                self._give(child)
        if answer[0] == "ok":
            content: bytes = answer[1]
            return content
        raise _rebuilt(*answer[1:])

    def _finish_later(self, child: _Child | None) -> None:
        """A stopped computation's child: its answer awaited for GRACE_S (and dropped), else it
        is killed; then its slot is free again."""
        if child is None:
            self._give(None)
            return

        def finish() -> None:
            kept: _Child | None = child
            try:
                if child.conn.poll(GRACE_S):
                    child.conn.recv()
                else:
                    logger.warning("the CAD kernel's process ran %g s past a stopped computation and was killed",
                                   GRACE_S)
                    child.kill()
                    kept = None
            except (EOFError, OSError):
                child.kill()
                kept = None
            if kept is not None:
                kept.last_used = time.monotonic()
            self._give(kept)

        threading.Thread(target=finish, daemon=True, name="cad-finish").start()

    def pids(self) -> list[int]:
        """The kernel processes alive now (free or busy are not told apart)."""
        with self._cond:
            return [c.proc.pid for c in self._free if c is not None and c.proc.poll() is None]
