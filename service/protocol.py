"""uvicorn's httptools protocol with TCP_NODELAY, header and URL size limits and read timeouts.

httptools (llhttp, in C) parses requests at about twice the rate of the pure-Python h11
(bench/README.md); uvicorn runs it on uvloop. Both are in requirements.lock.

TCP_NODELAY: with several workers, uvicorn binds the listening socket itself as
``socket.socket(family=...)`` (protocol number 0); asyncio only sets TCP_NODELAY on
accepted sockets whose protocol is IPPROTO_TCP, so every multi-worker connection ran with
Nagle's algorithm against delayed ACKs: ~40 ms per small answer, and two workers served
fewer requests than one (bench/README.md, workers_scaling).

Limits uvicorn's httptools protocol does not have (it has only the keep-alive timeout; h11's
``h11_max_incomplete_event_size`` does not apply to httptools): they are checked here, as the
bytes arrive, before the app (and so before the API-key check) sees the request:

- request line and headers over ``max_header_bytes`` → 431; the bytes are counted before
  they are fed to the parser, which otherwise buffers a header of any size (quadratically:
  httptools concatenates each piece to what it holds);
- request target over ``max_url_bytes`` → 414 (httptools cannot parse a URL over 64 KiB
  at all, and uvicorn answered that with a text/plain 400);
- headers not complete ``header_timeout_s`` after the connection opened (or, on a kept-alive
  connection, after the request's first byte), or the body not complete ``body_timeout_s``
  after the headers → 408, or only closing when an answer has already started. The time a
  request waits with reading paused by the server (a pipelined request, a body the app has
  not read yet) is not held against the client;
- an answer the client stops reading: when the transport's write buffer stays over its
  high-water mark for ``write_timeout_s`` (the client read nothing that brought it back
  under the low-water mark), the connection is reset: no answer can be sent any more;
- accepting: uvloop (libuv 1.52) accepts one connection per turn of the event loop, and
  under load a turn takes 50-100 ms (hundreds of callbacks, each taking the GIL back from a
  computing thread): 10-20 connections a second, so 100 connections queued in the kernel
  made a new one, a probe's too, wait 10-20 s, unseen by the server. Each connection made
  therefore takes every other one waiting in the listen queue at once (``accept()`` on the
  listening socket until it would block), so a connection waits at most one turn to be
  accepted;
- connections past ``max_connections`` open at once in this worker (issue 34): such a
  connection is accepted and its request head read, then answered 503 with ``Retry-After``
  and closed, at once, without reaching the app (``GET``/``HEAD /health`` excepted: probes
  see a busy worker alive). A worker keeps at most that many connections sending it
  requests, and a client past them learns at once to come back later (or a balancer to go
  elsewhere) instead of waiting in a queue (docs/robustness.md, "At the door").

Each refusal is the service's JSON error body with ``Connection: close``, and a line in the
log at info level (client, status, why; no traceback; a 503 at debug level). The server then
stops reading requests, half-closes, and discards what the client still sends for at most
``LINGER_S`` (so a client still writing its headers or body reads the answer instead of a
connection reset), then closes.
"""

from __future__ import annotations

import asyncio
import functools
import logging
import os
import socket
import stat
from asyncio import TimerHandle
from dataclasses import dataclass
from typing import Any, Literal

import httptools
import orjson
from uvicorn.config import Config
from uvicorn.protocols.http.httptools_impl import STATUS_LINE, HttpToolsProtocol
from uvicorn.server import ServerState

from service.settings import Settings
from service.wire import RETRY_AFTER_S, SECURITY_HEADERS

#: after a refusal, how long what the client still sends is read and discarded before closing [s]
LINGER_S = 2.0
#: paths answered on a connection past the connection limit (liveness and readiness probes)
PROBE_PATHS = frozenset({b"/health"})

Phase = Literal["headers", "body"]


@dataclass(frozen=True)
class TransportLimits:
    max_header_bytes: int
    max_url_bytes: int
    header_timeout_s: float
    body_timeout_s: float
    write_timeout_s: float
    max_connections: int = 100_000

    @classmethod
    def from_settings(cls, settings: Settings) -> TransportLimits:
        return cls(settings.max_header_bytes, settings.max_url_bytes, settings.header_timeout_s,
                   settings.body_timeout_s, settings.write_timeout_s, settings.max_connections)


