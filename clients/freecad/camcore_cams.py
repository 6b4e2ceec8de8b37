"""Build camcore's cams as FreeCAD solids: a plate cam, a barrel cam and a roller-gear rib, each on its
axis, with the follower roller(s) where they stand at a chosen cam angle.

Runs in FreeCAD's own Python (0.20 and later) with nothing but the standard library (urllib, json)
and FreeCAD's Part module. ``CamcoreCams.FCMacro`` is the entry point (a dialog in the GUI,
environment variables headless); docs/ecosystem.md, "FreeCAD", says which answers are used and why:

* plate cam: the service's STEP (``POST /v1/profiles?format=step``), read as it is: OpenCASCADE's
  lines and arcs within ``solid.tolerance_mm`` of the exact surface, and the bore. The roller's
  centre is the pitch point of ``POST /v1/profiles`` at the exact cam angle.
* barrel cam: ``POST /v1/cams/barrel`` (JSON), its two flank grids lofted round the turn into the
  groove, cut from a cylinder of the cam's outer radius. There is no STEP of it.
* roller-gear cam: ``POST /v1/cams/roller-gear`` (JSON), its two flank grids lofted along the turn
  into the rib (the STL is facets through the same points).

The lofts are ruled: straight between consecutive sampled cam angles, as the service's STL is, so the
solid strays from the exact flank by the chord's sagitta (r·Δθ²/8: 0.003 mm at r = 56 mm and 361
samples; the request's ``samples`` sets it). A smooth loft through hundreds of sections is an
approximation OpenCASCADE makes on its own terms: a barrel of 145 samples came out 200 mm³ off where
73 and 289 were within 30 mm³.

Frames are the service's (docs/api.md; camcore.profile, camcore.cams.barrel, camcore.cams.roller_gear):
each cam turns about its own z axis, moved to ``origin_mm``; the cam's solid is made in its own frame
and turned by the cam angle into the fixed frame, where the rollers stand.
"""

from __future__ import annotations

import json
import math
import os
import tempfile
import urllib.error
import urllib.request

import FreeCAD as App  # type: ignore[import-not-found]
import Part  # type: ignore[import-not-found]

V = App.Vector
Z_AXIS = V(0, 0, 1)
#: a request to the service; a barrel or rib of a few thousand samples answers within seconds
HTTP_TIMEOUT_S = 120
#: where each cam's axis stands when the spec says nothing (side by side along x, clear of each other)
DEFAULT_ORIGINS_MM = {"plate": (0.0, 0.0, 0.0), "barrel": (250.0, 0.0, 0.0), "roller_gear": (500.0, 0.0, 0.0)}
#: points on each arc of the barrel groove's cross-section (its bottom, and its outside beyond the cam):
#: a B-spline through 9 points of a circle of r·Δφ ≤ 60 mm strays from it by well under 1 µm
ARC_POINTS = 9


def post(url: str, path: str, body: dict, fmt: str | None = None) -> bytes:
    """POST ``body`` as JSON to the service; the answer's bytes. A refusal raises with the service's sentence."""
    target = url.rstrip("/") + path + (f"?format={fmt}" if fmt else "")
    request = urllib.request.Request(target, data=json.dumps(body).encode("utf-8"), method="POST",
                                     headers={"Content-Type": "application/json"})
    key = os.environ.get("CAMCORE_API_KEY")  # a deployment with an API key (docs/robustness.md)
    if key:
        request.add_header("X-API-Key", key)
    try:
        with urllib.request.urlopen(request, timeout=HTTP_TIMEOUT_S) as answer:
            return answer.read()
    except urllib.error.HTTPError as error:
        detail = error.read().decode("utf-8", "replace")
        try:
            detail = json.loads(detail).get("detail", detail)
        except ValueError:
            pass
        raise RuntimeError(f"{target} answered {error.code}: {detail}") from None


def post_json(url: str, path: str, body: dict) -> dict:
    return json.loads(post(url, path, body))


def nearest_index(angles_deg: list[float], angle_deg: float) -> int:
    """The sampled cam angle nearest ``angle_deg`` (taken modulo 360°)."""
    a = angle_deg % 360.0
    return min(range(len(angles_deg)), key=lambda i: abs(angles_deg[i] - a))


def _label(obj: object, text: str) -> None:
    obj.Label2 = text  # type: ignore[attr-defined]


