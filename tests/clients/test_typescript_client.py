"""A TypeScript client generated from the app's OpenAPI document compiles and talks to the service.

``openapi-typescript`` (pinned in clients/typescript/package-lock.json, run with its default
options) turns the app's current document into types; ``tsc`` (strict) compiles the example
clients/typescript/src/example.ts, which sends the README's request bodies through
``openapi-fetch``; the compiled example then runs once with Node against a live server
(``python -m service`` on a loopback port). Needs ``node`` (≥ 20, for its global fetch) and
``npm``; ``npm ci`` installs the pinned packages when clients/typescript/node_modules is missing.
"""

from __future__ import annotations

import json
import math
import shutil
import subprocess
from pathlib import Path

import pytest

import camcore
from service.app import create_app

ROOT = Path(__file__).resolve().parents[2]
CLIENT = ROOT / "clients" / "typescript"
pytestmark = [pytest.mark.e2e, pytest.mark.node]


def tool(name: str) -> str:
    path = shutil.which(name)
    if not path:
        pytest.fail(f"{name} is not installed: this test needs Node.js 20 and npm "
                    "(Debian: apt-get install -y nodejs npm).", pytrace=False)
    return path


def run(*args: str | Path, cwd: Path, timeout: float = 300) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(a) for a in args], cwd=cwd, capture_output=True, text=True, timeout=timeout,
                          check=False)


@pytest.fixture(scope="module")
def node_modules() -> Path:
    node = tool("node")
    version = run(node, "--version", cwd=ROOT).stdout.strip()
    assert int(version.lstrip("v").split(".")[0]) >= 20, f"Node {version}: the example needs Node 20's fetch"
    modules = CLIENT / "node_modules"
    if not (modules / ".package-lock.json").is_file():
        proc = run(tool("npm"), "ci", "--no-audit", "--no-fund", cwd=CLIENT, timeout=600)
        assert proc.returncode == 0, proc.stdout + proc.stderr
    return modules


def tsc(project: Path, *args: str) -> subprocess.CompletedProcess[str]:
    return run(tool("node"), project / "node_modules" / "typescript" / "bin" / "tsc", *args, cwd=project)


@pytest.fixture(scope="module")
def project(tmp_path_factory: pytest.TempPathFactory, node_modules: Path) -> Path:
    """clients/typescript with types generated from the app's current document, in a temp folder."""
    folder = tmp_path_factory.mktemp("typescript")
    (folder / "src").mkdir()
    for name in ("package.json", "tsconfig.json", "src/example.ts"):
        shutil.copyfile(CLIENT / name, folder / name)
    (folder / "node_modules").symlink_to(node_modules, target_is_directory=True)
    document = folder / "openapi.json"
    document.write_text(json.dumps(create_app().openapi()), encoding="utf-8")
    cli = node_modules / "openapi-typescript" / "bin" / "cli.js"
    proc = run(tool("node"), cli, document, "-o", folder / "src" / "api.d.ts", cwd=folder)  # default options
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return folder


def test_readme_bodies_compile_against_the_generated_types(project: Path) -> None:
    proc = tsc(project, "-p", ".", "--noEmit")
    assert proc.returncode == 0, proc.stdout + proc.stderr


WRONG = """\
import type { components } from "../src/api.js";
type Schemas = components["schemas"];
export const noName: Schemas["TableRequest"] = { curve: { type: "named" } };
export const badShape: Schemas["LoadPartSpec"] = { shape: "sphere", mass_kg: 1 };
export const answerIsNumber: string = ({} as Schemas["CharacteristicsAnswer"]).vm;
export const bothOk: Schemas["TableRequest"] = { curve: { type: "named", name: "MS" } };
"""


def test_the_types_are_strict(project: Path) -> None:
    # the types say something: a body without the curve name, an unknown load shape and a number
    # read as text are compile errors (lines 3, 4, 5); a body with defaults left out is not (line 6)
    (project / "wrong").mkdir(exist_ok=True)
    (project / "wrong" / "wrong.ts").write_text(WRONG, encoding="utf-8")
    config = {"extends": "./tsconfig.json", "compilerOptions": {"rootDir": ".", "noEmit": True},
              "include": ["wrong"]}
    (project / "tsconfig.wrong.json").write_text(json.dumps(config), encoding="utf-8")
    proc = tsc(project, "-p", "tsconfig.wrong.json")
    assert proc.returncode != 0
    lines = {int(line.split("(")[1].split(",")[0]) for line in proc.stdout.splitlines() if "wrong.ts(" in line}
    assert lines == {3, 4, 5}, proc.stdout


def test_compiled_example_talks_to_the_service(project: Path, base_url: str) -> None:
    proc = tsc(project, "-p", ".")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    proc = run(tool("node"), project / "dist" / "example.js", base_url, cwd=project, timeout=120)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    out = json.loads(proc.stdout)
    ms = camcore.named_curve("MS").characteristics
    # JSON carries the shortest round-trip text of each float: the numbers are the library's exactly
    assert out["ms_vm"] == ms.vm.value and out["ms_t_vm"] == 0.5  # INDEXMAN MS: Vm = 1.76 at T = 0.5
    assert math.isclose(out["ms_vm"], 1.7596, abs_tol=5e-5)
    assert (out["ms_am_abs"], out["ms_t_am_abs"]) == (ms.am, 0.125)
    # the universal curve with MS's break points is MS: table row T = 0.30 has S = 0.17789
    assert out["universal_rows"] == 101 and round(out["universal_s_at_t_0_3"], 5) == 0.17789
    # disc 50 kg Ø600: I = m·D²/8 = 2.25 kg·m²; friction μ·m·g·R = 0.1·50·9.80665·0.2 N·m
    assert out["sizing_inertia_kgm2"] == 2.25
    assert math.isclose(out["sizing_friction_torque_nm"], 9.80665, rel_tol=1e-15)
    assert out["profile_points"] == 361 and 0 < out["profile_max_pressure_angle_deg"] < 90
    assert out["csv_header"] == "t,s,v,a,j,q"
