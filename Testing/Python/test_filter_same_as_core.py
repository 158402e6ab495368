"""The filter solves the model the reader converted: in pvpython, STEP reader -> BRepThickness
(native device) gives every sample the same 2t as the core library run on the same file
(brt_thickness_bench --device none --counts 0 --values, which converts it with the same
defaults). The model reaches the filter through the reader's field data (docs/DataContract.md);
a field lost on the way changes the solve where it matters: the face degrees (FaceDegrees) tell
the certification where a face's patches are its surface, which Data/cubic_ridge.step's faces
are (every one a polynomial B-spline) and the unseen cover's extruded cubics are.

Usage: pvpython test_filter_same_as_core.py PLUGIN_FILE BENCH WORK_DIR MODEL...
"""
import math
import os
import subprocess
import sys

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager as sm

from brt_checks import check, finish

plugin, bench, work = sys.argv[1], sys.argv[2], sys.argv[3]
models = sys.argv[4:]
LoadPlugin(plugin, ns=globals())
os.makedirs(work, exist_ok=True)

for path in models:
    name = os.path.basename(path)
    out = subprocess.run([bench, "--device", "none", "--counts", "0", "--values", work, path],
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    check(out.returncode == 0, "%s: the bench ran%s" % (name, "" if out.returncode == 0 else ":\n" + out.stdout[-2000:]))
    with open(os.path.join(work, os.path.splitext(name)[0] + ".txt")) as f:
        core = [float(x) for x in f]
    reader = STEPReader(FileName=path)
    flt = BRepThickness(Input=reader, Device="native")
    mesh = sm.Fetch(flt, idx=0)
    arr = mesh.GetPointData().GetArray("Thickness")
    ours = [arr.GetValue(i) for i in range(arr.GetNumberOfTuples())]
    check(len(ours) == len(core) and len(core) > 0,
          "%s: one 2t per sample (%d filter, %d core)" % (name, len(ours), len(core)))
    differ, worst, first = 0, 0.0, None
    for i, (a, b) in enumerate(zip(ours, core)):
        if math.isnan(a) or math.isnan(b):
            same = math.isnan(a) and math.isnan(b)
            rel = 0.0 if same else math.inf
        else:
            rel = abs(a - b) / max(abs(b), 1e-300)
        if rel > 1e-9:
            differ += 1
            first = first if first is not None else (i, a, b)
        worst = max(worst, rel)
    print("[same as core] %-40s %6d samples, %d differ by more than 1e-9 relative, largest %.2e%s"
          % (name, len(core), differ, worst,
             "" if first is None else " (first: sample %d, filter %.9g, core %.9g)" % first))
    check(differ == 0, "%s: the filter's 2t is the core's on every sample (%d differ)" % (name, differ))
    Delete(flt)
    Delete(reader)

finish()
