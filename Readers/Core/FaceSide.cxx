#include "FaceSide.h"

#include <BRepAdaptor_Surface.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box2d.hxx>
#include <BndLib_Add2dCurve.hxx>
#include <Geom2d_Curve.hxx>
#include <Geom2d_Line.hxx>
#include <Standard_Failure.hxx>
#include <TopAbs.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>

#include <algorithm>
#include <cmath>

namespace brt
{
FaceSide::FaceSide(const TopoDS_Face& face)
  : Classifier(face, 1e-9)
{
  double u1 = 0.0, v1 = 0.0;
  BRepTools::UVBounds(face, U0, u1, V0, v1);
  DU = (u1 - U0) / Cells;
  DV = (v1 - V0) / Cells;
  // The classifier tries a point a period on where it finds it outside: on a face wider than the
  // period that point may lie in another cell's region.
  const BRepAdaptor_Surface surface(face, Standard_False);
  const bool wider = (surface.IsUPeriodic() && u1 - U0 > surface.UPeriod() * (1.0 + 1e-9)) ||
    (surface.IsVPeriodic() && v1 - V0 > surface.VPeriod() * (1.0 + 1e-9));
  if (!(DU > 0.0) || !(DV > 0.0) || wider)
    return;
  State.assign(static_cast<size_t>(Cells * Cells), Unknown);
  for (TopExp_Explorer ex(face, TopAbs_EDGE); ex.More(); ex.Next())
  {
    const TopoDS_Edge& e = TopoDS::Edge(ex.Current());
    // Both of a seam's pcurves (the edge in either orientation on the face).
    for (const TopAbs_Orientation o : { e.Orientation(), TopAbs::Reverse(e.Orientation()) })
    {
      double f = 0.0, l = 0.0;
      const Handle(Geom2d_Curve) pc =
        BRep_Tool::CurveOnSurface(TopoDS::Edge(e.Oriented(o)), face, f, l);
      if (pc.IsNull())
      {
        State.clear(); // a boundary it cannot bound: no cache
        return;
      }
      const int pieces = pc->IsKind(STANDARD_TYPE(Geom2d_Line)) ? 1 : 8;
      for (int k = 0; k < pieces; ++k)
      {
        Bnd_Box2d box;
        try
        {
          BndLib_Add2dCurve::Add(pc, f + (l - f) * k / pieces, f + (l - f) * (k + 1) / pieces,
            0.0, box);
        }
        catch (const Standard_Failure&)
        {
          // OpenCASCADE 7.6 cannot bound some B-spline pcurves (an Onshape part's: its
          // BndLib_Box2dCurve::PerformBSpline throws NCollection_Array1::Create, which stopped
          // the whole conversion): a boundary it cannot bound, no cache.
          State.clear();
          return;
        }
        if (box.IsVoid())
          continue;
        double a0, b0, a1, b1;
        box.Get(a0, b0, a1, b1);
        const double i0 = std::floor((a0 - U0) / DU - 0.5), i1 = std::floor((a1 - U0) / DU + 0.5);
        const double j0 = std::floor((b0 - V0) / DV - 0.5), j1 = std::floor((b1 - V0) / DV + 0.5);
        if (!(i0 <= i1) || !(j0 <= j1)) // (a NaN)
        {
          State.clear();
          return;
        }
        for (int i = static_cast<int>(std::max(0.0, i0));
             i <= static_cast<int>(std::min<double>(Cells - 1, i1)); ++i)
          for (int j = static_cast<int>(std::max(0.0, j0));
               j <= static_cast<int>(std::min<double>(Cells - 1, j1)); ++j)
            State[static_cast<size_t>(i * Cells + j)] = Near;
      }
    }
  }
}

bool FaceSide::Outside(const gp_Pnt2d& p)
{
  if (!State.empty())
  {
    const double x = (p.X() - U0) / DU, y = (p.Y() - V0) / DV;
    if (x >= 0.0 && y >= 0.0 && x < Cells && y < Cells)
    {
      const size_t cell = static_cast<size_t>(static_cast<int>(x) * Cells + static_cast<int>(y));
      signed char& s = State[cell];
      if (s == In || s == Out)
        return s == Out;
      ++Calls;
      const bool out = Classifier.Perform(p) == TopAbs_OUT;
      if (s == Unknown)
        s = out ? Out : In;
      return out;
    }
  }
  ++Calls;
  return Classifier.Perform(p) == TopAbs_OUT;
}
} // namespace brt
