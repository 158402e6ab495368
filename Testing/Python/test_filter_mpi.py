"""`mpirun -np 2 pvbatch` gives the same arrays as one process.

Usage (driver, any Python with numpy, e.g. pvpython):
    test_filter_mpi.py PLUGIN_FILE MODEL.step WORK_DIR
It runs this script as a worker twice, under `mpirun -np 2 pvbatch` and under a plain `pvbatch`,
and compares every point array of the Thickness and Medial Points ports and the Summary and
Residuals tables (the timing rows excepted). The CPU reference is used: the point arrays and the
counts must be equal bit for bit, the Summary's area sums (added in another order) within 1e-12.
Worker:
    pvbatch test_filter_mpi.py --worker PLUGIN_FILE MODEL.step OUT.npz
"""
import os
import subprocess
import sys

import numpy as np

TIMING_ROWS = ("PrepareSeconds", "SolveSeconds", "SolvingProcesses")


def worker(plugin, model, out):
    import paraview.simple as simple
    from paraview import servermanager as sm
    from vtkmodules.numpy_interface import dataset_adapter as dsa
    from vtkmodules.vtkParallelCore import vtkMultiProcessController

    simple.LoadPlugin(plugin)  # adds the plugin's proxies to paraview.simple
    reader = simple.STEPReader(FileName=model)
    f = simple.BRepThickness(Input=reader, Device="native")
    f.UpdatePipeline()
    arrays = {}
    for port, label in ((0, "thickness"), (1, "medial")):
        d = dsa.WrapDataObject(sm.Fetch(f, idx=port))
        arrays[label + ".Points"] = np.asarray(d.Points)
        for name in d.PointData.keys():
            arrays[label + "." + name] = np.asarray(d.PointData[name])
    summary = sm.Fetch(f, idx=3)
    rows = [(summary.GetValue(r, 0).ToString(), summary.GetValue(r, 1).ToDouble())
            for r in range(summary.GetNumberOfRows())]
    arrays["summary.values"] = np.array([r[1:] for r in rows if r[0] not in TIMING_ROWS])
    arrays["summary.names"] = np.array([r[0] for r in rows if r[0] not in TIMING_ROWS])
    arrays["summary.processes"] = np.array([r[1] for r in rows if r[0] == "SolvingProcesses"])
    for port, label in ((2, "residuals"), (4, "histogram"), (5, "per_solid"), (6, "per_face")):
        t = sm.Fetch(f, idx=port)
        arrays[label] = np.array([[t.GetValue(r, c).ToDouble() for c in range(t.GetNumberOfColumns())]
                                  for r in range(t.GetNumberOfRows())])
    ranks = vtkMultiProcessController.GetGlobalController().GetNumberOfProcesses()
    arrays["ranks"] = np.array([ranks])
    np.savez(out, **arrays)
    print("worker: %d process(es), %d samples" % (ranks, len(arrays["thickness.Thickness"])))


def driver(plugin, model, work):
    os.makedirs(work, exist_ok=True)
    here = os.path.abspath(__file__)
    # pvpython initialises MPI as a singleton: its OMPI_/PMIX_ variables would confuse the mpirun
    # started here, so the children get the environment without them.
    env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "OPAL_", "PRTE_"))}
    env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    one, two = os.path.join(work, "one.npz"), os.path.join(work, "two.npz")
    for path in (one, two):
        if os.path.exists(path):
            os.remove(path)
    mpirun, pvbatch = os.environ.get("BRT_MPIRUN", "mpirun"), os.environ.get("BRT_PVBATCH", "pvbatch")
    runs = [[pvbatch, here, "--worker", plugin, model, one],
            [mpirun, "-np", "2", pvbatch, here, "--worker", plugin, model, two]]
    for cmd in runs:
        print("$ " + " ".join(cmd), flush=True)
        r = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=600)
        print("\n".join(l for l in r.stdout.splitlines() if "INFO|" not in l))
        if r.returncode != 0:
            sys.exit("command failed with status %d" % r.returncode)
    a, b = np.load(one), np.load(two)
    failures = []
    if int(b["ranks"][0]) != 2 or int(a["ranks"][0]) != 1:
        failures.append("process counts %d and %d, expected 1 and 2" % (a["ranks"][0], b["ranks"][0]))
    if int(b["summary.processes"][0]) != 2:
        failures.append("only %d of the 2 processes solved samples" % b["summary.processes"][0])
    for key in sorted(set(a.files) | set(b.files)):
        if key in ("ranks", "summary.processes"):
            continue
        if key not in a.files or key not in b.files:
            failures.append("%s only in one run" % key)
        elif a[key].shape != b[key].shape:
            failures.append("%s: shapes %s and %s" % (key, a[key].shape, b[key].shape))
        elif key in ("summary.values", "histogram", "per_solid", "per_face"):
            # Area sums are added up in another order over two processes: equal to rounding.
            if not np.allclose(a[key], b[key], rtol=1e-12, atol=0, equal_nan=True):
                failures.append("%s: max relative difference %g" % (
                    key, np.nanmax(np.abs(a[key] - b[key]) / np.maximum(np.abs(a[key]), 1e-300))))
        elif a[key].dtype.kind in "fc" and not np.array_equal(a[key], b[key], equal_nan=True):
            failures.append("%s: max difference %g" % (key, np.nanmax(np.abs(a[key] - b[key]))))
        elif a[key].dtype.kind not in "fc" and not np.array_equal(a[key], b[key]):
            failures.append("%s differs" % key)
    print("compared %d arrays of %s: %d samples, 1 process vs 2" % (len(a.files), os.path.basename(model),
                                                                     len(a["thickness.Thickness"])))
    for f in failures:
        print("  FAIL: " + f)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    if sys.argv[1] == "--worker":
        worker(*sys.argv[2:5])
    else:
        driver(*sys.argv[1:4])
