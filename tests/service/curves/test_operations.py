"""The v1 curve endpoints through httpx.ASGITransport (docs/api.md, "Endpoints").

Numbers are checked against camcore called directly (the service must give the same
numbers as the library) and, where a source prints them, against the source.
"""

from __future__ import annotations

import csv
import io
import math

import httpx
import numpy as np
import pytest

import camcore
from service.settings import Settings

pytestmark = pytest.mark.anyio

MS = {"type": "named", "name": "MS"}


def parse_csv(text: str) -> dict[str, list[float]]:
    rows = list(csv.reader(io.StringIO(text)))
    header, body = rows[0], rows[1:]
    return {name: [float(r[i]) for r in body] for i, name in enumerate(header)}


# ----------------------------------------------------------------------------- catalog
async def test_list_curves_has_every_catalog_entry_with_characteristics(client: httpx.AsyncClient) -> None:
    r = await client.get("/v1/curves")
    assert r.status_code == 200
    curves = {c["id"]: c for c in r.json()["curves"]}
    assert set(curves) == set(camcore.CATALOG)
    ms = curves["MS"]
    assert "26" in ms["aliases"] and ms["family"] == "symmetric" and "INDEXMAN" in ms["source"]
    # INDEXMAN characteristic-value table: MS Vm 1.76, Am ±5.53, Qm ±0.99 (printed to 2 decimals)
    assert round(ms["characteristics"]["vm"], 2) == 1.76
    assert round(ms["characteristics"]["am_pos"], 2) == 5.53
    assert round(ms["characteristics"]["qm_pos"], 2) == 0.99


@pytest.mark.parametrize("name, expected_id", [("ms", "MS"), ("26", "MS"), ("MC", "MCV50"), ("Trapecloid II", "trapecloid-2"),
                                                ("4_5_6_7", "4-5-6-7"), ("43", "one-dwell-cycloid")])
async def test_get_curve_by_id_alias_or_number(client: httpx.AsyncClient, name: str, expected_id: str) -> None:
    r = await client.get(f"/v1/curves/{name}")
    assert r.status_code == 200, r.text
    assert r.json()["id"] == expected_id


async def test_unknown_curve_is_404_with_close_matches(client: httpx.AsyncClient) -> None:
    r = await client.get("/v1/curves/cycloyd")
    assert r.status_code == 404
    body = r.json()
    assert "No curve named 'cycloyd'" in body["detail"]
    assert "cycloid" in body["suggestions"]


# ----------------------------------------------------------------------------- characteristics
async def test_characteristics_of_makino_36_match_eq_14(client: httpx.AsyncClient) -> None:
    # Makino 1977 eq. (14), trapecloid II: Vm = 1.85, Am = 5.22, Jm = 65.6, Qmp = 7.75, Qmm = -5.34 (Q = A·V)
    r = await client.post("/v1/curves/characteristics", json={"curve": {"type": "makino", "number": 36}})
    assert r.status_code == 200
    c = r.json()
    assert (round(c["vm"], 2), round(c["am_pos"], 2), round(c["jm_pos"], 1)) == (1.85, 5.22, 65.6)
    assert (round(c["qm_raw_pos"], 2), round(c["qm_raw_neg"], 2)) == (7.75, -5.34)
    assert 0 <= c["t_vm"] <= 1


# ----------------------------------------------------------------------------- tables, every spec type
SPECS = {
    "named": MS,
    "named-return": {"type": "named", "name": "cycloid", "direction": "return"},
    "makino": {"type": "makino", "number": 4, "t1": 0.0625, "t3": 0.25},
    "makino-1": {"type": "makino", "number": 1, "z": 0.9},
    "makino-2": {"type": "makino", "number": 2, "t4": 0.6},
    "universal": {"type": "universal", "t": [0, 0.125, 0.125, 0.5, 0.5, 0.875, 0.875, 1]},
    "universal-m": {"type": "universal", "t": [0, 0.2, 0.2, 0.4, 0.4, 0.7, 0.7, 1], "m": 0.5},
    "polynomial-name": {"type": "polynomial", "name": "3-4-5"},
    "polynomial-bc": {"type": "polynomial", "start": {"s": 0, "v": 0, "a": 0}, "end": {"s": 1, "v": 0, "a": 0}},
    "bezier": {"type": "bezier", "control_points": [[0, 0], [30, 0], [60, 10], [90, 10]]},
    "points": {"type": "points", "t": [0, 10, 20, 30, 40], "s": [0, 1, 4, 7, 8]},
}


