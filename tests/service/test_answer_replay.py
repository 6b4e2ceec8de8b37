"""The operations answer their request examples byte for byte as they did when the reference
was recorded (tests/answer_replay.py says what is recorded and how to record it again).

The reference was recorded before the service was generated from its operation registry: every
path that answered then (the file twins' old paths included) answers the same bytes, with the
same status, media type and file name. The bytes are those of the CPU the test runs on: a CPU
with AVX512_SKX writes some numbers a few ulps from one without (tests/answer_replay.py), so each
kind has its record, both made from the same commit. An entry marked near (an answer changed on
purpose and recorded on the other kind of CPU) is held to that CPU's answer number by number.
"""

from __future__ import annotations

import json
from pathlib import Path

import httpx
import pytest

from service.app import create_app
from tests.answer_replay import (
    NEAR,
    RECORD,
    RECORD_WITHOUT_AVX512,
    answer_and_content,
    cpu_kind,
    matches,
    near_enough,
    record_of,
)

pytestmark = pytest.mark.anyio

ENTRIES = json.loads(record_of(cpu_kind()).read_text(encoding="utf-8"))
REQUEST_KEYS = ("method", "path", "body", "headers")


#: requests per test: the record in pieces, so that parallel runs share it out
CHUNK = 25


def test_the_record_is_whole() -> None:
    assert len(ENTRIES) > 200  # the record was found


def test_the_records_of_both_kinds_of_cpu_ask_the_same_and_differ_only_in_bytes() -> None:
    """The same requests in the same order, and the same status, media type and file name: only
    the bytes of numbers may differ between the kinds of CPU."""
    with_avx512, without = (json.loads(path.read_text(encoding="utf-8")) for path in (RECORD, RECORD_WITHOUT_AVX512))
    assert len(with_avx512) == len(without) > 200
    for a, b in zip(with_avx512, without):
        assert [a[key] for key in REQUEST_KEYS] == [b[key] for key in REQUEST_KEYS]
        assert [a["answer"][key] for key in ("status", "media_type", "disposition")] == \
               [b["answer"][key] for key in ("status", "media_type", "disposition")], a["path"]


@pytest.mark.parametrize("start", range(0, len(ENTRIES), CHUNK))
async def test_every_recorded_answer_is_the_same(start: int) -> None:
    transport = httpx.ASGITransport(app=create_app())
    differ = []
    async with httpx.AsyncClient(transport=transport, base_url="http://testserver", timeout=120) as client:
        for entry in ENTRIES[start:start + CHUNK]:
            got, content = await answer_and_content(client, entry)
            if not matches(entry["answer"], got, content):
                differ.append(f"{entry['method']} {entry['path']} {json.dumps(entry['body'])[:80]}: "
                              f"{entry['answer']} -> {got}")
    assert not differ, "\n".join(differ)


def test_every_kept_answer_is_named_by_a_near_entry_and_every_near_entry_has_one() -> None:
    named = {e["answer"]["near"] for path in (RECORD, RECORD_WITHOUT_AVX512)
             for e in json.loads(path.read_text(encoding="utf-8")) if "near" in e["answer"]}
    kept = {p.stem for p in NEAR.glob("*.xz")}
    assert named == kept


@pytest.mark.parametrize(("got", "kept", "same"), [
    (b'{"x_mm":[1.0,2.5000000000000004]}', b'{"x_mm":[1.0,2.5]}', True),  # an ulp apart
    (b'{"x_mm":[1.0,2.50001]}', b'{"x_mm":[1.0,2.5]}', False),  # 4e-6 relative
    (b'{"y":1.2e-17}', b'{"y":0.0}', True),  # rounding noise about zero, below a nanometre
    (b'{"y":2e-9}', b'{"y":0.0}', False),  # "0.0" is a shortest float, not a tenth's precision
    (b"X12.3457 Y1.0000", b"X12.3456 Y1.0000", True),  # a flip of the last printed digit (G-code)
    (b"X12.3458 Y1.0000", b"X12.3456 Y1.0000", False),  # two units of it
    (b'{"elements":33}', b'{"elements":32}', False),  # whole numbers: equal or not at all
    (b'{"side":"inside"}', b'{"side":"outside"}', False),  # the text between the numbers
    (b"1,2,3", b"1,2,3,4", False),
    (b"N10 G02 X1.5e-3", b"N10 G02 X1.5000000000000002e-3", True),
])
def test_near_enough_compares_numbers_within_ulps_and_text_exactly(got: bytes, kept: bytes, same: bool) -> None:
    assert near_enough(got, kept) is same


async def test_changed_answers_are_recorded_here_and_kept_near_in_the_other_record(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # `python -m tests.answer_replay --changed` on two recorded requests, one recorded with a wrong hash
    # (an answer that changed): this CPU's record gets the new hash, the other kind's record keeps its
    # unchanged entry as it was and marks the changed one near, with this CPU's answer kept beside it;
    # once the other kind records it exactly, the kept answer is dropped
    import lzma

    import tests.answer_replay as replay

    asked = [{"method": "GET", "path": f"/v1/curves/MS/table?samples={n}", "body": None, "headers": {}} for n in (5, 6)]
    async with httpx.AsyncClient(transport=httpx.ASGITransport(app=create_app()), base_url="http://testserver") as c:
        answers = [await answer_and_content(c, request) for request in asked]
    mine, theirs = tmp_path / "mine.json", tmp_path / "theirs.json"
    stale = {**answers[1][0], "sha256": "0" * 64}
    mine.write_text(json.dumps([{**asked[0], "answer": answers[0][0]}, {**asked[1], "answer": stale}]))
    other_answers = [{**a, "sha256": "1" * 64} for a, _ in answers]
    theirs.write_text(json.dumps([{**r, "answer": a} for r, a in zip(asked, other_answers)]))
    with_avx512 = cpu_kind() == "avx512"
    monkeypatch.setattr(replay, "RECORD", mine if with_avx512 else theirs)
    monkeypatch.setattr(replay, "RECORD_WITHOUT_AVX512", theirs if with_avx512 else mine)
    monkeypatch.setattr(replay, "NEAR", tmp_path / "near")

    await replay.record("changed")

    assert [e["answer"] for e in json.loads(mine.read_text())] == [a for a, _ in answers]
    kept_first, near = (e["answer"] for e in json.loads(theirs.read_text()))
    assert kept_first == other_answers[0]
    assert near == {"status": 200, "media_type": answers[1][0]["media_type"], "disposition": "",
                    "near": answers[1][0]["sha256"]}
    stored = tmp_path / "near" / f"{answers[1][0]['sha256']}.xz"
    assert lzma.decompress(stored.read_bytes()) == answers[1][1]
    assert matches(near, answers[1][0], answers[1][1])
    theirs.write_text(json.dumps([{**r, "answer": a} for r, a in zip(asked, other_answers)]))  # recorded there
    replay.drop_unused_near()
    assert not stored.exists()
