"""Answers held in memory for open downloads, bounded in bytes per worker (issue 34).

An answer is held from the moment it is computed until its last byte has left the process:
a file or a small JSON answer as its encoded bytes, a large (streamed) table as its numpy
columns and the chunk being written. A client that does not read keeps it for up to
``CAMCORE_WRITE_TIMEOUT_S``; 32 such clients held 768–1 243 MiB in one worker. Now each worker
holds at most ``CAMCORE_MAX_ANSWER_BYTES_IN_FLIGHT`` bytes of answers: an answer that would
pass it is refused, 503 with ``Retry-After`` naming the budget, and a request arriving while
the budget is used up is refused before it computes anything. An answer larger than the whole
budget is still given when it is the only one held (the largest an operation's limits allow,
an STL of ``CAMCORE_MAX_STL_TRIANGLES`` facets, is ~50 MB), so nothing the limits accept
becomes impossible.

"Held until its last byte has left" needs the answer's sending to last as long as the
bytes are in the process: a body sent in one piece is handed to the transport at once, and
the transport keeps it, whole, until the client reads it. So :class:`HeldAnswer` sends a body
larger than :data:`SEND_CHUNK_BYTES` in pieces of that size; uvicorn waits for the transport's
buffer to drain (below its high-water mark, 64 KiB) before each piece, as it does between a
streamed answer's chunks. The bytes counted are then the process's own, to within one piece
and the high-water mark per download.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import orjson
from starlette.responses import Response, StreamingResponse
from starlette.types import Receive, Scope, Send

from service.errors import ServiceBusyError
from service.operations.answers import Answer, Document, Payload, Raw, Table, Text
from service.responses import CHUNK_ROWS
from service.wire import RETRY_AFTER_S

#: a body over this is sent in pieces of this size, so that its sending lasts until it is out
SEND_CHUNK_BYTES = 256 * 1024
#: bytes of one number as text in a streamed chunk (orjson's shortest floats are up to 24
#: characters with the separator; typical ones 18–20), for the chunk being written and the one
#: in the transport's buffer
TEXT_BYTES_PER_VALUE = 24
MIB = 1024 * 1024


def _arrays(value: Any, seen: dict[int, int]) -> None:
    if isinstance(value, dict):
        for item in value.values():
            _arrays(item, seen)
    elif isinstance(value, (list, tuple)):
        for item in value:
            _arrays(item, seen)
    elif isinstance(value, np.ndarray):
        seen[id(value)] = value.nbytes


def held_bytes(answer: Answer, response: Response) -> int:
    """What an answer keeps in memory while it is sent: a body's bytes; a streamed one's
    numpy arrays and two chunks of text (the one being written, the one in the transport)."""
    if not isinstance(response, StreamingResponse):
        return len(response.body)
    seen: dict[int, int] = {}
    if isinstance(answer, Table):
        _arrays(dict(answer.columns), seen)
    elif isinstance(answer, Document):
        _arrays(dict(answer.value), seen)
        _arrays(dict(answer.table or {}), seen)
    elif isinstance(answer, Raw):
        _arrays(answer.value, seen)
    elif isinstance(answer, (Payload, Text)):
        return len(answer.content)
    values = sum(nbytes // 8 for nbytes in seen.values())
    columns = max(1, len(seen))
    return sum(seen.values()) + 2 * TEXT_BYTES_PER_VALUE * min(values, CHUNK_ROWS * columns)


class AnswerBudget:
    """The bytes of answers one worker holds for its open downloads, and its refusals."""

    def __init__(self, max_bytes: int, retry_after_s: int = RETRY_AFTER_S):
        self.max_bytes = max_bytes
        self.retry_after_s = retry_after_s
        self.held = 0  # bytes held now
        self.answers = 0  # answers held now
        self.peak = 0  # the most bytes held at once
        self.refused = 0

    def _sentence(self, more: str) -> str:
        return (f"this worker is busy: {self.answers} answers being downloaded hold {self.held / MIB:.1f} MiB, "
                f"{more}the budget for answers in flight is {self.max_bytes / MIB:g} MiB "
                f"(CAMCORE_MAX_ANSWER_BYTES_IN_FLIGHT); retry after {self.retry_after_s} s.")

    def check_room(self) -> None:
        """503 before any work when the budget is used up."""
        if self.answers and self.held >= self.max_bytes:
            self.refused += 1
            raise ServiceBusyError(self._sentence(""), self.retry_after_s)

    def hold(self, answer: Answer, response: Response) -> Response:
        """The response, sent within the budget (or its 503 when it would pass it)."""
        return HeldAnswer(response, self, held_bytes(answer, response))

    def take(self, nbytes: int) -> str | None:
        """Count ``nbytes`` in; the refusal's sentence instead when they do not fit."""
        if self.answers and self.held + nbytes > self.max_bytes:
            self.refused += 1
            return self._sentence(f"this one would hold {nbytes / MIB:.1f} MiB more; ")
        self.held += nbytes
        self.answers += 1
        self.peak = max(self.peak, self.held)
        return None

    def give_back(self, nbytes: int) -> None:
        self.held -= nbytes
        self.answers -= 1


class HeldAnswer(Response):
    """A response counted in the budget while it is sent, its body sent in pieces."""

    def __init__(self, inner: Response, budget: AnswerBudget, nbytes: int):
        # not Response.__init__: the inner response has rendered its body and headers
        self.inner = inner
        self.budget = budget
        self.nbytes = nbytes
        self.status_code = inner.status_code
        self.background = inner.background
        self.raw_headers = inner.raw_headers
        self.body = bytes(getattr(inner, "body", b""))

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        refusal = self.budget.take(self.nbytes)
        if refusal is not None:
            body = orjson.dumps({"detail": refusal, "errors": []})
            await send({"type": "http.response.start", "status": 503,
                        "headers": [(b"content-type", b"application/json"),
                                    (b"content-length", str(len(body)).encode()),
                                    (b"retry-after", str(self.budget.retry_after_s).encode())]})
            await send({"type": "http.response.body", "body": body})
            return
        try:
            if isinstance(self.inner, StreamingResponse) or len(self.body) <= SEND_CHUNK_BYTES:
                await self.inner(scope, receive, send)
                return
            await send({"type": "http.response.start", "status": self.status_code, "headers": self.raw_headers})
            view = memoryview(self.body)
            for start in range(0, len(view), SEND_CHUNK_BYTES):
                end = start + SEND_CHUNK_BYTES
                await send({"type": "http.response.body", "body": bytes(view[start:end]), "more_body": end < len(view)})
            if self.background is not None:
                await self.background()
        finally:
            self.budget.give_back(self.nbytes)
