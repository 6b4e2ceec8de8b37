"""The plot endpoints through httpx.ASGITransport: real PNG and SVG images, and 422/404 errors.

A PNG must carry the signature and an IHDR chunk with a positive size, decode, and not be
blank (pixel variance > 0); an SVG must parse as XML with an ``svg`` root and draw paths.
"""

from __future__ import annotations

import io
import struct
import xml.etree.ElementTree as ET

import httpx
import numpy as np
import pytest

pytestmark = pytest.mark.anyio

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
SVG_NS = "{http://www.w3.org/2000/svg}"

CURVE = "/v1/curves/MS/plot"
CURVE_Q = {"direction": "rise", "samples": 401}
INDEXER = "/v1/indexers/plot"
INDEXER_Q = {"stops": 6, "indexing_angle_deg": 270, "speed_rpm": 60, "curve": "MS"}
PROFILE = "/v1/profiles/plot"
PROFILE_Q = {"follower": "roller", "base_radius_mm": 40, "roller_radius_mm": 10, "rise_deg": 120, "dwell_deg": 60,
             "return_deg": 120, "lift_mm": 20, "curve": "cycloid"}
ENDPOINTS = [(CURVE, CURVE_Q), (INDEXER, INDEXER_Q), (PROFILE, PROFILE_Q),
             (PROFILE, {**PROFILE_Q, "follower": "flat-faced", "lift_mm": 10}),
             (PROFILE, {"motion": "oscillating", "arm_length_mm": 60, "pivot_distance_mm": 80, "swing_deg": 20}),
             ("/v1/curves/MC/plot", {"direction": "return"})]


def check_png(body: bytes) -> tuple[int, int]:
    assert body[:8] == PNG_SIGNATURE
    length, kind = struct.unpack(">I4s", body[8:16])
    assert kind == b"IHDR" and length == 13
    width, height = struct.unpack(">II", body[16:24])
    assert width > 0 and height > 0
    import matplotlib.image

    pixels = np.asarray(matplotlib.image.imread(io.BytesIO(body), format="png"))
    assert pixels.shape[:2] == (height, width)
    assert float(pixels[..., :3].var()) > 0, "the image is blank"
    # most of a chart is white background, but a real chart has plenty of ink
    ink = float((pixels[..., :3].mean(axis=-1) < 0.5).mean())
    assert 0.002 < ink < 0.5
    return width, height


def check_svg(body: bytes) -> ET.Element:
    root = ET.fromstring(body)
    assert root.tag == f"{SVG_NS}svg"
    assert len(root.findall(f".//{SVG_NS}path")) > 20
    return root


@pytest.mark.parametrize("url, params", ENDPOINTS)
async def test_png(client: httpx.AsyncClient, url: str, params: dict[str, object]) -> None:
    r = await client.get(url, params={**params, "format": "png"})
    assert r.status_code == 200, r.text
    assert r.headers["content-type"] == "image/png"
    width, height = check_png(r.content)
    assert width >= 700 and height >= 500


@pytest.mark.parametrize("url, params", ENDPOINTS)
async def test_svg_is_the_default(client: httpx.AsyncClient, url: str, params: dict[str, object]) -> None:
    r = await client.get(url, params=params)
    assert r.status_code == 200, r.text
    assert r.headers["content-type"].startswith("image/svg+xml")
    check_svg(r.content)
    r2 = await client.get(url, params={**params, "format": "svg"})
    assert r2.content == r.content, "the same query must draw the same chart (no date stamp)"


async def test_dpi_scales_the_png(client: httpx.AsyncClient) -> None:
    small = check_png((await client.get(CURVE, params={"format": "png", "dpi": 50})).content)
    large = check_png((await client.get(CURVE, params={"format": "png", "dpi": 150})).content)
    assert large[0] > 2 * small[0]


def svg_texts(body: bytes) -> list[str]:
    """Matplotlib draws text as paths and keeps each text as an XML comment beside it."""
    root = check_svg(body)
    del root
    import re

    return re.findall(r"<!-- (.*?) -->", body.decode())


async def test_curve_plot_names_the_curve_and_marks_characteristic_values(client: httpx.AsyncClient) -> None:
    texts = svg_texts((await client.get(CURVE)).content)
    assert "MS — modified sine" in texts
    for label in ("S (displacement)", "V (velocity)", "A (acceleration)", "J (jerk)", "T (dimensionless time)"):
        assert label in texts
    # INDEXMAN characteristic values of MS: Vm 1.76, Am ±5.53
    assert "Vm = 1.7596 at T = 0.5000" in texts
    assert "Am+ = 5.5280 at T = 0.1250" in texts and "Am− = −5.5280 at T = 0.8750" in texts


