"""Bad input through the ParaView reader: one error naming the file and the reason, empty
output, no crash or hang.

Usage: pvpython test_reader_bad_input.py PLUGIN_FILE DATA_DIR FIXTURE_DIR WORK_DIR
"""
import os
import shutil
import sys
import time

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager as sm
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.vtkConstants import VTK_STRING

LoadPlugin(sys.argv[1], ns=globals())
data_dir, fixtures, work = sys.argv[2], sys.argv[3], sys.argv[4]
os.makedirs(work, exist_ok=True)

cases = {}
cases["missing"] = (os.path.join(work, "no-such-file.step"), "does not exist")
empty = os.path.join(work, "empty.step")
open(empty, "w").close()
cases["empty"] = (empty, "empty")
text = os.path.join(work, "letter.stp")
with open(text, "w") as f:
    f.write("Dear reader,\nthis is not a STEP file.\n")
cases["text"] = (text, "ISO-10303-21 header")
with open(os.path.join(data_dir, "l_bracket.step"), "rb") as f:
    content = f.read()
truncated = os.path.join(work, "truncated.step")
with open(truncated, "wb") as f:
    f.write(content[: len(content) // 3])
cases["truncated"] = (truncated, "truncated")
cases["curves only"] = (os.path.join(fixtures, "curves_only.step"), "no solid, shell or face")
directory = os.path.join(work, "a-directory.step")
os.makedirs(directory, exist_ok=True)
cases["directory"] = (directory, "is a directory")
sparse = os.path.join(work, "sparse-2GB.step")
with open(sparse, "wb") as f:
    f.truncate(2 * 1024 ** 3)
cases["2 GB sparse"] = (sparse, "binary data")

failures = []
for label, (path, reason) in cases.items():
    reader = STEPReader(FileName=path)
    algo = reader.GetClientSideObject()
    messages = []

    @calldata_type(VTK_STRING)
    def on_error(obj, event, message, messages=messages):
        messages.append(message)

    algo.AddObserver("ErrorEvent", on_error)
    t0 = time.time()
    reader.UpdatePipeline()
    seconds = time.time() - t0
    output = sm.Fetch(reader)
    n = output.GetNumberOfPoints() + output.GetFieldData().GetNumberOfArrays()
    print("[bad input] %-12s %.3f s: %s" % (label, seconds, " | ".join(m.strip() for m in messages)))
    if n != 0:
        failures.append("%s: partial output passed downstream" % label)
    if len(messages) != 1:
        failures.append("%s: %d error messages, expected exactly one" % (label, len(messages)))
    elif path not in messages[0] or reason not in messages[0]:
        failures.append("%s: message does not name the file and '%s'" % (label, reason))
    Delete(reader)
os.remove(sparse)
shutil.rmtree(directory)
for f in failures:
    print("FAIL", f)
sys.exit(1 if failures else 0)
