"""vtkSTEPReader on every model of Data/: the output follows docs/DataContract.md.

Usage: pvpython test_reader_models.py PLUGIN_FILE DATA_DIR
"""
import math
import os
import sys

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager as sm

LoadPlugin(sys.argv[1], ns=globals())
data_dir = sys.argv[2]
models = sorted(f for f in os.listdir(data_dir) if f.lower().endswith((".step", ".stp")))
assert len(models) >= 9, models
failures = []


def check(name, cond, what):
    if not cond:
        failures.append("%s: %s" % (name, what))


for name in models:
    reader = STEPReader(FileName=os.path.join(data_dir, name))
    reader.UpdatePipeline()
    d = sm.Fetch(reader)
    fd, pd = d.GetFieldData(), d.GetPointData()

    def scalar(key):
        return fd.GetArray(key).GetValue(0)

    n = d.GetNumberOfPoints()
    check(name, n > 0 and d.GetNumberOfCells() > 0, "empty output")
    for arr in ("FaceId", "SolidId", "FaceUV", "Normals"):
        check(name, pd.GetArray(arr) is not None, "point array %s missing" % arr)
    faces, patches = int(scalar("NumberOfFaces")), int(scalar("NumberOfPatches"))
    sizes = {
        "BezierPatches": (patches, 48), "PatchFace": (patches, 1), "PatchDomain": (patches, 4),
        "FaceInfo": (faces, 9), "FaceDegrees": (faces, 2), "FaceDomain": (faces, 4),
        "TrimSegments": (int(scalar("NumberOfTrimSegments")), 8),
        "TrimSegmentInfo": (int(scalar("NumberOfTrimSegments")), 4),
        "TrimLoops": (int(scalar("NumberOfLoops")), 4),
        "EdgeSegments": (int(scalar("NumberOfEdgeSegments")), 12),
        "EdgeFaces": (int(scalar("NumberOfEdges")), 2),
        "FaceExactSurface": (faces, 8),
    }
    for arr, (tuples, comps) in sizes.items():
        a = fd.GetArray(arr)
        check(name, a is not None and a.GetNumberOfTuples() == tuples
              and a.GetNumberOfComponents() == comps, "field array %s shape" % arr)
    # Each analytic face (FaceInfo column 2: 0 plane .. 4 torus) carries a unit axis in its exact
    # surface (columns 3-5); the others carry zeros.
    info, exact = fd.GetArray("FaceInfo"), fd.GetArray("FaceExactSurface")
    if exact is not None:
        bad = [f for f in range(faces)
               if (abs(math.sqrt(sum(exact.GetComponent(f, 3 + k) ** 2 for k in range(3))) - 1.0) > 1e-9)
               != (info.GetComponent(f, 2) > 4)]
        check(name, not bad, "FaceExactSurface axis of faces %s" % bad[:5])
    # The surface's degrees: a B-spline or Bezier surface's (kinds 5, 6, and 0-4 where such a face
    # is analytic), an extruded B-spline or Bezier curve's (kind 8: the curve's, 1 along the line),
    # none for the other kinds.
    deg = fd.GetArray("FaceDegrees")
    if deg is not None:
        bad = []
        for f in range(faces):
            kind, du, dv = int(info.GetComponent(f, 2)), deg.GetComponent(f, 0), deg.GetComponent(f, 1)
            ok = 0 <= du <= 25 and 0 <= dv <= 25
            if kind in (5, 6):
                ok = ok and du >= 1 and dv >= 1
            elif kind == 8:
                ok = ok and ((du, dv) == (0, 0) or (du >= 1 and dv == 1))
            elif kind > 6:
                ok = ok and (du, dv) == (0, 0)
            if not ok:
                bad.append((f, kind, du, dv))
        check(name, not bad, "FaceDegrees of faces (face, kind, degrees) %s" % bad[:5])
    check(name, scalar("MaxPatchDeviation") <= scalar("Tolerance"), "patch deviation")
    check(name, int(scalar("OpenLoops")) == 0, "open trimming loops")
    face_ids = pd.GetArray("FaceId")
    lo, hi = face_ids.GetRange()
    check(name, lo >= 0 and hi < faces, "FaceId out of range")
    solids = set(int(pd.GetArray("SolidId").GetValue(i)) for i in range(0, n, 13))
    check(name, len(solids) == int(scalar("NumberOfSolids")) or len(solids) <= int(scalar("NumberOfSolids")),
          "SolidId count")
    normals = pd.GetArray("Normals")
    worst = max(abs(math.sqrt(sum(normals.GetComponent(i, k) ** 2 for k in range(3))) - 1.0)
                for i in range(0, n, 11))
    check(name, worst < 1e-9, "normals not unit (%g)" % worst)
    print("[reader] %-34s %2d solids %4d faces %5d patches %6d points, max deviation %.2e, "
          "read %.3f s, convert %.3f s, mesh %.3f s" % (
              name, int(scalar("NumberOfSolids")), faces, patches, n,
              scalar("MaxPatchDeviation"), scalar("ReadSeconds"), scalar("ConvertSeconds"),
              scalar("MeshSeconds")))
    Delete(reader)

