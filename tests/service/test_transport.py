"""Hostile and careless transport against the real server (service/protocol.py, service/middleware.py).

One ``python -m service`` on a loopback port with short read timeouts (so that the slow-client
cases take a second or two, not the 10 s / 20 s defaults), an API key (to show the transport
limits come before the key check) and a small body limit. The hostile cases speak raw HTTP over
sockets: httpx would not send a 16 MiB header or one byte per 0.2 s.
"""

from __future__ import annotations

import os
import select
import socket
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import httpx
import orjson
import pytest
from pydantic import ValidationError
from pydantic_settings.exceptions import SettingsError

from service.settings import Settings, settings_error_line
from tests.live_server import running_service

ROOT = Path(__file__).resolve().parents[2]
pytestmark = pytest.mark.e2e

KEY = "transport-test-key"
HEADER_TIMEOUT_S = 1.0
BODY_TIMEOUT_S = 1.5
WRITE_TIMEOUT_S = 1.0
KEEP_ALIVE_S = 1
MAX_HEADER_BYTES = 16 * 1024  # the defaults: the edges are tested where users meet them
MAX_URL_BYTES = 8 * 1024
MAX_BODY_BYTES = 64 * 1024
#: how late a cut-off may come: the timer fires on the event loop, which on a loaded 2-core CI
#: machine (other tests, other helpers) can be a few hundred ms late; a missing timeout would
#: instead wait forever (the reads below give up after 10 s)
LATE_S = 1.0
MS_TABLE = orjson.dumps({"curve": {"type": "named", "name": "MS"}, "samples": 5})


@dataclass
class Server:
    url: str
    host: str
    port: int
    pid: int


@pytest.fixture(scope="module")
def server() -> Iterator[Server]:
    with running_service(header_timeout_s=str(HEADER_TIMEOUT_S), body_timeout_s=str(BODY_TIMEOUT_S),
                         write_timeout_s=str(WRITE_TIMEOUT_S), keep_alive_s=str(KEEP_ALIVE_S),
                         max_body_bytes=str(MAX_BODY_BYTES),
                         api_key=KEY) as (url, proc):
        host, port = url.removeprefix("http://").split(":")
        yield Server(url, host, int(port), proc.pid)


@pytest.fixture
def client(server: Server) -> Iterator[httpx.Client]:
    with httpx.Client(base_url=server.url, timeout=10, headers={"X-API-Key": KEY}) as c:
        yield c


# ----------------------------------------------------------------------------- raw HTTP
def connect(server: Server) -> socket.socket:
    sock = socket.create_connection((server.host, server.port), timeout=10)
    sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    return sock


def send_ignoring_reset(sock: socket.socket, data: bytes) -> None:
    """The server may stop reading once it has refused the request; that is the point."""
    try:
        sock.sendall(data)
    except (BrokenPipeError, ConnectionResetError):
        pass


@dataclass
class Answer:
    status: int
    headers: dict[str, str]
    body: bytes
    closed: bool  # the server closed the connection after it


def read_answer(sock: socket.socket) -> Answer:
    """One HTTP answer with a Content-Length (or none, for HEAD); then whether EOF follows."""
    data = b""
    while b"\r\n\r\n" not in data:
        chunk = sock.recv(65536)
        assert chunk, f"connection closed before an answer: {data!r}"
        data += chunk
    head, _, rest = data.partition(b"\r\n\r\n")
    status_line, *lines = head.decode("latin-1").split("\r\n")
    headers: dict[str, str] = {}
    for line in lines:
        name, _, value = line.partition(":")
        assert name.lower() not in headers, f"header {name} twice"
        headers[name.lower()] = value.strip()
    length = int(headers.get("content-length", "0"))
    while len(rest) < length:
        chunk = sock.recv(65536)
        assert chunk
        rest += chunk
    closed = False
    if headers.get("connection") == "close":
        try:
            closed = sock.recv(1) == b""
        except ConnectionResetError:
            closed = True
    return Answer(int(status_line.split()[1]), headers, rest[:length], closed)


def assert_json_error(answer: Answer, status: int, words: str) -> None:
    assert answer.status == status, answer
    assert answer.headers["content-type"] == "application/json"
    assert answer.headers["x-content-type-options"] == "nosniff"
    assert "server" not in answer.headers
    body = orjson.loads(answer.body)
    assert set(body) == {"detail", "errors"} and body["errors"] == []
    assert words in body["detail"], body


