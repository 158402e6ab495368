"""The filter where no OpenCL platform exists (run with OCL_ICD_VENDORS set to an empty folder).

Usage: OCL_ICD_VENDORS=/empty pvpython test_filter_no_opencl.py PLUGIN_FILE MODEL.step

- Device "auto": no OpenCL GPU, so the native CPU device solves (the same solver source in
  double on every core: nothing is lost, so no warning); the Summary's Device says so and the
  thickness map is complete.
- Device "gpu": an error naming the device and the problem, empty outputs, no crash.
"""
import sys

import paraview.simple as simple
from paraview import servermanager as sm
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.vtkConstants import VTK_STRING

plugin, model = sys.argv[1], sys.argv[2]
simple.LoadPlugin(plugin)
reader = simple.STEPReader(FileName=model)
failures = []

events = []


@calldata_type(VTK_STRING)
def on_event(obj, event, message):
    events.append((event, message))


def run(device):
    del events[:]
    f = simple.BRepThickness(Input=reader, Device=device)
    algo = f.GetClientSideObject()
    algo.AddObserver("ErrorEvent", on_event)
    algo.AddObserver("WarningEvent", on_event)
    f.UpdatePipeline()
    return f


# auto -> native, no warning
f = run("auto")
warnings = [m for e, m in events if e == "WarningEvent"]
errors = [m for e, m in events if e == "ErrorEvent"]
out = sm.Fetch(f, idx=0)
summary = sm.Fetch(f, idx=3)
device = summary.GetFieldData().GetAbstractArray("Device").GetValue(0)
n = out.GetNumberOfPoints()
thickness = out.GetPointData().GetArray("Thickness")
print("auto: %d points, device '%s', %d warning(s), %d error(s)" % (n, device, len(warnings), len(errors)))
for w in warnings:
    print("  warning: " + w.strip().splitlines()[-1])
if errors:
    failures.append("auto: unexpected errors %s" % errors)
if warnings:
    failures.append("auto: expected no warning, got %s" % warnings)
if not device.startswith("native CPU (double"):
    failures.append("auto: Summary Device is '%s', expected the native CPU device" % device)
if n == 0 or thickness is None or thickness.GetNumberOfTuples() != n:
    failures.append("auto: no thickness map")
simple.Delete(f)

# an explicit OpenCL device -> error, empty output
f = run("gpu")
errors = [m for e, m in events if e == "ErrorEvent"]
out = sm.Fetch(f, idx=0)
print("gpu: %d points, %d error(s)" % (out.GetNumberOfPoints(), len(errors)))
for e in errors:
    print("  error: " + " | ".join(e.strip().splitlines()[1:]))
if len(errors) != 1 or "Device 'gpu'" not in errors[0]:
    failures.append("gpu: expected one error naming device 'gpu', got %s" % errors)
if out.GetNumberOfPoints() != 0:
    failures.append("gpu: the output should be empty, has %d points" % out.GetNumberOfPoints())

for msg in failures:
    print("FAIL: " + msg)
sys.exit(1 if failures else 0)
