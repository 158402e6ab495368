#!/usr/bin/env python3
"""Side-by-side comparison of BRepThickness with the mesh tools users know: trimesh's
max_sphere and ray thickness, MeshLib's in-sphere and ray thickness.

  python3 Utilities/compare_mesh_tools.py MODEL.step [MODEL.step ...] [--trimesh-samples N] [--gap]
                                         [--repeat N]

For each model, pvpython with the built plugin reads the STEP file, solves it with the native CPU
device (the solver's source compiled for the CPU, double: the reference) and with the OpenCL CPU
device in float (PoCL; its finish in double on the device) and in double (the same source, which
PoCL vectorises across samples), and writes the display mesh (the samples are
its vertices) and the exact thicknesses to an .npz. A private virtual environment
(build/compare-venv, made on first use with pip from PyPI: numpy, scipy, trimesh, rtree, meshlib; never
a dependency of the build or the tests) then runs the mesh tools on the same mesh, welded as an
STL user would have it. Printed per tool: samples/s, and the error against the exact values on
the samples inside faces (vertices of one face only: at face boundaries the welded mesh has one
normal where the B-Rep has two): median, 99th percentile and maximum of |T - T_exact|, and the
share within 1e-4 mm. The exact values are the native device's; failed samples are left out.
Rows marked (*) measure another quantity, the ray thickness along the sample's normal, against
the same exact sphere values: ours (Method Ray, native device; exact on the B-Rep) is timed and
listed beside the tools' rays, and the row "MeshLib ray vs ours" gives MeshLib's ray error
against our exact ray (the samples where ours meets a face).
A model that cannot be read, or whose mesh tools are stopped (a tool killed for memory on a large
mesh), gets one line saying so and the next model runs; the exit status is then 1.
Ours is timed for the solve alone (the Summary's SolveSeconds); the row "native + prep." adds
the preparation (PrepareSeconds: s1, the trees, the samples, the packing), the counterpart of the
tree MeshLib builds inside its timed call. Samples on open or non-manifold solids are flagged
without a solve (their count is printed with the model's counts) and count in our samples/s, as
every vertex counts in the tools'. After each model's rows, MeshLib's in-sphere rate over our
fastest (the issue's target: at most 0.5).

--repeat N runs each timed solve N times, ours and MeshLib's alike, and keeps the fastest (trimesh,
slow and single-threaded, runs once): on a shared machine one run can be a third off.

--gap adds the exterior gap (the air between walls): ours (Measure "Thickness and gap", native
device; the gap's time is the difference of the two solves' SolveSeconds) against trimesh's
exterior max_sphere and MeshLib's in-sphere on the mesh turned inside out (its maximum radius
the model's diagonal). Printed per tool: the error on the face-interior samples where ours is
finite, and how often the tool agrees that a gap is infinite (ours: no wall faces the sample;
a tool: no value, or a diameter beyond the model's diagonal).
"""
import argparse
import os
import re
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

