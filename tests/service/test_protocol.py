"""Every served connection runs with TCP_NODELAY, also with several workers.

uvicorn's multi-worker listener is a protocol-0 socket, on whose accepted connections asyncio
does not set TCP_NODELAY: small answers then waited ~40 ms on delayed ACKs and two workers
served fewer requests than one (bench/README.md). service.protocol sets it per connection.
"""

from __future__ import annotations

import asyncio
import socket

from uvicorn.config import Config
from uvicorn.server import ServerState

from service.main import app
from service.protocol import LimitedHttpToolsProtocol, TransportLimits


class _Transport(asyncio.Transport):
    def __init__(self, sock: socket.socket):
        super().__init__()
        self._sock = sock

    def get_extra_info(self, name: str, default: object = None) -> object:
        return {"socket": self._sock, "peername": self._sock.getpeername(),
                "sockname": self._sock.getsockname()}.get(name, default)

    def is_closing(self) -> bool:
        return False

    def close(self) -> None:
        pass


def test_connection_gets_tcp_nodelay() -> None:
    with socket.socket(socket.AF_INET) as listener:  # protocol 0, as uvicorn binds for workers
        listener.bind(("127.0.0.1", 0))
        listener.listen()
        with socket.create_connection(listener.getsockname()) as client:
            served, _ = listener.accept()
            with served:
                assert served.proto == 0
                assert served.getsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY) == 0
                config = Config(app=app)
                config.load()

                async def connect() -> None:
                    proto = LimitedHttpToolsProtocol(config=config, server_state=ServerState(), app_state={})
                    proto.connection_made(_Transport(served))
                    proto.connection_lost(None)  # cancels its read timer

                asyncio.run(connect())
                assert served.getsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY) == 1
            assert client.fileno() >= 0


def test_the_service_runs_with_this_protocol() -> None:
    from pathlib import Path

    main = (Path(__file__).resolve().parents[2] / "service" / "__main__.py").read_text(encoding="utf-8")
    assert "http=LimitedHttpToolsProtocol" in main


# ----------------------------------------------------------------------------- read timeouts, in-process
async def _serve_once(app: object, request: bytes, after_headers: bytes = b"",
                      send_rest_when: bytes | None = None) -> tuple[bytes, float]:
    """Serve ``app`` with the protocol (body timeout 0.2 s) on a loopback port; send
    ``request``, then ``after_headers`` once ``send_rest_when`` has been read (at once if
    None); return everything read until the server closes, and when its first status line came."""
    config = Config(app=app, lifespan="off")
    config.load()
    limits = TransportLimits(max_header_bytes=16384, max_url_bytes=8192, header_timeout_s=5,
                             body_timeout_s=0.2, write_timeout_s=5)
    loop = asyncio.get_running_loop()
    state = ServerState()
    server = await loop.create_server(lambda: LimitedHttpToolsProtocol(config, state, {}, limits=limits),
                                      "127.0.0.1", 0)
    port = server.sockets[0].getsockname()[1]
    reader, writer = await asyncio.open_connection("127.0.0.1", port)
    start = loop.time()
    writer.write(request)
    received = b""
    first_answer_s = -1.0
    if send_rest_when is None:
        writer.write(after_headers)
    try:
        while chunk := await asyncio.wait_for(reader.read(65536), 5):
            received += chunk
            if first_answer_s < 0 and b"HTTP/1.1 " in received:
                first_answer_s = loop.time() - start
            if send_rest_when is not None and send_rest_when in received:
                writer.write(after_headers)
                send_rest_when = None
            if b"\r\n\r\nok" in received:
                break
    finally:
        writer.close()
        server.close()
        await server.wait_closed()
    return received, first_answer_s


async def _body_echo(scope: dict, receive: object, send: object, delay_s: float = 0.0) -> None:
    await asyncio.sleep(delay_s)
    body = b""
    while True:
        message = await receive()  # type: ignore[operator]
        if message["type"] != "http.request":
            return
        body += message["body"]
        if not message["more_body"]:
            break
    await send({"type": "http.response.start", "status": 200, "headers": [(b"content-length", b"2")]})  # type: ignore[operator]
    await send({"type": "http.response.body", "body": b"ok"})  # type: ignore[operator]


def test_body_not_sent_is_408_at_the_body_timeout() -> None:
    head = b"POST / HTTP/1.1\r\nHost: t\r\nContent-Length: 4\r\n\r\n"
    received, answered_s = asyncio.run(_serve_once(_body_echo, head))
    assert received.startswith(b"HTTP/1.1 408 Request Timeout\r\n"), received
    assert 0.2 <= answered_s < 1.2, answered_s  # 1 s for a loaded machine's event loop


def test_waiting_for_100_continue_is_not_the_clients_delay() -> None:
    """The client waits for "100 Continue", which uvicorn sends when the app first reads; an
    app that reads only after 0.5 s (queued, say) must not make the client's body late."""
    async def slow_app(scope: dict, receive: object, send: object) -> None:
        await _body_echo(scope, receive, send, delay_s=0.5)

    head = b"POST / HTTP/1.1\r\nHost: t\r\nContent-Length: 4\r\nExpect: 100-continue\r\n\r\n"
    received, _ = asyncio.run(_serve_once(slow_app, head, after_headers=b"body",
                                          send_rest_when=b"100 Continue\r\n\r\n"))
    assert received.startswith(b"HTTP/1.1 100 Continue\r\n\r\nHTTP/1.1 200 OK\r\n"), received
    assert received.endswith(b"\r\n\r\nok")
