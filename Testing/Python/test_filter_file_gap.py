"""A file whose faces and edges miss each other, through the reader and the filter in pvpython:
the L-bracket with one plane's placement moved 10.7 mm off its face's edges (the placement's
point turned to another point of the file, as a damaged or mutated file has it). OpenCASCADE's
translation covers the gap by growing the vertices' tolerances; the reader warns of the vertices
and names the face, and the filter flags the face's samples, and those near its vertices or
whose sphere touches it, failed with FailReason 12 (FileGap); the Summary counts them. The file
as written: nothing of the kind.
Then a FreeCAD export whose solid has faces lying on one another with their outer sides the same
way (AngelLM/Thor's Art4BodyBot.step): the reader names them and carries them in the field data
(OverlappingFaces), and the filter flags every sample on them FileGap.

Usage: pvpython test_filter_file_gap.py PLUGIN_FILE L_BRACKET_STEP WORK_DIR THOR_ART4BODYBOT_STEP
"""
import os
import sys

import numpy as np
from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager as sm
from vtkmodules.numpy_interface import dataset_adapter as dsa

from brt_checks import check, finish, messages, table_rows

LoadPlugin(sys.argv[1], ns=globals())
source, work = sys.argv[2], sys.argv[3]
text = open(source).read()
placement = "#33 = AXIS2_PLACEMENT_3D('',#34,#35,#36);"
check(placement in text, "the L-bracket's plane placement is where the test expects it")
moved = os.path.join(work, "l_bracket_moved_plane.step")
with open(moved, "w") as out:
    out.write(text.replace(placement, "#33 = AXIS2_PLACEMENT_3D('',#46,#35,#36);"))


def run(path, overlapping=None):
    reader = STEPReader(FileName=path)
    warnings = messages(reader)
    if overlapping is not None:
        fd = dsa.WrapDataObject(sm.Fetch(reader)).FieldData
        overlapping.extend(int(x) for x in np.array(fd["OverlappingFaces"]).ravel())
    f = BRepThickness(Input=reader, Device="native")
    f.UpdatePipeline()
    pd = dsa.WrapDataObject(sm.Fetch(f, idx=0)).PointData
    rows = table_rows(sm.Fetch(f, idx=3))
    result = (warnings, np.array(pd["FailReason"]), np.array(pd["FaceId"]), rows)
    Delete(f)
    Delete(reader)
    return result


warnings, reason, face, rows = run(moved)
check(sum("has a tolerance of 10.7" in w for w in warnings) == 3, "three vertices named with their tolerance")
named = [w for w in warnings if "vertices lie more than" in w]
check(len(named) == 1, "the moved face named: %s" % named)
gap = reason == 12
check(gap.sum() > 0.1 * len(reason), "FileGap samples: %d of %d" % (gap.sum(), len(reason)))
moved_face = int(named[0].split("face ")[1].split(":")[0]) if named else -1
on_face = face == moved_face
check(on_face.any() and np.all(reason[on_face] == 12), "every sample on the moved face %d flagged FileGap" % moved_face)
check(int(rows.get("FailedFileGap", -1)) == int(gap.sum()), "Summary FailedFileGap = %s" % rows.get("FailedFileGap"))

warnings, reason, face, rows = run(source)
check(not any("tolerance of" in w or "vertices lie more than" in w for w in warnings), "the file as written: no such warning")
check(not np.any(reason == 12) and int(rows.get("FailedFileGap", -1)) == 0, "the file as written: nothing flagged FileGap")

overlapping = []
warnings, reason, face, rows = run(sys.argv[4], overlapping)
named = [w for w in warnings if "lie on one another with their outer sides the same way" in w]
check(len(named) == 1, "the faces lying on one another named once: %s" % named)
check(sorted(overlapping) == [38, 44, 67, 69, 79, 83, 86, 90], "field data OverlappingFaces: %s" % sorted(overlapping))
on = np.isin(face, overlapping)
check(on.sum() > 1000 and np.all(reason[on] == 12), "every one of the %d samples on them flagged FileGap" % on.sum())
check(int(rows.get("FailedFileGap", -1)) == int((reason == 12).sum()), "Summary FailedFileGap = %s" % rows.get("FailedFileGap"))
finish()