@functools.cache
def limits_from_environment() -> TransportLimits:
    """The limits of this process's settings (the same CAMCORE_* environment as the app's);
    ``python -m service`` has validated them before uvicorn started."""
    return TransportLimits.from_settings(Settings())


#: the file descriptors of this process's listening sockets, by the local address of the
#: connections they accept
_LISTENER_FDS: dict[Any, list[int]] = {}
_ANY_HOST = ("0.0.0.0", "::")


def _listens_for(sock: socket.socket, address: Any) -> bool:
    """Whether ``sock`` is a listening stream socket that accepts connections to ``address``,
    non-blocking as an event loop's are (a blocking one is someone else's: accept() would wait)."""
    if sock.type != socket.SOCK_STREAM or sock.getsockopt(socket.SOL_SOCKET, socket.SO_ACCEPTCONN) != 1:
        return False
    if os.get_blocking(sock.fileno()):
        return False
    bound = sock.getsockname()
    if isinstance(address, tuple) and isinstance(bound, tuple):  # IP: the same port, on that host or on all
        return bool(bound[1] == address[1] and bound[0] in (address[0], *_ANY_HOST))
    return bool(bound == address)


def _listener_fds(address: Any) -> list[int]:
    """Found once, among the process's file descriptors (/proc/self/fd; none elsewhere)."""
    if address not in _LISTENER_FDS:
        found = []
        try:
            fds = [int(name) for name in os.listdir("/proc/self/fd")]
        except OSError:
            fds = []
        for fd in fds:
            try:
                if stat.S_ISSOCK(os.fstat(fd).st_mode):
                    sock = socket.socket(fileno=fd)
                    try:
                        if _listens_for(sock, address):
                            found.append(fd)
                    finally:
                        sock.detach()  # the server's socket: not closed here
            except OSError:
                continue
        _LISTENER_FDS[address] = found
    return _LISTENER_FDS[address]


def waiting_connections(address: Any) -> list[socket.socket]:
    """The connections to ``address`` waiting in this process's listen queues, accepted now
    (non-blocking). A listener closed since (the server shutting down) is checked for each
    time and forgotten, so nothing is accepted after the server stopped listening."""
    accepted: list[socket.socket] = []
    fds = _listener_fds(address)
    for fd in list(fds):
        try:
            listener = socket.socket(fileno=fd)
        except OSError:
            fds.remove(fd)
            continue
        try:
            if not _listens_for(listener, address):
                fds.remove(fd)
                continue
            while True:
                conn, _ = listener.accept()  # the descriptor is non-blocking (libuv's)
                conn.setblocking(False)
                accepted.append(conn)
        except (BlockingIOError, InterruptedError):
            pass
        except OSError as exc:  # e.g. out of file descriptors: the rest waits for libuv's own accept
            logging.getLogger("uvicorn.error").warning("accept failed: %s", exc)
        finally:
            listener.detach()
    return accepted


class _Refusal(Exception):
    """Raised in a parser callback to stop parsing and answer ``status``."""

    def __init__(self, status: int, detail: str, headers: tuple[tuple[bytes, bytes], ...] = ()):
        super().__init__(detail)
        self.status = status
        self.detail = detail
        self.headers = headers


