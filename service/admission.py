"""Admission: what a worker takes on, and what it refuses at once.

Two bounds per worker process:

- :class:`InFlightLimit` (ASGI middleware): at most ``max_in_flight`` requests in progress,
  counted once they are ready to compute: a request without a body at once, one with a body
  when its last byte has arrived (issue 34: 64 clients trickling bodies at 1 byte/s held
  every place, and 87 of 88 real requests were refused meanwhile; a body's arrival is
  bounded by the transport's body timeout instead, service/protocol.py). One more is
  answered 503 with ``Retry-After``, a request without a body before the app sees it.
  ``/health`` is never refused (probes must see a busy worker as alive).
- :class:`WorkGate`: a computation runs in a worker thread only after its estimated work
  (camcore.work) has been checked against the budget (413 over it) and admitted: at most
  ``work_slots`` run at once, and the estimated seconds admitted but not finished stay
  under ``max_queued_work_s``. The wait for a slot is bounded by ``max_queue_wait_s``
  twice: at admission, from the work ahead and the pace this worker has shown (the
  measured run time per estimated second, which grows when the machine is loaded), so
  most refusals are immediate; and in the queue, where a computation that has waited that
  long leaves without running. Both answer 503 with ``Retry-After``. An admitted
  computation has a deadline (``work_deadline_s``, counted from admission, so the wait is
  in it) and is cancelled when its client disconnects; camcore's loops stop it at their
  next checkpoint (camcore.deadline), answered 503.
"""

from __future__ import annotations

import asyncio
import functools
import time
from collections.abc import Callable
from typing import Any, NoReturn, TypeVar

import anyio
import orjson
from starlette.requests import Request
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from camcore.deadline import Deadline, running_until
from camcore.errors import WorkLimitError
from camcore.work import WorkEstimate
from service.errors import ServiceBusyError
from service.settings import Settings
from service.wire import RETRY_AFTER_S

T = TypeVar("T")

#: weight of the newest run in the measured pace (an exponential average over ~10 runs)
PACE_WEIGHT = 0.1
#: the pace is kept in [PACE_MIN, PACE_MAX] run seconds per estimated second (one odd run cannot
#: make the worker refuse everything, nor admit everything)
PACE_MIN, PACE_MAX = 0.25, 20.0

#: paths never refused for being busy (liveness probes)
ALWAYS_ADMITTED = frozenset({"/health"})


def busy_body(detail: str) -> bytes:
    return orjson.dumps({"detail": detail, "errors": []})


def has_body(scope: Scope) -> bool:
    """Whether the request declares a body: a Content-Length over 0, or Transfer-Encoding."""
    for name, value in scope.get("headers", ()):
        if name == b"transfer-encoding":
            return True
        if name == b"content-length":
            return value.strip() not in (b"", b"0")
    return False


class InFlightLimit:
    """Answers 503 (with Retry-After) when ``max_in_flight`` requests ready to compute are in
    progress; a request whose body is still arriving is not one of them yet."""

    def __init__(self, app: ASGIApp, max_in_flight: int, retry_after_s: int = RETRY_AFTER_S):
        self.app = app
        self.max_in_flight = max_in_flight
        self.retry_after_s = retry_after_s
        self.in_flight = 0

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http" or scope["path"] in ALWAYS_ADMITTED:
            await self.app(scope, receive, send)
            return
        if not has_body(scope):
            if self.in_flight >= self.max_in_flight:
                await self._refuse(send)
                return
            self.in_flight += 1
            try:
                await self.app(scope, receive, send)
            finally:
                self.in_flight -= 1
            return
        counted = False  # the body is complete and the request holds a place
        refused = False  # ... or there was none: 503, and the app sees a disconnect
        started = False  # the app has begun an answer (e.g. 413 before the whole body came)

        async def counting_receive() -> Message:
            nonlocal counted, refused
            if refused:
                return {"type": "http.disconnect"}
            message = await receive()
            if message["type"] == "http.request" and not message.get("more_body", False) and not counted:
                if self.in_flight >= self.max_in_flight and not started:
                    # answered here, the app told the client has gone (as BodySizeLimit does: an
                    # exception in receive() would become FastAPI's 400)
                    refused = True
                    await self._refuse(send)
                    return {"type": "http.disconnect"}
                self.in_flight += 1
                counted = True
            return message

        async def tracking_send(message: Message) -> None:
            nonlocal started
            if refused:
                return
            if message["type"] == "http.response.start":
                started = True
            await send(message)

        try:
            await self.app(scope, counting_receive, tracking_send)
        finally:
            if counted:
                self.in_flight -= 1

    async def _refuse(self, send: Send) -> None:
        payload = busy_body(f"this worker is busy: {self.in_flight} requests in progress, the limit is "
                            f"{self.max_in_flight}; retry after {self.retry_after_s} s.")
        await send({"type": "http.response.start", "status": 503,
                    "headers": [(b"content-type", b"application/json"),
                                (b"content-length", str(len(payload)).encode()),
                                (b"retry-after", str(self.retry_after_s).encode())]})
        await send({"type": "http.response.body", "body": payload})