EXPORT = r'''
import sys, numpy as np
from paraview.simple import *
from paraview import servermanager as sm
from vtkmodules.numpy_interface import dataset_adapter as dsa
LoadPlugin(sys.argv[1], ns=globals())
model, out, gap, repeat = sys.argv[2], sys.argv[3], sys.argv[4] == "1", int(sys.argv[5])
reader = STEPReader(FileName=model)
def solve_once(device, measure, precision, method="Sphere"):
    f = BRepThickness(Input=reader, Device=device, Precision=precision, Measure=measure, Method=method)
    f.UpdatePipeline()
    mesh = dsa.WrapDataObject(sm.Fetch(f, idx=0))
    summary = sm.Fetch(f, idx=3)
    rows = {summary.GetValue(r, 0).ToString(): summary.GetValue(r, 1).ToDouble() for r in range(summary.GetNumberOfRows())}
    name = device
    for port in (0, 3):
        dev = sm.Fetch(f, idx=port).GetFieldData().GetAbstractArray("Device")
        if dev is not None and dev.GetNumberOfValues() > 0:
            name = dev.GetValue(0)
    Delete(f)
    return mesh, rows, name
def solve(device, measure="Thickness", precision=None, method="Sphere"):
    # The first run's mesh and names, each timing the fastest of `repeat` runs.
    if precision is None:
        precision = "Double" if device == "native" else "Float"
    mesh, rows, name = solve_once(device, measure, precision, method)
    for _ in range(repeat - 1):
        if mesh.VTKObject.GetNumberOfPoints() == 0:
            break
        again = solve_once(device, measure, precision, method)[1]
        for key in ("SolveSeconds", "PrepareSeconds"):
            rows[key] = min(rows[key], again[key])
    return mesh, rows, name
mesh, rows_ref, _ = solve("native")
if mesh.VTKObject.GetNumberOfPoints() == 0:
    sys.exit(1)  # the reader's or the filter's error is on stderr
_, rows_dev, dev_name = solve("cpu")
_, rows_dev2, _ = solve("cpu", precision="Double")
# Our ray thickness alone (Method Ray, native device): the counterpart of the tools' rays.
rmesh, rows_ray, _ = solve("native", method="Ray")
extra = {}
if rmesh.VTKObject.GetNumberOfPoints() == mesh.VTKObject.GetNumberOfPoints():
    # (The same display mesh, so the same samples; otherwise the ray's rows are left out.)
    extra = dict(ray=np.asarray(rmesh.PointData["RayThickness"]), ray_seconds=rows_ray["SolveSeconds"])
if gap:
    gmesh, rows_gap, _ = solve("native", "Thickness and gap")
    extra.update(gap=np.asarray(gmesh.PointData["Gap"]),
                 gap_seconds=rows_gap["SolveSeconds"] - rows_ref["SolveSeconds"])
polys = dsa.vtkDataArrayToVTKArray(mesh.VTKObject.GetPolys().GetConnectivityArray())
np.savez(out, **extra, points=np.asarray(mesh.Points), triangles=np.asarray(polys).reshape(-1, 3),
         normals=np.asarray(mesh.PointData["Normals"]), face=np.asarray(mesh.PointData["FaceId"]),
         thickness=np.asarray(mesh.PointData["Thickness"]), contact=np.asarray(mesh.PointData["ContactType"]),
         reason=np.asarray(mesh.PointData["FailReason"]),
         ref_seconds=rows_ref["SolveSeconds"], ref_prepare=rows_ref["PrepareSeconds"],
         dev_seconds=rows_dev["SolveSeconds"],
         dev2_seconds=rows_dev2["SolveSeconds"], dev_name=dev_name)
'''


def venv_python(build):
    venv = os.path.join(build, "compare-venv")
    py = os.path.join(venv, "bin", "python")
    if not os.path.exists(py):
        subprocess.check_call([sys.executable, "-m", "venv", venv])
        subprocess.check_call([py, "-m", "pip", "install", "-q", "numpy", "scipy", "trimesh", "rtree", "meshlib"])
    return py


