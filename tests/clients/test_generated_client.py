"""A Python client generated from the committed openapi/openapi.json talks to the real service.

``openapi-python-client`` generates the package into a temporary folder (it is not committed:
see docs/ecosystem.md); the service runs as users start it (``python -m service`` on a
loopback port); the numbers that come back through the generated models are the catalog's,
and the files (a CSV table, a DXF contour) come back as text and bytes a reader accepts.
"""

from __future__ import annotations

import csv
import importlib
import io
import math
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parents[2]
SPEC = ROOT / "openapi" / "openapi.json"
PACKAGE = "camcore_client"
pytestmark = [pytest.mark.e2e, pytest.mark.generator]

#: no formatter post-hooks (ruff need not be on PATH); image, DXF, STEP and STL answers are bytes
#: (the generator knows application/json, text/* and application/octet-stream only; the same
#: file is in docs/ecosystem.md)
CONFIG = """\
post_hooks: []
content_type_overrides:
  image/png: application/octet-stream
  image/svg+xml: application/octet-stream
  application/dxf: application/octet-stream
  model/step: application/octet-stream
  model/stl: application/octet-stream
"""


@pytest.fixture(scope="module")
def client_package(tmp_path_factory: pytest.TempPathFactory) -> Iterator[ModuleType]:
    try:
        import openapi_python_client  # noqa: F401
    except ImportError:
        pytest.fail("openapi-python-client is not installed (it is a test dependency in requirements.lock)",
                    pytrace=False)
    out = tmp_path_factory.mktemp("generated")
    config = out / "config.yaml"
    config.write_text(CONFIG, encoding="utf-8")
    proc = subprocess.run(
        [sys.executable, "-m", "openapi_python_client", "generate", "--path", str(SPEC),
         "--output-path", str(out / PACKAGE), "--meta", "none", "--config", str(config)],
        capture_output=True, text=True, timeout=300, check=False)
    log = proc.stdout + proc.stderr
    assert proc.returncode == 0, log
    # a warning means an operation or answer was left out of the client: our schema must not cause one
    assert "Warning" not in log and "WARNING" not in log, log
    sys.path.insert(0, str(out))
    try:
        yield importlib.import_module(PACKAGE)
    finally:
        sys.path.remove(str(out))
        for name in [m for m in sys.modules if m == PACKAGE or m.startswith(PACKAGE + ".")]:
            del sys.modules[name]


@pytest.fixture(scope="module")
def api(client_package: ModuleType, base_url: str) -> Iterator[Any]:
    with client_package.Client(base_url=base_url, raise_on_unexpected_status=True, timeout=30) as client:
        yield client


def module(name: str) -> Any:
    return importlib.import_module(f"{PACKAGE}.{name}")


def test_generated_modules_read_well(client_package: ModuleType) -> None:
    root = Path(client_package.__file__).parent
    modules = {str(p.relative_to(root / "api")) for p in (root / "api").rglob("*.py") if p.name != "__init__.py"}
    for expected in ("curves/sample_curve.py", "curves/invert_curve.py", "curves/sample_named_curve.py",
                     "curves/plot_curve.py", "indexers/size_indexer.py", "indexers/plot_indexer_motion.py",
                     "profiles/compute_profile.py", "profiles/plot_profile.py", "service/get_health.py",
                     "curves/sample_named_curve_csv.py", "curves/invert_curve_csv.py",
                     "indexers/get_indexer_motion_csv.py", "profiles/export_profile_dxf.py",
                     "profiles/export_profile_xyz.py", "profiles/export_profile_contour_csv.py"):
        assert expected in modules, sorted(modules)
    # an id is the operation's and its format's name ({id}{Format}) or an older path's alias: the longest,
    # compute_follower_dynamics_table_csv (an alias), has 35 characters
    assert all(len(Path(m).stem) <= 35 for m in modules), sorted(m for m in modules if len(Path(m).stem) > 35)


def test_sample_curve_table(api: Any) -> None:
    models = module("models")
    sample_curve = module("api.curves.sample_curve")
    table = sample_curve.sync(client=api, body=models.TableRequest(curve=models.NamedCurveSpec(name="MS"),
                                                                   samples=101))
    assert isinstance(table, models.CurveTable), table
    # INDEXMAN MS table row T = 0.30: S = 0.17789
    assert round(table.t[30], 10) == 0.3 and round(table.s[30], 5) == 0.17789
    assert len(table.s) == 101 and table.s[0] == 0.0 and math.isclose(table.s[-1], 1.0)


