"""Every operation's answers on its request examples, recorded once and replayed.

``python -m tests.answer_replay`` records (run it on the commit whose answers are the
reference): for every POST operation of the committed OpenAPI document, each request
example as JSON, as CSV (``Accept: text/csv``) where the operation answers CSV, and with
every ``?format=`` its document lists; the toolpath's files through its body's ``format``;
and a fixed list of GET requests (the README's, the charts, the spreadsheet cells) and of
refusals. Each answer is kept as its status, media type, disposition and the SHA-256 of its
bytes (the moment a STEP or DXF file was written blanked, :data:`_MOMENTS`, and a DXF's
classes sorted, :data:`_DXF_CLASSES`). ``tests/service/test_answer_replay.py`` sends the same requests to today's app.

The last bits of a float64 sine, cosine, exponential or power depend on the CPU: numpy calls Intel's
SVML kernels for them where the CPU has AVX512_SKX and other code elsewhere, so the same commit writes
some numbers a few ulps apart (an MS table's 101 rows, a barrel cam's contour). Each answer is
therefore recorded once per kind of CPU (:func:`cpu_kind`): ``answers.json`` on a CPU with AVX512_SKX,
``answers-without-avx512.json`` elsewhere, the same requests in the same order; the test replays the
record of the CPU it runs on. ``python -m tests.answer_replay --same-requests`` answers the requests of
``answers.json`` again into this CPU's record: run it on the commit whose answers are the reference,
on a CPU of the other kind.
"""

from __future__ import annotations

import asyncio
import hashlib
import json
import re
import sys
from pathlib import Path
from typing import Any

import httpx

ROOT = Path(__file__).resolve().parents[1]
RECORD = ROOT / "tests" / "data" / "answers.json"
#: the same requests answered on a CPU without AVX512_SKX (module notes)
RECORD_WITHOUT_AVX512 = ROOT / "tests" / "data" / "answers-without-avx512.json"
DOCUMENT = ROOT / "openapi" / "openapi.json"

#: what a file says of the moment it was written: OpenCASCADE's STEP header
#: (FILE_NAME('…','2026-11-27T12:28:38',…)); ezdxf's creation and update dates ($TDCREATE,
#: $TDUPDATE: Julian days), GUIDs and its own "1.4.5 @ <time>" stamp
_MOMENTS = [
    (re.compile(rb"FILE_NAME\('([^']*)','\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d'"), rb"FILE_NAME('\1','(time)'"),
    (re.compile(rb"(\$TD\w+\r?\n *40\r?\n)[0-9.]+"), rb"\1(time)"),
    (re.compile(rb"\{[0-9A-F]{8}-[0-9A-F]{4}-[0-9A-F]{4}-[0-9A-F]{4}-[0-9A-F]{12}\}"), rb"{guid}"),
    (re.compile(rb" @ \d{4}-\d\d-\d\dT[0-9:.+]+"), rb" @ (time)"),
]

PROFILE = {"follower": {"type": "roller", "roller_radius_mm": 10}, "base_radius_mm": 40,
           "segments": [{"type": "rise", "angle_deg": 120, "lift_mm": 20, "curve": {"type": "named", "name": "MS"}},
                        {"type": "dwell", "angle_deg": 60}, {"type": "return", "angle_deg": 120, "lift_mm": 20},
                        {"type": "dwell", "angle_deg": 60}]}

#: GET requests: the README's, the charts, spreadsheet cells, and refusals (not /health: its
#: cache counts tell what the process did before)
GETS: list[str] = [
    "/v1/curves", "/v1/curves/26", "/v1/curves/MS", "/v1/curves/cycloyd",
    "/v1/curves/MS/table?samples=101", "/v1/curves/MS/table?samples=101&format=csv",
    "/v1/curves/MS/table.csv?samples=11&direction=return", "/v1/curves/MS/table?samples=1",
    "/v1/curves/MS/inverse?s=0.1833", "/v1/curves/MS/inverse?s=0.1833&method=table&table_decimals=5&format=csv",
    "/v1/curves/MS/inverse.csv?s=0.1,0.2&s=0.5", "/v1/curves/cycloid/inverse?s=2",
    "/v1/curves/MS/value?t=0.3", "/v1/curves/MS/value?t=0.3&quantity=q", "/v1/curves/MS/value?s=0.1833",
    "/v1/curves/MS/value?t=0.3&s=0.2", "/v1/curves/MS/value",
    "/v1/indexers/accuracy?arc_seconds=30&radius_mm=200",
    "/v1/curves/MS/plot", "/v1/curves/MT/plot?format=png&samples=201",
    "/v1/indexers/plot?stops=6&indexing_angle_deg=270&speed_rpm=60",
    "/v1/indexers/plot?stops=6&indexing_angle_deg=270&speed_rpm=60&curve=MT&format=png&dpi=72",
    "/v1/profiles/plot", "/v1/profiles/plot?follower=knife-edge&base_radius_mm=25&format=png",
    "/v1/profiles/plot?rise_deg=200&return_deg=200",
    "/v1/profiles/dynamics/plot?speed_rpm=600&mass_kg=0.5&spring_rate_n_mm=2&preload_n=30&safety_margin_n=5",
    "/v1/curves/vibration/plot", "/v1/curves/vibration/plot?curves=MS,TR&quantity=peak_deviation&format=png",
]

