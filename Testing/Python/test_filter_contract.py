"""B-Rep Thickness on inputs that break docs/DataContract.md: the reader's output of the plate,
spoiled one way at a time by a Programmable Filter (a quad among the triangles, a triangle
naming a point that does not exist, a triangle across two faces, no Bezier patches). Each gives
one error naming the problem, empty outputs, and no crash; the unspoiled output is measured.

Usage: pvpython test_filter_contract.py PLUGIN_FILE PLATE_STEP
"""
import sys

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager as sm

from brt_checks import check, finish, messages

LoadPlugin(sys.argv[1], ns=globals())

reader = STEPReader(FileName=sys.argv[2])
reader.UpdatePipeline()

# Each script copies the input and spoils one thing; the last keeps it whole.
SPOIL = {
    "a quad": """
from vtkmodules.vtkCommonDataModel import vtkCellArray
src = self.GetPolyDataInput(); out = self.GetPolyDataOutput(); out.DeepCopy(src)
cells = vtkCellArray()
polys = src.GetPolys(); polys.InitTraversal()
from vtkmodules.vtkCommonCore import vtkIdList
ids = vtkIdList(); first = True
while polys.GetNextCell(ids):
    pts = [ids.GetId(k) for k in range(ids.GetNumberOfIds())]
    if first:
        pts.append(pts[0]); first = False
    cells.InsertNextCell(len(pts), pts)
out.SetPolys(cells)
""",
    "a point that does not exist": """
src = self.GetPolyDataInput(); out = self.GetPolyDataOutput(); out.DeepCopy(src)
conn = out.GetPolys().GetConnectivityArray()
conn.SetValue(0, src.GetNumberOfPoints() + 5)
""",
    "two faces": """
src = self.GetPolyDataInput(); out = self.GetPolyDataOutput(); out.DeepCopy(src)
faces = out.GetPointData().GetArray("FaceId")
conn = out.GetPolys().GetConnectivityArray()
p = conn.GetValue(0)
faces.SetValue(p, (faces.GetValue(p) + 1) % 2)
""",
    "no patches": """
src = self.GetPolyDataInput(); out = self.GetPolyDataOutput(); out.DeepCopy(src)
out.GetFieldData().RemoveArray("BezierPatches")
""",
    "whole": """
src = self.GetPolyDataInput(); out = self.GetPolyDataOutput(); out.DeepCopy(src)
""",
}
EXPECT = {
    "a quad": "a polygon with 4 vertices; only triangles are expected",
    "a point that does not exist": "a triangle names point",
    "two faces": "a triangle joins vertices of different faces",
    "no patches": "no field array 'BezierPatches'",
}

for name, script in SPOIL.items():
    spoiled = ProgrammableFilter(Input=reader, OutputDataSetType="vtkPolyData", Script=script)
    spoiled.UpdatePipeline()
    f = BRepThickness(Input=spoiled, Device="native")
    errors = messages(f, "ErrorEvent")
    f.UpdatePipeline()
    points = sm.Fetch(f, idx=0).GetNumberOfPoints()
    if name == "whole":
        check(not errors and points > 0, "whole: measured, no error (%d points)" % points)
    else:
        hits = [e for e in errors if EXPECT[name] in e]
        check(len(errors) == 1 and hits, "%s: one error naming it (%d errors: %s)" % (
            name, len(errors), " | ".join(e.strip().splitlines()[-1] for e in errors)[:300]))
        check(points == 0, "%s: empty output (%d points)" % (name, points))
    Delete(f)
    Delete(spoiled)
finish()
