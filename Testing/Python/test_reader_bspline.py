"""B-splines whose data contradict each other, through the ParaView reader: the cubic ridge with
a pcurve whose knot multiplicities do not add up (OpenCASCADE reads no curve from it and the
healing rebuilds it from its edge) reads, with one warning that names the entity and its line,
and the thickness of the file as written (the same samples' values); with its B-spline surface so damaged (OpenCASCADE
reads no surface, the face is lost, the solid open), the reader gives one error that names the
file and, as the likely cause, the entity. The file as written: no such warning.

Usage: pvpython test_reader_bspline.py PLUGIN_FILE CUBIC_RIDGE_STEP WORK_DIR
"""
import os
import sys

import numpy as np
from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager as sm
from vtkmodules.numpy_interface import dataset_adapter as dsa

from brt_checks import check, finish, messages

LoadPlugin(sys.argv[1], ns=globals())
source, work = sys.argv[2], sys.argv[3]
os.makedirs(work, exist_ok=True)
text = open(source).read()
pcurve = "  ,(3,3),(0.,4.),.PIECEWISE_BEZIER_KNOTS.);"
surface = "(4,4),(2,2),(0.,1.),(-4.,0.)"
check(text.count(pcurve) >= 1 and surface in text, "the cubic ridge's lists are where the test expects them")


def write(name, old, new):
    path = os.path.join(work, name)
    with open(path, "w") as out:
        out.write(text.replace(old, new, 1))
    return path


def run(path):
    reader = STEPReader(FileName=path)
    warnings = messages(reader)
    errors = messages(reader, "ErrorEvent")
    f = BRepThickness(Input=reader, Device="native")
    f.UpdatePipeline()
    out = sm.Fetch(f, idx=0)
    thickness = np.array(dsa.WrapDataObject(out).PointData["Thickness"]) if out.GetNumberOfPoints() else np.array([])
    Delete(f)
    Delete(reader)
    return warnings, errors, thickness


warnings, errors, plain = run(source)
check(not errors and not any("B-spline" in w for w in warnings), "the file as written: no B-spline warning")

warnings, errors, rebuilt = run(write("ridge_pcurve_sum.step", pcurve, "  ,(3,2),(0.,4.),.PIECEWISE_BEZIER_KNOTS.);"))
named = [w for w in warnings if "#41 (line 60), a B-spline curve: its knot multiplicities add up to 5" in w]
check(len(named) == 1 and "reads no curve from it" in named[0], "the pcurve named once: %s" % named)
check(not errors, "the damaged pcurve: no error (%s)" % errors)
# The same samples, in another order (the display mesh numbers the rebuilt edge's vertices
# otherwise): their sorted values agree (2.4e-11 relative at most when this test was written).
same = rebuilt.shape == plain.shape
diff = (np.abs(np.sort(rebuilt) - np.sort(plain)) / np.maximum(np.sort(plain), 1e-300)
        if same else np.array([np.inf]))
check(same and np.nanmax(diff) <= 1e-9,
      "the thickness of the file as written (%d samples, sorted: %.3g relative at most)"
      % (len(rebuilt), np.nanmax(diff)))

warnings, errors, lost = run(write("ridge_surface_sum.step", surface, "(4,3),(2,2),(0.,1.),(-4.,0.)"))
check(len(errors) == 1 and "ridge_surface_sum.step" in errors[0] and "holds no closed solid" in errors[0]
      and "The likely cause: #31 (line 49), a B-spline surface: its u knot multiplicities add up to 7" in errors[0],
      "one error naming the file and the surface: %s" % errors)
check(lost.size == 0, "no thickness from the refused file")
finish()