def add_solid(doc: object, group: object, name: str, shape: object, origin: object, turn_deg: float,
              cam_angle_deg: float, note: str) -> object:
    """A Part::Feature holding ``shape`` (made in its own frame), turned about z and moved to ``origin``."""
    obj = doc.addObject("Part::Feature", name)  # type: ignore[attr-defined]
    obj.Shape = shape
    obj.Placement = App.Placement(origin, App.Rotation(Z_AXIS, turn_deg))
    obj.addProperty("App::PropertyAngle", "CamAngle", "camcore", "the cam angle the assembly stands at")
    obj.CamAngle = cam_angle_deg
    _label(obj, note)
    group.addObject(obj)  # type: ignore[attr-defined]
    return obj


def add_roller(doc: object, group: object, name: str, start: object, end: object, radius_mm: float,
               origin: object, cam_angle_deg: float, end_radius_mm: float | None = None) -> object:
    """A roller between two axis points of the fixed frame (a cone when ``end_radius_mm`` differs), its
    axis and radius kept as properties (in the document's frame) for whoever checks the contact."""
    axis = end - start
    if end_radius_mm is None:
        shape = Part.makeCylinder(radius_mm, axis.Length, start, axis)
    else:
        shape = Part.makeCone(radius_mm, end_radius_mm, axis.Length, start, axis)
    obj = add_solid(doc, group, name, shape, origin, 0.0, cam_angle_deg, f"roller at cam angle {cam_angle_deg:g}°")
    obj.addProperty("App::PropertyVectorDistance", "AxisStart", "camcore", "roller axis, first end")
    obj.addProperty("App::PropertyVectorDistance", "AxisEnd", "camcore", "roller axis, second end")
    obj.addProperty("App::PropertyLength", "RollerRadius", "camcore", "roller radius (at AxisStart)")
    obj.AxisStart, obj.AxisEnd, obj.RollerRadius = start + origin, end + origin, radius_mm
    return obj


def _group(doc: object, name: str, request: dict) -> object:
    group = doc.addObject("App::DocumentObjectGroup", name)  # type: ignore[attr-defined]
    group.addProperty("App::PropertyString", "Request", "camcore", "the body sent to the service")
    group.Request = json.dumps(request)
    return group


def _origin(part: dict, kind: str) -> object:
    return V(*part.get("origin_mm", DEFAULT_ORIGINS_MM[kind]))


# ----------------------------------------------------------------------------------------------- plate cam
def read_step(data: bytes) -> object:
    """The one solid of a STEP file's bytes."""
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "cam.step")
        with open(path, "wb") as f:
            f.write(data)
        shape = Part.read(path)
    solids = shape.Solids
    if len(solids) != 1:
        raise RuntimeError(f"the service's STEP holds {len(solids)} solids, not one")
    return solids[0]


def build_plate(doc: object, url: str, part: dict, cam_angle_deg: float) -> dict:
    """The plate cam from its STEP, and its roller (a roller follower) from the pitch point at the cam angle."""
    request = part["request"]
    if "solid" not in request:
        raise ValueError('plate.request needs "solid": {"thickness_mm": …} (the STEP is an extrusion)')
    profile = request["profile"]
    origin = _origin(part, "plate")
    sense = 1.0 if profile.get("rotation", "ccw") == "ccw" else -1.0
    # camcore.profile.cam: cam-frame points are fixed-frame points turned back by σθ
    turn_deg = sense * cam_angle_deg
    group = _group(doc, "PlateCamAssembly", request)
    cam = add_solid(doc, group, "PlateCam", read_step(post(url, "/v1/profiles", request, "step")), origin,
                    turn_deg, cam_angle_deg, "plate cam (service STEP)")
    built = {"cam": cam.Name, "rollers": [], "cam_angle_deg": cam_angle_deg}
    follower = profile["follower"]
    if follower.get("type") != "roller":
        return built  # a knife edge or a flat face: no roller to place
    at = post_json(url, "/v1/profiles", {"profile": profile, "cam_angle_deg": [cam_angle_deg]})
    turn = App.Rotation(Z_AXIS, turn_deg)
    centre = turn.multVec(V(at["pitch_x_mm"][0], at["pitch_y_mm"][0], 0))
    thickness = request["solid"]["thickness_mm"]
    roller = add_roller(doc, group, "PlateCamRoller", centre, centre + V(0, 0, thickness),
                        follower["roller_radius_mm"], origin, cam_angle_deg)
    built["rollers"].append(roller.Name)
    return built


# ----------------------------------------------------------------------------------------------- barrel cam
def _polar(p: object) -> tuple[float, float]:
    return math.hypot(p.x, p.y), math.atan2(p.y, p.x)


