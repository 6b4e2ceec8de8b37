"""Swagger UI's "Try it out" pre-fills every POST with a body that answers 200: a real headless Chromium.

The page is Swagger UI itself (the bundle the service serves at /static/docs, the app's
/openapi.json with only the POSTs under test among its paths); a few lines of script open each
POST in turn, press "Try it out", copy the body editor's text into the page and close the
operation again, and Chromium dumps the page. Each pre-filled body is
then posted to the same live server (``python -m service`` on a loopback port). Chromium's
network is limited to the loopback interface; the page is a local file, so it may read the
service's document across origins (``--disable-web-security``, this throwaway profile only).

Needs Debian's ``chromium`` (tests/chromium.py); without it the test FAILS.
"""

from __future__ import annotations

import html
import json
import re
from pathlib import Path

import httpx
import pytest

from tests.chromium import run_chromium

pytestmark = [pytest.mark.e2e, pytest.mark.chromium]

# the page is a local file reading the service's document across origins (this throwaway profile only)
FLAGS = ["--disable-web-security", "--virtual-time-budget=60000"]

PAGE = """<!doctype html>
<html><head><meta charset="utf-8"></head><body>
<div id="swagger-ui"></div><pre id="prefill">pending</pre>
<script src="BASE/static/docs/swagger-ui-bundle.js"></script>
<script>
const WANTED = PATHS;
// the service's document with only the POSTs WANTED among its paths (every component kept): Swagger UI
// renders every listed operation again on each click, and the 140-odd of the whole document took
// 116 s of a 2-vCPU VM for the 25 POSTs (2026-12-07)
fetch("BASE/openapi.json").then(r => r.json()).then(doc => {
  doc.paths = Object.fromEntries(Object.entries(doc.paths).filter(([path]) => WANTED.includes(path))
                                 .map(([path, item]) => [path, {post: item.post}]));
  SwaggerUIBundle({spec: doc, dom_id: "#swagger-ui", docExpansion: "list", deepLinking: false,
                   defaultModelsExpandDepth: -1});
});
// one POST at a time (of those WANTED): open it, press "Try it out", read its body editor, close it again, so the page
// never holds more than one expanded operation (with all of them open every update re-rendered
// every operation: 150-180 s for the 60-odd POSTs on a 2-core machine, against a 180 s limit)
const bodies = {};
let queue = null, stage = 0;
function pathOf(op) { return op.querySelector(".opblock-summary-path").getAttribute("data-path"); }
function step() {
  const ops = [...document.querySelectorAll(".opblock-post")];
  if (!ops.length) { setTimeout(step, 50); return; }
  if (queue === null) queue = ops.map(pathOf).filter(path => WANTED.includes(path));
  if (!queue.length) { document.getElementById("prefill").textContent = JSON.stringify(bodies); return; }
  const op = ops.find(o => pathOf(o) === queue[0]);
  if (stage === 0) { op.querySelector(".opblock-summary-control").click(); stage = 1; }
  else if (stage === 1) { const button = op.querySelector(".try-out__btn"); if (button) { button.click(); stage = 2; } }
  else {
    const editor = op.querySelector("textarea.body-param__text");
    if (editor) { bodies[queue.shift()] = editor.value; op.querySelector(".opblock-summary-control").click(); stage = 0; }
  }
  setTimeout(step, 50);
}
setTimeout(step, 100);
</script></body></html>
"""


def swagger_prefill(base_url: str, folder: Path, paths: list[str]) -> dict[str, str | None]:
    """What Swagger UI pre-fills in the body of each POST of ``paths``."""
    page = folder / "swagger.html"
    page.write_text(PAGE.replace("BASE", base_url).replace("PATHS", json.dumps(paths)), encoding="utf-8")
    proc = run_chromium(*FLAGS, "--dump-dom", page.as_uri(), timeout_s=180)
    found = re.search(r'<pre id="prefill">(.*?)</pre>', proc.stdout.decode(), re.DOTALL)
    assert found and found.group(1) != "pending", "Swagger UI did not render the operations"
    return json.loads(html.unescape(found.group(1)))


def test_swagger_ui_prefills_every_post_with_a_body_that_answers_200(base_url: str, tmp_path: Path) -> None:
    document = httpx.get(f"{base_url}/openapi.json", timeout=10).json()
    # one POST per distinct request body: a file twin or an older path takes its operation's body and
    # examples, so Swagger UI pre-fills it alike (with all 60-odd POSTs Chromium ran past its budget)
    distinct: dict[str, str] = {}
    for path, ops in document["paths"].items():
        if "post" in ops:
            distinct.setdefault(json.dumps(ops["post"]["requestBody"], sort_keys=True), path)
    posts = sorted(distinct.values())
    assert len(posts) >= 18, posts  # every POST operation with a body of its own (the solids twins share one)
    bodies = swagger_prefill(base_url, tmp_path, posts)
    assert sorted(bodies) == posts
    for path in posts:
        text = bodies[path]
        assert text, f"Swagger UI left the body of POST {path} empty"
        body = json.loads(text)
        first = next(iter(document["paths"][path]["post"]["requestBody"]["content"]["application/json"]
                          ["examples"].values()))["value"]
        assert body == first, f"POST {path}: Swagger UI pre-filled {body}, not the first example"
        r = httpx.post(f"{base_url}{path}", json=body, timeout=60)
        assert r.status_code == 200, f"POST {path} with Swagger UI's body: {r.status_code} {r.text[:300]}"