def test_sample_named_curve_and_errors(api: Any) -> None:
    models = module("models")
    sample_named_curve = module("api.curves.sample_named_curve")
    table = sample_named_curve.sync("MS", client=api, samples=11)
    assert isinstance(table, models.CurveTable) and len(table.t) == 11
    missing = sample_named_curve.sync_detailed("cycloyd", client=api)
    assert missing.status_code == 404
    assert isinstance(missing.parsed, models.ErrorAnswer) and "cycloyd" in missing.parsed.detail


def test_invert_curve(api: Any) -> None:
    models = module("models")
    invert_curve = module("api.curves.invert_curve")
    answer = invert_curve.sync(client=api, body=models.InverseRequest(curve=models.NamedCurveSpec(name="MS"),
                                                                      s=[0.17789]))
    assert isinstance(answer, models.InverseTable), answer
    assert round(answer.t[0], 4) == 0.3  # exact inverse of the table row above


def test_size_indexer(api: Any) -> None:
    models = module("models")
    size_indexer = module("api.indexers.size_indexer")
    indexer = models.IndexerSpec(stops=6, indexing_angle_deg=270, speed_rpm=60)
    load = models.LoadSpec(parts=[models.LoadPartSpec(shape=models.LoadPartSpecShape.DISC, mass_kg=50,
                                                      diameter_mm=600)],
                           friction_coefficient=0.1, friction_radius_mm=200)
    answer = size_indexer.sync(client=api, body=models.SizingRequest(indexer=indexer, load=load))
    assert isinstance(answer, models.SizingAnswer), answer
    # disc 50 kg Ø600: I = m D²/8 = 2.25 kg·m²; α max = (π/3)/0.75² · Am(MS) = 10.2913 rad/s²
    assert math.isclose(answer.inertia_kgm2, 2.25, rel_tol=1e-15)
    assert math.isclose(answer.alpha_max_rad_s2, math.pi / 3 / 0.75**2 * 5.52795707054409, rel_tol=1e-12)
    assert math.isclose(answer.friction_torque_nm, 9.80665, rel_tol=1e-15)


def test_compute_profile(api: Any) -> None:
    models = module("models")
    compute_profile = module("api.profiles.compute_profile")
    cv = models.NamedCurveSpec(name="constant-velocity")
    rise = models.SegmentSpec(type_=models.SegmentSpecType.RISE, angle_deg=180, lift_mm=20, curve=cv)
    back = models.SegmentSpec(type_=models.SegmentSpecType.RETURN, angle_deg=180, lift_mm=20, curve=cv)
    spec = models.ProfileSpec(follower=models.FollowerSpec(type_=models.FollowerSpecType.KNIFE_EDGE),
                              base_radius_mm=15, segments=[rise, back])
    answer = compute_profile.sync(client=api, body=models.ProfileRequest(profile=spec,
                                                                         cam_angle_deg=[10, 30, 45, 120, 270]))
    assert isinstance(answer, models.ProfileAnswer), answer
    # Shinzato 1988, table 1: 21.56, 19.15, 17.66, 12.66 and −14.29 (numerical column at 270°)
    assert [round(x, 2) for x in answer.pressure_angle_deg] == [21.56, 19.15, 17.66, 12.66, -14.29]
    assert answer.checks.max_pressure_angle_deg > 21.56


def test_plot_curve_answers_image_bytes(api: Any) -> None:
    models = module("models")
    plot_curve = module("api.curves.plot_curve")
    png = plot_curve.sync_detailed("MS", client=api, format_=models.PlotCurveFormat.PNG, samples=101)
    assert png.status_code == 200 and png.content[:8] == b"\x89PNG\r\n\x1a\n"
    bad = plot_curve.sync_detailed("MS", client=api, samples=100_000)
    assert bad.status_code == 422 and isinstance(bad.parsed, models.ErrorAnswer)


def test_download_csv_table(api: Any) -> None:
    models = module("models")
    csv_table = module("api.curves.sample_named_curve_csv")
    text = csv_table.sync("MS", client=api, samples=101)
    assert isinstance(text, str), type(text)  # text/csv comes back as text, not a JSONDecodeError
    rows = list(csv.reader(io.StringIO(text)))
    assert rows[0] == ["t", "s", "v", "a", "j", "q"] and len(rows) == 102
    # INDEXMAN MS table row T = 0.30: S = 0.17789; the last row ends at rest exactly
    assert rows[31][0] == "0.3" and round(float(rows[31][1]), 5) == 0.17789
    assert rows[-1][:4] == ["1.0", "1.0", "0.0", "0.0"]
    posted = module("api.curves.sample_curve_csv").sync(
        client=api, body=models.TableRequest(curve=models.NamedCurveSpec(name="MS"), samples=101))
    assert posted == text  # the POST twin answers the same table


