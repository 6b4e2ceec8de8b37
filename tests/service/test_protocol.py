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
from service.protocol import LimitedHttpToolsProtocol


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
