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

A change that moves answers on purpose (a faster fit within its tolerance) can only be recorded
byte for byte on the CPU at hand. ``python -m tests.answer_replay --changed`` answers the record's
requests on this CPU, records the answers that changed here, and marks the same entries of the other
kind's record *near*: their answer as this CPU wrote it is kept (``tests/data/near/<sha256>.xz``), and
there the test compares numbers, not bytes (:func:`near_enough`: the text between the numbers equal,
whole numbers equal, the others within 1e-9 relative, 1e-9 absolute or, printed to the same
decimals (a file's fixed format), a unit of the last; the CPUs differ by a few ulps). ``--same-requests`` on a CPU of that kind makes them exact again
and drops the kept answers no record needs.
"""

from __future__ import annotations

import asyncio
import hashlib
import json
import lzma
import math
import os
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
#: answers as one kind of CPU wrote them, for the near entries of the other kind's record (module notes)
NEAR = ROOT / "tests" / "data" / "near"
#: a near answer's numbers agree within this, relative and absolute ([mm], [s], [deg]: a nanometre, a
#: nanosecond), or a unit of their last printed digit; the kinds of CPU differ by ulps (~1e-16 relative)
NEAR_RELATIVE = NEAR_ABSOLUTE = 1e-9
_NUMBER = re.compile(rb"[-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?")

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
    return (await answer_and_content(client, request))[0]


async def answer_and_content(client: httpx.AsyncClient, request: dict[str, Any]) -> tuple[dict[str, Any], bytes]:
    """What the app answers to one recorded request, and the answer's bytes (normalised)."""
    r = await client.request(request["method"], request["path"], json=request["body"], headers=request["headers"])
    content = _normalise(r.content)
    return {"status": r.status_code, "media_type": r.headers.get("content-type", ""),
            "disposition": r.headers.get("content-disposition", ""),
            "sha256": hashlib.sha256(content).hexdigest(), "bytes": len(content)}, content


def matches(recorded: dict[str, Any], got: dict[str, Any], content: bytes) -> bool:
    """Whether an answer is the recorded one: byte for byte, or for a near entry number by number."""
    if "near" not in recorded:
        return got == recorded
    same = all(got[key] == recorded[key] for key in ("status", "media_type", "disposition"))
    return same and near_enough(content, near_content(recorded["near"]))


def near_content(sha256: str) -> bytes:
    """A kept answer (module notes)."""
    return lzma.decompress((NEAR / f"{sha256}.xz").read_bytes())


def _whole(token: bytes) -> bool:
    return b"." not in token and b"e" not in token.lower()


def _printed_unit(a_token: bytes, b_token: bytes) -> float:
    """A unit of the last printed digit where both numbers are printed to it (a file's fixed
    decimals: rounding may flip that digit), else 0 (shortest floats: a short one is no precision)."""
    a_mantissa, _, a_exponent = a_token.lower().partition(b"e")
    b_mantissa, _, b_exponent = b_token.lower().partition(b"e")
    decimals = len(a_mantissa.partition(b".")[2])
    if decimals != len(b_mantissa.partition(b".")[2]) or int(a_exponent or b"0") != int(b_exponent or b"0"):
        return 0.0
    return 10.0 ** (int(a_exponent or b"0") - decimals)


def near_enough(got: bytes, kept: bytes) -> bool:
    """Whether two answers say the same, read as text and numbers: the text between the numbers
    equal, whole numbers equal, other numbers within NEAR_RELATIVE, NEAR_ABSOLUTE or, where both are
    printed to the same decimals, a unit of the last (:func:`_printed_unit`)."""
    if _NUMBER.split(got) != _NUMBER.split(kept):
        return False
    a_tokens, b_tokens = _NUMBER.findall(got), _NUMBER.findall(kept)
    if len(a_tokens) != len(b_tokens):
        return False
    for a_token, b_token in zip(a_tokens, b_tokens):
        if a_token == b_token:
            continue
        if _whole(a_token) and _whole(b_token):
            return False
        unit = _printed_unit(a_token, b_token)
        a, b = float(a_token), float(b_token)
        if not math.isclose(a, b, rel_tol=NEAR_RELATIVE, abs_tol=max(NEAR_ABSOLUTE, unit * (1 + 1e-9))):
            return False
    return True


def cpu_kind() -> str:
    """``avx512`` where numpy dispatches its AVX512_SKX kernels (SVML's float64 sine, cosine,
    exponential, …), else ``without-avx512``."""
    from numpy._core._multiarray_umath import __cpu_features__

    return "avx512" if __cpu_features__.get("AVX512_SKX") else "without-avx512"


def record_of(kind: str) -> Path:
    """The record of the answers on a kind of CPU (:func:`cpu_kind`)."""
    return RECORD if kind == "avx512" else RECORD_WITHOUT_AVX512


def _write(path: Path, entries: list[dict[str, Any]]) -> None:
    path.write_text(json.dumps(entries, indent=1, ensure_ascii=False) + "\n", encoding="utf-8")


#: the answers written as text, whose numbers a near entry can compare (PNG and binary STL are not)
TEXT_MEDIA = ("text/", "application/json", "application/dxf", "model/step", "image/svg+xml")


def _binary(media_type: str) -> bool:
    return not media_type.startswith(TEXT_MEDIA)


def drop_unused_near() -> None:
    """Delete the kept answers that no near entry of either record names."""
    named = {e["answer"]["near"] for path in (RECORD, RECORD_WITHOUT_AVX512)
             for e in json.loads(path.read_text(encoding="utf-8")) if "near" in e["answer"]}
    for kept in NEAR.glob("*.xz"):
        if kept.stem not in named:
            kept.unlink()


async def record(how: str) -> None:
    """Answer :func:`requests` (``all``), those of :data:`RECORD` (``same-requests``) into this CPU's
    record, or (``changed``) those of this CPU's record, marking the answers that changed near in the
    other kind's record (module notes)."""
    from service.app import create_app

    mine = record_of(cpu_kind())
    other = RECORD_WITHOUT_AVX512 if mine == RECORD else RECORD
    base = mine if how == "changed" else RECORD
    recorded = json.loads(base.read_text(encoding="utf-8"))
    asked = [{key: e[key] for key in ("method", "path", "body", "headers")} for e in recorded] \
        if how != "all" else requests()
    async with httpx.AsyncClient(transport=httpx.ASGITransport(app=create_app()), base_url="http://testserver",
                                 timeout=120) as client:
        entries, contents = [], []
        for request in asked:
            got, content = await answer_and_content(client, request)
            entries.append({**request, "answer": got})
            contents.append(content)
    if how == "changed":
        theirs = json.loads(other.read_text(encoding="utf-8"))
        # changed: not the recorded answer (a near entry, kept from the other kind, when its numbers moved)
        changed = [k for k, (old, new) in enumerate(zip(recorded, entries))
                   if not matches(old["answer"], new["answer"], contents[k])]
        binary = [entries[k]["path"] for k in changed if _binary(entries[k]["answer"]["media_type"])]
        if binary:
            raise SystemExit(f"binary answers changed, record them on both kinds of CPU: {binary}")
        NEAR.mkdir(exist_ok=True)
        for k in changed:
            got = entries[k]["answer"]
            (NEAR / f"{got['sha256']}.xz").write_bytes(lzma.compress(contents[k], preset=9 | lzma.PRESET_EXTREME))
            theirs[k]["answer"] = {key: got[key] for key in ("status", "media_type", "disposition")} | \
                {"near": got["sha256"]}
        _write(other, theirs)
        print(f"{len(changed)} answers changed: recorded in {os.path.relpath(mine, ROOT)}, near in "
              f"{os.path.relpath(other, ROOT)}")
    _write(mine, entries)
    drop_unused_near()
    print(f"{len(entries)} answers recorded in {os.path.relpath(mine, ROOT)}")


if __name__ == "__main__":
    options = sys.argv[1:]
    asyncio.run(record("same-requests" if "--same-requests" in options else
                       "changed" if "--changed" in options else "all"))
