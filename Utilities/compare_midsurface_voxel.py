#!/usr/bin/env python3
"""Our midsurface against voxel midsurfaces in the spirit of Vertex Climax (Schinko & Ullrich).

  python3 Utilities/compare_midsurface_voxel.py [--pitch P ...] [MODEL.step ...]

For each model pvpython with the built plugin reads the STEP file, solves it (native device) and
builds B-Rep Midsurface; it writes the part's display mesh and the midsurface to an .npz. A private
virtual environment (build/compare-venv, made on first use with pip from PyPI: numpy, scipy,
trimesh, rtree, meshlib, scikit-image; never a dependency of the build or the tests) then
voxelises the part (trimesh: surface voxels, filled) at each pitch and builds two voxel
midsurfaces:
  - skeletonize: scikit-image's 3-D thinning (Lee et al. 1994), the off-the-shelf voxel skeleton;
  - climax: the crest of the Euclidean distance transform, the voxels where its normalised
    gradient converges (divergence below -0.5 per voxel, Siddiqi's average outward flux): the
    ridge Vertex Climax climbs to (its midsurface vertices lie on it).
Each surface is sampled densely (voxel centres; our triangles subdivided to 1/4 of the pitch; the
exact one on a grid of half the pitch) and compared with the exact midsurface of the analytic models (plate.step, tube.step, t_profile.step:
the mid-planes and the mid-cylinder, extended to the outline and to the junction as docs/
Midsurface.md says) by directed distances: "off" = max distance from the surface's samples to the
exact one (how far it strays; with its 95th percentile, the bulk without the corner branches),
"miss" = max distance from the exact one's samples to the surface
(what it leaves out); the Hausdorff distance is the larger. Other models (no closed form) compare
the voxel midsurfaces with ours the same way.
"""
import argparse
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_MODELS = ["Data/plate.step", "Data/tube.step", "Data/t_profile.step",
                  "Data/ExpansionCard_SelfTapping.stp"]

EXPORT = r'''
import sys, numpy as np
from paraview.simple import *
from paraview import servermanager as sm
from vtkmodules.numpy_interface import dataset_adapter as dsa
LoadPlugin(sys.argv[1], ns=globals())
model, out = sys.argv[2], sys.argv[3]
reader = STEPReader(FileName=model)
f = BRepThickness(Input=reader, Device="native")
m = BRepMidsurface(Input=f)
m.UpdatePipeline()
def tri(obj):
    return np.asarray(dsa.vtkDataArrayToVTKArray(obj.GetPolys().GetConnectivityArray())).reshape(-1, 3)
part = sm.Fetch(f, idx=0)
mid = sm.Fetch(m, idx=0)
np.savez(out, points=np.asarray(dsa.WrapDataObject(part).Points), triangles=tri(part),
         mid_points=np.asarray(dsa.WrapDataObject(mid).Points), mid_triangles=tri(mid),
         thickness=np.asarray(dsa.WrapDataObject(part).PointData["Thickness"]))
'''


def venv_python(build):
    venv = os.path.join(build, "compare-venv")
    py = os.path.join(venv, "bin", "python")
    if not os.path.exists(py):
        subprocess.check_call([sys.executable, "-m", "venv", venv])
    try:
        subprocess.check_call([py, "-c", "import numpy, scipy, trimesh, skimage"],
                              stderr=subprocess.DEVNULL)
    except subprocess.CalledProcessError:
        subprocess.check_call([py, "-m", "pip", "install", "-q", "numpy", "scipy", "trimesh", "rtree",
                               "meshlib", "scikit-image"])
    return py


def exact_samples(name, step):
    """Dense samples of the exact midsurface of an analytic model, or None."""
    import numpy as np

    def grid(a0, a1, b0, b1):
        a = np.arange(a0, a1 + step / 2, step)
        b = np.arange(b0, b1 + step / 2, step)
        return np.meshgrid(a, b, indexing="ij")

    if name == "plate":
        x, y = grid(0, 100, 0, 60)
        return np.stack([x.ravel(), y.ravel(), np.full(x.size, 2.5)], 1)
    if name == "tube":
        a, z = grid(0, 2 * np.pi, 0, 80)
        a = a * 17.5  # arc length
        th = a.ravel() / 17.5
        return np.stack([17.5 * np.cos(th), 17.5 * np.sin(th), z.ravel()], 1)
    if name == "t_profile":
        x, z = grid(-40, 40, 0, 30)
        flange = np.stack([x.ravel(), np.full(x.size, -3.0), z.ravel()], 1)
        y, z = grid(-3, 40, 0, 30)
        web = np.stack([np.zeros(y.size), y.ravel(), z.ravel()], 1)
        return np.vstack([flange, web])
    return None


def exact_distance(name, p):
    """Distance from points p to the exact midsurface (plate, tube, T profile)."""
    import numpy as np

    def rect(p, ax, lo, hi, c):  # distance to a rectangle in the plane p[ax] = c
        d = np.abs(p[:, ax] - c) ** 2
        for k in range(3):
            if k != ax:
                d += np.maximum(0, np.maximum(lo[k] - p[:, k], p[:, k] - hi[k])) ** 2
        return np.sqrt(d)

    if name == "plate":
        return rect(p, 2, [0, 0, 0], [100, 60, 0], 2.5)
    if name == "tube":
        r = np.hypot(p[:, 0], p[:, 1])
        dz = np.maximum(0, np.maximum(-p[:, 2], p[:, 2] - 80))
        return np.hypot(r - 17.5, dz)
    if name == "t_profile":
        return np.minimum(rect(p, 1, [-40, 0, 0], [40, 0, 30], -3.0),
                          rect(p, 0, [0, -3, 0], [0, 40, 30], 0.0))
    return None


