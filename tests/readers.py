"""A reader for each media type the service answers: a second program that takes the bytes back.

Each reader raises when the bytes are not what their type says, and returns something to count
(rows, entities, facets, solids...). The readers are others' code wherever there is one: the
standard library's json, csv and XML parsers, ezdxf for DXF, OpenCASCADE's STEP reader, Pillow
for PNG; the STL and G-code readers are the tests' own (tests/stl_mesh.py,
tests/toolpath_reference.py), written from the formats' definitions, not from our writers.
"""

from __future__ import annotations

import csv
import io
import json
import os
import tempfile
import xml.etree.ElementTree as ET
from collections.abc import Callable
from typing import Any

from tests.stl_mesh import read_stl
from tests.toolpath_reference import parse_gcode


def read_json(data: bytes) -> int:
    value = json.loads(data)
    return len(value) if isinstance(value, dict | list) else 1


def read_csv(data: bytes) -> int:
    """Rows after the header; every row as long as the header."""
    rows = list(csv.reader(io.StringIO(data.decode("utf-8"))))
    header, body = rows[0], rows[1:]
    assert header and all(len(row) == len(header) for row in body), "ragged CSV"
    return len(body)


def read_text_numbers(data: bytes) -> int:
    """Whitespace-separated numbers (an X Y Z file, one cell's number)."""
    numbers = [float(word) for word in data.decode("utf-8").split()]
    return len(numbers)


def read_dxf(data: bytes) -> int:
    import ezdxf

    doc = ezdxf.read(io.StringIO(data.decode("utf-8")))
    return len(doc.modelspace())


def step_shape(data: bytes) -> Any:
    """The shape a STEP file holds, through the kernel's STEP reader."""
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.STEPControl import STEPControl_Reader

    fd, name = tempfile.mkstemp(suffix=".step")
    try:
        os.write(fd, data)
        os.close(fd)
        reader = STEPControl_Reader()
        assert reader.ReadFile(name) == IFSelect_RetDone
        reader.TransferRoots()
        return reader.OneShape()
    finally:
        os.unlink(name)


def count_solids(shape: Any) -> int:
    """Solids in a kernel shape."""
    from OCP.TopAbs import TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer

    solids = 0
    explorer = TopExp_Explorer(shape, TopAbs_SOLID)
    while explorer.More():
        solids += 1
        explorer.Next()
    return solids


def read_step(data: bytes) -> int:
    """Solids in a STEP file."""
    return count_solids(step_shape(data))


def read_stl_facets(data: bytes) -> int:
    return len(read_stl(data))


def read_gcode(data: bytes) -> int:
    return len(parse_gcode(data.decode("utf-8")))


def read_svg(data: bytes) -> int:
    root = ET.fromstring(data)
    assert root.tag.endswith("svg"), root.tag
    return len(list(root.iter()))


def read_png(data: bytes) -> int:
    from PIL import Image

    image = Image.open(io.BytesIO(data))
    image.verify()
    return int(image.size[0] * image.size[1])


#: bare media type → its reader
READERS: dict[str, Callable[[bytes], Any]] = {
    "application/json": read_json,
    "text/csv": read_csv,
    "text/plain": read_text_numbers,
    "application/dxf": read_dxf,
    "model/step": read_step,
    "model/stl": read_stl_facets,
    "text/x-gcode": read_gcode,
    "image/svg+xml": read_svg,
    "image/png": read_png,
}


def read(media_type: str, data: bytes) -> Any:
    """The bytes read back by the reader of their media type (KeyError: no reader for it)."""
    return READERS[media_type.split(";")[0].strip()](data)