def tools(npz, trimesh_samples, repeat=1, seed=1):
    """Runs inside the venv: the mesh tools on the exported mesh."""
    import numpy as np
    import trimesh
    import meshlib.mrmeshpy as mr
    import meshlib.mrmeshnumpy as mn

    d = np.load(npz)
    P, tri, N, face = d["points"], d["triangles"], d["normals"], d["face"]
    exact = d["thickness"]
    # Weld coincident vertices (one vertex per position, as in an STL), remembering how many
    # faces' vertices each welded vertex carries.
    key = np.round(P / 1e-9).astype(np.int64)
    uniq, first, inverse, counts = np.unique(key, axis=0, return_index=True, return_inverse=True, return_counts=True)
    inverse = inverse.reshape(-1)
    W = P[first]
    wtri = inverse[tri]
    interior = (counts[inverse] == 1) & np.isfinite(exact)
    n_w = len(W)
    # Samples on open or non-manifold solids (FailReason 8, 9) are flagged without a solve; they
    # count in our samples/s as in the tools' (which measure every vertex).
    unsolved = int(np.isin(d["reason"], (8, 9)).sum()) if "reason" in d else 0
    print("COUNTS\t%d\t%d\t%d\t%s\t%d" % (len(P), n_w, interior.sum(), str(d["dev_name"]), unsolved), flush=True)

    def emit(row):
        # Each row as soon as it is measured: a tool that dies later (memory) leaves the rows
        # before it.
        print("ROW\t%s\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g" % row, flush=True)

    def report(name, values, seconds, computed, idx):
        """values: per original vertex; computed: how many points the tool ran on; idx: the
        face-interior samples the error is taken over."""
        v, e = values[idx], exact[idx]
        ok = np.isfinite(v) & (v < 1e30)
        err = np.abs(v[ok] - e[ok])
        emit((name, computed / seconds, np.median(err), np.percentile(err, 99), err.max(),
              np.mean(err <= 1e-4), 1.0 - ok.mean()))

    all_idx = np.nonzero(interior)[0]
    rng = np.random.default_rng(seed)
    sub = np.sort(rng.choice(all_idx, size=min(trimesh_samples, len(all_idx)), replace=False))

    # MeshLib (its own threads), on every welded vertex.
    m = mn.meshFromFacesVerts(wtri.astype(np.int32), W.astype(np.float32))
    settings = mr.InSphereSearchSettings()
    # The default maxRadius (1) caps the diameter at 2 model units: lift it to the model's size.
    settings.maxRadius = float(np.linalg.norm(W.max(axis=0) - W.min(axis=0)))
    t_ins = t_ray = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        ins = mr.computeInSphereThicknessAtVertices(m, settings)
        t_ins = min(t_ins, time.perf_counter() - t0)
    ins = np.fromiter(ins.vec, dtype=float, count=n_w)
    for _ in range(repeat):
        t0 = time.perf_counter()
        ray = mr.computeRayThicknessAtVertices(m)
        t_ray = min(t_ray, time.perf_counter() - t0)
    ray = np.fromiter(ray.vec, dtype=float, count=n_w)
    report("MeshLib in-sphere", ins[inverse], t_ins, n_w, all_idx)
    report("MeshLib ray (*)", ray[inverse], t_ray, n_w, all_idx)
    if "ray" in d:
        # Ours along the same normals (exact, on the B-Rep), and MeshLib's rays against it: the
        # error of the tool's ray where ours met a face.
        ours_ray = np.asarray(d["ray"], dtype=float)
        report("ours, ray native (*)", ours_ray, float(d["ray_seconds"]), len(P), all_idx)
        hit = all_idx[np.isfinite(ours_ray[all_idx])]
        v = ray[inverse][hit]
        ok = np.isfinite(v) & (v < 1e30)
        err = np.abs(v[ok] - ours_ray[hit][ok])
        if len(err):
            emit(("MeshLib ray vs ours", len(W) / t_ray, np.median(err), np.percentile(err, 99), err.max(),
                  np.mean(err <= 1e-4), 1.0 - ok.mean()))

    # trimesh (single-threaded), on a random subset of the face-interior samples.
    tm = trimesh.Trimesh(W, wtri, process=False)
    for method in ("max_sphere", "ray"):
        t0 = time.perf_counter()
        th = trimesh.proximity.thickness(tm, P[sub], exterior=False, normals=N[sub], method=method)
        sec = time.perf_counter() - t0
        full = np.full(len(P), np.nan)
        full[sub] = th
        report("trimesh %s" % ("max_sphere" if method == "max_sphere" else "ray (*)"), full, sec, len(sub), sub)
    if "gap" in d:
        # The exterior gap: ours against the tools' exterior in-spheres, on the face-interior
        # samples; a value beyond the model's diagonal (or none) counts as infinite.
        exact_gap = d["gap"]
        diag = float(np.linalg.norm(W.max(axis=0) - W.min(axis=0)))
        ours_inf = ~np.isfinite(exact_gap)

        def report_gap(name, values, seconds, computed, idx):
            v = values[idx]
            tool_inf = ~np.isfinite(v) | (v >= 2 * diag * 0.999)
            both = idx[~ours_inf[idx] & ~tool_inf]
            err = np.abs(values[both] - exact_gap[both])
            agree_inf = np.mean(tool_inf == ours_inf[idx])
            emit(("gap: " + name, computed / seconds, np.median(err) if len(err) else np.nan,
                  np.percentile(err, 99) if len(err) else np.nan, err.max() if len(err) else np.nan,
                  np.mean(err <= 1e-4) if len(err) else np.nan, 1.0 - agree_inf))

        emit(("gap: ours, native CPU", len(P) / max(float(d["gap_seconds"]), 1e-9), 0.0, 0.0, 0.0, 1.0, 0.0))
        mo = mn.meshFromFacesVerts(wtri[:, ::-1].astype(np.int32), W.astype(np.float32))  # inside out
        settings = mr.InSphereSearchSettings()
        settings.maxRadius = diag
        t0 = time.perf_counter()
        ext = mr.computeInSphereThicknessAtVertices(mo, settings)
        t_ext = time.perf_counter() - t0
        ext = np.fromiter(ext.vec, dtype=float, count=n_w)
        report_gap("MeshLib in-sphere", ext[inverse], t_ext, n_w, all_idx)
        t0 = time.perf_counter()
        th = trimesh.proximity.thickness(tm, P[sub], exterior=True, normals=N[sub], method="max_sphere")
        sec = time.perf_counter() - t0
        full = np.full(len(P), np.nan)
        full[sub] = th
        report_gap("trimesh max_sphere", full, sec, len(sub), sub)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("models", nargs="+")
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--trimesh-samples", type=int, default=2000)
    ap.add_argument("--gap", action="store_true", help="also the exterior gap against the tools' exterior in-spheres")
    ap.add_argument("--repeat", type=int, default=1,
                    help="run each timed solve (ours, MeshLib's) this many times and keep the fastest")
    ap.add_argument("--phase", default="all", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.repeat < 1:
        ap.error("--repeat must be at least 1")
    if args.phase == "tools":
        import numpy as np
        d = np.load(args.models[0])
        n = len(d["points"])
        print("OURS\t%.6g\t%.6g\t%.6g\t%.6g" % (n / float(d["ref_seconds"]), n / float(d["dev_seconds"]),
                                                n / float(d["dev2_seconds"]),
                                                n / (float(d["ref_seconds"]) + float(d["ref_prepare"]))),
              flush=True)
        tools(args.models[0], args.trimesh_samples, args.repeat)
        return 0
    plugin = os.path.join(args.build, "lib", "paraview-plugins", "BRepThickness", "BRepThickness.so")
    if not os.path.exists(plugin):
        sys.exit("error: plugin '%s' not built (bash Utilities/run-tests.sh or cmake --build build)" % plugin)
    py = venv_python(args.build)
    work = os.path.join(args.build, "compare")
    os.makedirs(work, exist_ok=True)
    script = os.path.join(work, "export.py")
    with open(script, "w") as f:
        f.write(EXPORT)
    print("%-34s %-22s %12s %12s %12s %12s %10s %8s" % ("model", "tool", "samples/s", "median_err", "p99_err",
                                                          "max_err", "<=1e-4mm", "no_value"))
    incomplete = 0  # models not compared, or whose tools stopped: the exit status says so
    for model in args.models:
        name = os.path.basename(model)
        npz = os.path.join(work, os.path.splitext(name)[0] + ".npz")
        export = subprocess.run(["pvpython", script, plugin, os.path.abspath(model), npz, "1" if args.gap else "0",
                                 str(args.repeat)],
                                stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if export.returncode != 0:
            # The reader's or the filter's error names the file and the problem (VTK's error
            # lines carry "ERR|", colour codes and the object's address before it).
            errors = [re.sub(r"\x1b\[[0-9;]*m", "", l) for l in export.stderr.splitlines() if "ERR|" in l]
            why = errors[0].split("): ", 1)[-1].strip() if errors else "exit status %d" % export.returncode
            print("%-34s   not compared: %s" % (name, why))
            sys.stdout.flush()
            incomplete += 1
            continue
        run = subprocess.run([py, os.path.abspath(__file__), npz, "--phase", "tools",
                              "--trimesh-samples", str(args.trimesh_samples), "--repeat", str(args.repeat)],
                             stdout=subprocess.PIPE, text=True)
        lines = run.stdout.splitlines()
        ours_best, meshlib = 0.0, 0.0
        # The counts come first from the tools' phase; printed last, after the rows.
        counts = [l for l in lines if l.startswith("COUNTS\t")]
        for line in [l for l in lines if not l.startswith("COUNTS\t")] + counts:
            p = line.split("\t")
            if p[0] == "OURS":
                ours_best = max(float(p[1]), float(p[2]), float(p[3]))
                print("%-34s %-22s %12.0f %12s" % (name, "ours, native CPU", float(p[1]), "(exact)"))
                print("%-34s %-22s %12.0f" % (name, "ours, OpenCL CPU float", float(p[2])))
                print("%-34s %-22s %12.0f" % (name, "ours, OpenCL CPU double", float(p[3])))
                print("%-34s %-22s %12.0f" % (name, "ours, native + prep.", float(p[4])))
            elif p[0] == "ROW":
                if p[1] == "MeshLib in-sphere":
                    meshlib = float(p[2])
                print("%-34s %-22s %12.0f %12.3g %12.3g %12.3g %9.1f%% %7.1f%%" % (
                    name, p[1], float(p[2]), float(p[3]), float(p[4]), float(p[5]), 100 * float(p[6]), 100 * float(p[7])))
            elif p[0] == "COUNTS":
                print("%-34s   samples %s, welded vertices %s, face-interior samples compared %s; OpenCL CPU device: %s"
                      % (name, p[1], p[2], p[3], p[4]))
                if len(p) > 5 and int(p[5]) > 0:
                    print("%-34s   %s samples on open or non-manifold solids flagged without a solve (counted in "
                          "our samples/s, as every vertex is in the tools')" % (name, p[5]))
                if ours_best > 0 and meshlib > 0:
                    print("%-34s   MeshLib in-sphere / our fastest: %.2f (target: at most 0.5; timings the "
                          "fastest of %d)" % (name, meshlib / ours_best, args.repeat))
        if run.returncode != 0:
            # A tool that runs out of memory on a large mesh is killed by the system: the rows
            # before it stand, the model's comparison ends there and the next model is run.
            why = ("killed by signal %d (out of memory, most likely)" % -run.returncode if run.returncode < 0
                   else "exit status %d" % run.returncode)
            print("%-34s   the mesh tools' run stopped: %s; the tools after the last row above gave no figures"
                  % (name, why))
            incomplete += 1
        sys.stdout.flush()
    if args.gap:
        print("gap rows: the error over the face-interior samples where ours is finite and the tool gives a "
              "value; the last column is the share where the tool and ours disagree whether the gap is "
              "infinite.")
    print("(*) ray thickness: the distance along the inward normal to the opposite wall, a different "
          "measure; its error against the sphere diameter shows how far the two differ.")
    return 1 if incomplete else 0


if __name__ == "__main__":
    sys.exit(main())
