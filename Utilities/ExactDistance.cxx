#include "ExactDistance.h"

#include <BRepBndLib.hxx>
#include <BRepClass_FaceClassifier.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <GeomAPI_ProjectPointOnCurve.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <Geom_Curve.hxx>
#include <Geom_Surface.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <gp_Pnt2d.hxx>

#include <limits>

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

double ExtremaDistance(const std::vector<TopoDS_Face>& faces, const std::vector<Bnd_Box>& boxes,
  const gp_Pnt& X, double reach, const std::function<bool(size_t)>& use, gp_Pnt* at, int* atFace)
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
