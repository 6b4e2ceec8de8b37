"""The residual-vibration operations through httpx.ASGITransport: the numbers are camcore's, CSV
equals JSON, limits answer 413 and bad input 422 naming the field; the spectrum chart draws.

The numbers themselves are proved in tests/camcore/dynamics/test_vibration.py and tests/camcore/dynamics/test_indexer_vibration.py
(closed forms, an independent integration, a direct simulation); here: that the service hands
them over unchanged, in the documented shape.
"""

from __future__ import annotations

import csv
import io
import math

import httpx
import numpy as np
import pytest

import camcore
from camcore.dynamics import indexer_vibration, residual_vibration
from service.app import create_app
from service.settings import Settings
from tests.service.test_charts import check_png, check_svg, svg_texts

pytestmark = pytest.mark.anyio

SPECTRUM = "/v1/curves/vibration"
INDEXER = "/v1/indexers/vibration"
CHART = "/v1/curves/vibration/plot"
MS = {"type": "named", "name": "MS"}
UNIVERSAL = {"type": "universal", "t": [0, 0.2, 0.2, 0.4, 0.4, 0.7, 0.7, 1], "s0": 2, "s7": 5}
GUIDE = {"stops": 6, "indexing_angle_deg": 270, "speed_rpm": 60}
GUIDE_LOAD = {"indexer": GUIDE, "inertia_kgm2": 2.25, "stiffness_nm_rad": 2e5, "damping_ratio": 0.05,
              "tolerance_arcsec": 10, "samples": 21}


def rows(text: str) -> dict[str, list[float]]:
    table = list(csv.reader(io.StringIO(text)))
    return {name: [float(row[i]) for row in table[1:]] for i, name in enumerate(table[0])}


# ----------------------------------------------------------------------------- the spectrum
async def test_spectrum_is_camcore_s_numbers(client: httpx.AsyncClient) -> None:
    body = {"curve": UNIVERSAL, "damping_ratio": 0.1, "tau": [0.05, 1.0, 3.7, 250.0]}
    r = await client.post(SPECTRUM, json=body)
    assert r.status_code == 200, r.text
    answer = r.json()
    assert list(answer) == ["tau", "residual_amplitude", "peak_deviation"]
    expected = residual_vibration(camcore.universal_curve(UNIVERSAL["t"], s0=2, s7=5), body["tau"], 0.1)
    # JSON carries every float in its shortest round-trip form: the same numbers, bit for bit
    assert answer["tau"] == body["tau"]
    assert answer["residual_amplitude"] == expected.residual_amplitude.tolist()
    assert answer["peak_deviation"] == expected.peak_deviation.tolist()


async def test_tau_range_csv_and_the_file_twin(client: httpx.AsyncClient) -> None:
    body = {"curve": MS, "tau_range": {"start": 4, "stop": 0.5, "samples": 8}}
    answer = (await client.post(SPECTRUM, json=body)).json()
    assert answer["tau"] == np.linspace(4, 0.5, 8).tolist()  # either order
    as_csv = await client.post(SPECTRUM, json=body, headers={"Accept": "text/csv"})
    assert as_csv.headers["content-type"].startswith("text/csv")
    assert as_csv.text.startswith("tau,residual_amplitude,peak_deviation\n")
    assert rows(as_csv.text) == answer
    twin = await client.post(f"{SPECTRUM}.csv", json=body)
    query = await client.post(SPECTRUM, params={"format": "csv"}, json=body)
    assert twin.content == as_csv.content == query.content


async def test_undamped_cycloid_through_the_service(client: httpx.AsyncClient) -> None:
    r = await client.post(SPECTRUM, json={"curve": {"type": "named", "name": "cycloid"}, "tau": [1, 2, 3]})
    residual = r.json()["residual_amplitude"]
    assert abs(residual[0] - 0.5) < 1e-13 and max(residual[1:]) < 1e-13