def direct_curve(spec: dict) -> camcore.Curve:
    from service.curves.library import CurveLibrary
    from service.curves.specs import TableRequest

    return CurveLibrary(Settings()).curve(TableRequest.model_validate({"curve": spec}).curve.core())


@pytest.mark.parametrize("kind", list(SPECS))
async def test_table_json_matches_the_library(client: httpx.AsyncClient, kind: str) -> None:
    spec = SPECS[kind]
    r = await client.post("/v1/curves/table", json={"curve": spec, "samples": 11})
    assert r.status_code == 200, r.text
    body = r.json()
    assert list(body) == ["t", "s", "v", "a", "j", "q"]
    curve = direct_curve(spec)
    expected = curve.table(11)
    for col in body:
        # JSON carries the shortest round-trip text of each float: equality is exact
        assert body[col] == getattr(expected, col).tolist(), col


@pytest.mark.parametrize("kind", ["named", "bezier", "points", "universal"])
async def test_table_csv_on_accept_header(client: httpx.AsyncClient, kind: str) -> None:
    r = await client.post("/v1/curves/table", json={"curve": SPECS[kind], "samples": 5},
                          headers={"Accept": "text/csv"})
    assert r.status_code == 200
    assert r.headers["content-type"].startswith("text/csv")
    table = parse_csv(r.text)
    assert list(table) == ["t", "s", "v", "a", "j", "q"] and len(table["t"]) == 5
    expected = direct_curve(SPECS[kind]).table(5)
    assert table["s"] == expected.s.tolist()  # full precision: CSV floats round-trip exactly


async def test_table_at_given_times(client: httpx.AsyncClient) -> None:
    r = await client.post("/v1/curves/table", json={"curve": MS, "t": [0.3, 0.31]})
    assert r.status_code == 200
    # INDEXMAN MS table rows T = 0.30, 0.31: S = 0.17789, 0.19132; V = 1.32295, 1.36325 (5 decimals)
    body = r.json()
    assert [round(x, 5) for x in body["s"]] == [0.17789, 0.19132]
    assert [round(x, 5) for x in body["v"]] == [1.32295, 1.36325]


async def test_get_table_csv_for_spreadsheets(client: httpx.AsyncClient) -> None:
    r = await client.get("/v1/curves/MS/table", params={"samples": 101, "format": "csv"})
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/csv")
    table = parse_csv(r.text)
    assert len(table["t"]) == 101
    # INDEXMAN MS table, row T = 0.50: S = 0.50000, V = 1.75960, J = -23.15545
    assert round(table["v"][50], 5) == 1.75960 and round(table["j"][50], 5) == -23.15545
    again = await client.get("/v1/curves/MS/table", params={"samples": 101, "format": "csv"})
    assert again.content == r.content
    health = (await client.get("/health")).json()
    assert health["caches"]["tables"]["hits"] >= 1  # the repeat came from the cache, unchanged


async def test_get_table_json_and_return_direction(client: httpx.AsyncClient) -> None:
    r = await client.get("/v1/curves/cycloid/table", params={"samples": 3, "direction": "return"})
    assert r.status_code == 200
    body = r.json()
    # Makino INIT = 2: S_return(T) = S(1 - T); the cycloid return falls 1 → 0.5 → 0
    assert body["s"][0] == 1.0 and body["s"][2] == 0.0 and math.isclose(body["s"][1], 0.5)
    assert body["v"][1] < 0