def extend_to_radius(p: object, toward: object, radius_mm: float) -> object:
    """The point on the line through ``toward`` and ``p``, on p's side, at ``radius_mm`` from the z axis
    (the flank carried on along its own direction to the groove's bottom or beyond the cam's outside)."""
    d = p - toward
    a, b = d.x**2 + d.y**2, 2 * (p.x * d.x + p.y * d.y)
    c = p.x**2 + p.y**2 - radius_mm**2
    root = math.sqrt(max(b * b - 4 * a * c, 0.0))
    t = min(((-b - root) / (2 * a), (-b + root) / (2 * a)), key=abs)
    return p + d * t


def arc_edge(start: object, end: object, radius_mm: float) -> object:
    """An edge at ``radius_mm`` from the z axis between two points at that radius (polar angle and z
    linear between them): the groove's bottom, or the section's closing side outside the cam."""
    (_, a0), (_, a1) = _polar(start), _polar(end)
    a1 = a0 + math.remainder(a1 - a0, 2 * math.pi)
    points = [start]
    for i in range(1, ARC_POINTS - 1):
        f = i / (ARC_POINTS - 1)
        a = a0 + f * (a1 - a0)
        points.append(V(radius_mm * math.cos(a), radius_mm * math.sin(a), start.z + f * (end.z - start.z)))
    points.append(end)
    curve = Part.BSplineCurve()
    curve.interpolate(points)
    return curve.toShape()


def groove_section(lower: list, upper: list, bottom_mm: float, outside_mm: float) -> object:
    """One cam angle's cross-section of the groove: the lower flank from the bottom out, the closing
    side outside the cam, the upper flank back in, the bottom (points from the roller's inner end out).

    Each flank's end points are moved along its end segments to the bottom and outside radii (not
    added to them: a dwell's flank already starts at the bottom, and every section must have as many
    edges for the loft)."""
    low, up = list(lower), list(upper)
    for flank in (low, up):
        flank[0], flank[-1] = (extend_to_radius(flank[0], flank[1], bottom_mm),
                               extend_to_radius(flank[-1], flank[-2], outside_mm))
    edges = [*Part.makePolygon(low).Edges, arc_edge(low[-1], up[-1], outside_mm),
             *Part.makePolygon(up[::-1]).Edges, arc_edge(up[0], low[0], bottom_mm)]
    return Part.Wire(edges)


def _grid_points(flank: dict, row: int) -> list:
    return [V(x, y, z) for x, y, z in zip(flank["x_mm"][row], flank["y_mm"][row], flank["z_mm"][row])]


def build_barrel(doc: object, url: str, part: dict, cam_angle_deg: float) -> dict:
    """The barrel cam: a cylinder of the outer radius, the groove between the two flank grids cut from it
    (lofted through one cross-section per sampled cam angle, closed round the turn), and the roller."""
    request = part["request"]
    answer = post_json(url, "/v1/cams/barrel", request)
    origin = _origin(part, "barrel")
    pitch, rho = request["pitch_radius_mm"], request["roller_radius_mm"]
    length = request.get("roller_length_mm") or rho  # the service's defaults (BarrelCamRequest)
    depth = request.get("groove_depth_mm") or length
    outer = pitch + length / 2
    bottom = outer - depth
    # the section's outside stands clear of the cylinder, so the cut meets no face of it edge-on
    outside = outer + 1.0 + 0.1 * depth
    angles, flanks = answer["cam_angle_deg"], answer["flanks"]
    rows = len(angles) - 1 if abs(angles[-1] - angles[0] - 360.0) < 1e-9 else len(angles)  # 360° = 0°
    sections = [groove_section(_grid_points(flanks["lower"], i), _grid_points(flanks["upper"], i), bottom, outside)
                for i in range(rows)]
    groove = Part.makeLoft(sections, True, True, True)
    shoulder = part.get("shoulder_mm", rho)
    z_low = min(min(row) for row in flanks["lower"]["z_mm"]) - shoulder
    z_high = max(max(row) for row in flanks["upper"]["z_mm"]) + shoulder
    blank = Part.makeCylinder(outer, z_high - z_low, V(0, 0, z_low), Z_AXIS)
    cam_shape = blank.cut(groove)
    if len(cam_shape.Solids) != 1:
        raise RuntimeError(f"the groove cut left {len(cam_shape.Solids)} solids, not one")
    i = nearest_index(angles, cam_angle_deg)
    at_deg = angles[i]
    group = _group(doc, "BarrelCamAssembly", request)
    # camcore.cams.barrel: cam-frame points are fixed-frame points turned by +θ
    cam = add_solid(doc, group, "BarrelCam", cam_shape.Solids[0], origin, -at_deg, at_deg,
                    "barrel cam (service flank grids, lofted)")
    x_in, x_out = pitch - length / 2, pitch + length / 2
    if request.get("follower", "translating") == "oscillating":
        arm = request["arm_length_mm"]
        psi = math.radians(request.get("initial_arm_angle_deg", 0.0) + answer["swing_deg"][i])
        y, z = arm * (math.cos(psi) - 1), arm * math.sin(psi)
    else:
        y, z = 0.0, answer["lift_mm"][i]
    start, end = V(x_in, y, z), V(x_out, y, z)
    if request.get("roller", "cylindrical") == "conical":  # apex on the cam axis: ρ(x) = x·ρ/R
        roller = add_roller(doc, group, "BarrelCamRoller", start, end, rho * x_in / pitch, origin, at_deg,
                            end_radius_mm=rho * x_out / pitch)
    else:
        roller = add_roller(doc, group, "BarrelCamRoller", start, end, rho, origin, at_deg)
    return {"cam": cam.Name, "rollers": [roller.Name], "cam_angle_deg": at_deg}


