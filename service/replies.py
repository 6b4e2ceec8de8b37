"""Replies kept by request: a request whose bytes were answered from an operation's own cache
before is answered again with the same reply bytes, before FastAPI matches its parameters.

A cached answer (a table or a sizing asked again, as a recalculating spreadsheet asks) costs
little to compute; what it paid was FastAPI's work around it: solving the endpoint's
dependencies, validating the body, choosing the format and the answer's response (≈ 55 µs of
the 117 µs such a request took in-process; a bare app answers the same bytes in 33 µs). A reply
is kept only when its operation answered it from its own cache, so the operations' cache
settings still decide what is kept (``CAMCORE_TABLE_CACHE_SIZE=0``: no table is), and a kept
reply is the same bytes the operation would send again.

The key is the request as it came — method, path, query, ``Accept``, ``Content-Type`` and body
bytes — so a reply is never given for a different request; small requests and replies only (their bytes are the
cache's memory, bounded by :data:`REPLIES_MAX_BYTES`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

from starlette.requests import Request
from starlette.responses import Response

from service.cache import LRUCache

#: request bodies up to this size are keys [bytes] (a table's or a sizing's body is < 1 kB)
KEY_MAX_BYTES = 16 * 1024
#: replies up to this size are kept [bytes] (a 101-row table: 8 kB; a sizing: ~10 kB)
REPLY_MAX_BYTES = 256 * 1024
#: bytes all kept replies and their keys may hold
REPLIES_MAX_BYTES = 16 * 1024 * 1024
#: the request-state flag an operation's answer sets when it came from the operation's own cache
KEPT_FLAG = "answer_was_kept"


@dataclass(frozen=True)
class Reply:
    """A reply as sent: status, raw headers (its length included) and body."""

    status_code: int
    headers: tuple[tuple[bytes, bytes], ...]
    body: bytes
    #: the size of the request's body, which its key holds [bytes]
    request_bytes: int

    def response(self) -> Response:
        return KeptReply(self)


class KeptReply(Response):
    """A kept reply sent again (its headers and body as they were rendered)."""

    def __init__(self, reply: Reply):  # not Response.__init__: nothing to render
        self.status_code = reply.status_code
        self.raw_headers = list(reply.headers)
        self.body = reply.body
        self.background = None


class RequestKey(NamedTuple):
    """What identifies a request's reply: the request as it came, and the headers the routes read
    (the answer's format, ``Accept``; whether the body is JSON at all, ``Content-Type``)."""

    method: str
    path: str
    query: bytes
    accept: str
    content_type: str | None
    body: bytes


def request_key(request: Request, body: bytes) -> RequestKey | None:
    """The request's key; None for a body too large to be one."""
    if len(body) > KEY_MAX_BYTES:
        return None
    scope, headers = request.scope, request.headers
    return RequestKey(scope["method"], scope["path"], scope["query_string"], headers.get("accept", ""),
                      headers.get("content-type"), body)


def keep(replies: LRUCache[Reply], request: Request, key: RequestKey, response: Response) -> None:
    """Keep the response for the key when its operation answered from its own cache, whole and small."""
    if not getattr(request.state, KEPT_FLAG, False) or response.status_code != 200:
        return
    body = getattr(response, "body", None)
    if not isinstance(body, bytes) or not 0 < len(body) <= REPLY_MAX_BYTES:
        return
    length = dict(response.raw_headers).get(b"content-length")
    if length is None or int(length) != len(body):  # a streamed answer's body is not all here
        return
    reply = Reply(response.status_code, tuple(response.raw_headers), body, len(key.body))
    replies.get_or_create(key, lambda: reply)


def reply_size(reply: Reply) -> int:
    """Bytes a kept reply and its key hold (bodies and headers)."""
    return len(reply.body) + sum(len(k) + len(v) for k, v in reply.headers) + reply.request_bytes
