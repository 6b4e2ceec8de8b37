"""The DXF the service writes, read by two readers: ezdxf (header, units, view) and
LibreOffice Draw (headless conversion to PNG, the picture measured with Pillow).

LibreOffice scales a DXF to its header extents; with ezdxf's default ±1e20 it drew the
whole cam into one point and showed a blank page.
"""

from __future__ import annotations

import io
from pathlib import Path

import ezdxf
import httpx
import numpy as np
import pytest
from ezdxf import bbox
from PIL import Image

from tests.libreoffice import convert

pytestmark = pytest.mark.anyio

ROLLER = {"follower": {"type": "roller", "roller_radius_mm": 10}, "base_radius_mm": 40,
          "segments": [{"type": "rise", "angle_deg": 120, "lift_mm": 20, "curve": {"type": "named", "name": "MS"}},
                       {"type": "dwell", "angle_deg": 60},
                       {"type": "return", "angle_deg": 120, "lift_mm": 20},
                       {"type": "dwell", "angle_deg": 60}]}
SAMPLES = 721


async def _cam(client: httpx.AsyncClient) -> tuple[bytes, np.ndarray, np.ndarray]:
    """The DXF download and, from the JSON answer of the same request, the contour."""
    body = {"profile": ROLLER, "samples": SAMPLES}
    dxf = await client.post("/v1/profiles?format=dxf", json=body)
    assert dxf.status_code == 200 and dxf.headers["content-type"] == "application/dxf"
    columns = (await client.post("/v1/profiles", json=body)).json()
    return dxf.content, np.array(columns["x_mm"]), np.array(columns["y_mm"])


def _drawing_box(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The bounding box of the contour and the base circle (centred on the cam axis) [mm]."""
    r = ROLLER["base_radius_mm"]
    return np.minimum([x.min(), y.min()], -r), np.maximum([x.max(), y.max()], r)


def _max_sagitta(x: np.ndarray, y: np.ndarray) -> float:
    """The largest distance of a contour point from the chord through its two neighbours [mm]."""
    p = np.column_stack([x, y])[:-1]  # the last point repeats the first
    prev, nxt = np.roll(p, 1, axis=0), np.roll(p, -1, axis=0)
    chord = nxt - prev
    cross = chord[:, 0] * (p - prev)[:, 1] - chord[:, 1] * (p - prev)[:, 0]
    return float(np.max(np.abs(cross) / np.hypot(chord[:, 0], chord[:, 1])))


async def test_dxf_header_has_the_drawing_extents_units_and_view(client: httpx.AsyncClient) -> None:
    content, x, y = await _cam(client)
    doc = ezdxf.read(io.StringIO(content.decode()))
    lo, hi = _drawing_box(x, y)
    # the DXF and the JSON both carry shortest round-trip floats: the very same numbers
    assert tuple(doc.header["$EXTMIN"]) == (lo[0], lo[1], 0.0)
    assert tuple(doc.header["$EXTMAX"]) == (hi[0], hi[1], 0.0)
    assert tuple(doc.header["$LIMMIN"]) == tuple(lo) and tuple(doc.header["$LIMMAX"]) == tuple(hi)
    assert doc.header["$INSUNITS"] == 4 and doc.header["$MEASUREMENT"] == 1  # millimetres, metric
    (view,) = doc.viewports.get_config("*Active")
    assert tuple(view.dxf.center)[:2] == pytest.approx(tuple((lo + hi) / 2), abs=1e-12)  # rounding of a mean
    assert view.dxf.height >= hi[1] - lo[1]  # the opening view shows the whole height
    # every entity inside the extents: polyline and circle exactly; the spline through the
    # same points may bulge past them between points, by less than the largest sagitta over
    # two neighbouring intervals (a smooth interpolant's bulge over one is ~1/4 of that)
    bulge = _max_sagitta(x, y)
    assert 0 < bulge < 0.01  # 721 points on a ~100 mm cam: a bound that is a few µm, not a loophole
    for entity in doc.modelspace():
        box = bbox.extents([entity], fast=False)
        slack = bulge if entity.dxftype() == "SPLINE" else 0.0
        assert np.all(np.asarray(box.extmin)[:2] >= lo - slack), entity.dxftype()
        assert np.all(np.asarray(box.extmax)[:2] <= hi + slack), entity.dxftype()


@pytest.mark.libreoffice
async def test_libreoffice_draws_the_cam(client: httpx.AsyncClient, tmp_path: Path) -> None:
    content, x, y = await _cam(client)
    source = tmp_path / "cam.dxf"
    source.write_bytes(content)
    png = convert(source, "png", tmp_path / "out", profile=tmp_path / "profile")
    with Image.open(png) as picture:
        page = Image.alpha_composite(Image.new("RGBA", picture.size, "white"), picture.convert("RGBA"))
    gray = np.asarray(page.convert("L"))
    rows, cols = np.nonzero(gray < 200)  # anti-aliased black lines on white; 200 keeps their cores
    assert rows.size > 500, "LibreOffice drew a blank page"
    left, right, top, bottom = cols.min(), cols.max(), rows.min(), rows.max()
    width_px, height_px = right - left, bottom - top
    page_w, page_h = gray.shape[1], gray.shape[0]
    # a sensible part of the page: LibreOffice places the drawing 10 cm wide on A4 (~48 % of the width)
    assert width_px > 0.25 * page_w and height_px > 0.2 * page_h, (width_px, height_px, page_w, page_h)
    lo, hi = _drawing_box(x, y)
    size = hi - lo
    # the cam's proportions: lines 1 px wide, each edge found to ±1 px, so the ratio to ±2/370
    assert width_px / height_px == pytest.approx(size[0] / size[1], abs=3 / min(width_px, height_px))

    # the right drawing, the right way up: map the contour and the base circle from the box
    # onto the ink box (DXF y points up, image rows down) and find ink at every point
    def pixel(px_mm: np.ndarray, py_mm: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        col = left + (px_mm - lo[0]) / size[0] * width_px
        row = bottom - (py_mm - lo[1]) / size[1] * height_px
        return np.rint(row).astype(int), np.rint(col).astype(int)

    angle = np.linspace(0, 2 * np.pi, 360, endpoint=False)
    r = ROLLER["base_radius_mm"]
    ink = gray < 200
    # ink within 2 px: the box edges are found to ±1 px and a line is drawn to the nearest pixel
    reach = 2
    padded = np.pad(ink, reach)
    near = np.zeros_like(ink)
    for dr in range(2 * reach + 1):
        for dc in range(2 * reach + 1):
            near |= padded[dr:dr + ink.shape[0], dc:dc + ink.shape[1]]
    for name, (px_mm, py_mm) in {"contour": (x, y), "base circle": (r * np.cos(angle), r * np.sin(angle))}.items():
        row, col = pixel(px_mm, py_mm)
        missing = int(np.count_nonzero(~near[row, col]))
        assert missing == 0, f"{missing} of {row.size} {name} points have no ink within {reach} px"
