#include "ExactDistance.h"

#include <BRepAdaptor_Surface.hxx>
#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepClass_FaceClassifier.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRep_Builder.hxx>
#include <TopTools_DataMapOfShapeInteger.hxx>
#include <TopTools_MapOfShape.hxx>
#include <TopoDS_Compound.hxx>
#include <BRepTools.hxx>
#include <BRepTopAdaptor_FClass2d.hxx>
#include <BRep_Tool.hxx>
#include <GeomAPI_ProjectPointOnCurve.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <IntCurvesFace_ShapeIntersector.hxx>
#include <Standard_Failure.hxx>
#include <gp_Lin.hxx>
#include <Geom_Curve.hxx>
#include <Geom_Surface.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <gp_Pnt2d.hxx>

#include <algorithm>
#include <cmath>
#include <memory>
#include <limits>
#include <utility>

namespace brt
{
namespace exact
{
namespace
{
// Each face's polygon classifier, built once (building it polygonises the face's wires): the
// faces stay alive with the map, so none is mistaken for another.
BRepTopAdaptor_FClass2d& Polygon(const TopoDS_Face& F)
{
  static TopTools_DataMapOfShapeInteger index;
  static std::vector<std::unique_ptr<BRepTopAdaptor_FClass2d>> polygons;
  if (const int* i = index.Seek(F))
    return *polygons[static_cast<size_t>(*i)];
  polygons.push_back(std::make_unique<BRepTopAdaptor_FClass2d>(F, BRep_Tool::Tolerance(F)));
  index.Bind(F, static_cast<int>(polygons.size() - 1));
  return *polygons.back();
}

// On the face by both of OpenCASCADE's classifiers at the face's tolerance: where they differ,
// BRepClass_FaceClassifier was the one wrong in each case seen (a plane's corner, a sliver's).
bool OnFace(const TopoDS_Face& F, double u, double v)
{
  const TopAbs_State a =
    BRepClass_FaceClassifier(F, gp_Pnt2d(u, v), BRep_Tool::Tolerance(F)).State();
  if (a != TopAbs_IN && a != TopAbs_ON)
    return false;
  const TopAbs_State b = Polygon(F).Perform(gp_Pnt2d(u, v));
  return b == TopAbs_IN || b == TopAbs_ON;
}
} // namespace

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
  // Two classifiers must agree (OnFace): BRepClass_FaceClassifier put a corner of a plane's
  // parameter box on the face where BRepTopAdaptor_FClass2d and the face's distance did not (the
  // Ventilator's face 10: a point 0.75 mm "inside" a sphere that is 0.6 mm clear of the face).
  // The nearest of the cell centres of an m x m grid over [ua, ub] x [va, vb] that are on the
  // face: candidates by distance, each classified in turn until one is on it. *cells (where
  // given) gets every cell centre's distance, cell (i, j) at i m + j.
  auto nearestOn = [&](double ua, double ub, double va, double vb, int m, double& bu, double& bv,
                     std::vector<double>* cells = nullptr) {
    std::vector<std::pair<double, std::pair<double, double>>> cand;
    cand.reserve(static_cast<size_t>(m * m));
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j)
      {
        const double u = ua + (ub - ua) * (i + 0.5) / m, v = va + (vb - va) * (j + 0.5) / m;
        cand.push_back({ X.Distance(S->Value(u, v)), { u, v } });
      }
    if (cells)
    {
      cells->resize(cand.size());
      for (size_t k = 0; k < cand.size(); ++k)
        (*cells)[k] = cand[k].first;
    }
    std::sort(cand.begin(), cand.end());
    for (const auto& c : cand)
    {
      if (OnFace(F, c.second.first, c.second.second))
      {
        bu = c.second.first;
        bv = c.second.second;
        return c.first;
      }
    }
    return std::numeric_limits<double>::max();
  };
  // Refined three times around (bu, bv): a 9 x 9 grid over the cell and its neighbours, then
  // over a quarter of that, and so on.
  auto refine = [&](double& bu, double& bv, double best) {
    double du = (u1 - u0) / n, dv = (v1 - v0) / n;
    for (int level = 0; level < 3; ++level)
    {
      double nu = bu, nv = bv;
      const double d = nearestOn(std::max(u0, bu - du), std::min(u1, bu + du),
        std::max(v0, bv - dv), std::min(v1, bv + dv), 9, nu, nv);
      if (d < best)
      {
        best = d;
        bu = nu;
        bv = nv;
      }
      du /= 4.0;
      dv /= 4.0;
    }
    return best;
  };
  double bu = 0.0, bv = 0.0;
  std::vector<double> g; // the grid's distances, for its local minima below
  double best = nearestOn(u0, u1, v0, v1, n, bu, bv, &g);
  if (!(best < std::numeric_limits<double>::max()))
    return best;
  best = refine(bu, bv, best);
  // The grid's nearest cell is one basin of the distance; another, narrower than a cell, can
  // hold the nearest point (the unseen cover's extruded face 24, 93 mm long: a dip 0.08 mm from
  // O, between the grid's columns, while the cell at O itself, barely farther, won). So every
  // other cell on the face whose distance is a local minimum of the grid (no neighbour nearer)
  // and within a cell's reach of the best is refined too, the 8 nearest of them. Not enough on
  // that face: its nearest points can lie between its border and the first column, and a 30 x
  // 30 grid then finds them in some runs and not in others (docs/Solver.md, "A third opinion").
  {
    std::vector<std::pair<double, std::pair<int, int>>> minima;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
      {
        const double here = g[static_cast<size_t>(i * n + j)];
        bool local = true;
        double reach = 0.0; // the largest step to a neighbouring cell's centre
        for (int a = -1; a <= 1 && local; ++a)
          for (int b = -1; b <= 1; ++b)
          {
            const int ii = i + a, jj = j + b;
            if ((a == 0 && b == 0) || ii < 0 || jj < 0 || ii >= n || jj >= n)
              continue;
            const double there = g[static_cast<size_t>(ii * n + jj)];
            if (there < here)
            {
              local = false;
              break;
            }
            reach = std::max(reach, there - here);
          }
        if (local && here - reach < best)
          minima.push_back({ here, { i, j } });
      }
    std::sort(minima.begin(), minima.end());
    int refined = 0;
    for (const auto& c : minima)
    {
      if (refined == 8)
        break;
      double mu = u0 + (u1 - u0) * (c.second.first + 0.5) / n,
             mv = v0 + (v1 - v0) * (c.second.second + 0.5) / n;
      if ((mu == bu && mv == bv) || !OnFace(F, mu, mv))
        continue;
      ++refined;
      const double d = refine(mu, mv, c.first);
      if (d < best)
      {
        best = d;
        bu = mu;
        bv = mv;
      }
    }
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
        if (OnFace(F, u, v))
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
double CheckedDistance(const TopoDS_Shape& shape, const gp_Pnt& X, int grid, gp_Pnt* at,
  TopoDS_Face* onFace)
{
  const TopoDS_Vertex V = BRepBuilderAPI_MakeVertex(X).Vertex();
  TopTools_MapOfShape dropped;
  std::vector<TopoDS_Face> droppedFaces;
  TopoDS_Shape rest = shape;
  double best = std::numeric_limits<double>::max();
  gp_Pnt bestAt;
  TopoDS_Face bestFace;
  for (int round = 0; round <= 8; ++round)
  {
    BRepExtrema_DistShapeShape dist(V, rest, Extrema_ExtFlag_MIN);
    if (!dist.IsDone())
      return -1.0;
    if (dist.NbSolution() == 0)
      break;
    // The solutions all lie at the distance found: one that is really on its face (or an edge or
    // vertex) settles it; the faces whose solutions are off them are dropped.
    bool trusted = false;
    std::vector<TopoDS_Face> off;
    for (int i = 1; i <= dist.NbSolution() && !trusted; ++i)
    {
      TopoDS_Face F; // null on an edge or a vertex
      if (dist.SupportTypeShape2(i) == BRepExtrema_IsInFace)
      {
        F = TopoDS::Face(dist.SupportOnShape2(i));
        double u, v;
        dist.ParOnFaceS2(i, u, v);
        if (!OnFace(F, u, v))
        {
          off.push_back(F);
          continue;
        }
      }
      trusted = true;
      if (dist.Value() < best)
      {
        best = dist.Value();
        bestAt = dist.PointOnShape2(i);
        bestFace = F;
      }
    }
    if (trusted || off.empty())
      break;
    if (round == 8)
      return -1.0; // (not seen)
    for (const TopoDS_Face& F : off)
      if (dropped.Add(F))
        droppedFaces.push_back(F);
    BRep_Builder b;
    TopoDS_Compound c;
    b.MakeCompound(c);
    int kept = 0;
    for (TopExp_Explorer ex(shape, TopAbs_FACE); ex.More(); ex.Next())
      if (!dropped.Contains(ex.Current()))
      {
        b.Add(c, ex.Current());
        ++kept;
      }
    if (kept == 0)
      break;
    rest = c;
  }
  // The dropped faces, each measured by the extremum searches and the grid.
  if (!droppedFaces.empty())
  {
    gp_Pnt P;
    int f = -1;
    const double d = ExtremaDistance(droppedFaces, FaceBoxes(droppedFaces), X,
      std::numeric_limits<double>::max(), {}, &P, &f, grid);
    if (d < best)
    {
      best = d;
      bestAt = P;
      bestFace = f >= 0 ? droppedFaces[static_cast<size_t>(f)] : TopoDS_Face();
    }
  }
  if (!(best < std::numeric_limits<double>::max()))
    return -1.0;
  if (at)
    *at = bestAt;
  if (onFace)
    *onFace = bestFace;
  return best;
}

const char* RayAgreementName(RayAgreement a)
{
  switch (a)
  {
    case RayAgreement::Within:
      return "within 1e-4 relative";
    case RayAgreement::Glancing:
      return "glancing";
    case RayAgreement::Grazing:
      return "grazing";
    case RayAgreement::ExactOff:
      return "OpenCASCADE's point off the faces";
    case RayAgreement::ExactTouch:
      return "OpenCASCADE's hit a touch";
    case RayAgreement::Other:
      return "other";
    case RayAgreement::OursAlone:
      return "ours alone";
    case RayAgreement::ExactAlone:
      return "OpenCASCADE's alone";
    case RayAgreement::Neither:
      return "neither";
    case RayAgreement::ExactFailed:
      return "OpenCASCADE failed";
  }
  return "?";
}

RayAgreement CompareRay(double ours, IntCurvesFace_ShapeIntersector& in, const TopoDS_Shape& shape,
  const gp_Pnt& O, const gp_Dir& d, double sMin, double tolerance, double* exactOut)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (exactOut)
    *exactOut = nan;
  try
  {
    in.Perform(gp_Lin(O, d), sMin, RealLast());
  }
  catch (const Standard_Failure&)
  {
    return RayAgreement::ExactFailed; // (its intersector throws on some faces: a null curve)
  }
  double first = std::numeric_limits<double>::infinity();
  int at = 0;
  for (int i = 1; in.IsDone() && i <= in.NbPnt(); ++i)
    if (in.WParameter(i) > sMin && in.WParameter(i) < first)
    {
      first = in.WParameter(i);
      at = i;
    }
  const bool hitOurs = std::isfinite(ours), hitExact = at > 0;
  if (hitExact && exactOut)
    *exactOut = first;
  if (!hitOurs || !hitExact)
    return hitOurs ? RayAgreement::OursAlone
                   : (hitExact ? RayAgreement::ExactAlone : RayAgreement::Neither);
  if (std::fabs(ours - first) <= 1e-4 * first)
    return RayAgreement::Within;
  // A point's distance from the exact faces: about 0 where the ray meets a face there.
  auto off = [&](double s) {
    BRepExtrema_DistShapeShape dist(
      BRepBuilderAPI_MakeVertex(O.Translated(s * gp_Vec(d))).Vertex(), shape);
    return dist.IsDone() ? dist.Value() : std::numeric_limits<double>::infinity();
  };
  // Along the ray the patches' accuracy is that over the cosine between the ray and the face's
  // normal at OpenCASCADE's hit.
  double cosine = 0.0;
  {
    BRepAdaptor_Surface S(in.Face(at));
    gp_Pnt P;
    gp_Vec Du, Dv;
    S.D1(in.UParameter(at), in.VParameter(at), P, Du, Dv);
    const gp_Vec n = Du.Crossed(Dv);
    if (n.Magnitude() > 0.0)
      cosine = std::fabs(n.Normalized().Dot(gp_Vec(d)));
  }
  const double oursOff = off(ours);
  if (std::fabs(ours - first) * cosine <= 2.0 * tolerance && oursOff <= 2.0 * tolerance)
    return RayAgreement::Glancing;
  if (ours < first && oursOff <= 2.0 * tolerance)
    return RayAgreement::Grazing;
  if (off(first) > tolerance)
    return RayAgreement::ExactOff;
  if (first < ours &&
    (in.Transition(at) == IntCurveSurface_Tangent || in.State(at) == TopAbs_ON))
    return RayAgreement::ExactTouch;
  return RayAgreement::Other;
}
} // namespace exact
} // namespace brt
