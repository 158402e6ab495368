"""Baseline images: the batch script's thickness map and medial point cloud of a model, rendered
headless, compared with the PNGs in Testing/Data/Baseline.

Usage: run-headless.sh pvpython test_images.py PLUGIN_FILE MODEL.step BASELINE_DIR WORK_DIR

Each image is compared with vtkImageDifference (small shifts allowed, as in VTK's regression
tests); the thresholded error must stay at most 10. With BRT_UPDATE_BASELINES=1 the rendered images
replace the baselines (review them before committing). The CPU reference solves, so the picture
does not depend on the OpenCL device.
"""
import os
import shutil
import sys

plugin, model, baseline_dir, work = sys.argv[1:5]
here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "..", "Utilities"))
import brepthickness_batch  # noqa: E402

from vtkmodules.vtkIOImage import vtkPNGReader  # noqa: E402
from vtkmodules.vtkImagingCore import vtkImageDifference  # noqa: E402

THRESHOLD = 10.0
name = os.path.splitext(os.path.basename(model))[0]
out = os.path.join(work, name)
shutil.rmtree(out, ignore_errors=True)
status = brepthickness_batch.main([model, "--out", out, "--plugin", plugin, "--device", "native",
                                   "--size", "640", "480"])
if status:
    sys.exit("batch script failed with status %s" % status)


def read(path):
    r = vtkPNGReader()
    r.SetFileName(path)
    r.Update()
    return r.GetOutput()


failures = []
for suffix in ("", "-medial"):
    image = os.path.join(out, name + suffix + ".png")
    baseline = os.path.join(baseline_dir, name + suffix + ".png")
    if os.environ.get("BRT_UPDATE_BASELINES") == "1":
        shutil.copyfile(image, baseline)
        print("updated %s" % baseline)
        continue
    if not os.path.exists(baseline):
        failures.append("no baseline %s (rendered image: %s; BRT_UPDATE_BASELINES=1 adds it)" % (baseline, image))
        continue
    diff = vtkImageDifference()
    diff.SetInputData(read(image))
    diff.SetImageData(read(baseline))
    diff.AllowShiftOn()
    diff.AveragingOn()
    diff.Update()
    error = diff.GetThresholdedError()
    print("%s: thresholded error %.3f (limit %.0f) against %s" % (os.path.basename(image), error, THRESHOLD, baseline))
    if error > THRESHOLD:
        failures.append("%s differs from its baseline: error %.3f" % (image, error))
for f in failures:
    print("FAIL: " + f)
sys.exit(1 if failures else 0)