# ----------------------------------------------------------------------------- inverse
async def test_inverse_table_method_reproduces_the_guide_example(client: httpx.AsyncClient) -> None:
    # INDEXMAN guide, worked example before the characteristic-value table:
    # S = 0.1833 between rows 0.30/0.31 of the MS table → T = 0.304, V = 1.339
    r = await client.post("/v1/curves/inverse", json={"curve": MS, "s": [0.1833], "method": "table",
                                                      "table_step": 0.01, "table_decimals": 5})
    assert r.status_code == 200
    body = r.json()
    assert round(body["t"][0], 3) == 0.304 and round(body["v"][0], 3) == 1.339


async def test_inverse_exact_round_trips(client: httpx.AsyncClient) -> None:
    t = np.linspace(0.05, 0.95, 19)
    s = camcore.named_curve("MS").derivatives(t, 0)[0]
    r = await client.post("/v1/curves/inverse", json={"curve": MS, "s": s.tolist()})
    assert r.status_code == 200
    # V ≥ 0.08 on this range, so dT = dS / V stays within a few 1e-15
    assert np.allclose(r.json()["t"], t, rtol=0, atol=1e-14)


async def test_get_inverse_csv_with_comma_list(client: httpx.AsyncClient) -> None:
    r = await client.get("/v1/curves/MS/inverse", params={"s": "0.1833,0.5", "format": "csv",
                                                          "method": "table", "table_decimals": 5})
    assert r.status_code == 200
    table = parse_csv(r.text)
    assert list(table) == ["s", "t", "v", "a"]
    assert round(table["t"][0], 3) == 0.304 and table["t"][1] == 0.5


async def test_get_inverse_repeated_parameter(client: httpx.AsyncClient) -> None:
    r = await client.get("/v1/curves/MS/inverse?s=0&s=1")
    assert r.status_code == 200
    assert r.json()["t"] == [0.0, 1.0]  # dwell ends: S = 0 at T0, S = 1 at T7


# ----------------------------------------------------------------------------- errors
async def test_break_points_out_of_order_422_with_sentence(client: httpx.AsyncClient) -> None:
    bad = {"type": "universal", "t": [0, 0.2, 0.1, 0.5, 0.5, 0.8, 0.8, 1]}
    r = await client.post("/v1/curves/table", json={"curve": bad})
    assert r.status_code == 422
    body = r.json()
    assert "T0 ≤ T1 ≤ … ≤ T7" in body["detail"] and "T2 = 0.1" in body["detail"]
    assert body["errors"][0]["loc"][:2] == ["body", "curve"]


async def test_nan_is_refused(client: httpx.AsyncClient) -> None:
    raw = b'{"curve": {"type": "universal", "t": [0, NaN, 0.1, 0.5, 0.5, 0.8, 0.8, 1]}}'
    r = await client.post("/v1/curves/table", content=raw, headers={"content-type": "application/json"})
    assert r.status_code in (400, 422)
    assert r.json()["detail"]


async def test_malformed_json_is_400(client: httpx.AsyncClient) -> None:
    r = await client.post("/v1/curves/table", content=b"{not json", headers={"content-type": "application/json"})
    assert r.status_code == 400
    assert "not a valid JSON" in r.json()["detail"]


async def test_unknown_spec_type_422(client: httpx.AsyncClient) -> None:
    r = await client.post("/v1/curves/table", json={"curve": {"type": "spline"}})
    assert r.status_code == 422
    assert "curve" in r.json()["detail"]


async def test_m_that_cannot_close_the_stroke_is_422(client: httpx.AsyncClient) -> None:
    # no deceleration sections (T4 = T7) and V7 = V0: no m closes the velocity
    spec = {"type": "universal", "t": [0, 0.25, 0.25, 0.5, 1, 1, 1, 1]}
    r = await client.post("/v1/curves/characteristics", json={"curve": spec})
    assert r.status_code == 422
    assert "no ratio m" in r.json()["detail"]


