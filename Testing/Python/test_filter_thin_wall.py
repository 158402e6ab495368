"""A plate 0.0002 thick (Testing/Data/thin_plate.step: analytic::Plate(2, 1.5, 0.0002) written by
OpenCASCADE's STEP writer) through the reader and the filter at the default tolerance (1e-4): its
wall is thinner than 4 conversion tolerances, below what the conversion resolves. The samples the
solve cannot measure are flagged failed with FailReason 11 (ThinWall), none as Unbounded or
NoOppositePoint; one warning names the count and the remedy; no sample reads thicker than the
wall and 4 tolerances; the Summary counts them (FailedThinWall).

Usage: pvpython test_filter_thin_wall.py PLUGIN_FILE THIN_PLATE_STEP
"""
import sys

import numpy as np
from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager as sm
from vtkmodules.numpy_interface import dataset_adapter as dsa

from brt_checks import check, finish, messages, table_rows

LoadPlugin(sys.argv[1], ns=globals())

reader = STEPReader(FileName=sys.argv[2])
f = BRepThickness(Input=reader, Device="native")
warnings = messages(f)
f.UpdatePipeline()
pd = dsa.WrapDataObject(sm.Fetch(f, idx=0)).PointData
T, ct, reason = pd["Thickness"], pd["ContactType"], pd["FailReason"]
n = len(T)
failed = ct == 0
check(n > 1000, "%d samples" % n)
check(np.all(reason[failed] == 11), "every failed sample ThinWall (reasons %s)" % np.unique(reason[failed]))
check(failed.mean() > 0.5, "most samples flagged (%.1f%%)" % (100 * failed.mean()))
solved = ~failed
check(np.all(T[solved] <= 0.0002 + 4e-4), "no sample thicker than the wall and 4 tolerances (max %.3g)" % np.nanmax(T))
thin = [w for w in warnings if "thinner than 4 times the conversion tolerance" in w]
check(len(thin) == 1 and "smaller Tolerance" in thin[0], "one warning with the remedy (%d warnings)" % len(warnings))
check(not any("FailReason 10" in w for w in warnings), "no Unbounded warning")
rows = table_rows(sm.Fetch(f, idx=3))
check(int(rows.get("FailedThinWall", -1)) == int(failed.sum()), "Summary FailedThinWall = %s" % rows.get("FailedThinWall"))
check(int(rows.get("FailedUnbounded", -1)) == 0, "Summary FailedUnbounded = %s" % rows.get("FailedUnbounded"))
finish()
