"""The filter's Clearance property, in pvpython, on the hole plate (6 mm, convex edges all round).

Usage: pvpython test_filter_clearance.py PLUGIN_FILE HOLE_PLATE_STEP

A sample next to a convex edge has a sphere touching the face across the edge. With the
clearance delta, what lies less than delta inside a sphere does not limit it, so there the
thickness does not drop below about delta (docs/Solver.md, step 0); delta = 0 is the paper's
eq. 1. Checked for the native device and the first OpenCL device in float ("any"), changing the property on one filter
(the solve cache must see it): the thinnest sample grows with the clearance, reads about the
clearance at 0.01 mm, and the plate's 6 mm away from the edges does not move.
"""
import sys

import numpy as np
from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager as sm
from vtkmodules.numpy_interface import dataset_adapter as dsa

from brt_checks import check, finish

plugin, model = sys.argv[1], sys.argv[2]
LoadPlugin(plugin, ns=globals())


reader = STEPReader(FileName=model)
for device in ("native", "any"):
    f = BRepThickness(Input=reader, Device=device)
    low = {}
    for clearance in (0.0, -1.0, 0.01):
        f.Clearance = clearance
        f.UpdatePipeline()
        mesh = dsa.WrapDataObject(sm.Fetch(f, idx=0))
        T = np.asarray(mesh.PointData["Thickness"])
        failed = int(np.isnan(T).sum())
        low[clearance] = float(np.nanmin(T))
        median = float(np.nanmedian(T))
        print("%-9s clearance %5g: min 2t %.6g mm, median %.9g mm, %d failed of %d"
              % (device, clearance, low[clearance], median, failed, len(T)))
        check(failed == 0, "%s, clearance %g: %d failed samples" % (device, clearance, failed))
        check(abs(median - 6.0) <= 6e-6, "%s, clearance %g: median %.9g, not 6" % (device, clearance, median))
    check(low[0.0] < low[-1.0] < low[0.01],
          "%s: thinnest sample does not grow with the clearance: %s" % (device, low))
    check(0.005 <= low[0.01] <= 0.02, "%s: thinnest sample %.4g mm at clearance 0.01" % (device, low[0.01]))
    Delete(f)

finish("clearance checks passed")
