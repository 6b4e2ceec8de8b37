"""POST /v1/curves/characteristics/sweep: Makino's appendix 3-2 reproduced by one request (every
printed row), each row equal to its single characteristics request, invalid combinations as
rows with their error, CSV, the design chart (Makino's fig. 3) and the limits."""

from __future__ import annotations

import csv
import io

import httpx
import pytest

from service.settings import Settings
from tests.camcore.curves.test_makino import APPENDIX_3_2, APPENDIX_3_2_MISPRINTS, HALF_DIGIT
from tests.service.apps import app_client

pytestmark = pytest.mark.anyio

PATH = "/v1/curves/characteristics/sweep"
#: appendix 2's loops, the printed part: T3 = I/32 (I = 1..4), T1 = J/64 (J = 1..6); the program
#: runs J to 2I only, so the combinations with T1 > T3 are the rows with an error
APPENDIX_3_2_SWEEP = {"curve": {"type": "makino", "number": 4, "t1": 0.015625, "t3": 0.03125},
                      "vary": {"t3": [i / 32 for i in range(1, 5)], "t1": [j / 64 for j in range(1, 7)]}}


async def test_appendix_3_2_by_one_request(client: httpx.AsyncClient) -> None:
    """Every printed row (T3, T1, VM, AM, F15.5) within half a printed digit; the last row's AM
    is the misprint named in tests/camcore/curves/test_makino.py: the sweep gives the corrected value, and the
    printed one does NOT match."""
    r = await client.post(PATH, json=APPENDIX_3_2_SWEEP)
    assert r.status_code == 200, r.text
    rows = r.json()
    assert len(rows["vm"]) == 24
    index = {(round(t3 * 32), round(t1 * 64)): k for k, (t3, t1) in enumerate(zip(rows["t3"], rows["t1"]))}
    assert index[(1, 1)] == 0 and index[(1, 2)] == 1 and index[(2, 1)] == 6  # t3 slowest, as the program loops
    for i, j, _t3_p, _t1_p, vm_p, am_p in APPENDIX_3_2:
        k = index[(i, j)]
        assert rows["error"][k] is None
        assert abs(rows["vm"][k] - vm_p) <= HALF_DIGIT, (i, j, rows["vm"][k], vm_p)
        am = rows["am_pos"][k]
        assert rows["am_neg"][k] == pytest.approx(-am, rel=1e-13)  # equal areas, symmetric: Amm = Amp
        misprint = APPENDIX_3_2_MISPRINTS.get((i, j, "AM"))
        if misprint is None:
            assert abs(am - am_p) <= HALF_DIGIT, (i, j, am, am_p)
        else:
            assert abs(am - misprint) <= HALF_DIGIT, (i, j, am, misprint)
            assert abs(am - am_p) > 1.0, "the named misprint now matches"
    for (i, j), k in index.items():
        if j > 2 * i:  # T1 > T3: no curve 4; the row says why
            assert "curve 4 needs 0 < T1 ≤ T3 ≤ 0.5" in rows["error"][k] and rows["vm"][k] is None
        else:
            assert rows["error"][k] is None


async def test_rows_equal_single_requests(client: httpx.AsyncClient) -> None:
    """Each row is what POST /v1/curves/characteristics answers for that spec (the same
    camcore computation: identical numbers); a universal spec varies a break point and m."""
    body = {"curve": {"type": "universal", "t": [0, 0.1, 0.1, 0.3, 0.5, 0.75, 0.75, 1], "m": 0.5},
            "vary": {"t3": [0.2, 0.3, 0.6], "m": [0.5, 1.0]}}
    rows = (await client.post(PATH, json=body)).json()
    for k, (t3, m) in enumerate(zip(rows["t3"], rows["m"])):
        t = [0, 0.1, 0.1, t3, 0.5, 0.75, 0.75, 1]
        single = await client.post("/v1/curves/characteristics",
                                   json={"curve": {"type": "universal", "t": t, "m": m}})
        if single.status_code != 200:
            assert t3 > 0.5 and single.status_code == 422
            assert rows["error"][k] and rows["error"][k] in single.text
            continue
        for name in ("vm", "am_pos", "am_neg", "jm_pos", "jm_neg", "qm_pos", "qm_neg"):
            assert rows[name][k] == single.json()[name], (k, name)


async def test_vm_target_sweep_reports_solved_parameters(client: httpx.AsyncClient) -> None:
    """Varying the target vm: each row's curve has that Vm (its extrema, 1e-14: rounding of the
    closed-form solution and of the extrema), and the row lists the solved t1, t3."""
    body = {"curve": {"type": "makino", "number": 4, "vm": 1.2}, "vary": {"vm": [1.1, 1.27526, 1.9]}}
    rows = (await client.post(PATH, json=body)).json()
    assert rows["vm_target"] == [1.1, 1.27526, 1.9]
    assert rows["vm"][:2] == pytest.approx([1.1, 1.27526], rel=1e-14)
    assert rows["t1"][1] == pytest.approx(rows["t3"][1] / 4, rel=1e-15)
    assert rows["t3"][1] == pytest.approx(0.25, abs=1e-5)  # the printed Vm's half digit carried to T3 (< 7e-6)
    assert "out of reach" in rows["error"][2] and rows["vm"][2] is None


async def test_csv(client: httpx.AsyncClient) -> None:
    r = await client.post(PATH + "?format=csv", json=APPENDIX_3_2_SWEEP)
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/csv")
    table = list(csv.DictReader(io.StringIO(r.text)))
    assert list(table[0]) == ["t3", "t1", "vm", "am_pos", "am_neg", "jm_pos", "jm_neg", "qm_pos", "qm_neg", "error"]
    assert len(table) == 24
    assert abs(float(table[0]["vm"]) - 1.03226) <= HALF_DIGIT and table[0]["error"] == ""
    assert table[2]["vm"] == "" and "T1 ≤ T3" in table[2]["error"]


@pytest.mark.parametrize("fmt, magic", [("png", b"\x89PNG"), ("svg", b"<?xml")])
async def test_design_chart(client: httpx.AsyncClient, fmt: str, magic: bytes) -> None:
    r = await client.post(PATH + f"?format={fmt}", json=APPENDIX_3_2_SWEEP)
    assert r.status_code == 200, r.text
    assert r.content.startswith(magic)
    one = await client.post(PATH + f"?format={fmt}",
                            json={"curve": {"type": "makino", "number": 1, "z": 0.5}, "vary": {"z": [0.2, 0.5, 0.9]}})
    assert one.status_code == 200 and one.content.startswith(magic)


async def test_bad_requests(client: httpx.AsyncClient) -> None:
    base = {"type": "makino", "number": 4, "t1": 0.05, "t3": 0.2}
    three = await client.post(PATH, json={"curve": base, "vary": {"t1": [0.1], "t3": [0.2], "vm": [1.2]}})
    assert three.status_code == 422
    wrong = await client.post(PATH, json={"curve": base, "vary": {"t5": [0.1]}})
    assert wrong.status_code == 422 and "a makino spec varies" in wrong.text
    named = await client.post(PATH, json={"curve": {"type": "named", "name": "MS"}, "vary": {"m": [1]}})
    assert named.status_code == 422


async def test_combination_limit() -> None:
    async with app_client(Settings(max_sweep_combinations=20)) as client:
        r = await client.post(PATH, json=APPENDIX_3_2_SWEEP)  # 24 combinations
    assert r.status_code == 413 and "characteristics sweep combinations" in r.text