#: POST refusals: (path, body)
REFUSALS: list[tuple[str, Any]] = [
    ("/v1/curves/table", {"curve": {"type": "named", "name": "MS"}, "samples": 10**9}),
    ("/v1/curves/table", {"curve": {"type": "universal", "t": [0, 0.5, 0.2, 0.5, 0.5, 0.875, 0.875, 1]}}),
    ("/v1/curves/characteristics", {"curve": {"type": "named", "name": "cycloyd"}}),
    ("/v1/motions", {"motion": {"segments": [{"span_deg": 300, "to": 10}]}}),
    ("/v1/profiles", {"profile": {**PROFILE, "base_radius_mm": -1}}),
    ("/v1/indexers/sizing", {"indexer": {"stops": 6, "indexing_angle_deg": 270}, "load": {}}),
    ("/v1/cams/barrel", {"pitch_radius_mm": 50, "roller_radius_mm": 10, "follower": "oscillating",
                         "segments": PROFILE["segments"]}),
]


#: a DXF's CLASSES section: ezdxf writes its records in the order of a set (so of the
#: process's string hashes); they are compared sorted
_DXF_CLASSES = re.compile(rb"(\n *2\r?\nCLASSES\r?\n)(.*?)(\n *0\r?\nENDSEC)", re.DOTALL)
_DXF_CLASS = re.compile(rb"\n *0\r?\nCLASS\r?\n")


def _sorted_classes(match: re.Match[bytes]) -> bytes:
    records = _DXF_CLASS.split(match.group(2))
    return match.group(1) + records[0] + b"".join(b"\n  0\nCLASS\n" + r for r in sorted(records[1:])) + match.group(3)


def _normalise(content: bytes) -> bytes:
    for pattern, replacement in _MOMENTS:
        content = pattern.sub(replacement, content)
    return _DXF_CLASSES.sub(_sorted_classes, content, count=1)


def requests() -> list[dict[str, Any]]:
    """The requests to record, from the committed document."""
    doc = json.loads(DOCUMENT.read_text(encoding="utf-8"))
    out: list[dict[str, Any]] = []
    for path, ops in doc["paths"].items():
        op = ops.get("post")
        if op is None:
            continue
        answers = op["responses"]["200"].get("content", {})
        formats = [p for p in op.get("parameters", []) if p["name"] == "format" and p["in"] == "query"]
        values: list[str] = []
        if formats:
            schema = formats[0]["schema"]
            for option in schema.get("anyOf", [schema]):
                values += option.get("enum", [])
        for example in op["requestBody"]["content"]["application/json"].get("examples", {}).values():
            body = example["value"]
            out.append({"method": "POST", "path": path, "body": body, "headers": {}})
            if "text/csv" in answers and not values:
                out.append({"method": "POST", "path": path, "body": body, "headers": {"accept": "text/csv"}})
            for value in values:
                out.append({"method": "POST", "path": f"{path}?format={value}", "body": body, "headers": {}})
            if path == "/v1/profiles/toolpath":
                for fmt in ("gcode", "dxf"):
                    out.append({"method": "POST", "path": path, "body": {**body, "format": fmt}, "headers": {}})
    out += [{"method": "GET", "path": path, "body": None, "headers": {}} for path in GETS]
    out += [{"method": "POST", "path": path, "body": body, "headers": {}} for path, body in REFUSALS]
    return out


async def answer(client: httpx.AsyncClient, request: dict[str, Any]) -> dict[str, Any]:
    """What the app answers to one recorded request."""
    r = await client.request(request["method"], request["path"], json=request["body"], headers=request["headers"])
    content = _normalise(r.content)
    return {"status": r.status_code, "media_type": r.headers.get("content-type", ""),
            "disposition": r.headers.get("content-disposition", ""),
            "sha256": hashlib.sha256(content).hexdigest(), "bytes": len(content)}


def cpu_kind() -> str:
    """``avx512`` where numpy dispatches its AVX512_SKX kernels (SVML's float64 sine, cosine,
    exponential, …), else ``without-avx512``."""
    from numpy._core._multiarray_umath import __cpu_features__

    return "avx512" if __cpu_features__.get("AVX512_SKX") else "without-avx512"


def record_of(kind: str) -> Path:
    """The record of the answers on a kind of CPU (:func:`cpu_kind`)."""
    return RECORD if kind == "avx512" else RECORD_WITHOUT_AVX512


async def record(same_requests: bool) -> None:
    """Answer :func:`requests` (or, with ``same_requests``, those of :data:`RECORD`) into this CPU's record."""
    from service.app import create_app

    asked = [{key: e[key] for key in ("method", "path", "body", "headers")}
             for e in json.loads(RECORD.read_text(encoding="utf-8"))] if same_requests else requests()
    async with httpx.AsyncClient(transport=httpx.ASGITransport(app=create_app()), base_url="http://testserver",
                                 timeout=120) as client:
        entries = []
        for request in asked:
            entries.append({**request, "answer": await answer(client, request)})
    path = record_of(cpu_kind())
    path.write_text(json.dumps(entries, indent=1, ensure_ascii=False) + "\n", encoding="utf-8")
    print(f"{len(entries)} answers recorded in {path.relative_to(ROOT)}")


if __name__ == "__main__":
    asyncio.run(record(same_requests="--same-requests" in sys.argv[1:]))
