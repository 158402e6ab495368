"""B-Rep Midsurface on the plate 100 x 60 x 5, its shell deck, and CalculiX as the deck's consumer.

Usage: pvpython test_midsurface.py PLUGIN_FILE PLATE_STEP WORK_DIR

The midsurface is one sheet at z = 2.5 reaching the outline, Thickness 5; saved as .vtp it reads
back the same; saved as .inp (File > Save Data, CalculiX shell deck) it is run by CalculiX (ccx)
as a simply supported plate under a uniform pressure of 0.01 MPa, and the centre deflection is
compared with the plate's series solution: Reissner-Mindlin (the plate is 12 thicknesses wide, so
shear adds 2.4% to Kirchhoff's). Without ccx the CalculiX part is skipped (exit 77).
"""
import math
import os
import re
import shutil
import subprocess
import sys

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager as sm
from vtkmodules.numpy_interface import dataset_adapter as dsa
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
import numpy as np

from brt_checks import check, failures, finish, table_rows

plugin, model, work = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(work, exist_ok=True)
LoadPlugin(plugin, ns=globals())

reader = STEPReader(FileName=model)
thickness = BRepThickness(Input=reader, Device="native")
mid = BRepMidsurface(Input=thickness)
mid.UpdatePipeline()
rows = table_rows(sm.Fetch(mid, idx=2))
print(rows)
check(rows["Sheets"] == 1, "one sheet")
check(abs(rows["SheetArea"] - 6000.0) < 1e-6, "the sheet covers the plate's 100 x 60 outline")
check(rows["Junctions"] == 0 and rows["NonManifoldEdges"] == 0, "no junction")
check(rows["NotThinFaces"] == 0, "nothing reported as not thin")

out = dsa.WrapDataObject(sm.Fetch(mid, idx=0))
pts = np.asarray(out.Points)
t = np.asarray(out.PointData["Thickness"])
check(np.max(np.abs(pts[:, 2] - 2.5)) <= 1e-6, "every vertex on the mid-plane z = 2.5")
check(np.max(np.abs(t - 5.0)) <= 5e-6, "Thickness 5 within 1e-6 relative")

# The plate has no rod: an empty skeleton. The reader's output (no thickness arrays): one error.
skel = BRepSkeleton(Input=thickness)
skel.UpdatePipeline()
check(sm.Fetch(skel).GetNumberOfPoints() == 0, "no skeleton on a plate")
errors = []
wrong = BRepMidsurface(Input=reader)
from vtkmodules.vtkCommonCore import vtkCommand
wrong.GetClientSideObject().AddObserver(vtkCommand.ErrorEvent, lambda o, e: errors.append(e))
wrong.UpdatePipeline()
check(len(errors) == 1 and sm.Fetch(wrong).GetNumberOfPoints() == 0,
      "B-Rep Midsurface on the reader's output: one error, empty output")
Delete(wrong)

vtp = os.path.join(work, "plate_midsurface.vtp")
SaveData(vtp, proxy=OutputPort(mid, 0))
r = vtkXMLPolyDataReader()
r.SetFileName(vtp)
r.Update()
back = dsa.WrapDataObject(r.GetOutput())
check(back.GetNumberOfCells() == out.GetNumberOfCells() and "Thickness" in back.PointData.keys()
      and "SheetId" in back.CellData.keys(), ".vtp reads back with its arrays")

inp = os.path.join(work, "plate_midsurface.inp")
SaveData(inp, proxy=OutputPort(mid, 0))
text = open(inp).read()
check("*ELEMENT, TYPE=S6, ELSET=SHEET1" in text and "*NODAL THICKNESS" in text,
      "the deck has S6 elements and nodal thicknesses")

# The nodes: the centre (50, 30) and two corners for the in-plane rigid-body modes.
nodes = {}
block = text.split("*NODE, NSET=NALL\n", 1)[1].split("*", 1)[0]
for line in block.strip().splitlines():
    n, x, y, z = line.split(",")
    nodes[int(n)] = (float(x), float(y), float(z))
centre = min(nodes, key=lambda n: math.hypot(nodes[n][0] - 50, nodes[n][1] - 30))
corner0 = min(nodes, key=lambda n: math.hypot(nodes[n][0], nodes[n][1]))
corner1 = min(nodes, key=lambda n: math.hypot(nodes[n][0] - 100, nodes[n][1]))
check(math.hypot(nodes[centre][0] - 50, nodes[centre][1] - 30) < 1e-9, "a node at the centre")
thick = dict((int(a), float(b)) for a, b in re.findall(r"^(\d+), ([0-9.eE+-]+)$",
                                                        text.split("*NODAL THICKNESS\n", 1)[1], re.M))
check(len(thick) == len(nodes) and max(abs(v - 5.0) for v in thick.values()) < 5e-6,
      "*NODAL THICKNESS: 5 at every node (%d)" % len(thick))

ccx = shutil.which("ccx")
if not ccx:
    print("SKIP: ccx (Debian calculix-ccx) is not installed; the deck was not run")
    if failures:
        finish()
    sys.exit(77)

q, E, nu, h, a, b = 0.01, 210000.0, 0.3, 5.0, 100.0, 60.0
step = os.path.join(work, "plate_ss.inp")
with open(step, "w") as f:
    f.write("""*INCLUDE, INPUT=%s
*NSET, NSET=NCENTER
%d
*BOUNDARY
NBOUNDARY, 3, 3
%d, 1, 2
%d, 2, 2
*STEP
*STATIC
*DLOAD
EALL, P, %g
*NODE PRINT, NSET=NCENTER
U
*END STEP
""" % (inp, centre, corner0, corner1, q))
run = subprocess.run([ccx, "plate_ss"], cwd=work, capture_output=True, text=True, timeout=600)
check(run.returncode == 0 and "ERROR" not in run.stdout, "ccx ran the deck")
dat = open(os.path.join(work, "plate_ss.dat")).read()
m = re.search(r"^\s*%d\s+(\S+)\s+(\S+)\s+(\S+)\s*$" % centre, dat, re.M)
check(m is not None, "ccx printed the centre's displacement")
w = abs(float(m.group(3))) if m else math.nan

# Navier series of the simply supported plate: Kirchhoff, and Mindlin's shear term (k = 5/6).
D = E * h ** 3 / (12 * (1 - nu ** 2))
G = E / (2 * (1 + nu))
wk = ws = 0.0
for i in range(1, 400, 2):
    for j in range(1, 400, 2):
        qij = 16 * q / (math.pi ** 2 * i * j) * math.sin(i * math.pi / 2) * math.sin(j * math.pi / 2)
        al2 = (i * math.pi / a) ** 2 + (j * math.pi / b) ** 2
        wk += qij / (D * al2 * al2)
        ws += qij / (5.0 / 6.0 * G * h * al2)
print("centre deflection: CalculiX %.6e mm, Kirchhoff %.6e (%+.2f%%), Mindlin %.6e (%+.2f%%)"
      % (w, wk, 100 * (w / wk - 1), wk + ws, 100 * (w / (wk + ws) - 1)))
check(abs(w / (wk + ws) - 1) < 0.05, "CalculiX's centre deflection within 5% of Mindlin plate theory")
finish("midsurface, deck and CalculiX: all checks passed")