def sample_triangles(points, triangles, step):
    import numpy as np
    out = [points]
    a, b, c = points[triangles[:, 0]], points[triangles[:, 1]], points[triangles[:, 2]]
    longest = np.max(np.stack([np.linalg.norm(b - a, axis=1), np.linalg.norm(c - b, axis=1),
                               np.linalg.norm(a - c, axis=1)]), axis=0)
    n = np.maximum(1, np.ceil(longest / step).astype(int))
    for k in np.unique(n):
        sel = n == k
        for i in range(k + 1):
            for j in range(k + 1 - i):
                u, v = i / k, j / k
                out.append(a[sel] + u * (b[sel] - a[sel]) + v * (c[sel] - a[sel]))
    return np.vstack(out)


def voxel_phase(npz, name, pitches):
    """Runs inside the venv."""
    import numpy as np
    import trimesh
    from scipy import ndimage
    from scipy.spatial import cKDTree
    from skimage.morphology import skeletonize

    d = np.load(npz)
    mesh = trimesh.Trimesh(d["points"], d["triangles"], process=True)
    mesh.merge_vertices()
    ours = sample_triangles(d["mid_points"], d["mid_triangles"], min(pitches) / 4)
    exact = exact_samples(name, min(pitches) / 2)

    def directed(a, b_tree):
        return float(np.max(b_tree.query(a)[0])) if len(a) else float("nan")

    def p95(x):
        return float(np.percentile(x, 95)) if len(x) else float("nan")

    rows = []

    def compare(label, pts, seconds, surface=None):
        if exact is not None:
            offs = exact_distance(name, pts) if len(pts) else np.zeros(0)
            off = float(np.max(offs)) if len(pts) else float("nan")
            if surface is not None:  # our triangles: the exact distance to them
                miss = float(np.max(surface.nearest.on_surface(exact)[1]))
            else:
                miss = directed(exact, cKDTree(pts)) if len(pts) else float("nan")
            ref = "exact"
        else:
            offs = cKDTree(ours).query(pts)[0] if len(pts) else np.zeros(0)
            off = float(np.max(offs)) if len(pts) else float("nan")
            miss = directed(ours, cKDTree(pts)) if len(pts) else float("nan")
            ref = "ours"
        rows.append((label, ref, len(pts), off, miss, max(off, miss), seconds, p95(offs)))

    compare("ours (B-Rep Midsurface)", ours, float("nan"),
            trimesh.Trimesh(d["mid_points"], d["mid_triangles"], process=False))
    for pitch in pitches:
        t0 = time.time()
        vox = mesh.voxelized(pitch).fill()
        grid = vox.matrix.astype(bool)
        tv = time.time() - t0
        t0 = time.time()
        skel = skeletonize(grid)
        ts = time.time() - t0
        t0 = time.time()
        dist = ndimage.distance_transform_edt(np.pad(grid, 1))[1:-1, 1:-1, 1:-1]
        # The crest of the distance field: where its unit gradient converges (the divergence of
        # the normalised gradient below -0.5 per voxel: the average outward flux of Siddiqi et
        # al.; axis-wise maxima would also take every radial line of a curved wall).
        g = np.array(np.gradient(dist))
        g /= np.maximum(np.linalg.norm(g, axis=0), 1e-12)
        div = sum(np.gradient(g[k], axis=k) for k in range(3))
        ridge = div < -0.5
        ridge &= grid
        tc = time.time() - t0
        to_world = lambda ijk: vox.indices_to_points(np.argwhere(ijk))  # noqa: E731
        compare("skeletonize, pitch %g (%d^3 cells)" % (pitch, max(grid.shape)), to_world(skel), tv + ts)
        compare("climax ridge, pitch %g" % pitch, to_world(ridge), tv + tc)
    for r in rows:
        print("  %-38s vs %-5s %8d pts  off %9.3g (95%% %9.3g)  miss %9.3g  Hausdorff %9.3g  %s"
              % (r[0], r[1], r[2], r[3], r[7], r[4], r[5], "" if r[6] != r[6] else "%.2f s" % r[6]))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("models", nargs="*", default=[os.path.join(ROOT, m) for m in DEFAULT_MODELS])
    ap.add_argument("--pitch", type=float, nargs="+", default=[1.0, 0.5],
                    help="voxel sizes (mm); the T and the plate walls are 4-6 mm thick")
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--phase", default="all")
    ap.add_argument("--name", default="")
    args = ap.parse_args(argv)
    if args.phase == "voxel":
        voxel_phase(args.models[0], args.name, args.pitch)
        return 0
    plugin = os.path.join(args.build, "lib", "paraview-plugins", "BRepThickness", "BRepThickness.so")
    py = venv_python(args.build)
    script = os.path.join(args.build, "compare_midsurface_export.py")
    with open(script, "w") as f:
        f.write(EXPORT)
    for model in args.models:
        name = os.path.splitext(os.path.basename(model))[0]
        npz = os.path.join(args.build, "compare-midsurface-%s.npz" % name)
        subprocess.check_call(["pvpython", script, plugin, os.path.abspath(model), npz],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        print("%s:" % model)
        sys.stdout.flush()
        subprocess.check_call([py, os.path.abspath(__file__), npz, "--phase", "voxel", "--name", name,
                               "--pitch"] + [str(p) for p in args.pitch])
    return 0


if __name__ == "__main__":
    sys.exit(main())
