#include "CurvesOnFaces.h"

#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Geom2d_Curve.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <GeomProjLib.hxx>
#include <Geom_Curve.hxx>
#include <Geom_Surface.hxx>
#include <ShapeAnalysis_Curve.hxx>
#include <ShapeConstruct_ProjectCurveOnSurface.hxx>
#include <Standard_Failure.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <gp_Vec2d.hxx>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace brt
{
namespace
{
// The samples of the measure. 23 evenly spread points (as many as OpenCASCADE's own check takes)
// missed a pcurve of Ploopy's Adept BTU top lying 0.044 mm off its circle, 51 found it; 101 cost
// 1-2% of the conversion of the Data/ parts. A narrower bump can still pass between them. A
// replacement is checked on ten times as many.
constexpr int MeasureSamples = 100;
constexpr int CheckSamples = 1000;

double Distance(const Handle(Geom2d_Curve)& pc, const Handle(Geom_Surface)& surface,
  const Handle(Geom_Curve)& curve, double first, double last, double threshold, int samples)
{
  double worst = 0.0;
  for (int k = 0; k <= samples; ++k)
  {
    const double t = first + (last - first) * k / samples;
    const gp_Pnt2d uv = pc->Value(t);
    const gp_Pnt p = surface->Value(uv.X(), uv.Y());
    double d = p.Distance(curve->Value(t));
    if (d > threshold)
    {
      // the nearest point of the 3D curve near t: Newton on (C(s) - p).C'(s) = 0, and where that
      // does not settle (the two curves' parameters far apart), OpenCASCADE's projection
      double s = t;
      bool settled = false;
      for (int it = 0; it < 8 && !settled; ++it)
      {
        gp_Pnt c;
        gp_Vec d1, d2;
        curve->D2(s, c, d1, d2);
        const gp_Vec w(p, c);
        const double g = w.Dot(d1), h = d1.Dot(d1) + w.Dot(d2);
        if (!(h > 0.0))
          break;
        const double next = std::clamp(s - g / h, first, last);
        settled = std::fabs(next - s) <= 1e-12 * (1.0 + std::fabs(s));
        s = next;
      }
      d = std::min(d, p.Distance(curve->Value(s)));
      if (!settled)
      {
        gp_Pnt nearest;
        double at = t;
        d = std::min(d, ShapeAnalysis_Curve().Project(curve, p, 1e-10, nearest, at, first, last,
                          Standard_False));
      }
    }
    worst = std::max(worst, d);
  }
  return worst;
}

// Moves `c2` by whole periods of the surface so that it starts where `old` starts.
void AlignPeriods(const Handle(Geom2d_Curve)& c2, const Handle(Geom2d_Curve)& old,
  const Handle(Geom_Surface)& surface, double first)
{
  const gp_Pnt2d a = old->Value(first), b = c2->Value(first);
  double du = 0.0, dv = 0.0;
  if (surface->IsUPeriodic())
    du = std::round((a.X() - b.X()) / surface->UPeriod()) * surface->UPeriod();
  if (surface->IsVPeriodic())
    dv = std::round((a.Y() - b.Y()) / surface->VPeriod()) * surface->VPeriod();
  if (du != 0.0 || dv != 0.0)
    c2->Translate(gp_Vec2d(du, dv));
}

// The curves of one kind (projected again, or left): how many, on how many faces, the worst
// distance, its face and the largest edge tolerance among them.
struct Tally
{
  int Count = 0, Faces = 0, WorstFace = -1, LastFace = -1;
  double Worst = 0.0, Tolerance = 0.0;
  void Add(int face, double off, double edgeTolerance)
  {
    ++Count;
    Faces += face != LastFace ? 1 : 0;
    LastFace = face;
    if (off > Worst)
    {
      Worst = off;
      WorstFace = face;
    }
    Tolerance = std::max(Tolerance, edgeTolerance);
  }
  // "face F and N more: C edges' curves on the face lay off the edge by up to W" and the rest
  std::string Summary(const char* verb, const char* beforeTolerance, const char* after) const
  {
    std::ostringstream s;
    s << "face " << WorstFace;
    if (Faces > 1)
      s << " and " << Faces - 1 << " more";
    s << ": " << Count << (Count == 1 ? " edge's curve" : " edges' curves") << " on the face "
      << verb << " off the edge by up to " << Worst << beforeTolerance << Tolerance << after;
    return s.str();
  }
};
} // namespace

double CurveOnFaceDistance(const TopoDS_Edge& edge, const TopoDS_Face& face, double threshold,
  int samples)
{
  double f = 0.0, l = 0.0, f3 = 0.0, l3 = 0.0;
  const Handle(Geom2d_Curve) pc = BRep_Tool::CurveOnSurface(edge, face, f, l);
  const Handle(Geom_Curve) curve = BRep_Tool::Curve(edge, f3, l3);
  const Handle(Geom_Surface) surface = BRep_Tool::Surface(face);
  if (pc.IsNull() || curve.IsNull() || surface.IsNull())
    return 0.0;
  return Distance(pc, surface, curve, f, l, threshold, samples);
}

CurvesOnFacesResult RepairCurvesOnFaces(
  const std::vector<TopoDS_Face>& faces, double tolerance, std::vector<std::string>& warnings)
{
  CurvesOnFacesResult result;
  Tally rebuilt, left;
  BRep_Builder builder;
  for (size_t fi = 0; fi < faces.size(); ++fi)
  {
    const TopoDS_Face& face = faces[fi];
    const Handle(Geom_Surface) surface = BRep_Tool::Surface(face);
    if (surface.IsNull())
      continue;
    for (TopExp_Explorer ex(face, TopAbs_EDGE); ex.More(); ex.Next())
    {
      const TopoDS_Edge edge = TopoDS::Edge(ex.Current());
      if (BRep_Tool::Degenerated(edge))
        continue;
      double f = 0.0, l = 0.0, f3 = 0.0, l3 = 0.0;
      const Handle(Geom2d_Curve) pc = BRep_Tool::CurveOnSurface(edge, face, f, l);
      const Handle(Geom_Curve) curve = BRep_Tool::Curve(edge, f3, l3);
      if (pc.IsNull() || curve.IsNull())
        continue;
      ++result.Checked;
      const double edgeTolerance = BRep_Tool::Tolerance(edge);
      // The edge's tolerance is the tube its curves must lie in. The healing sets it to the
      // distance it measured on fewer points, so a curve a little beyond it is the rule: twice
      // it. From 1.05 times it, Ploopy's secondary buttons (SolidWorks) had 27 curves tried
      // where twice it tried 14, and 12 of the 13 more in vain (no projection nearer by half;
      // measured with this function's first measure, OpenCASCADE's projection at every point).
      const double threshold = std::max(2.0 * edgeTolerance, 0.1 * tolerance);
      double off = 0.0;
      try
      {
        off = Distance(pc, surface, curve, f, l, threshold, MeasureSamples);
        if (off <= threshold)
          continue;
      }
      catch (const Standard_Failure&)
      {
        continue; // a curve OpenCASCADE cannot evaluate there: the conversion warns of it
      }
      // Projections of the 3D curve, the nearer kept where it is nearer by half.
      Handle(Geom2d_Curve) best;
      double bestOff = 0.5 * off;
      const bool seam = BRep_Tool::IsClosed(edge, face);
      const bool sameRange = std::fabs(f - f3) < 1e-9 * (1.0 + std::fabs(f3)) &&
        std::fabs(l - l3) < 1e-9 * (1.0 + std::fabs(l3));
      // A projection lies no nearer the 3D curve than the curve lies to the surface: where the
      // curve itself stands off the surface by half the pcurve's distance or more (a face whose
      // edges are 165 mm off it, a libFuzzer mutation), no projection is nearer by half, and
      // OpenCASCADE's projection onto such a face took 21 s. Measured at five points, where a
      // projection would be tried.
      bool curveOnSurface = !seam && BRep_Tool::SameParameter(edge) && sameRange;
      try
      {
        for (int i = 0; i < 5 && curveOnSurface; ++i)
        {
          GeomAPI_ProjectPointOnSurf onto(curve->Value(f3 + (l3 - f3) * (i + 0.5) / 5.0), surface);
          curveOnSurface = onto.NbPoints() == 0 || onto.LowerDistance() < bestOff;
        }
      }
      catch (const Standard_Failure&)
      {
      }
      if (curveOnSurface)
      {
        auto consider = [&](const Handle(Geom2d_Curve)& c2) {
          if (c2.IsNull())
            return;
          AlignPeriods(c2, pc, surface, f);
          // ends where the old one ends, on the surface (the loop's neighbours meet it there)
          const gp_Pnt2d a0 = pc->Value(f), a1 = pc->Value(l), b0 = c2->Value(f), b1 = c2->Value(l);
          if (surface->Value(a0.X(), a0.Y()).Distance(surface->Value(b0.X(), b0.Y())) > threshold ||
            surface->Value(a1.X(), a1.Y()).Distance(surface->Value(b1.X(), b1.Y())) > threshold)
            return;
          const double d = Distance(c2, surface, curve, f, l, threshold, CheckSamples);
          if (d < bestOff)
          {
            bestOff = d;
            best = c2;
          }
        };
        try
        {
          double reached = 0.1 * threshold;
          consider(GeomProjLib::Curve2d(curve, f, l, surface, reached));
        }
        catch (const Standard_Failure&)
        {
        }
        if (best.IsNull() || bestOff > threshold)
        {
          try
          {
            ShapeConstruct_ProjectCurveOnSurface projector;
            projector.Init(surface, 0.1 * threshold);
            Handle(Geom_Curve) c3 = curve;
            Handle(Geom2d_Curve) c2;
            double pf = f, pl = l;
            const bool done = projector.Perform(c3, pf, pl, c2);
            if (done && std::fabs(pf - f) < 1e-12 * (1.0 + std::fabs(f)) &&
              std::fabs(pl - l) < 1e-12 * (1.0 + std::fabs(l)))
              consider(c2);
          }
          catch (const Standard_Failure&)
          {
          }
        }
      }
      const int at = static_cast<int>(fi);
      if (!best.IsNull())
      {
        builder.UpdateEdge(edge, best, face, std::max(edgeTolerance, bestOff));
        rebuilt.Add(at, off, edgeTolerance);
        off = bestOff;
      }
      if (off > threshold)
        left.Add(at, off, edgeTolerance);
    }
  }
  result.Rebuilt = rebuilt.Count;
  result.WorstRebuilt = rebuilt.Worst;
  result.Left = left.Count;
  result.WorstLeft = left.Worst;
  if (rebuilt.Count > 0)
    warnings.push_back(rebuilt.Summary(
      "lay", " (edge tolerance up to ", "); projected again from the edge"));
  if (left.Count > 0)
    warnings.push_back(left.Summary(left.Count == 1 ? "lies" : "lie",
      ", beyond the edge's tolerance (up to ",
      "): the file's faces and edges disagree there by as much"));
  return result;
}
} // namespace brt
