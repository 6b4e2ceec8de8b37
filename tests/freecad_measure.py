"""Run by ``freecadcmd`` (tests/freecad.py): measures every solid of a saved document and every roller's
contact with the cam of its group, and writes them as JSON to $CAMCORE_MEASURE_OUT.

Per Part::Feature: volume, validity, closedness, solid count and the tight bounding box (OpenCASCADE's
optimal box: the plain box of a B-spline face bounds its control points, not the face). Per roller
(an object with AxisStart): the distance from its solid to the cam's, and its clearance to the flank it
works on (below), in the document's frame (placements applied).
"""

import json
import os

import FreeCAD as App
import Part

#: the roller core's radius is the roller's less this share of it: overlaps up to 1 mm deep on a 10 mm
#: roller are measured, not merely found
CORE_DEPTH_SHARE = 0.1
#: and its ends are drawn in by this share of the roller's length each
CORE_END_SHARE = 0.25

doc = App.openDocument(os.environ["CAMCORE_MEASURE_DOC"])
objects, contacts = {}, {}
for group in doc.findObjects("App::DocumentObjectGroup"):
    solids = [o for o in group.Group if o.isDerivedFrom("Part::Feature")]
    cams = [o for o in solids if not hasattr(o, "AxisStart")]
    for obj in solids:
        shape = obj.Shape
        box = shape.optimalBoundingBox()
        objects[obj.Name] = {
            "group": group.Name, "volume_mm3": shape.Volume, "valid": shape.isValid(), "closed": shape.isClosed(),
            "solids": len(shape.Solids), "shape_type": shape.ShapeType, "cam_angle_deg": float(obj.CamAngle),
            "box_min_mm": [box.XMin, box.YMin, box.ZMin], "box_max_mm": [box.XMax, box.YMax, box.ZMax],
            "placement": {"base_mm": list(obj.Placement.Base), "angle_deg": obj.Placement.Rotation.Angle * 180 / 3.141592653589793,
                          "axis": list(obj.Placement.Rotation.Axis)}}
    for roller in (o for o in solids if hasattr(o, "AxisStart")):
        (cam,) = cams
        start, end, radius = roller.AxisStart, roller.AxisEnd, float(roller.RollerRadius)
        axis = end - start
        # the roller's core: radius less CORE_DEPTH_SHARE·r, ends drawn in by CORE_END_SHARE of its length
        # (a barrel roller's end stands on the groove's bottom); its distance to the cam less the
        # radius taken off is the roller's clearance to the flank it works on, negative where they overlap
        # (as long as the overlap is shallower than the depth taken off)
        depth = CORE_DEPTH_SHARE * radius
        trim = App.Vector(axis).multiply(CORE_END_SHARE)
        core = Part.makeCylinder(radius - depth, axis.Length - 2 * trim.Length, start + trim, axis)
        # the cam's faces near the roller (boxes within a roller radius of its box): a ruled rib or groove has
        # thousands of faces, and OpenCASCADE's distance over all of them takes minutes; the distance to
        # the solid is the distance to its boundary as long as the roller is not wholly inside it
        near = roller.Shape.BoundBox
        near.enlarge(radius)
        faces = Part.makeCompound([f for f in cam.Shape.Faces if f.BoundBox.intersect(near)])
        contacts[roller.Name] = {
            "cam": cam.Name, "radius_mm": radius, "axis_start_mm": list(start), "axis_end_mm": list(end),
            "near_faces": len(faces.Faces), "solid_distance_mm": roller.Shape.distToShape(faces)[0],
            "clearance_mm": core.distToShape(faces)[0] - depth}
with open(os.environ["CAMCORE_MEASURE_OUT"], "w", encoding="utf-8") as f:
    json.dump({"objects": objects, "contacts": contacts}, f, indent=1)
