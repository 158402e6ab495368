#include "ExactDistance.h"

#include <BRepBndLib.hxx>
#include <BRepClass_FaceClassifier.hxx>
#include <BRepTools.hxx>
#include <BRepTopAdaptor_FClass2d.hxx>
#include <BRep_Tool.hxx>
#include <GeomAPI_ProjectPointOnCurve.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <Geom_Curve.hxx>
#include <Geom_Surface.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <gp_Pnt2d.hxx>

#include <algorithm>
#include <limits>
#include <utility>

namespace brt
{
namespace exact
{
std::vector<Bnd_Box> FaceBoxes(const std::vector<TopoDS_Face>& faces)
{
  std::vector<Bnd_Box> boxes(faces.size());
  for (size_t f = 0; f < faces.size(); ++f)
    BRepBndLib::Add(faces[f], boxes[f]);
  return boxes;
}

double GridDistance(const TopoDS_Face& F, const gp_Pnt& X, int n, gp_Pnt* at)
{
  const Handle(Geom_Surface) S = BRep_Tool::Surface(F);
  if (S.IsNull() || n < 1)
    return std::numeric_limits<double>::max();
  double u0, u1, v0, v1;
  BRepTools::UVBounds(F, u0, u1, v0, v1);
  const double tol = BRep_Tool::Tolerance(F);
  // Two classifiers must agree: BRepClass_FaceClassifier put a corner of a plane's parameter box
  // on the face where BRepTopAdaptor_FClass2d and the face's distance did not (the Ventilator's
  // face 10: a point 0.75 mm "inside" a sphere that is 0.6 mm clear of the face).
  BRepTopAdaptor_FClass2d polygon(F, tol);
  auto onFace = [&](double u, double v) {
    const TopAbs_State a = BRepClass_FaceClassifier(F, gp_Pnt2d(u, v), tol).State();
    const TopAbs_State b = polygon.Perform(gp_Pnt2d(u, v));
    return (a == TopAbs_IN || a == TopAbs_ON) && (b == TopAbs_IN || b == TopAbs_ON);
  };
  // The nearest of the cell centres of an m x m grid over [ua, ub] x [va, vb] that are on the
  // face: candidates by distance, each classified in turn until one is on it.
  auto nearestOn = [&](double ua, double ub, double va, double vb, int m, double& bu, double& bv) {
    std::vector<std::pair<double, std::pair<double, double>>> cand;
    cand.reserve(static_cast<size_t>(m * m));
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j)
      {
        const double u = ua + (ub - ua) * (i + 0.5) / m, v = va + (vb - va) * (j + 0.5) / m;
        cand.push_back({ X.Distance(S->Value(u, v)), { u, v } });
      }
    std::sort(cand.begin(), cand.end());
    for (const auto& c : cand)
    {
      if (onFace(c.second.first, c.second.second))
      {
        bu = c.second.first;
        bv = c.second.second;
        return c.first;
      }
    }
    return std::numeric_limits<double>::max();
  };
  double bu = 0.0, bv = 0.0;
  double best = nearestOn(u0, u1, v0, v1, n, bu, bv);
  if (!(best < std::numeric_limits<double>::max()))
    return best;
  double du = (u1 - u0) / n, dv = (v1 - v0) / n;
  for (int level = 0; level < 3; ++level)
  {
    double nu = bu, nv = bv;
    const double d = nearestOn(std::max(u0, bu - du), std::min(u1, bu + du), std::max(v0, bv - dv),
      std::min(v1, bv + dv), 9, nu, nv);
    if (d < best)
    {
      best = d;
      bu = nu;
      bv = nv;
    }
    du /= 4.0;
    dv /= 4.0;
  }
  if (at)
    *at = S->Value(bu, bv);
  return best;
}

double ExtremaDistance(const std::vector<TopoDS_Face>& faces, const std::vector<Bnd_Box>& boxes,
  const gp_Pnt& X, double reach, const std::function<bool(size_t)>& use, gp_Pnt* at, int* atFace,
  int grid)
{
  double best = std::numeric_limits<double>::max();
  auto keep = [&](double dist, const gp_Pnt& P, int face) {
    if (dist < best)
    {
      best = dist;
      if (at)
        *at = P;
      if (atFace)
        *atFace = face;
    }
  };
  for (size_t f = 0; f < faces.size(); ++f)
  {
    if ((use && !use(f)) || boxes[f].IsVoid() || boxes[f].Distance(Bnd_Box(X, X)) > reach)
      continue;
    const TopoDS_Face& F = faces[f];
    if (grid > 0)
    {
      gp_Pnt P;
      const double d = GridDistance(F, X, grid, &P);
      if (d < std::numeric_limits<double>::max())
        keep(d, P, static_cast<int>(f));
    }
    double u0, u1, v0, v1;
    BRepTools::UVBounds(F, u0, u1, v0, v1);
    const Handle(Geom_Surface) S = BRep_Tool::Surface(F);
    if (!S.IsNull())
    {
      GeomAPI_ProjectPointOnSurf proj(X, S, u0, u1, v0, v1);
      for (int i = 1; i <= proj.NbPoints(); ++i)
      {
        double u, v;
        proj.Parameters(i, u, v);
        const BRepClass_FaceClassifier in(F, gp_Pnt2d(u, v), BRep_Tool::Tolerance(F));
        if (in.State() == TopAbs_IN || in.State() == TopAbs_ON)
          keep(proj.Distance(i), proj.Point(i), static_cast<int>(f));
      }
    }
    for (TopExp_Explorer ex(F, TopAbs_EDGE); ex.More(); ex.Next())
    {
      const TopoDS_Edge& E = TopoDS::Edge(ex.Current());
      double t0, t1;
      const Handle(Geom_Curve) C = BRep_Tool::Curve(E, t0, t1);
      if (C.IsNull())
        continue;
      keep(X.Distance(C->Value(t0)), C->Value(t0), -1);
      keep(X.Distance(C->Value(t1)), C->Value(t1), -1);
      GeomAPI_ProjectPointOnCurve proj(X, C, t0, t1);
      for (int i = 1; i <= proj.NbPoints(); ++i)
        keep(proj.Distance(i), proj.Point(i), -1);
    }
  }
  return best;
}
} // namespace exact
} // namespace brt
