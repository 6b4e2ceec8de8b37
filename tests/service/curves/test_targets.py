"""Makino's curves designed from a target over HTTP: the answer reports the solved parameters,
and a target out of reach is a 422 that gives the attainable range."""

from __future__ import annotations

import httpx
import pytest

from camcore import makino_curve

pytestmark = pytest.mark.anyio


async def test_curve_4_from_vm_reports_t1_t3(client: httpx.AsyncClient) -> None:
    """Curve 27's exact Vm (appendix 3-1 prints 1.27526) gives back T1 = 1/16, T3 = 1/4."""
    vm = makino_curve(27).characteristics.vm.value
    r = await client.post("/v1/curves/characteristics", json={"curve": {"type": "makino", "number": 4, "vm": vm}})
    assert r.status_code == 200, r.text
    answer = r.json()
    # 1/Vm and (1 − 1/Vm)/c each round once: a few ulp
    assert answer["parameters"]["t1"] == pytest.approx(1 / 16, abs=1e-15)
    assert answer["parameters"]["t3"] == pytest.approx(1 / 4, abs=1e-15)
    assert answer["vm"] == pytest.approx(vm, rel=1e-14)  # the built curve's Vm, found by its extrema
    assert "vm" not in answer["parameters"]


async def test_curve_1_from_v_ratio_reports_z(client: httpx.AsyncClient) -> None:
    r = await client.post("/v1/curves/characteristics",
                          json={"curve": {"type": "makino", "number": 1, "v_ratio": 0.1}})
    assert r.status_code == 200, r.text
    assert r.json()["parameters"] == {"z": 0.9}
    plain = await client.post("/v1/curves/characteristics", json={"curve": {"type": "named", "name": "MS"}})
    assert plain.json().get("parameters") is None  # only a makino spec has parameters to report


@pytest.mark.parametrize("vm, words", [(1.8, "reaches 1 < Vm ≤ 1.7596"), (1.0, "greater than 1")])
async def test_vm_out_of_reach_is_a_422_with_the_range(client: httpx.AsyncClient, vm: float, words: str) -> None:
    r = await client.post("/v1/curves/characteristics", json={"curve": {"type": "makino", "number": 4, "vm": vm}})
    assert r.status_code == 422, r.text
    assert words in r.text
