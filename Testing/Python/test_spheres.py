"""B-Rep Maximal Spheres on the hole plate (80 x 80 x 6, hole r 10 at the centre): the spheres of
top-face samples away from every edge are the closed form (radius 3, centre 3 below the sample,
contact straight below on the bottom face), chosen by SampleIds and by a point selection. At the reader's default tolerance (1e-4 mm) the
solved spheres are within 1e-5 mm of the closed form.

    pvpython test_spheres.py PLUGIN hole_plate.step
"""
import math
import sys

import numpy as np
from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager as sm
from vtkmodules.numpy_interface import dataset_adapter as dsa

from brt_checks import check, finish

plugin, model = sys.argv[1], sys.argv[2]
LoadPlugin(plugin, ns=globals())


reader = STEPReader(FileName=model)
f = BRepThickness(Input=reader, Device="native")
f.UpdatePipeline()
mesh = dsa.WrapDataObject(sm.Fetch(f, idx=0))
pts = np.asarray(mesh.Points)
normals = np.asarray(mesh.PointData["Normals"])
# Top-face samples at least 4 mm from the outer edges and from the hole's edge.
r = np.hypot(pts[:, 0] - 40, pts[:, 1] - 40)
inner = ((normals[:, 2] > 0.999) & (pts[:, 0] > 4) & (pts[:, 0] < 76) & (pts[:, 1] > 4)
         & (pts[:, 1] < 76) & (r > 14))
ids = [int(i) for i in np.flatnonzero(inner)[[0, 7, 31]]]
print("samples %s" % ids)


def spheres_of(proxy):
    out = dsa.WrapDataObject(sm.Fetch(proxy))
    return out, np.asarray(out.CellData["Part"]), np.asarray(out.CellData["SampleId"])


def check_closed_form(label, proxy, expected_ids):
    out, part, sid = spheres_of(proxy)
    check(sorted(set(sid.tolist())) == sorted(expected_ids), "%s: the spheres of samples %s" % (label, sorted(expected_ids)))
    check(int((part == 1).sum()) == len(expected_ids), "%s: one segment O-M-P per sample" % label)
    poly = out.VTKObject
    for c in range(poly.GetNumberOfCells()):
        cell_ids = poly.GetCell(c).GetPointIds()
        P = np.array([poly.GetPoint(cell_ids.GetId(k)) for k in range(cell_ids.GetNumberOfIds())])
        s = int(sid[c])
        O = pts[s]
        if part[c] == 1:  # O, M = O - 3 z, P = O - 6 z
            want = np.array([O, O - [0, 0, 3], O - [0, 0, 6]])
            if not np.allclose(P, want, rtol=0, atol=1e-5):
                check(False, "%s: segment of sample %d is %s, expected %s" % (label, s, P.tolist(), want.tolist()))
                return
        elif part[c] == 0:  # the sphere's surface: radius 3 about M
            d = np.linalg.norm(P - (O - [0, 0, 3]), axis=1)
            if np.max(np.abs(d - 3.0)) > 1e-5:
                check(False, "%s: sphere of sample %d off by %.2e" % (label, s, np.max(np.abs(d - 3.0))))
                return
    thick = np.asarray(out.CellData["Thickness"])
    check(np.allclose(thick, 6.0, rtol=1e-6), "%s: Thickness 6 on every cell (%.9g .. %.9g)" % (label, thick.min(), thick.max()))
    check(True, "%s: segments O-M-P and sphere surfaces at the closed form within 1e-5 mm" % label)


by_id = BRepMaximalSpheres(Input=f, SampleIds=ids, SphereResolution=16)
by_id.UpdatePipeline()
check_closed_form("SampleIds", by_id, ids)

# A point selection, as ParaView's Select Points gives it: (process, id) pairs.
selection = IDSelectionSource(IDs=sum(([0, i] for i in ids[:2]), []), FieldType="POINT")
by_selection = BRepMaximalSpheres(Input=f, Selection=selection, SphereResolution=16)
by_selection.UpdatePipeline()
check_closed_form("selection", by_selection, ids[:2])

finish("maximal spheres passed")
