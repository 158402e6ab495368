"""The exterior gap in the filter (Measure "Thickness and gap") on the hole plate (80 x 80 x 6,
hole r 10): on the hole's wall the gap is the hole's diameter (20), within 1e-5 relative away
from the rims (the reader's default tolerance 1e-4 mm on the hole's patches; the core test, at
1e-6, finds 9e-9) and 5e-4 at the rims, where the sphere grazes the rim circle; every other face faces nothing: infinite, flagged, never a bounding-box value.
MinimumGap and MaximumGap act without solving again; GapScope "All solids" changes nothing on
one solid.

    pvpython test_filter_gap.py PLUGIN hole_plate.step
"""
import math
import sys

import numpy as np
from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager as sm
from vtkmodules.numpy_interface import dataset_adapter as dsa

from brt_checks import check, finish, summary_rows

plugin, model = sys.argv[1], sys.argv[2]
LoadPlugin(plugin, ns=globals())


reader = STEPReader(FileName=model)
f = BRepThickness(Input=reader, Device="native", Measure="Thickness and gap", MinimumGap=25.0)
f.UpdatePipeline()
m = dsa.WrapDataObject(sm.Fetch(f, idx=0))
pts = np.asarray(m.Points)
gap = np.asarray(m.PointData["Gap"])
inf = np.asarray(m.PointData["GapInfinite"])
gtype = np.asarray(m.PointData["GapContactType"])
centre = np.asarray(m.PointData["GapSphereCenter"])
normals = np.asarray(m.PointData["Normals"])
# The hole's wall (its rim vertices on the top and bottom faces face up and down: infinite).
hole = (np.abs(np.hypot(pts[:, 0] - 40, pts[:, 1] - 40) - 10) < 1e-3) & (np.abs(normals[:, 2]) < 0.5)
rim = (pts[:, 2] < 0.05) | (pts[:, 2] > 5.95)
err = np.abs(gap - 20.0) / 20.0
print("hole wall: %d samples, max |gap - 20| / 20 = %.2e away from the rims, %.2e at the rims; "
      "%d other samples, %d infinite" % (hole.sum(), err[hole & ~rim].max(), err[hole & rim].max(),
                                         (~hole).sum(), np.isinf(gap[~hole]).sum()))
check(err[hole & ~rim].max() <= 1e-5, "the hole's gap is its diameter away from the rims")
check(err[hole & rim].max() <= 5e-4, "the hole's gap at its rims")
check(np.all(np.isinf(gap[~hole])) and np.all(inf[~hole] == 1), "every other face: infinite, flagged")
check(np.all(inf[hole] == 0) and np.all(gtype[hole] > 0), "hole wall: finite, solved")
axis = np.hypot(centre[hole & ~rim, 0] - 40, centre[hole & ~rim, 1] - 40)
check(axis.max() < 1e-4, "the gap's sphere centres lie on the hole's axis away from the rims (max %.2e)" % axis.max())
check(np.all(np.isnan(centre[~hole])), "no sphere centre where the gap is infinite")
rows = summary_rows(f)
wall, total = 2 * math.pi * 10 * 6, 2 * (80**2 - math.pi * 100) + 4 * 80 * 6 + 2 * math.pi * 10 * 6
print("Summary: GapMin %.9g, GapMax %.9g, below 25 mm %.4f (hole wall %.4f of the area), infinite %.4f"
      % (rows["GapMin"], rows["GapMax"], rows["AreaShareBelowMinimumGap"], wall / total, rows["AreaShareInfiniteGap"]))
check(rows["GapMax"] == np.max(gap[np.isfinite(gap)]), "GapMax from the array")
check(abs(rows["AreaShareBelowMinimumGap"] - wall / total) < 0.005, "the share below 25 mm is the hole's wall")
check(abs(rows["AreaShareBelowMinimumGap"] + rows["AreaShareInfiniteGap"] - 1.0) < 1e-12, "shares add up")
check(rows["GapFailed"] == 0, "no failed gap")
solve = rows["SolveSeconds"]

f.MaximumGap = 15.0  # the hole is wider: infinite everywhere, without solving again
f.UpdatePipeline()
rows = summary_rows(f)
gap = np.asarray(dsa.WrapDataObject(sm.Fetch(f, idx=0)).PointData["Gap"])
check(np.all(np.isinf(gap)) and rows["AreaShareInfiniteGap"] == 1.0, "MaximumGap 15: every gap infinite")
check(rows["SolveSeconds"] == solve, "MaximumGap solved again")

f.MaximumGap = 0.0
f.GapScope = "All solids"
f.UpdatePipeline()
gap2 = np.asarray(dsa.WrapDataObject(sm.Fetch(f, idx=0)).PointData["Gap"])
check(np.array_equal(np.isinf(gap2), ~hole), "All solids on one solid: the same infinite samples")

# Measure Gap: the gap alone, the same values; the histogram and tables measure the finite gaps.
f.GapScope = "Own solid"
f.Measure = "Gap"
f.UpdatePipeline()
mg = dsa.WrapDataObject(sm.Fetch(f, idx=0))
names = list(mg.PointData.keys())
check("Thickness" not in names and "ThicknessClass" not in names and "Gap" in names,
      "Measure Gap: gap arrays only (%s)" % names)
check(np.array_equal(np.asarray(mg.PointData["Gap"]), gap2, equal_nan=True), "Measure Gap: the same Gap as with the thickness")
rows = summary_rows(f)
check("ThicknessMin" not in rows and rows["GapMax"] == np.max(gap2[np.isfinite(gap2)]), "Measure Gap: Summary rows")
hist = sm.Fetch(f, idx=4)
shares = [hist.GetValue(r, 1).ToDouble() for r in range(hist.GetNumberOfRows())]
check(abs(sum(shares) - 1.0) < 1e-9 and shares[-1] > 0.9, "Measure Gap: the histogram of the finite gaps (the hole's 20 mm in the last bin)")
check(sm.Fetch(f, idx=5).GetColumnByName("GapMin") is not None, "Measure Gap: per-solid table of the gap")
check(sm.Fetch(f, idx=1).GetNumberOfPoints() == 0, "Measure Gap: no medial points")

f.Measure = "Thickness"
f.UpdatePipeline()
names = list(dsa.WrapDataObject(sm.Fetch(f, idx=0)).PointData.keys())
check("Gap" not in names and "GapMin" not in summary_rows(f), "no gap arrays or rows with Measure Thickness")

finish("gap passed")
