"""How the OpenAPI document reads: its header, its tags in order with their descriptions, and
the operations of each tag in order (the computations, then their files, then the older paths).

Swagger UI and ReDoc show the tags in the order of the document's ``tags`` and each tag's
operations in the order of its ``paths``; a tag's name stays what the operations declare
(openapi-python-client makes a module of each: ``camcore_client.api.profiles``), so the file
twins are grouped by order within their tag, not by a tag of their own.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

#: each tag, in the order the document shows them, with what its operations do
TAGS: tuple[dict[str, str], ...] = (
    {"name": "curves", "description":
        "Dimensionless motion curves (S, V, A, J, Q over T from 0 to 1): the catalog of named curves, "
        "Makino's universal curve and special curves, polynomial, Bezier and measured-point curves. "
        "Characteristic values, tables, exact inverse lookups, sweeps of their parameters, charts, and "
        "the residual vibration a curve leaves in an elastic follower."},
    {"name": "motions", "description":
        "Motion programs: a machine cycle of moves and dwells in real units over the master angle, each "
        "law matched to its neighbours at the joins; as tables and as servo cam tables."},
    {"name": "indexers", "description":
        "Cam indexers (a turret indexed by a cam): the output motion over the input angle, position "
        "lookup, torque and power sizing and its sweep over designs, indexing accuracy, and the residual "
        "vibration of the load on an elastic drive."},
    {"name": "profiles", "description":
        "Plate cams: the profile for a follower (pressure angle, radius of curvature, undercut checks), "
        "base-circle sizing, the contour as DXF, CSV or X Y Z points, the cam as a STEP or STL solid, the "
        "cutter-centre toolpath as G-code or DXF, and the dynamics of a spring-loaded follower."},
    {"name": "cams", "description":
        "Cams beyond the plate cam: barrel cams, parallel indexing cams and roller-gear (globoidal) cams, "
        "with their geometry, checks and, for the roller-gear cam, the rib as an STL solid."},
    {"name": "machines", "description":
        "Several axes on one camshaft: the timing diagram, each axis's torque on the camshaft and the total, "
        "the flywheel, the motor, the machine's top speed and why, and timing rules with their phase slack."},
    {"name": "spreadsheets", "description":
        "One field of any computation as text, for a spreadsheet cell's formula."},
    {"name": "service", "description": "The service itself: liveness, version and cache figures."},
)

#: the document's header before its list of operations
DESCRIPTION = """Cam design as a service: motion curves, motion programs, indexers, plate-cam profiles,
toolpaths, solids, follower dynamics, residual vibration, barrel, parallel-indexing and roller-gear
cams, and machines of several axes on one camshaft.

- **Curves**: Makino's universal cam curve and his special curves, the INDEXMAN catalog curves (MS, MCV50,
  MT, TR, …), polynomial laws, Bezier and measured-point curves: characteristic values (Vm, Am±, Jm±, Qm±),
  tables, exact inverse lookups, parameter sweeps, charts, residual vibration.
- **Motion programs**: machine cycles of moves and dwells matched at every join, as tables or servo cam
  tables.
- **Indexers**: motion, position, torque and power sizing and its sweep, accuracy, vibration of the load.
- **Plate cams (profiles)**: contour, pressure angle, curvature, checks, base-circle sizing; the contour as
  DXF, CSV or X Y Z; the cam as a STEP or STL solid; the cutter-centre toolpath as G-code or DXF; the
  dynamics of a spring-loaded follower.
- **Cams**: barrel cams, parallel indexing cams, roller-gear (globoidal) cams.

Tables are column-oriented JSON, or CSV on `Accept: text/csv` (POST) or `?format=csv` (GET). Every
further format of an operation is also an operation of its own at `{path}.{format}` (a file twin:
`POST /v1/profiles.dxf`, `computeProfileDxf`); in each tag the twins follow the computations, and the
older paths, deprecated, come last. Rules between a request's fields are listed in its schema's
description."""

#: where a route stands within its tag: the computations, their files, the older paths
_RANK = {"operation": 0, "twin": 1, "alias": 2}


def operations_by_tag(document: Mapping[str, Any]) -> dict[str, list[str]]:
    """The id of every operation of the document that is not deprecated, by tag in the order of
    :data:`TAGS` (a tag not there after them), each tag's in the document's order."""
    order = [tag["name"] for tag in TAGS]
    found: dict[str, list[str]] = {}
    for item in document["paths"].values():
        for operation in item.values():
            if not operation.get("deprecated"):
                found.setdefault(operation.get("tags", ["service"])[0], []).append(operation["operationId"])
    return dict(sorted(found.items(), key=lambda entry: order.index(entry[0]) if entry[0] in order else len(order)))


def operation_list(document: Mapping[str, Any], kinds: Mapping[str, str]) -> str:
    """Markdown: each tag's operation ids on one line, its computations then its files
    (``kinds``: route kind by operation id) — the header's list, and the README's."""
    lines = []
    for tag, ids in operations_by_tag(document).items():
        computations = ", ".join(f"`{op_id}`" for op_id in ids if kinds.get(op_id) != "twin")
        files = ", ".join(f"`{op_id}`" for op_id in ids if kinds.get(op_id) == "twin")
        lines.append(f"- **{tag}**: {computations}" + (f"; files: {files}" if files else ""))
    return "\n".join(lines)


def arrange(document: dict[str, Any], kinds: Mapping[str, str]) -> None:
    """Lay the document out (in place): the described tags its operations use, in order; each
    tag's paths as computations, files, older paths (``kinds``: route kind by operation id; any
    other route counts as a computation); the header ending with every operation by tag."""
    used = {tag for item in document["paths"].values() for op in item.values() for tag in op.get("tags", ())}
    document["tags"] = [dict(tag) for tag in TAGS if tag["name"] in used]

    def rank(entry: tuple[str, Any]) -> int:
        first = next(iter(entry[1].values()))
        return _RANK[kinds.get(first.get("operationId", ""), "operation")]

    document["paths"] = dict(sorted(document["paths"].items(), key=rank))  # stable: the routes' order within a rank
    document["info"]["description"] = (f"{DESCRIPTION}\n\n**Operations** (the deprecated older paths left out):"
                                       f"\n\n{operation_list(document, kinds)}")