@pytest.mark.parametrize(("body", "loc", "words"), [
    ({"curve": MS, "tau": [1], "damping_ratio": 1}, ["body", "damping_ratio"], "less than 1"),
    ({"curve": MS, "tau": [1], "damping_ratio": -0.1}, ["body", "damping_ratio"], "greater than or equal to 0"),
    ({"curve": MS, "tau": [1, 0]}, ["body", "tau", 1], "greater than or equal to 0.001"),
    ({"curve": MS, "tau": [1001]}, ["body", "tau", 0], "less than or equal to 1000"),
    ({"curve": MS, "tau": []}, ["body"], "tau must list at least one value"),
    ({"curve": MS}, ["body"], "give either tau (a list of values) or tau_range"),
    ({"curve": MS, "tau": [1], "tau_range": {"start": 1, "stop": 2, "samples": 2}}, ["body"], "not both"),
    ({"curve": MS, "tau_range": {"start": 1, "stop": 2, "samples": 1}}, ["body", "tau_range", "samples"],
     "greater than or equal to 2"),
    ({"curve": {"type": "polynomial", "start": {"s": 0, "v": 0}, "end": {"s": 0, "v": 0}}, "tau": [1]},
     ["body", "curve"], "the curve must move"),
])
async def test_bad_spectrum_requests_are_422_naming_the_field(client: httpx.AsyncClient, body: dict[str, object],
                                                              loc: list[object], words: str) -> None:
    r = await client.post(SPECTRUM, json=body)
    assert r.status_code == 422, r.text
    errors = r.json()["errors"]
    assert any(e["loc"][:len(loc)] == loc and words in e["msg"] for e in errors), errors


async def test_too_many_tau_values_is_413_naming_the_setting() -> None:
    app = create_app(Settings(max_vibration_tau_values=50))
    async with httpx.AsyncClient(transport=httpx.ASGITransport(app=app), base_url="http://testserver") as client:
        ok = await client.post(SPECTRUM, json={"curve": MS, "tau": [1.0] * 50})
        assert ok.status_code == 200
        r = await client.post(SPECTRUM, json={"curve": MS, "tau": [1.0] * 51})
        assert r.status_code == 413
        assert r.json()["limit"] == {"name": "number of τ values", "requested": 51, "limit": 50}
        assert r.json()["errors"][0]["loc"] == ["body", "tau"]
        r = await client.post(SPECTRUM, json={"curve": MS, "tau_range": {"start": 1, "stop": 2, "samples": 51}})
        assert r.status_code == 413 and r.json()["errors"][0]["loc"] == ["body", "tau_range", "samples"]


async def test_work_over_the_budget_is_413_before_it_runs(client: httpx.AsyncClient) -> None:
    # 10 000 values of τ up to 1000: ~1600 subcells of 32 nodes each at the top, far over 1 s
    body = {"curve": MS, "tau_range": {"start": 500, "stop": 1000, "samples": 10_000}}
    r = await client.post(SPECTRUM, json=body)
    assert r.status_code == 413, r.text
    assert r.json()["limit"]["name"] == "estimated work [s]"
    assert r.json()["errors"][0]["loc"] == ["body", "tau_range", "samples"]


# ----------------------------------------------------------------------------- the indexer
async def test_indexer_vibration_is_camcore_s_numbers(client: httpx.AsyncClient) -> None:
    r = await client.post(INDEXER, json=GUIDE_LOAD)
    assert r.status_code == 200, r.text
    answer = r.json()
    expected = indexer_vibration(camcore.Indexer(**GUIDE), 2.25, 2e5, 0.05, 10, 21)
    assert answer == {**camcore.as_dict(expected), "table": {k: v.tolist() for k, v in expected.table.columns().items()}}
    assert answer["natural_frequency_hz"] == pytest.approx(math.sqrt(2e5 / 2.25) / (2 * math.pi), rel=1e-15)
    assert answer["tau"] == pytest.approx(0.75 * answer["natural_frequency_hz"], rel=1e-15)
    as_csv = await client.post(INDEXER, json=GUIDE_LOAD, headers={"Accept": "text/csv"})
    assert as_csv.text.startswith("time_s,output_error_arcsec\n")
    assert rows(as_csv.text) == answer["table"]
    assert (await client.post(f"{INDEXER}.csv", json=GUIDE_LOAD)).content == as_csv.content


async def test_a_load_gives_its_inertia(client: httpx.AsyncClient) -> None:
    # the guide's 50 kg disc of Ø600 mm: I = m·D²/8 = 2.25 kg·m² (friction is no part of this model)
    body = {**GUIDE_LOAD, "inertia_kgm2": None,
            "load": {"parts": [{"shape": "disc", "mass_kg": 50, "diameter_mm": 600}], "friction_coefficient": 0.1,
                     "friction_radius_mm": 200}}
    by_load = (await client.post(INDEXER, json=body)).json()
    direct = (await client.post(INDEXER, json=GUIDE_LOAD)).json()
    assert by_load["inertia_kgm2"] == pytest.approx(2.25, rel=1e-15)
    assert by_load["tau"] == pytest.approx(direct["tau"], rel=1e-14)


async def test_undamped_never_settles_null(client: httpx.AsyncClient) -> None:
    r = await client.post(INDEXER, json={**GUIDE_LOAD, "stiffness_nm_rad": 2e3, "damping_ratio": 0})
    answer = r.json()
    assert answer["residual_amplitude_arcsec"] > 10
    assert answer["settling_time_s"] is None and answer["settles_within_dwell"] is False