async def test_inverse_outside_the_stroke_is_422(client: httpx.AsyncClient) -> None:
    r = await client.post("/v1/curves/inverse", json={"curve": MS, "s": [0.5, 1.5]})
    assert r.status_code == 422
    assert "s[1] = 1.5 is outside the stroke" in r.json()["detail"]


async def test_inverse_of_a_non_monotone_curve_is_422(client: httpx.AsyncClient) -> None:
    spec = {"type": "points", "t": [0, 1, 2, 3, 4], "s": [0, 5, 10, 5, 0]}
    r = await client.post("/v1/curves/inverse", json={"curve": spec, "s": [0.5]})
    assert r.status_code == 422
    assert "not monotone" in r.json()["detail"]


async def test_bad_makino_parameters_are_422(client: httpx.AsyncClient) -> None:
    r = await client.post("/v1/curves/characteristics", json={"curve": {"type": "makino", "number": 4, "t1": 0.3, "t3": 0.2}})
    assert r.status_code == 422
    assert "T1 ≤ T3" in r.json()["detail"]
    r = await client.post("/v1/curves/characteristics", json={"curve": {"type": "makino", "number": 26, "z": 0.5}})
    assert r.status_code == 422 and "takes no parameter z" in r.json()["detail"]
    r = await client.post("/v1/curves/characteristics", json={"curve": {"type": "makino", "number": 3}})
    assert r.status_code == 422 and "not one of" in r.json()["detail"]


async def test_get_inverse_with_text_is_422(client: httpx.AsyncClient) -> None:
    r = await client.get("/v1/curves/MS/inverse", params={"s": "abc"})
    assert r.status_code == 422
    assert "'abc' is not a number" in r.json()["detail"]


@pytest.fixture
def small_limits() -> Settings:
    return Settings(max_table_samples=50, max_inverse_points=3, max_body_bytes=2048, max_bezier_degree=3,
                    max_curve_points=4)


@pytest.fixture
async def limited(small_limits: Settings):  # type: ignore[no-untyped-def]
    from service.app import create_app

    app = create_app(small_limits)
    async with httpx.AsyncClient(transport=httpx.ASGITransport(app=app), base_url="http://t") as c:
        yield c


async def test_limits_are_413_naming_the_limit(limited: httpx.AsyncClient) -> None:
    cases = [
        (("POST", "/v1/curves/table"), {"curve": MS, "samples": 51}, "table samples is 51, over the limit of 50"),
        (("POST", "/v1/curves/table"), {"curve": MS, "t": [0.1] * 51}, "number of times t is 51"),
        (("POST", "/v1/curves/inverse"), {"curve": MS, "s": [0.1] * 4}, "number of s values is 4, over the limit of 3"),
        (("POST", "/v1/curves/table"), {"curve": {"type": "bezier", "control_points": [[i, i] for i in range(5)]}},
         "Bezier degree is 4, over the limit of 3"),
        (("POST", "/v1/curves/table"), {"curve": {"type": "points", "t": [0, 1, 2, 3, 4], "s": [0, 1, 2, 3, 4]}},
         "number of points is 5, over the limit of 4"),
        (("POST", "/v1/curves/table"), {"curve": MS, "t": [0.123456789] * 300}, "request body size"),
    ]
    for (method, url), body, words in cases:
        r = await limited.request(method, url, json=body)
        assert r.status_code == 413, (words, r.text)
        assert words in r.json()["detail"]
    r = await limited.get("/v1/curves/MS/table", params={"samples": 51})
    assert r.status_code == 413 and "over the limit of 50" in r.json()["detail"]


async def test_health(client: httpx.AsyncClient) -> None:
    r = await client.get("/health")
    assert r.status_code == 200
    body = r.json()
    assert body["status"] == "ok" and body["version"] == camcore.__version__
    assert set(body["caches"]) == {"curves", "tables", "profile_checks", "sizings", "replies"}