def get(path: str, *headers: str) -> bytes:
    lines = [f"GET {path} HTTP/1.1", "Host: t", *headers, "", ""]
    return "\r\n".join(lines).encode()


def vm_kib(pid: int, field: str) -> int:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith(field + ":"):
            return int(line.split()[1])
    raise AssertionError(field)


# ----------------------------------------------------------------------------- header and URL size
def test_headers_over_the_limit_are_431_before_the_key_check(server: Server) -> None:
    """The exact edge: request line and headers of 16 384 bytes pass, one byte more is 431 —
    on a path behind the key, without the key (the limit comes first)."""
    def request_of(total: int, path: str) -> bytes:
        start = get(path, "X-API-Key: " + KEY, "X-Fill: ")
        fill = total - len(start)
        return start.replace(b"X-Fill: ", b"X-Fill: " + b"f" * fill)

    with connect(server) as sock:
        request = request_of(MAX_HEADER_BYTES, "/v1/curves/MS")
        assert len(request) == MAX_HEADER_BYTES
        sock.sendall(request)
        answer = read_answer(sock)
        assert answer.status == 200 and orjson.loads(answer.body)["id"] == "MS"
    with connect(server) as sock:
        sock.sendall(request_of(MAX_HEADER_BYTES + 1, "/v1/curves/MS").replace(KEY.encode(), b"wrong-key-123456789"))
        answer = read_answer(sock)
        assert_json_error(answer, 431, "larger than the limit of 16384 bytes")
        assert answer.closed