def test_download_dxf_contour(api: Any) -> None:
    import ezdxf

    models = module("models")
    export_dxf = module("api.profiles.export_profile_dxf")
    rise = models.SegmentSpec(type_=models.SegmentSpecType.RISE, angle_deg=180, lift_mm=20)
    back = models.SegmentSpec(type_=models.SegmentSpecType.RETURN, angle_deg=180, lift_mm=20)
    spec = models.ProfileSpec(follower=models.FollowerSpec(type_=models.FollowerSpecType.KNIFE_EDGE),
                              base_radius_mm=15, segments=[rise, back])
    file = export_dxf.sync(client=api, body=models.ProfileRequest(profile=spec, samples=361))
    data = file.payload.read()  # the generator's File: the answer's bytes
    assert isinstance(data, bytes) and data.split(None, 2)[:2] == [b"0", b"SECTION"], data[:40]
    doc = ezdxf.read(io.StringIO(data.decode("utf-8")))
    polylines = doc.modelspace().query("LWPOLYLINE")
    assert len(polylines) == 1 and polylines[0].closed
    radii = [math.hypot(x, y) for x, y in polylines[0].get_points("xy")]
    # a knife edge on a 15 mm base circle lifted 20 mm: the contour runs from r = 15 to r = 35 mm
    # (1e-9 mm: the points are written with full float precision)
    assert math.isclose(min(radii), 15, abs_tol=1e-9) and math.isclose(max(radii), 35, abs_tol=1e-9)
    circles = doc.modelspace().query("CIRCLE")
    assert [c.dxf.radius for c in circles] == [15.0]


def test_download_contour_text_files(api: Any) -> None:
    models = module("models")
    rise = models.SegmentSpec(type_=models.SegmentSpecType.RISE, angle_deg=180, lift_mm=20)
    back = models.SegmentSpec(type_=models.SegmentSpecType.RETURN, angle_deg=180, lift_mm=20)
    body = models.ProfileRequest(profile=models.ProfileSpec(
        follower=models.FollowerSpec(type_=models.FollowerSpecType.KNIFE_EDGE), base_radius_mm=15,
        segments=[rise, back]), samples=361)
    xyz = module("api.profiles.export_profile_xyz").sync(client=api, body=body)
    points = [tuple(map(float, line.split())) for line in xyz.splitlines()]
    assert len(points) == 361 and points[0] == points[-1] and all(p[2] == 0.0 for p in points)
    contour = module("api.profiles.export_profile_contour_csv").sync(client=api, body=body)
    assert contour.splitlines()[0] == "cam_angle_deg,x_mm,y_mm,z_mm"
    table = module("api.profiles.compute_profile_csv").sync(client=api, body=body)
    assert table.splitlines()[0].startswith("cam_angle_deg,")


def test_download_step_solid_and_gcode(api: Any) -> None:
    # the solid comes back as bytes (model/step mapped to octet-stream), the G-code as text
    models = module("models")
    rise = models.SegmentSpec(type_=models.SegmentSpecType.RISE, angle_deg=180, lift_mm=20)
    back = models.SegmentSpec(type_=models.SegmentSpecType.RETURN, angle_deg=180, lift_mm=20)
    spec = models.ProfileSpec(follower=models.FollowerSpec(type_=models.FollowerSpecType.ROLLER, roller_radius_mm=10),
                              base_radius_mm=40, segments=[rise, back])
    solid = models.SolidSpec(thickness_mm=12, bore_diameter_mm=20)
    file = module("api.profiles.export_profile_step").sync(client=api, body=models.SolidRequest(profile=spec,
                                                                                                   solid=solid))
    data = file.payload.read()
    assert isinstance(data, bytes) and data.startswith(b"ISO-10303-21;"), data[:40]
    gcode = module("api.profiles.export_toolpath_gcode").sync(
        client=api, body=models.ToolpathRequest(profile=spec, tool_radius_mm=6))
    assert isinstance(gcode, str) and "G17 G21 G90" in gcode and gcode.rstrip().endswith("%")