# Several solids in one file keep their SolidId.
reader = STEPReader(FileName=os.path.join(data_dir, "fw13_hinge_l_assy.stp"))
reader.UpdatePipeline()
d = sm.Fetch(reader)
ids = set(int(d.GetPointData().GetArray("SolidId").GetValue(i)) for i in range(d.GetNumberOfPoints()))
check("fw13_hinge_l_assy.stp", len(ids) == 7, "expected 7 solids, got %s" % sorted(ids))

# Properties reach the reader: a tighter tolerance gives more patches, a shorter edge more points.
r1 = STEPReader(FileName=os.path.join(data_dir, "toroidal_shell.step"), Tolerance=1e-3)
r2 = STEPReader(FileName=os.path.join(data_dir, "toroidal_shell.step"), Tolerance=1e-5,
                MaxEdgeLength=1.0)
d1, d2 = sm.Fetch(r1), sm.Fetch(r2)
p1 = d1.GetFieldData().GetArray("NumberOfPatches").GetValue(0)
p2 = d2.GetFieldData().GetArray("NumberOfPatches").GetValue(0)
check("toroidal_shell.step", p2 > p1, "tolerance property has no effect (%d vs %d)" % (p1, p2))
check("toroidal_shell.step", d2.GetNumberOfPoints() > d1.GetNumberOfPoints(),
      "MaxEdgeLength property has no effect")
# DelaunayRefinement reaches the worker process: the hole plate's faces, none of which bisection
# refines beyond 4 times its flipped mesh, go from 18,881 to 7,375 vertices, the same faces.
r3 = STEPReader(FileName=os.path.join(data_dir, "hole_plate.step"))
r4 = STEPReader(FileName=os.path.join(data_dir, "hole_plate.step"), DelaunayRefinement=1)
d3, d4 = sm.Fetch(r3), sm.Fetch(r4)
check("hole_plate.step", d4.GetNumberOfPoints() < d3.GetNumberOfPoints() / 2,
      "DelaunayRefinement property has no effect (%d vs %d points)"
      % (d3.GetNumberOfPoints(), d4.GetNumberOfPoints()))
check("hole_plate.step", d4.GetNumberOfCells() > 0 and d3.GetFieldData().GetArray("NumberOfPatches").GetValue(0)
      == d4.GetFieldData().GetArray("NumberOfPatches").GetValue(0), "DelaunayRefinement changed the patches")
# The sliver guard (ConversionOptions::SliverRatio) in the worker process, by default: the tube's
# cylinders, whose bisection would end at 62,962 vertices, get their flipped meshes (12,258 in all).
r5 = STEPReader(FileName=os.path.join(data_dir, "tube.step"))
d5 = sm.Fetch(r5)
n5 = d5.GetNumberOfPoints()
check("tube.step", 0 < n5 < 15000, "the default mesh keeps the sliver strips (%d points)" % n5)
check("tube.step", d5.GetFieldData().GetArray("FlippedMeshFaces").GetValue(0) == 2,
      "FlippedMeshFaces is not the tube's two cylinders")
# Every face of the tube gets BRepMesh's mesh at once: none is meshed again (the count travels
# through the worker's model file).
check("tube.step", d5.GetFieldData().GetArray("RemeshedFaces") is not None and
      d5.GetFieldData().GetArray("RemeshedFaces").GetValue(0) == 0, "RemeshedFaces missing or not 0")

for f in failures:
    print("FAIL", f)
sys.exit(1 if failures else 0)
