"""uvicorn's httptools protocol with TCP_NODELAY on every connection.

httptools (llhttp, in C) parses requests at about twice the rate of the pure-Python h11
(bench/README.md); uvicorn runs it on uvloop. Both are in requirements.lock.

With several workers, uvicorn binds the listening socket itself as
``socket.socket(family=...)`` (protocol number 0); asyncio only sets TCP_NODELAY on
accepted sockets whose protocol is IPPROTO_TCP, so every multi-worker connection ran with
Nagle's algorithm against delayed ACKs: ~40 ms per small answer, and two workers served
fewer requests than one (bench/README.md, workers_scaling).
"""

from __future__ import annotations

import asyncio
import socket

from uvicorn.protocols.http.httptools_impl import HttpToolsProtocol


class NoDelayHttpToolsProtocol(HttpToolsProtocol):
    def connection_made(self, transport: asyncio.Transport) -> None:  # type: ignore[override]
        sock = transport.get_extra_info("socket")
        if sock is not None and sock.family in (socket.AF_INET, socket.AF_INET6):
            sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        super().connection_made(transport)