def test_huge_headers_do_not_grow_the_server(server: Server) -> None:
    """Four 16 MiB headers at once. Before the limit, httptools buffered each (by repeated
    concatenation): the worker's peak RSS rose by ~86 MiB here (4 × 64 MiB: +346 MiB, /health
    p50 2.6 s). Now the server reads 16 KiB of each, answers 431 and discards the rest."""
    rss_before_kib = vm_kib(server.pid, "VmRSS")
    answers: list[int] = []

    def flood() -> None:
        with connect(server) as sock:
            send_ignoring_reset(sock, b"GET /health HTTP/1.1\r\nHost: t\r\nX-Big: " + b"a" * (16 << 20) + b"\r\n\r\n")
            answers.append(read_answer(sock).status)

    threads = [threading.Thread(target=flood) for _ in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert answers == [431] * 4
    # the peak (VmHWM) since the server started, against what it held before the flood: 20 MiB
    # leaves room for the interpreter's own noise, a quarter of what the unlimited server took
    peak_growth_mib = (vm_kib(server.pid, "VmHWM") - rss_before_kib) / 1024
    assert peak_growth_mib < 20, peak_growth_mib
    assert httpx.get(f"{server.url}/health", timeout=5).status_code == 200


def test_url_over_the_limit_is_414_json(server: Server) -> None:
    with connect(server) as sock:  # 8 192 bytes of request target pass
        path = "/health?pad=" + "p" * (MAX_URL_BYTES - len("/health?pad="))
        sock.sendall(get(path))
        assert read_answer(sock).status == 200
    for length in (MAX_URL_BYTES + 1, 70_000):  # uvicorn answered 70 000 with a text/plain 400
        with connect(server) as sock:
            send_ignoring_reset(sock, get("/health?pad=" + "p" * (length - len("/health?pad="))))
            answer = read_answer(sock)
            assert_json_error(answer, 414, "longer than the limit of 8192 bytes")
            assert answer.closed


def test_malformed_request_is_400_json(server: Server) -> None:
    with connect(server) as sock:
        sock.sendall(b"GET /health HTTP/1.1\r\nHost: t\r\nBad Header\r\n\r\n")
        assert_json_error(read_answer(sock), 400, "Invalid HTTP request")


# ----------------------------------------------------------------------------- read timeouts
def trickle(sock: socket.socket, data: bytes, interval_s: float) -> tuple[float, int]:
    """Send ``data`` one byte per ``interval_s`` until the server answers; returns the seconds
    from the start to the answer's first byte, and how many bytes were sent by then."""
    start = time.monotonic()
    for sent, byte in enumerate(data):
        readable, _, _ = select.select([sock], [], [], interval_s)
        if readable:
            return time.monotonic() - start, sent
        send_ignoring_reset(sock, bytes([byte]))
    readable, _, _ = select.select([sock], [], [], 10)
    assert readable, "no answer 10 s after the last byte"
    return time.monotonic() - start, len(data)


def test_idle_connection_gets_408_after_the_header_timeout(server: Server) -> None:
    with connect(server) as sock:
        start = time.monotonic()
        readable, _, _ = select.select([sock], [], [], 10)
        waited = time.monotonic() - start
        assert readable
        answer = read_answer(sock)
        assert_json_error(answer, 408, "headers did not arrive within 1 s")
        assert answer.closed
    assert HEADER_TIMEOUT_S - 0.05 <= waited < HEADER_TIMEOUT_S + LATE_S, waited


def test_slow_headers_are_cut_off_at_the_header_timeout(server: Server) -> None:
    """One byte per 0.2 s: the whole request would take 7 s; the server answers 408 at 1 s."""
    request = get("/health")
    with connect(server) as sock:
        waited, sent = trickle(sock, request, 0.2)
        answer = read_answer(sock)
    assert_json_error(answer, 408, "headers did not arrive within 1 s")
    assert sent < len(request)
    assert HEADER_TIMEOUT_S - 0.05 <= waited < HEADER_TIMEOUT_S + LATE_S, waited


def test_slow_body_is_cut_off_at_the_body_timeout(server: Server) -> None:
    """Headers at once, then the body one byte per 0.2 s: 408 at the body timeout after the
    headers (its app saw a disconnect: nothing else is written on the connection)."""
    body = b" " * 30 + MS_TABLE
    with connect(server) as sock:
        sock.sendall(f"POST /v1/curves/table HTTP/1.1\r\nHost: t\r\nX-API-Key: {KEY}\r\nContent-Type: application/json\r\n"
                     f"Content-Length: {len(body)}\r\n\r\n".encode())
        waited, sent = trickle(sock, body, 0.2)
        answer = read_answer(sock)
        assert answer.closed
    assert_json_error(answer, 408, "body did not arrive within 1.5 s")
    assert sent < len(body)
    assert BODY_TIMEOUT_S - 0.05 <= waited < BODY_TIMEOUT_S + LATE_S, waited


def test_slow_but_timely_client_is_served(server: Server) -> None:
    """A request sent in pieces within both timeouts is answered as usual."""
    with connect(server) as sock:
        sock.sendall(f"POST /v1/curves/table HTTP/1.1\r\nHost: t\r\nX-API-Key: {KEY}\r\n".encode())
        time.sleep(HEADER_TIMEOUT_S / 2)
        sock.sendall(f"Content-Type: application/json\r\nContent-Length: {len(MS_TABLE)}\r\n\r\n".encode())
        sock.sendall(MS_TABLE[:10])
        time.sleep(BODY_TIMEOUT_S / 2)
        sock.sendall(MS_TABLE[10:])
        answer = read_answer(sock)
    assert answer.status == 200 and len(orjson.loads(answer.body)["s"]) == 5


def test_idle_kept_alive_connection_is_closed_without_an_answer(server: Server) -> None:
    """Between requests the keep-alive timeout (1 s here) applies, and ends the connection
    silently: a 408 there would be read as the answer to the client's next request."""
    with connect(server) as sock:
        sock.sendall(get("/health"))
        assert read_answer(sock).status == 200
        start = time.monotonic()
        readable, _, _ = select.select([sock], [], [], 10)
        assert readable and sock.recv(100) == b""
        waited = time.monotonic() - start
    assert KEEP_ALIVE_S - 0.05 <= waited < KEEP_ALIVE_S + LATE_S, waited


def test_answer_not_read_is_dropped_after_the_write_timeout(server: Server) -> None:
    """A client that asks for a 23 MB CSV table and reads nothing: once the server's buffers are
    full it waits the write timeout, then resets the connection. Reading afterwards yields what
    the buffers held (a few MB), then the end; before, the whole answer waited for ever."""
    with socket.socket() as sock:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
        sock.connect((server.host, server.port))
        sock.sendall(get("/v1/curves/MS/table.csv?samples=200000", "X-API-Key: " + KEY))
        time.sleep(WRITE_TIMEOUT_S + LATE_S + 0.5)  # + the ~0.3 s the table takes to build
        sock.settimeout(10)
        received = b""
        try:
            while chunk := sock.recv(1 << 20):
                received += chunk
        except ConnectionResetError:
            pass
    head, _, body = received.partition(b"\r\n\r\n")
    assert head.startswith(b"HTTP/1.1 200 ")
    # rows, not bytes: the same whether the table comes with a Content-Length or in chunks
    assert body.count(b"\n") < 100_000, body.count(b"\n")  # of 200 001 lines


# ----------------------------------------------------------------------------- bodies
def test_chunked_body_over_the_limit_is_413(server: Server) -> None:
    """No Content-Length: the limit is found while reading (FastAPI used to turn it into 400)."""
    def chunked(total: int) -> bytes:
        body = b" " * (total - len(MS_TABLE)) + MS_TABLE
        chunks = [body[i:i + 8192] for i in range(0, len(body), 8192)]
        return b"".join(b"%x\r\n%s\r\n" % (len(c), c) for c in chunks) + b"0\r\n\r\n"

    head = (f"POST /v1/curves/table HTTP/1.1\r\nHost: t\r\nX-API-Key: {KEY}\r\nContent-Type: application/json\r\n"
            "Transfer-Encoding: chunked\r\n\r\n").encode()
    with connect(server) as sock:
        sock.sendall(head + chunked(MAX_BODY_BYTES))
        answer = read_answer(sock)
        assert answer.status == 200 and len(orjson.loads(answer.body)["s"]) == 5
    with connect(server) as sock:
        send_ignoring_reset(sock, head + chunked(MAX_BODY_BYTES + 1))
        answer = read_answer(sock)
    assert answer.status == 413 and answer.headers["x-content-type-options"] == "nosniff"
    body = orjson.loads(answer.body)
    assert body["limit"]["name"] == "request body size" and body["limit"]["limit"] == MAX_BODY_BYTES
    assert body["limit"]["requested"] > MAX_BODY_BYTES


@pytest.mark.parametrize("content_type", ["text/plain", "application/x-www-form-urlencoded",
                                          "multipart/form-data; boundary=b", "application/xml"])
def test_post_in_another_media_type_is_415(client: httpx.Client, content_type: str) -> None:
    r = client.post("/v1/curves/table", content=MS_TABLE, headers={"Content-Type": content_type})
    assert r.status_code == 415, r.text
    assert r.json() == {"detail": f"Content-Type {content_type.split(';')[0]} is not supported: "
                                  "send the request body as application/json.", "errors": []}


def test_json_media_types_and_missing_content_type_are_as_before(client: httpx.Client) -> None:
    for content_type in ("application/json", "application/json; charset=utf-8", "application/merge-patch+json"):
        r = client.post("/v1/curves/table", content=MS_TABLE, headers={"Content-Type": content_type})
        assert r.status_code == 200, (content_type, r.text)
    # no Content-Type: FastAPI reads no JSON from it (strict), the route answers 400 as it did
    for headers in ({}, {"Content-Type": ""}):
        r = client.post("/v1/curves/table", content=MS_TABLE, headers=headers)
        assert "content-type" not in r.request.headers or not r.request.headers["content-type"]
        assert r.status_code == 400 and "not a valid JSON object" in r.json()["detail"]
    # an unknown path stays 404, a GET-only path 405: the media type matters only to a route that reads it
    assert client.post("/v1/nowhere", content=b"x", headers={"Content-Type": "text/plain"}).status_code == 404
    assert client.post("/v1/curves", content=b"x", headers={"Content-Type": "text/plain"}).status_code == 405


# ----------------------------------------------------------------------------- methods, headers
def test_head_health_is_200_without_a_body(server: Server) -> None:
    """HEAD then GET on one connection: right after HEAD's headers comes the GET's status
    line (a body after HEAD would sit in between)."""
    with connect(server) as sock:
        sock.sendall(b"HEAD /health HTTP/1.1\r\nHost: t\r\n\r\n" + get("/health"))
        data = b""
        while data.count(b"\r\n\r\n") < 2:
            chunk = sock.recv(65536)
            assert chunk
            data += chunk
    head, _, rest = data.partition(b"\r\n\r\n")
    assert head.startswith(b"HTTP/1.1 200 OK\r\n")
    assert b"content-type: application/json" in head and b"x-content-type-options: nosniff" in head
    assert rest.startswith(b"HTTP/1.1 200 OK\r\n")


def test_405_allow_lists_every_method_of_the_path(client: httpx.Client) -> None:
    # POST /v1/curves/table and GET /v1/curves/{name} both match: Starlette named only the second
    r = client.request("OPTIONS", "/v1/curves/table")
    assert r.status_code == 405 and r.headers["allow"] == "GET, POST"
    assert r.json() == {"detail": "Method Not Allowed", "errors": []}
    assert client.delete("/v1/curves/MS").headers["allow"] == "GET"
    assert client.put("/health").headers["allow"] == "GET, HEAD"
    assert client.get("/v1/profiles").headers["allow"] == "POST"


def test_no_server_banner_and_nosniff_everywhere(server: Server, client: httpx.Client) -> None:
    answers = {
        "json": client.get("/v1/curves/MS"),
        "svg": client.get("/v1/curves/MS/plot"),
        "csv": client.get("/v1/curves/MS/table.csv", params={"samples": 3}),
        "404": client.get("/v1/curves/nope"),
        "422": client.post("/v1/curves/table", json={"curve": {"type": "named", "name": "MS"}, "samples": 1}),
        "401": httpx.get(f"{server.url}/v1/curves", timeout=10),
        "docs": client.get("/docs"),
        "openapi": client.get("/openapi.json"),
        "health": client.get("/health"),
    }
    assert answers["svg"].headers["content-type"].startswith("image/svg+xml")
    for name, r in answers.items():
        assert "server" not in r.headers, name
        assert r.headers.get_list("x-content-type-options") == ["nosniff"], name
    assert [r.status_code for r in answers.values()] == [200, 200, 200, 404, 422, 401, 200, 200, 200]


# ----------------------------------------------------------------------------- settings errors
def run_service(**env: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "service"], cwd=ROOT, capture_output=True, text=True, timeout=60, check=False,
                          env={**os.environ, "CAMCORE_PORT": "1", **env})