class LimitedHttpToolsProtocol(HttpToolsProtocol):
    def __init__(self, config: Config, server_state: ServerState, app_state: dict[str, Any],
                 _loop: asyncio.AbstractEventLoop | None = None, limits: TransportLimits | None = None) -> None:
        super().__init__(config, server_state, app_state, _loop)
        self.limits = limits or limits_from_environment()
        self._read_timer: TimerHandle | None = None
        self._write_timer: TimerHandle | None = None
        self._read_phase: Phase = "headers"
        self._reading_headers = True  # the next bytes belong to a request line or headers
        self._header_bytes = 0  # bytes of the current request line and headers seen so far
        self._refused = False  # an answer to a refusal is out: discard everything else
        self._over_capacity = False  # accepted past max_connections: only /health is answered

    # ------------------------------------------------------------------ connection
    def connection_made(self, transport: asyncio.Transport) -> None:  # type: ignore[override]
        sock = transport.get_extra_info("socket")
        if sock is not None and sock.family in (socket.AF_INET, socket.AF_INET6):
            sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        super().connection_made(transport)
        # this worker's open connections (uvicorn's set, this one in it)
        self._over_capacity = len(self.connections) > self.limits.max_connections
        self._arm("headers")  # a connection that sends nothing is timed like a slow one
        if sock is not None:
            self._accept_waiting(sock.getsockname())

    def _accept_waiting(self, address: Any) -> None:
        """Takes every connection waiting in the listen queue of ``address`` now, instead of
        one per turn of the event loop (see the module's docstring)."""
        for conn in waiting_connections(address):
            self.loop.create_task(self.loop.connect_accepted_socket(self._sibling, conn))

    def _sibling(self) -> LimitedHttpToolsProtocol:
        return type(self)(self.config, self.server_state, self.app_state, self.loop, self.limits)

    def connection_lost(self, exc: Exception | None) -> None:
        self._disarm()
        self._stop_write_timer()
        super().connection_lost(exc)

    def data_received(self, data: bytes) -> None:
        if self._refused:
            return  # lingering after a refusal
        self._unset_keepalive_if_required()
        view = memoryview(data)
        while view:
            if self._reading_headers:
                # feed no more than the limit allows; what follows the headers in the same
                # read is fed on the next turn. A pipelined request that starts inside a
                # piece is counted from the next read on (so it may pass the limit by one
                # read, <= 256 KiB on uvloop, before it is refused).
                room = self.limits.max_header_bytes - self._header_bytes
                if room <= 0:
                    self._refuse(431, f"The request line and headers are larger than the limit of "
                                      f"{self.limits.max_header_bytes} bytes.")
                    return
                piece, view = view[:room], view[room:]
                self._header_bytes += len(piece)
            else:
                piece, view = view, view[:0]
            if not self._feed(piece):
                return

    def _feed(self, piece: memoryview) -> bool:
        """Parse ``piece``; False once the connection is answered, closing or upgraded."""
        try:
            self.parser.feed_data(piece)
        except httptools.HttpParserCallbackError as exc:
            refusal = exc.__context__
            if isinstance(refusal, _Refusal):
                self._refuse(refusal.status, refusal.detail, refusal.headers)
            else:
                self.logger.warning("Invalid HTTP request received.")
                self.send_400_response("Invalid HTTP request received.")
            return False
        except httptools.HttpParserError:
            self.logger.warning("Invalid HTTP request received.")
            self.send_400_response("Invalid HTTP request received.")
            return False
        except httptools.HttpParserUpgrade:  # as uvicorn does
            if self._should_upgrade():
                self._disarm()
                self.handle_websocket_upgrade()
            else:
                self._unsupported_upgrade_warning()
            return False
        return not self.transport.is_closing()

    # ------------------------------------------------------------------ parser callbacks
    def on_message_begin(self) -> None:
        super().on_message_begin()
        if self._read_timer is None:  # on a fresh connection the clock runs since it opened
            self._arm("headers")

    def on_url(self, url: bytes) -> None:
        if len(self.url) + len(url) > self.limits.max_url_bytes:
            raise _Refusal(414, f"The request URL is longer than the limit of {self.limits.max_url_bytes} bytes.")
        super().on_url(url)

    def on_headers_complete(self) -> None:
        if self._over_capacity and httptools.parse_url(self.url).path not in PROBE_PATHS:
            raise _Refusal(503, f"this worker is busy: {len(self.connections) - 1} connections are open, the limit "
                                f"is {self.limits.max_connections}; retry after {RETRY_AFTER_S} s.",
                           ((b"retry-after", str(RETRY_AFTER_S).encode()),))
        self._reading_headers = False
        self._arm("body")  # disarmed again at the message's end, at once when it has no body
        super().on_headers_complete()

    def on_message_complete(self) -> None:
        self._disarm()
        self._reading_headers = True
        self._header_bytes = 0
        super().on_message_complete()

    # ------------------------------------------------------------------ timeouts
    def _arm(self, phase: Phase) -> None:
        self._disarm()
        self._read_phase = phase
        timeout = self.limits.header_timeout_s if phase == "headers" else self.limits.body_timeout_s
        self._read_timer = self.loop.call_later(timeout, self._read_timed_out)

    def _disarm(self) -> None:
        if self._read_timer is not None:
            self._read_timer.cancel()
            self._read_timer = None

    def _read_timed_out(self) -> None:
        self._read_timer = None
        if self.transport.is_closing() or self._refused:
            return
        phase = self._read_phase
        previous_running = self.cycle is not None and not self.cycle.response_complete
        awaiting_continue = phase == "body" and self.cycle is not None and self.cycle.waiting_for_100_continue
        if self.flow.read_paused or awaiting_continue or (phase == "headers" and previous_running):
            # the server is the slow side (reading paused, a client waiting for the
            # "100 Continue" the app has not asked for yet, or a pipelined request waiting
            # for the one before it): give the client a new period
            self._arm(phase)
            return
        if phase == "body" and self.cycle is not None and self.cycle.response_started:
            # answered already (e.g. 401 or 413 before the whole body came): just close
            self.transport.close()
            return
        timeout = self.limits.header_timeout_s if phase == "headers" else self.limits.body_timeout_s
        self._refuse(408, f"The request {phase} did not arrive within {timeout:g} s; the connection is closed.")

    def pause_writing(self) -> None:
        super().pause_writing()
        if self._write_timer is None:
            self._write_timer = self.loop.call_later(self.limits.write_timeout_s, self._write_timed_out)

    def resume_writing(self) -> None:
        self._stop_write_timer()
        super().resume_writing()

    def _stop_write_timer(self) -> None:
        if self._write_timer is not None:
            self._write_timer.cancel()
            self._write_timer = None

    def _write_timed_out(self) -> None:
        self._write_timer = None
        if self.flow.write_paused:
            # close() would wait to flush a buffer nobody reads: reset instead; the app's
            # pending send returns (disconnected) when connection_lost runs
            self.logger.info("Answer not read for %g s: connection reset.", self.limits.write_timeout_s)
            self.transport.abort()

    # ------------------------------------------------------------------ answers
    def send_400_response(self, msg: str) -> None:
        self._refuse(400, msg)

    def _refuse(self, status: int, detail: str, extra_headers: tuple[tuple[bytes, bytes], ...] = ()) -> None:
        """Answer ``status`` with the JSON error body, half-close, and discard the rest."""
        self._disarm()
        self._refused = True
        client = self.transport.get_extra_info("peername")
        # a 503 at the door comes by the thousand under overload: not at the default level
        self.logger.log(logging.DEBUG if status == 503 else logging.INFO, "%s - %d: %s",
                        f"{client[0]}:{client[1]}" if client else "-", status, detail)
        if self.cycle is not None and not self.cycle.response_complete:
            if self.cycle.response_started:
                self.transport.close()  # an answer is being written: cannot put one inside it
                return
            # the app of this (or an earlier pipelined) request still runs: it sees a
            # disconnect, and nothing it sends is written
            self.cycle.disconnected = True
            self.cycle.message_event.set()
        body = orjson.dumps({"detail": detail, "errors": []})
        head = [STATUS_LINE[status]]
        headers = [*self.server_state.default_headers, *SECURITY_HEADERS, *extra_headers,
                   (b"content-type", b"application/json"), (b"content-length", str(len(body)).encode()),
                   (b"connection", b"close")]
        for name, value in headers:
            head += [name, b": ", value, b"\r\n"]
        head += [b"\r\n", body]
        self.transport.write(b"".join(head))
        if self.transport.can_write_eof():
            self.transport.write_eof()
        self.flow.resume_reading()  # keep reading, to discard, so the client is not reset mid-write
        self.loop.call_later(LINGER_S, self._close)

    def _close(self) -> None:
        if not self.transport.is_closing():
            self.transport.close()
