"""The mutation corpus through the ParaView reader in one pvpython session: every file either
reads (a mesh, no error) or gives exactly one error naming it and an empty output; the session
never crashes or hangs. Then a file that crashes OpenCASCADE, and after it a good file in the
same session, read and measured.

Usage: pvpython test_reader_corpus.py PLUGIN_FILE CORPUS_DIR REGRESSION_DIR CRASHING_FILE GOOD_FILE
"""
import glob
import os
import sys
import time

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager as sm
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.vtkConstants import VTK_STRING

LoadPlugin(sys.argv[1], ns=globals())
corpus, regressions, crashing, good = sys.argv[2:6]


def read(path, time_limit=60.0):
    reader = STEPReader(FileName=path, TimeLimit=time_limit)
    messages = []

    @calldata_type(VTK_STRING)
    def on_error(obj, event, message, messages=messages):
        messages.append(message)

    reader.GetClientSideObject().AddObserver("ErrorEvent", on_error)
    t0 = time.time()
    reader.UpdatePipeline()
    seconds = time.time() - t0
    out = sm.Fetch(reader)
    return reader, out, messages, seconds


files = sorted(glob.glob(os.path.join(corpus, "*.step"))) + sorted(glob.glob(os.path.join(regressions, "*.step")))
if len(files) < 500:
    print("FAIL: only %d corpus files (run the corpus fixture first)" % len(files))
    sys.exit(1)
failures = []
counts = {"read": 0, "error": 0}
slowest = 0.0
t_all = time.time()
for path in files:
    reader, out, messages, seconds = read(path)
    slowest = max(slowest, seconds)
    if messages:
        counts["error"] += 1
        if len(messages) != 1 or path not in messages[0]:
            failures.append("%s: %d messages, first: %s" % (path, len(messages), messages[0][:200]))
        if out.GetNumberOfPoints() != 0:
            failures.append("%s: error but partial output" % path)
    else:
        counts["read"] += 1
        if out.GetNumberOfPoints() == 0:
            failures.append("%s: no error and no output" % path)
    Delete(reader)
print("[corpus] %d files in %.0f s: %d read, %d clear errors, slowest %.1f s"
      % (len(files), time.time() - t_all, counts["read"], counts["error"], slowest))

# A file that crashes OpenCASCADE in-process (the text check stops it before OpenCASCADE), then
# a worker that really crashes (a stand-in that kills itself with SIGSEGV, through
# BRT_STEP_WORKER), then a good file measured in the same session.
reader, out, messages, seconds = read(crashing)
print("[crashing file] %.2f s: %s" % (seconds, " | ".join(m.strip() for m in messages)))
if len(messages) != 1 or crashing not in messages[0]:
    failures.append("crashing file: expected one error naming it, got %r" % messages)
Delete(reader)
stand_in = os.path.join(os.environ.get("TMPDIR", "/tmp"), "brt-segv-worker-%d.sh" % os.getpid())
with open(stand_in, "w") as f:
    f.write("#!/bin/sh\nkill -SEGV $$\n")
os.chmod(stand_in, 0o755)
os.environ["BRT_STEP_WORKER"] = stand_in
reader, out, messages, seconds = read(good)
del os.environ["BRT_STEP_WORKER"]
os.remove(stand_in)
print("[worker crash] %.2f s: %s" % (seconds, " | ".join(m.strip() for m in messages)))
if len(messages) != 1 or "crashed" not in messages[0] or good not in messages[0]:
    failures.append("crashing worker: expected one 'crashed' error naming the file, got %r" % messages)
Delete(reader)
reader, out, messages, seconds = read(good)
if messages or out.GetNumberOfPoints() == 0:
    failures.append("good file after the crash: %r" % messages)
else:
    thick = BRepThickness(Input=reader, Device="native")
    result = sm.Fetch(thick)
    arr = result.GetPointData().GetArray("Thickness")
    lo, hi = arr.GetRange()
    print("[after crash] %s: %d samples, thickness %.4f .. %.4f" % (os.path.basename(good), arr.GetNumberOfTuples(), lo, hi))
    if not (arr.GetNumberOfTuples() > 1000 and 0 <= lo <= hi < 1e3):
        failures.append("good file after the crash: implausible thickness range %g .. %g" % (lo, hi))
for f in failures:
    print("FAIL", f)
sys.exit(1 if failures else 0)