# ----------------------------------------------------------------------------------------------- roller-gear cam
def build_roller_gear(doc: object, url: str, part: dict, cam_angle_deg: float) -> dict:
    """The rib of a roller-gear cam, lofted through one cross-section per sampled cam angle (the forward
    flank from the rollers' inner end out, the back flank back in), and the two rollers straddling it."""
    request = part["request"]
    answer = post_json(url, "/v1/cams/roller-gear", request)
    origin = _origin(part, "roller_gear")
    forward, back = answer["flanks"]["forward"], answer["flanks"]["back"]
    angles = answer["cam_angle_deg"]
    rings = []
    for i in range(len(angles)):
        ring = [*_grid_points(forward, i), *_grid_points(back, i)[::-1]]
        rings.append(Part.makePolygon([*ring, ring[0]]))
    rib = Part.makeLoft(rings, True, True, False)
    i = nearest_index(angles, cam_angle_deg)
    at_deg = angles[i]
    group = _group(doc, "RollerGearCamAssembly", request)
    # camcore.cams.roller_gear: a fixed-frame point p is R_z(−θ)·p in the cam's frame
    cam = add_solid(doc, group, "RollerGearRib", rib, origin, at_deg, at_deg,
                    "roller-gear cam rib (service flank grids, lofted)")
    c, rp, half = request["center_distance_mm"], request["roller_pitch_radius_mm"], request["roller_length_mm"] / 2
    turret = V(c, 0, 0)
    phi, pitch_angle = math.radians(answer["turret_angle_deg"][i]), 2 * math.pi / request["stops"]
    names = []
    # the roller ahead of the rib (forward flank) at α = φ, the one behind (back flank) at α = φ − h
    for name, alpha in (("RollerGearRollerAhead", phi), ("RollerGearRollerBehind", phi - pitch_angle)):
        u = V(-math.cos(alpha), 0, math.sin(alpha))
        roller = add_roller(doc, group, name, turret + u * (rp - half), turret + u * (rp + half),
                            request["roller_radius_mm"], origin, at_deg)
        names.append(roller.Name)
    return {"cam": cam.Name, "rollers": names, "cam_angle_deg": at_deg}


BUILDERS = {"plate": build_plate, "barrel": build_barrel, "roller_gear": build_roller_gear}


def build(url: str, spec: dict, doc: object | None = None) -> tuple[object, dict]:
    """Every cam the spec names (``plate``, ``barrel``, ``roller_gear``) in ``doc`` (a new document by
    default); the document and what was built where."""
    doc = doc or App.newDocument("CamcoreCams")
    unknown = set(spec) - set(BUILDERS) - {"cam_angle_deg"}
    if unknown:
        raise ValueError(f"unknown spec keys {sorted(unknown)}: use {sorted(BUILDERS)} and cam_angle_deg")
    built = {}
    for kind, builder in BUILDERS.items():
        if kind in spec:
            part = spec[kind]
            built[kind] = builder(doc, url, part, float(part.get("cam_angle_deg", spec.get("cam_angle_deg", 0.0))))
    doc.recompute()  # type: ignore[attr-defined]
    return doc, built
