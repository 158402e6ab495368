"""An assembly of a closed box and an open shell (a box without its top) through the reader and
the filter in pvpython: the reader warns about the open shell, the open shell's samples are
flagged failed with FailReason 8 (OpenShell) and no thickness without being solved, the closed
box is measured, no
value is infinite, and the Summary counts the flagged samples.

Usage: pvpython test_filter_flags.py PLUGIN_FILE OPEN_AND_CLOSED_STEP
"""
import sys

import numpy as np
from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager as sm
from vtkmodules.numpy_interface import dataset_adapter as dsa

from brt_checks import check, finish, messages, table_rows

LoadPlugin(sys.argv[1], ns=globals())


reader = STEPReader(FileName=sys.argv[2])
warnings = messages(reader)
f = BRepThickness(Input=reader, Device="native")
f.UpdatePipeline()
check(any("is open" in w for w in warnings), "the reader warns about the open shell")
mesh = dsa.WrapDataObject(sm.Fetch(f, idx=0))
pd = mesh.PointData
T, ct, reason, solid = pd["Thickness"], pd["ContactType"], pd["FailReason"], pd["SolidId"]
open_solid = solid == 1
check(open_solid.any() and (~open_solid).any(), "samples on both solids")
check(np.all(reason[open_solid] == 8) and np.all(ct[open_solid] == 0), "open shell: every sample failed, FailReason 8")
check(np.all(np.isnan(T[open_solid])), "open shell: no thickness")
check(np.all(pd["Iterations"][open_solid] == 0), "open shell: not solved at all (no iterations)")
solved = ct > 0
check(solved[~open_solid].mean() > 0.5, "closed box: measured (%.1f%% solved)" % (100 * solved[~open_solid].mean()))
check(np.all(np.isfinite(T[solved])) and np.nanmax(T) <= np.sqrt(10 ** 2 * 2 + 2 ** 2), "no infinite or impossible thickness")
summary = sm.Fetch(f, idx=3)
rows = table_rows(summary)
check(int(rows.get("FailedOpenShell", -1)) == int(open_solid.sum()), "Summary FailedOpenShell = %s" % rows.get("FailedOpenShell"))
Delete(f)

# The same on the first OpenCL device, which takes the closed box's samples alone too.
g = BRepThickness(Input=reader, Device="any")
g.UpdatePipeline()
pd = dsa.WrapDataObject(sm.Fetch(g, idx=0)).PointData
check(np.all(pd["FailReason"][open_solid] == 8) and np.all(pd["Iterations"][open_solid] == 0),
      "OpenCL: open shell flagged, not solved")
check((pd["ContactType"][~open_solid] > 0).mean() > 0.5, "OpenCL: closed box measured")
finish()