@pytest.mark.parametrize(("change", "loc", "words"), [
    ({"stiffness_nm_rad": 1e12}, ["body", "stiffness_nm_rad"], "must lie within 0.001 ≤ τ ≤ 1000"),
    ({"stiffness_nm_rad": 0}, ["body", "stiffness_nm_rad"], "greater than 0"),
    ({"inertia_kgm2": -1}, ["body", "inertia_kgm2"], "greater than 0"),
    ({"damping_ratio": 1.5}, ["body", "damping_ratio"], "less than 1"),
    ({"tolerance_arcsec": 0}, ["body", "tolerance_arcsec"], "greater than 0"),
    ({"inertia_kgm2": None}, ["body"], "give the load's inertia as inertia_kgm2 or as load"),
    ({"inertia_kgm2": None, "load": {"parts": [{"shape": "point", "mass_kg": 3}]}}, ["body", "load"],
     "the load's inertia must be greater than 0"),
    ({"indexer": {**GUIDE, "curve": {"type": "polynomial", "start": {"s": 0}, "end": {"s": 0}}}},
     ["body", "indexer"], "must move"),
])
async def test_bad_indexer_requests_are_422_naming_the_field(client: httpx.AsyncClient, change: dict[str, object],
                                                             loc: list[object], words: str) -> None:
    r = await client.post(INDEXER, json={**GUIDE_LOAD, **change})
    assert r.status_code == 422, r.text
    errors = r.json()["errors"]
    assert any(e["loc"][:len(loc)] == loc and words in e["msg"] for e in errors), errors


# ----------------------------------------------------------------------------- the chart
async def test_chart_png_and_svg(client: httpx.AsyncClient) -> None:
    query = {"curves": "MS,cycloid", "samples": 201, "tau_stop": 8}
    png = await client.get(CHART, params={**query, "format": "png"})
    assert png.status_code == 200 and png.headers["content-type"] == "image/png"
    width, height = check_png(png.content)
    assert width >= 700 and height >= 500
    svg = await client.get(CHART, params=query)
    assert svg.headers["content-type"].startswith("image/svg+xml")
    texts = svg_texts(svg.content)
    assert "MS — modified sine" in texts and "cycloid" in texts
    assert "Residual vibration over τ = th·fn (undamped)" in texts
    assert "residual amplitude / stroke h" in texts
    # the undamped cycloid's notches (integer τ) run to the axis' bottom edge, which says so
    assert "a notch running to the bottom edge: a τ where the curve leaves (almost) nothing" in texts
    assert (await client.get(CHART, params=query)).content == svg.content  # the same query, the same bytes


async def test_chart_is_not_a_curve_named_vibration(client: httpx.AsyncClient) -> None:
    # /v1/curves/{name}/plot would take "vibration" for a curve name: the chart's route comes first
    r = await client.get(CHART, params={"curves": ["TR", "MT"], "samples": 51, "quantity": "peak_deviation"})
    assert r.status_code == 200, r.text
    assert "Peak deviation during the motion over τ = th·fn (undamped)" in svg_texts(r.content)
    assert (await client.get("/v1/curves/vibration")).status_code == 404  # GET /v1/curves/{name}: no such curve
    check_svg((await client.get("/v1/curves/MS/plot")).content)


@pytest.mark.parametrize(("params", "status", "loc"), [
    ({"curves": "MS,nope"}, 404, ["query", "curves", 1]),
    ({"curves": ",".join(["MS"] * 9)}, 422, ["query", "curves"]),
    ({"damping_ratio": 1}, 422, ["query", "damping_ratio"]),
    ({"tau_start": 0}, 422, ["query", "tau_start"]),
    ({"samples": 5}, 422, ["query", "samples"]),
    ({"quantity": "energy"}, 422, ["query", "quantity"]),
])
async def test_bad_chart_queries(client: httpx.AsyncClient, params: dict[str, object], status: int,
                                 loc: list[object]) -> None:
    r = await client.get(CHART, params=params)
    assert r.status_code == status, r.text
    assert any(e["loc"][:len(loc)] == loc for e in r.json()["errors"]), r.text


@pytest.mark.parametrize("fmt", ["svg", "png"])
async def test_the_default_chart_fits_the_default_budget(client: httpx.AsyncClient, fmt: str) -> None:
    # five curves, 781 values of τ each, from 0.5 to 20: what a link without a query draws
    r = await client.get(CHART, params={"format": fmt})
    assert r.status_code == 200, r.text