async def test_indexer_plot_has_units_and_peaks(client: httpx.AsyncClient) -> None:
    texts = svg_texts((await client.get(INDEXER, params=INDEXER_Q)).content)
    assert "Indexer: 6 stops, θh = 270°, 60 rpm, curve MS" in texts
    for label in ("output angle [deg]", "ω [rad/s]", "α [rad/s²]", "jerk [rad/s³]"):
        assert label in texts
    assert "h = 60°" in texts
    assert any(t.startswith("ωmax = 2.457 rad/s") for t in texts)


async def test_profile_plot_has_contour_and_pressure_angle(client: httpx.AsyncClient) -> None:
    texts = svg_texts((await client.get(PROFILE, params=PROFILE_Q)).content)
    for label in ("x [mm]", "y [mm]", "cam angle [deg]", "pressure angle φ [deg]", "base circle r = 40 mm",
                  "pitch curve (roller centre)", "cam contour", "rise", "dwell", "return"):
        assert label in texts
    assert any(t.startswith("max |φ| = ") for t in texts)


# ----------------------------------------------------------------------------- errors
@pytest.mark.parametrize("url, params, field", [
    (CURVE, {"samples": 5000}, "samples"),
    (CURVE, {"samples": 3}, "samples"),
    (CURVE, {"format": "gif"}, "format"),
    (CURVE, {"direction": "up"}, "direction"),
    (CURVE, {"dpi": 1000}, "dpi"),
    (INDEXER, {"stops": 6, "speed_rpm": 60}, "indexing_angle_deg"),
    (INDEXER, {**INDEXER_Q, "indexing_angle_deg": 400}, "indexing_angle_deg"),
    (INDEXER, {**INDEXER_Q, "speed_rpm": "nan"}, "speed_rpm"),
    (PROFILE, {**PROFILE_Q, "base_radius_mm": -5}, "base_radius_mm"),
    (PROFILE, {**PROFILE_Q, "follower": "spring"}, "follower"),
    (PROFILE, {**PROFILE_Q, "samples": 100_000}, "samples"),
])
async def test_out_of_range_query_is_422_naming_the_field(client: httpx.AsyncClient, url: str,
                                                          params: dict[str, object], field: str) -> None:
    r = await client.get(url, params=params)
    assert r.status_code == 422, r.text
    body = r.json()
    assert body["detail"].startswith("Invalid request")
    assert any(e["loc"][-1] == field for e in body["errors"]), body


async def test_indexer_spec_rules_are_422_with_the_sentence(client: httpx.AsyncClient) -> None:
    r = await client.get(INDEXER, params={"indexing_angle_deg": 270, "speed_rpm": 60})
    assert r.status_code == 422
    assert "give exactly one of stops (n) and swing_angle_deg" in r.json()["detail"]
    r = await client.get(INDEXER, params={**INDEXER_Q, "cycle_time_s": 2})
    assert r.status_code == 422
    assert "give exactly one of speed_rpm (N) and cycle_time_s" in r.json()["detail"]
    r = await client.get(INDEXER, params={**INDEXER_Q, "indexing_angle_deg": 200, "dwells": 2})
    assert r.status_code == 422
    assert "must not exceed 360°" in r.json()["detail"]


async def test_profile_rules_are_422_with_the_sentence(client: httpx.AsyncClient) -> None:
    r = await client.get(PROFILE, params={**PROFILE_Q, "rise_deg": 200, "return_deg": 200})
    assert r.status_code == 422
    assert "rise_deg + dwell_deg + return_deg must not exceed 360°" in r.json()["detail"]
    assert r.json()["errors"][0]["loc"] == ["query", "return_deg"]
    r = await client.get(PROFILE, params={**PROFILE_Q, "offset_mm": 60})
    assert r.status_code == 422
    assert "offset must be smaller than the base radius" in r.json()["detail"]
    r = await client.get(PROFILE, params={"motion": "oscillating", "swing_deg": 20})
    assert r.status_code == 422
    assert "pivot_distance_mm" in r.json()["detail"]


async def test_unknown_curve_is_404_with_close_matches(client: httpx.AsyncClient) -> None:
    r = await client.get("/v1/curves/cycloyd/plot")
    assert r.status_code == 404
    assert "cycloid" in r.json()["suggestions"]
    r = await client.get(INDEXER, params={**INDEXER_Q, "curve": "cycloyd"})
    assert r.status_code == 404
    r = await client.get(PROFILE, params={**PROFILE_Q, "curve": "cycloyd"})
    assert r.status_code == 404


async def test_plots_are_in_the_openapi_document_as_images(client: httpx.AsyncClient) -> None:
    spec = (await client.get("/openapi.json")).json()
    for path, op_id in [("/v1/curves/{name}/plot", "plotCurve"), ("/v1/indexers/plot", "plotIndexerMotion"),
                        ("/v1/profiles/plot", "plotProfile")]:
        op = spec["paths"][path]["get"]
        assert op["operationId"] == op_id
        assert set(op["responses"]["200"]["content"]) == {"image/svg+xml", "image/png"}
        assert "422" in op["responses"]
        samples = next(p for p in op["parameters"] if p["name"] == "samples")
        assert samples["schema"]["maximum"] == 2001
