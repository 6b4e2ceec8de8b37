"""The operations answer their request examples byte for byte as they did when the reference
was recorded (tests/answer_replay.py says what is recorded and how to record it again).

The reference was recorded before the service was generated from its operation registry: every
path that answered then (the file twins' old paths included) answers the same bytes, with the
same status, media type and file name.
"""

from __future__ import annotations

import json

import httpx
import pytest

from service.app import create_app
from tests.answer_replay import RECORD, answer

pytestmark = pytest.mark.anyio

ENTRIES = json.loads(RECORD.read_text(encoding="utf-8"))


#: requests per test: the record in pieces, so that parallel runs share it out
CHUNK = 25


def test_the_record_is_whole() -> None:
    assert len(ENTRIES) > 200  # the record was found


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