@pytest.mark.parametrize(("env", "line"), [
    ({"CAMCORE_LOG_LEVEL": "bogus"}, ("camcore: invalid setting: CAMCORE_LOG_LEVEL='bogus' must be 'critical', "
                                      "'error', 'warning', 'info', 'debug' or 'trace'")),
    # several workers: checked once in the parent, before any worker starts
    ({"CAMCORE_WORKERS": "0"}, "camcore: invalid setting: CAMCORE_WORKERS='0' must be greater than or equal to 1"),
])
def test_bad_setting_is_one_line_and_exit_2(env: dict[str, str], line: str) -> None:
    done = run_service(**env)
    assert done.returncode == 2
    assert done.stdout == ""
    assert done.stderr == line + "\n"


@pytest.mark.parametrize(("env", "line"), [
    ({"CAMCORE_PORT": "abc"}, "CAMCORE_PORT='abc' must be a valid integer, unable to parse string as an integer"),
    ({"CAMCORE_HEADER_TIMEOUT_S": "0"}, "CAMCORE_HEADER_TIMEOUT_S='0' must be greater than 0"),
    ({"CAMCORE_MAX_URL_BYTES": "1e9"}, "CAMCORE_MAX_URL_BYTES='1e9' must be a valid integer"),
    ({"CAMCORE_CORS_ORIGINS": "[oops"}, "CAMCORE_CORS_ORIGINS must be a JSON list"),
    # the key is never echoed, whatever is wrong
    ({"CAMCORE_API_KEY": "secret", "CAMCORE_WORKERS": "99"}, "CAMCORE_WORKERS='99' must be less than or equal to 64"),
    ({"CAMCORE_PORT": "0", "CAMCORE_LOG_LEVEL": "loud"}, ("CAMCORE_PORT='0' must be greater than or equal to 1; "
                                                          "CAMCORE_LOG_LEVEL='loud' must be")),
])
def test_settings_error_line(monkeypatch: pytest.MonkeyPatch, env: dict[str, str], line: str) -> None:
    for name, value in env.items():
        monkeypatch.setenv(name, value)
    with pytest.raises((ValidationError, SettingsError)) as caught:
        Settings()
    text = settings_error_line(caught.value)
    assert text.startswith(line) and "\n" not in text and "secret" not in text


def test_log_level_is_case_insensitive(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("CAMCORE_LOG_LEVEL", "WARNING")
    assert Settings().log_level == "warning"