class WorkGate:
    """Budget, slots, queue and deadline of the computations of one worker process."""

    def __init__(self, settings: Settings):
        self.budget_s = settings.max_work_s
        self.deadline_s = settings.work_deadline_s
        self.max_queued_s = settings.max_queued_work_s
        self.max_wait_s = settings.max_queue_wait_s
        self.inline_s = settings.inline_work_s
        self.pace = 1.0  # measured run seconds per estimated second
        self.retry_after_s = RETRY_AFTER_S
        self.slots = settings.work_slots
        self.admitted_s = 0.0  # estimated seconds admitted and not finished (waiting or running)
        self.admitted = 0
        self.refused_busy = 0
        self._semaphore: asyncio.Semaphore | None = None

    def check_budget(self, estimate: WorkEstimate) -> None:
        """413 (WorkLimitError) when the estimate is over the budget, naming its largest part."""
        if estimate.seconds > self.budget_s:
            largest = estimate.largest()
            raise WorkLimitError(estimate.seconds, self.budget_s, largest.what, field=largest.field)

    async def run(self, request: Request, estimate: WorkEstimate, work: Callable[..., T], *args: Any) -> T:
        """``work(*args)`` in a worker thread, once admitted; its deadline and the client's
        disconnect stop it (camcore.errors.WorkStoppedError, answered 503). Work estimated at
        most ``inline_work_s`` runs on the event loop instead: a thread hop, a slot and a
        disconnect watcher cost about 0.2 ms, more than such work blocks the loop."""
        self.check_budget(estimate)
        seconds = estimate.seconds
        if seconds <= self.inline_s:
            return work(*args)
        if self.admitted:
            if self.admitted_s + seconds > self.max_queued_s:
                self._busy(f"{self.admitted} computations ({self.admitted_s:.2g} s of estimated work) are admitted, "
                           f"the limit is {self.max_queued_s:g} s")
            wait_s = self.projected_wait_s()
            if wait_s > self.max_wait_s:
                self._busy(f"{self.admitted} computations are ahead, about {wait_s:.2g} s of waiting "
                           f"at this worker's pace, the limit is {self.max_wait_s:g} s")
        if self._semaphore is None:
            self._semaphore = asyncio.Semaphore(self.slots)
        deadline = Deadline(self.deadline_s)
        self.admitted_s += seconds
        self.admitted += 1
        try:
            try:
                async with asyncio.timeout(self.max_wait_s):
                    await self._semaphore.acquire()
            except TimeoutError:
                self._busy(f"this computation waited {self.max_wait_s:g} s for one of {self.slots} slots")
            try:
                started = time.perf_counter()
                result = await self._run_watched(request, deadline, work, *args)
                self._measure(seconds, time.perf_counter() - started)
                return result
            finally:
                self._semaphore.release()
        finally:
            self.admitted_s = max(0.0, self.admitted_s - seconds)
            self.admitted -= 1

    def projected_wait_s(self) -> float:
        """How long a computation admitted now would wait for a slot: the estimated work
        ahead of it at this worker's measured pace, shared over the slots."""
        return self.admitted_s * self.pace / self.slots

    def _measure(self, estimated_s: float, run_s: float) -> None:
        ratio = min(PACE_MAX, max(PACE_MIN, run_s / estimated_s)) if estimated_s > 0 else self.pace
        self.pace += PACE_WEIGHT * (ratio - self.pace)

    def _busy(self, why: str) -> NoReturn:
        self.refused_busy += 1
        raise ServiceBusyError(f"this worker is busy: {why}; retry after {self.retry_after_s} s.", self.retry_after_s)

    async def _run_watched(self, request: Request, deadline: Deadline, work: Callable[..., T], *args: Any) -> T:

        async def watch_disconnect() -> None:
            while (await request.receive())["type"] != "http.disconnect":
                pass
            deadline.cancel("the client closed the connection; the computation was stopped.")

        failure: Exception | None = None
        async with anyio.create_task_group() as group:
            group.start_soon(watch_disconnect)
            with running_until(deadline):  # the thread runs in a copy of this context
                try:
                    result = await anyio.to_thread.run_sync(functools.partial(work, *args))
                except Exception as exc:  # noqa: BLE001  # re-raised below, outside the group (not as an ExceptionGroup)
                    failure = exc
                finally:
                    group.cancel_scope.cancel()
        if failure is not None:
            raise failure
        return result
