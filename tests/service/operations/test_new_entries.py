"""A new law, or a new file format, is one registry entry in camcore: the service serves it
everywhere it belongs with no line of its own changed.

Each entry is added in a fresh interpreter (a temporary registry entry: the service reads its
registries when it is imported) that then answers the requests this test sends it over stdin,
in-process (httpx over ASGI), and prints what came back.
"""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap
from pathlib import Path
from typing import Any

from service.curves.specs import KIND_SPECS, CurveSpec
from service.motions.specs import PROGRAM_SPECS, ProgramCurveSpec
from service.registry import OPERATIONS
from tests.readers import read

ROOT = Path(__file__).resolve().parents[3]

#: a law of one parameter, n cycles of a sine in the acceleration: S = T − sin(2πnT)/(2πn); n = 1 is
#: the cycloid (S rises from 0 to 1 with V = 1 − cos 2πnT ≥ 0, at rest at both ends)
MULTICYCLOID = textwrap.dedent('''
    import math
    import numpy as np
    from camcore.curves import Curve
    from camcore.curves.kinds import CLOSED_FORM_COST, CURVE_KINDS, CurveKind, Parameter

    class MultiCycloid(Curve):
        def __init__(self, n: int = 1):
            self.n = n
            self.piece_starts = np.array([0.0])
            self.t_end = 1.0

        def eval_pieces(self, t, piece, order):
            w = 2 * math.pi * self.n
            out = [t - np.sin(w * t) / w, 1 - np.cos(w * t), w * np.sin(w * t), w**2 * np.cos(w * t),
                   -w**3 * np.sin(w * t)]
            return out[: order + 1]

    CURVE_KINDS["multicycloid"] = CurveKind(
        "multicycloid", "n sine cycles in the acceleration", MultiCycloid, ("n",), lambda p: CLOSED_FORM_COST,
        fields=(Parameter("n", int, "cycles of the acceleration", default=1, required=False, minimum=1, maximum=9),),
        example={"n": 2})
''')

RUN = textwrap.dedent('''
    import asyncio, base64, json, sys
    import httpx
    from service.app import create_app

    async def main():
        requests = json.loads(sys.stdin.read())
        app = create_app()
        out = []
        async with httpx.AsyncClient(transport=httpx.ASGITransport(app=app), base_url="http://t", timeout=120) as c:
            for method, url, body in requests:
                r = await c.request(method, url, json=body)
                out.append([r.status_code, r.headers.get("content-type", ""), base64.b64encode(r.content).decode()])
        doc = app.openapi()
        print(json.dumps({"answers": out, "schemas": sorted(doc["components"]["schemas"])}))

    asyncio.run(main())
''')


def served(entry: str, requests: list[tuple[str, str, Any]]) -> dict[str, Any]:
    """What a service whose camcore registries have ``entry`` added answers to ``requests``."""
    proc = subprocess.run([sys.executable, "-c", entry + RUN], input=json.dumps(requests), capture_output=True,
                          text=True, cwd=ROOT, timeout=600, check=False)
    assert proc.returncode == 0, proc.stderr[-3000:]
    import base64

    result = json.loads(proc.stdout.splitlines()[-1])
    result["answers"] = [(status, media, base64.b64decode(body)) for status, media, body in result["answers"]]
    return result


def test_every_kind_is_in_both_unions_of_curve_specs() -> None:
    from camcore.curves import CURVE_KINDS

    def kinds(union: Any) -> set[str]:
        return {model.model_fields["type"].default for model in union.__args__[0].__args__}

    assert set(KIND_SPECS) == set(PROGRAM_SPECS) == set(CURVE_KINDS) == kinds(CurveSpec) == kinds(ProgramCurveSpec)


def _with_law(value: Any, law: dict[str, Any]) -> tuple[Any, int]:
    """The example with every curve spec in it (a dict whose type is a kind) replaced by ``law``."""
    if isinstance(value, dict):
        if value.get("type") in KIND_SPECS:
            return dict(law), 1
        out, count = {}, 0
        for key, item in value.items():
            out[key], n = _with_law(item, law)
            count += n
        return out, count
    if isinstance(value, list):
        items = [_with_law(item, law) for item in value]
        return [item for item, _ in items], sum(n for _, n in items)
    return value, 0


def test_a_new_law_is_served_by_every_operation_that_takes_a_curve() -> None:
    law = {"type": "multicycloid", "n": 2}
    requests, ids = [], []
    for operation in OPERATIONS:
        if operation.method != "POST" or operation.id == "sweepCurveCharacteristics":  # makino or universal only
            continue
        # the first example that does not solve a stroke from a law's start velocity: the new law starts
        # at rest, so a stroke after it cannot be solved (a 422 that says so)
        candidates = [ex["value"] for ex in operation.examples.values() if '"to": null' not in json.dumps(ex["value"])]
        body, count = _with_law(candidates[0], law) if candidates else (None, 0)
        if count:
            requests.append(("POST", operation.path, body))
            ids.append(operation.id)
    takers = {"sampleCurve", "getCurveCharacteristics", "invertCurve", "computeMotion", "computeProfile",
              "sizeIndexer", "getIndexerMotion", "computeBarrelCam", "computeParallelIndexingCam",
              "computeRollerGearCam"}
    assert takers <= set(ids), sorted(takers - set(ids))  # the list, at least
    result = served(MULTICYCLOID, requests)
    assert "MulticycloidCurveSpec" in result["schemas"]  # in the document, with its parameter
    refused = [(i, status, content[:300]) for i, (status, _, content) in zip(ids, result["answers"]) if status != 200]
    assert not refused, refused
    table = json.loads(result["answers"][ids.index("sampleCurve")][2])
    # S(0.25) = 0.25 − sin(π)/(4π) = 0.25 and V(0.25) = 1 − cos(π) = 2 for n = 2
    i = table["t"].index(0.25)
    assert abs(table["s"][i] - 0.25) < 1e-15 and abs(table["v"][i] - 2.0) < 1e-15


SVG_FORMAT = textwrap.dedent('''
    from camcore import export

    def write_svg(contour):
        points = " ".join(f"{x!r},{y!r}" for x, y in zip(contour.x_mm.tolist(), contour.y_mm.tolist()))
        return (f'<svg xmlns="http://www.w3.org/2000/svg"><polygon points="{points}"/></svg>').encode()

    export.FORMATS["svg"] = export.ContourFormat("svg", "image/svg+xml", "cam.svg", "the contour as an SVG polygon",
                                                 write_svg, lambda points: 1e-6 * points)
''')


def test_a_new_format_is_served_and_read_back_by_its_reader() -> None:
    from service.profiles.specs import ROLLER_PROFILE_EXAMPLE

    body = {"profile": ROLLER_PROFILE_EXAMPLE, "samples": 37}
    result = served(SVG_FORMAT, [("POST", "/v1/profiles?format=svg", body), ("POST", "/v1/profiles.svg", body),
                                 ("POST", "/v1/profiles?format=bogus", body)])
    (query, twin, bogus) = result["answers"]
    for status, media, content in (query, twin):
        assert status == 200 and media == "image/svg+xml", content[:300]
        assert read(media, content) == 2  # the svg element and its polygon
        assert content.count(b",") == 37  # the 37 samples, 0° and 360° both
    assert bogus[0] == 422 and b"format" in bogus[2]
