"""Shared fixtures: a real uvicorn on a loopback port, started as the README says."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from tests.live_server import running_service


@pytest.fixture(scope="module")
def base_url() -> Iterator[str]:
    """``python -m service`` on 127.0.0.1 (settings from the environment), stopped afterwards."""
    with running_service() as (url, _):
        yield url
