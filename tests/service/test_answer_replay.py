"""The operations answer their request examples byte for byte as they did when the reference
was recorded (tests/answer_replay.py says what is recorded and how to record it again).

The reference was recorded before the service was generated from its operation registry: every
path that answered then (the file twins' old paths included) answers the same bytes, with the
same status, media type and file name. The bytes are those of the CPU the test runs on: a CPU
with AVX512_SKX writes some numbers a few ulps from one without (tests/answer_replay.py), so each
kind has its record, both made from the same commit.
"""

from __future__ import annotations

import json

import httpx
import pytest

from service.app import create_app
from tests.answer_replay import RECORD, RECORD_WITHOUT_AVX512, answer, cpu_kind, record_of

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
            got = await answer(client, entry)
            if got != entry["answer"]:
                differ.append(f"{entry['method']} {entry['path']} {json.dumps(entry['body'])[:80]}: "
                              f"{entry['answer']} -> {got}")
    assert not differ, "\n".join(differ)
