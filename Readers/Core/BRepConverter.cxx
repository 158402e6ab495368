#include "BRepConverter.h"
#include "CoincidentFaces.h"
#include "CurvesOnFaces.h"
#include "FaceSide.h"
#include "StepScan.h"

#include "Bezier.h"
#include "TouchingBodies.h"
#include "ModelIO.h"
#include "StepFile.h"

#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <Precision.hxx>
#include <TopTools_MapOfShape.hxx>
#include <ShapeBuild_Edge.hxx>
#include <ShapeAnalysis_Curve.hxx>
#include <GCPnts_AbscissaPoint.hxx>
#include <BRepBndLib.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <ShapeAnalysis_Surface.hxx>
#include <BRepBuilderAPI_NurbsConvert.hxx>
#include <BRepBuilderAPI_Copy.hxx>
#include <BRepBuilderAPI_MakeSolid.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepTools_ReShape.hxx>
#include <BRep_Builder.hxx>
#include <IMeshTools_Parameters.hxx>
#include <BRepLib.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepTopAdaptor_FClass2d.hxx>
#include <BRepTools.hxx>
#include <BRepTools_WireExplorer.hxx>
#include <BRep_Tool.hxx>
#include <BRepGProp.hxx>
#include <GProp_GProps.hxx>
#include <Bnd_Box.hxx>
#include <Geom2dConvert_ApproxCurve.hxx>
#include <Geom2dConvert_BSplineCurveToBezierCurve.hxx>
#include <Geom2d_BSplineCurve.hxx>
#include <Geom2d_BezierCurve.hxx>
#include <Geom2d_Line.hxx>
#include <Geom2d_TrimmedCurve.hxx>
#include <Geom2dAPI_ProjectPointOnCurve.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <GeomConvert_ApproxCurve.hxx>
#include <GeomConvert_BSplineCurveToBezierCurve.hxx>
#include <GeomConvert_BSplineSurfaceToBezierSurface.hxx>
#include <Geom_BSplineCurve.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_ElementarySurface.hxx>
#include <Geom_BezierCurve.hxx>
#include <Geom_BezierSurface.hxx>
#include <Geom_ConicalSurface.hxx>
#include <Geom_CylindricalSurface.hxx>
#include <Geom_Line.hxx>
#include <Geom_OffsetCurve.hxx>
#include <Geom_OffsetSurface.hxx>
#include <Geom_Plane.hxx>
#include <Geom_RectangularTrimmedSurface.hxx>
#include <Geom_SphericalSurface.hxx>
#include <Geom_SurfaceOfLinearExtrusion.hxx>
#include <Geom_SurfaceOfRevolution.hxx>
#include <Geom_ToroidalSurface.hxx>
#include <Geom_TrimmedCurve.hxx>
#include <Poly_PolygonOnTriangulation.hxx>
#include <Poly_Triangulation.hxx>
#include <ShapeCustom_Surface.hxx>
#include <ShapeFix_Shape.hxx>
#include <Standard_Failure.hxx>
#include <TColGeom_Array2OfBezierSurface.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Iterator.hxx>
#include <TopoDS_Vertex.hxx>
#include <TopoDS_Wire.hxx>
#include <gp_Ax3.hxx>
#include <math_Jacobi.hxx>
#include <math_Matrix.hxx>
#include <gp_Pnt.hxx>
#include <gp_Pnt2d.hxx>
#include <gp_Vec.hxx>

#include <array>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <memory>
#include <numeric>
#include <queue>
#include <random>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

namespace brt
{

const char* SurfaceKindName(SurfaceKind kind)
{
  switch (kind)
  {
    case SurfaceKind::Plane: return "plane";
    case SurfaceKind::Cylinder: return "cylinder";
    case SurfaceKind::Cone: return "cone";
    case SurfaceKind::Sphere: return "sphere";
    case SurfaceKind::Torus: return "torus";
    case SurfaceKind::BezierSurface: return "bezier";
    case SurfaceKind::BSplineSurface: return "bspline";
    case SurfaceKind::SurfaceOfRevolution: return "revolution";
    case SurfaceKind::SurfaceOfExtrusion: return "extrusion";
    case SurfaceKind::OffsetSurface: return "offset";
    case SurfaceKind::Other: break;
  }
  return "other";
}

namespace
{
using Clock = std::chrono::steady_clock;
double Since(Clock::time_point t0)
{
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// The principal curvatures of a surface at a point from its derivatives there, n its unit
/// outward normal: positive where the surface bends away from n (convex seen from outside,
/// towards the material), the largest first; zeros where the first fundamental form is
/// singular. The eigenvalues of the shape operator I^-1 II with II taken along -n.
std::array<double, 2> PrincipalConvexity(const gp_Vec& du, const gp_Vec& dv, const gp_Vec& duu,
  const gp_Vec& dvv, const gp_Vec& duv, const gp_Vec& n)
{
  const double E = du.Dot(du), F = du.Dot(dv), G = dv.Dot(dv);
  const double L = -duu.Dot(n), M = -duv.Dot(n), N = -dvv.Dot(n);
  const double A = E * G - F * F;
  if (!(A > 1e-24 * std::max(1.0, E * G)) || n.Magnitude() < 0.5)
    return { 0.0, 0.0 };
  const double H = 0.5 * (E * N + G * L - 2.0 * F * M) / A, K = (L * N - M * M) / A;
  const double s = std::sqrt(std::max(0.0, H * H - K));
  const std::array<double, 2> c{ H + s, H - s };
  return std::isfinite(c[0]) && std::isfinite(c[1]) ? c : std::array<double, 2>{ 0.0, 0.0 };
}

// ---------------------------------------------------------------------------------------------
// Surfaces
// ---------------------------------------------------------------------------------------------
Handle(Geom_Surface) Unwrap(Handle(Geom_Surface) s)
{
  while (auto t = Handle(Geom_RectangularTrimmedSurface)::DownCast(s))
    s = t->BasisSurface();
  return s;
}

/// Runs work(i) for i in [0, count) on every core, items taken in turn; the calling thread works
/// too and calls report(finished) after each of its items (the progress, which may throw to
/// abort). The first failure in any thread stops the others after their item and is rethrown
/// here.
template <class Work, class Report>
void OnEveryCore(int count, Work&& work, Report&& report)
{
  std::atomic<int> next{ 0 }, done{ 0 };
  std::mutex failureMutex;
  std::exception_ptr failure;
  auto run = [&](bool reporting) {
    for (int i = next++; i < count; i = next++)
    {
      try
      {
        work(i);
        const int finished = ++done;
        if (reporting)
          report(finished);
      }
      catch (...)
      {
        const std::lock_guard<std::mutex> lock(failureMutex);
        if (!failure)
          failure = std::current_exception();
        next = count; // the others stop after their item
        return;
      }
    }
  };
  std::vector<std::thread> helpers;
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  for (unsigned k = 1; k < cores && static_cast<int>(k) < count; ++k)
    helpers.emplace_back(run, false);
  run(true);
  for (std::thread& h : helpers)
    h.join();
  if (failure)
    std::rethrow_exception(failure);
}

/// Face::Exact from a point, a direction and two sizes.
void SetExact(std::array<double, 8>& exact, const gp_Ax3& a, double p1, double p2)
{
  const gp_Pnt& o = a.Location();
  const gp_Dir& z = a.Direction();
  exact = { o.X(), o.Y(), o.Z(), z.X(), z.Y(), z.Z(), p1, p2 };
}

/// The face's kind and, for an analytic surface, its exact description (BRepModel::FaceExact).
void Classify(const Handle(Geom_Surface)& surface, Face& face, std::array<double, 8>& exact)
{
  const Handle(Geom_Surface) s = Unwrap(surface);
  exact = {};
  if (auto pl = Handle(Geom_Plane)::DownCast(s))
  {
    face.Kind = SurfaceKind::Plane;
    SetExact(exact, pl->Position(), 0.0, 0.0);
  }
  else if (auto cy = Handle(Geom_CylindricalSurface)::DownCast(s))
  {
    face.Kind = SurfaceKind::Cylinder;
    SetExact(exact, cy->Position(), cy->Radius(), 0.0);
  }
  else if (auto co = Handle(Geom_ConicalSurface)::DownCast(s))
  {
    face.Kind = SurfaceKind::Cone;
    SetExact(exact, co->Position(), co->RefRadius(), co->SemiAngle());
  }
  else if (auto sp = Handle(Geom_SphericalSurface)::DownCast(s))
  {
    face.Kind = SurfaceKind::Sphere;
    SetExact(exact, sp->Position(), sp->Radius(), 0.0);
  }
  else if (auto to = Handle(Geom_ToroidalSurface)::DownCast(s))
  {
    face.Kind = SurfaceKind::Torus;
    SetExact(exact, to->Position(), to->MajorRadius(), to->MinorRadius());
  }
  else if (auto bz = Handle(Geom_BezierSurface)::DownCast(s))
  {
    face.Kind = SurfaceKind::BezierSurface;
    face.Rational = bz->IsURational() || bz->IsVRational();
    face.DegreeU = bz->UDegree();
    face.DegreeV = bz->VDegree();
  }
  else if (auto bs = Handle(Geom_BSplineSurface)::DownCast(s))
  {
    face.Kind = SurfaceKind::BSplineSurface;
    face.Rational = bs->IsURational() || bs->IsVRational();
    face.DegreeU = bs->UDegree();
    face.DegreeV = bs->VDegree();
  }
  else if (s->IsKind(STANDARD_TYPE(Geom_SurfaceOfRevolution)))
    face.Kind = SurfaceKind::SurfaceOfRevolution;
  else if (auto ex = Handle(Geom_SurfaceOfLinearExtrusion)::DownCast(s))
  {
    face.Kind = SurfaceKind::SurfaceOfExtrusion;
    // A B-spline or Bezier curve swept along a line is a B-spline surface of degree 1 along the
    // line (v): the degrees tell the solver where the patches are the surface
    // (PatchesAreTheSurface: an extruded polynomial cubic converts exactly).
    Handle(Geom_Curve) c = ex->BasisCurve();
    while (auto tc = Handle(Geom_TrimmedCurve)::DownCast(c))
      c = tc->BasisCurve();
    if (auto bc = Handle(Geom_BSplineCurve)::DownCast(c))
    {
      face.Rational = bc->IsRational();
      face.DegreeU = bc->Degree();
      face.DegreeV = 1;
    }
    else if (auto zc = Handle(Geom_BezierCurve)::DownCast(c))
    {
      face.Rational = zc->IsRational();
      face.DegreeU = zc->Degree();
      face.DegreeV = 1;
    }
  }
  else if (s->IsKind(STANDARD_TYPE(Geom_OffsetSurface)))
    face.Kind = SurfaceKind::OffsetSurface;
  else
    face.Kind = SurfaceKind::Other;
}

/// Adds the equation row . x = rhs to least-squares normal equations [A | b].
template <int N>
void AddEquation(double (&A)[N][N + 1], const double (&row)[N], double rhs)
{
  for (int a = 0; a < N; ++a)
  {
    for (int b = 0; b < N; ++b)
      A[a][b] += row[a] * row[b];
    A[a][N] += row[a] * rhs;
  }
}

/// Gauss-Jordan elimination with partial pivoting on least-squares normal equations [A | b]:
/// afterwards x_i = A[i][N] / A[i][i]. False where a pivot falls below 1e-12 of the largest
/// diagonal entry (the points do not determine the fit).
template <int N>
bool SolveNormalEquations(double (&A)[N][N + 1])
{
  double scale = 0.0;
  for (int a = 0; a < N; ++a)
    scale = std::max(scale, std::fabs(A[a][a]));
  for (int c = 0; c < N; ++c)
  {
    int piv = c;
    for (int r = c + 1; r < N; ++r)
      if (std::fabs(A[r][c]) > std::fabs(A[piv][c]))
        piv = r;
    if (!(std::fabs(A[piv][c]) > 1e-12 * scale))
      return false;
    for (int k = 0; k <= N; ++k)
      std::swap(A[c][k], A[piv][k]);
    for (int r = 0; r < N; ++r)
      if (r != c)
      {
        const double f = A[r][c] / A[c][c];
        for (int k = c; k <= N; ++k)
          A[r][k] -= f * A[c][k];
      }
  }
  return true;
}

/// The sphere through the surface's points on a 5 x 5 grid of the domain, by least squares on
/// x^2 + y^2 + z^2 + D x + E y + F z + G = 0 (relative to the first point); null where they are
/// (nearly) coplanar. OpenCASCADE 7.6's ShapeCustom_Surface finds no sphere in a B-spline.
Handle(Geom_Surface) FitSphere(const Handle(Geom_Surface)& surface, const std::array<double, 4>& d)
{
  std::vector<gp_XYZ> pts;
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; j <= 4; ++j)
      pts.push_back(
        surface->Value(d[0] + (d[1] - d[0]) * i / 4.0, d[2] + (d[3] - d[2]) * j / 4.0).XYZ());
  const gp_XYZ o = pts[0];
  double A[4][5] = {};
  for (const gp_XYZ& q : pts)
  {
    const gp_XYZ p = q - o;
    const double row[4] = { p.X(), p.Y(), p.Z(), 1.0 };
    AddEquation(A, row, -p.SquareModulus());
  }
  if (!SolveNormalEquations(A))
    return nullptr;
  const gp_XYZ centre = o - 0.5 * gp_XYZ(A[0][4] / A[0][0], A[1][4] / A[1][1], A[2][4] / A[2][2]);
  const double r2 = (centre - o).SquareModulus() - A[3][4] / A[3][3];
  if (!(r2 > 0.0))
    return nullptr;
  return new Geom_SphericalSurface(gp_Ax3(gp_Pnt(centre), gp_Dir(0, 0, 1)), std::sqrt(r2));
}

/// The cylinder through the surface's points on a 17 x 17 grid of the domain: its axis the
/// direction all the surface normals there are perpendicular to (the eigenvector of the sum of
/// n n^T with the least eigenvalue, which must be about 0 while the next is not), its circle
/// fitted by least squares to the points projected along the axis (x^2 + y^2 + D x + E y + F = 0,
/// relative to their mean). Null where the normals do not lie in one plane or the projected
/// points lie on a line. OpenCASCADE 7.6's ShapeCustom_Surface misses some cylinders written as
/// B-splines: every one of the 70 round faces of its own assembly sample as1-oc-214 (rational in
/// the degree-1 direction, cubic around), cylinders within 7e-11 mm.
Handle(Geom_Surface) FitCylinder(const Handle(Geom_Surface)& surface, const std::array<double, 4>& d)
{
  constexpr int n = 16;
  std::vector<gp_Pnt> points;
  math_Matrix nn(1, 3, 1, 3, 0.0);
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j)
    {
      gp_Pnt p;
      gp_Vec du, dv;
      surface->D1(d[0] + (d[1] - d[0]) * i / n, d[2] + (d[3] - d[2]) * j / n, p, du, dv);
      gp_Vec normal = du.Crossed(dv);
      if (!(normal.Magnitude() > 1e-12 * std::max(1.0, du.Magnitude() * dv.Magnitude())))
        continue;
      normal.Normalize();
      points.push_back(p);
      const double c[3] = { normal.X(), normal.Y(), normal.Z() };
      for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 3; ++k)
          nn(r + 1, k + 1) += c[r] * c[k];
    }
  const double count = static_cast<double>(points.size());
  if (points.size() < 9)
    return nullptr;
  math_Jacobi eigen(nn);
  if (!eigen.IsDone())
    return nullptr;
  int least = 1;
  for (int k = 2; k <= 3; ++k)
    if (eigen.Value(k) < eigen.Value(least))
      least = k;
  double next = std::numeric_limits<double>::max();
  for (int k = 1; k <= 3; ++k)
    if (k != least)
      next = std::min(next, eigen.Value(k));
  // Normals within 1e-6 rad of perpendicular to the axis, and spread around it.
  if (!(eigen.Value(least) <= 1e-12 * count && next >= 1e-6 * count))
    return nullptr;
  math_Vector axis(1, 3);
  eigen.Vector(least, axis);
  const gp_Dir a(axis(1), axis(2), axis(3));
  const gp_Dir e1 = std::fabs(a.X()) < 0.9 ? a.Crossed(gp_Dir(1, 0, 0)) : a.Crossed(gp_Dir(0, 1, 0));
  const gp_Dir e2 = a.Crossed(e1);
  gp_XYZ mean(0, 0, 0);
  for (const gp_Pnt& p : points)
    mean += p.XYZ() / count;
  double A[3][4] = {};
  for (const gp_Pnt& p : points)
  {
    const gp_XYZ w = p.XYZ() - mean;
    const double x = w.Dot(e1.XYZ()), y = w.Dot(e2.XYZ()), row[3] = { x, y, 1.0 };
    AddEquation(A, row, -(x * x + y * y));
  }
  if (!SolveNormalEquations(A))
    return nullptr;
  const double D = A[0][3] / A[0][0], E = A[1][3] / A[1][1], F = A[2][3] / A[2][2];
  const double cx = -0.5 * D, cy = -0.5 * E, r2 = cx * cx + cy * cy - F;
  if (!(r2 > 0.0) || !std::isfinite(r2))
    return nullptr;
  const gp_Pnt centre(mean + cx * e1.XYZ() + cy * e2.XYZ());
  return new Geom_CylindricalSurface(gp_Ax3(centre, a, e1), std::sqrt(r2));
}

/// A B-spline or Bezier surface that is a plane, cylinder, cone, sphere or torus within
/// `tolerance` over the face's domain (some CAD systems write every round or hole as a rational
/// B-spline): that surface, found by OpenCASCADE's ShapeCustom_Surface or else fitted to the
/// surface's points (a sphere, which it does not find; a cylinder, which it misses in some
/// parametrisations) and confirmed here on a 33 x 33 grid of the domain: each of those points of
/// the surface lies within `tolerance` of it; null otherwise.
Handle(Geom_Surface) RecogniseAnalytic(
  const Handle(Geom_Surface)& surface, const std::array<double, 4>& d, double tolerance)
{
  Handle(Geom_Surface) analytic;
  try
  {
    ShapeCustom_Surface sc(surface);
    analytic = sc.ConvertToAnalytical(tolerance, Standard_False);
    if (!analytic.IsNull() && !(sc.Gap() <= tolerance))
      analytic.Nullify();
    // The candidates in turn: OpenCASCADE's, a fitted sphere, a fitted cylinder; the first that
    // every grid point confirms.
    for (int candidate = 0; candidate < 3; ++candidate)
    {
      if (candidate == 1)
        analytic = FitSphere(surface, d);
      else if (candidate == 2)
        analytic = FitCylinder(surface, d);
      if (analytic.IsNull())
        continue;
      bool confirmed = true;
      for (int i = 0; i <= 32 && confirmed; ++i)
        for (int j = 0; j <= 32 && confirmed; ++j)
        {
          const gp_Pnt P =
            surface->Value(d[0] + (d[1] - d[0]) * i / 32.0, d[2] + (d[3] - d[2]) * j / 32.0);
          // OpenCASCADE's projection, in closed form on these surfaces (Extrema_ExtPElS).
          GeomAPI_ProjectPointOnSurf proj(P, analytic);
          const double e = proj.NbPoints() > 0 ? proj.LowerDistance() : -1.0;
          confirmed = e >= 0.0 && e <= tolerance;
        }
      if (confirmed)
        return analytic;
    }
  }
  catch (const Standard_Failure&)
  {
    return nullptr;
  }
  return nullptr;
}

/// A face's patches before they are appended to the model: a nu x nv grid, u fastest.
struct PatchGrid
{
  int NU = 0, NV = 0;
  std::vector<BezierPatch> Patches;
};

BezierPatch FromBezier(Handle(Geom_BezierSurface) bz, double u0, double u1, double v0, double v1)
{
  if (bz->UDegree() < 3 || bz->VDegree() < 3)
  {
    bz = Handle(Geom_BezierSurface)::DownCast(bz->Copy());
    bz->Increase(3, 3);
  }
  BezierPatch p;
  p.Domain = { u0, u1, v0, v1 };
  for (int i = 0; i < 4; ++i)
  {
    for (int j = 0; j < 4; ++j)
    {
      const gp_Pnt& q = bz->Pole(i + 1, j + 1);
      double* c = &p.ControlPoints[(4 * i + j) * 3];
      c[0] = q.X();
      c[1] = q.Y();
      c[2] = q.Z();
    }
  }
  return p;
}

PatchGrid FromBSpline(const Handle(Geom_BSplineSurface)& bs)
{
  GeomConvert_BSplineSurfaceToBezierSurface conv(bs);
  PatchGrid grid;
  grid.NU = conv.NbUPatches();
  grid.NV = conv.NbVPatches();
  TColStd_Array1OfReal uk(1, grid.NU + 1), vk(1, grid.NV + 1);
  conv.UKnots(uk);
  conv.VKnots(vk);
  for (int j = 1; j <= grid.NV; ++j)
  {
    for (int i = 1; i <= grid.NU; ++i)
    {
      grid.Patches.push_back(
        FromBezier(conv.Patch(i, j), uk(i), uk(i + 1), vk(j), vk(j + 1)));
    }
  }
  return grid;
}

/// An affine surface (plane) restricted to a rectangle is exactly the bicubic patch whose control
/// points are its values at the thirds of the rectangle.
PatchGrid PlanePatches(const Handle(Geom_Surface)& s, const std::array<double, 4>& d)
{
  PatchGrid grid;
  grid.NU = grid.NV = 1;
  BezierPatch p;
  p.Domain = d;
  for (int i = 0; i < 4; ++i)
  {
    for (int j = 0; j < 4; ++j)
    {
      const gp_Pnt q = s->Value(d[0] + (d[1] - d[0]) * i / 3.0, d[2] + (d[3] - d[2]) * j / 3.0);
      double* c = &p.ControlPoints[(4 * i + j) * 3];
      c[0] = q.X();
      c[1] = q.Y();
      c[2] = q.Z();
    }
  }
  grid.Patches.push_back(p);
  return grid;
}

/// Exact conversion of a polynomial B-spline or Bezier surface of degree <= 3; empty if the
/// surface is not of that kind.
PatchGrid ExactPatches(const Handle(Geom_Surface)& surface, const std::array<double, 4>& d)
{
  const Handle(Geom_Surface) s = Unwrap(surface);
  Handle(Geom_BSplineSurface) bs = Handle(Geom_BSplineSurface)::DownCast(s);
  if (bs.IsNull() || bs->IsURational() || bs->IsVRational() || bs->UDegree() > 3 ||
    bs->VDegree() > 3)
  {
    return {};
  }
  bs = Handle(Geom_BSplineSurface)::DownCast(bs->Copy());
  if (bs->IsUPeriodic())
    bs->SetUNotPeriodic();
  if (bs->IsVPeriodic())
    bs->SetVNotPeriodic();
  double U1, U2, V1, V2;
  bs->Bounds(U1, U2, V1, V2);
  // Faces on periodic B-splines may use a shifted parameter range: leave those to the
  // approximation, which evaluates the surface wherever the face lies.
  const double eps = 1e-9 * std::max(1.0, std::max(std::fabs(U2 - U1), std::fabs(V2 - V1)));
  if (d[0] < U1 - eps || d[1] > U2 + eps || d[2] < V1 - eps || d[3] > V2 + eps)
  {
    return {};
  }
  const double u0 = std::max(d[0], U1), u1 = std::min(d[1], U2);
  const double v0 = std::max(d[2], V1), v1 = std::min(d[3], V2);
  if (u1 - u0 <= eps || v1 - v0 <= eps)
  {
    return {};
  }
  bs->Segment(u0, u1, v0, v1);
  return FromBSpline(bs);
}

/// How a patch fits the surface along one direction: four conditions on the cubic, each the
/// value (Derivative false) or the first derivative at a local parameter t in [0, 1].
/// - Hermite: the value and the derivative at both ends. Neighbouring patches join with C1
///   continuity, and the patches match the surface's tangent planes at every grid corner. Faces
///   with an exact surface (a plane, cylinder, cone, sphere or torus, also one recognised in a
///   B-spline) take it: there the solver bounds the patches by their measured deviation and
///   finishes on the exact surface, and the Hermite fit's deviation, below the tolerance by the
///   grid's halvings, keeps those bounds tight (interpolated, they were tried and not kept:
///   docs/Design.md).
/// - Interpolation, on free-form faces (rational and high-degree B-splines, offsets, sweeps),
///   whose patches are the solver's surface. Inside the face the cubic interpolates the surface
///   at its ends and at 1 - 1/sqrt(2), 1/sqrt(2): there the error factor
///   t (t - a) (t - 1 + a) (t - 1) has its three extremes equal, a sixth of the Hermite factor
///   t^2 (t - 1)^2, so patches may be 1.5 times as long for the same error (the Ploopy
///   headband, 276 rational faces of 506: 19,392 patches -> 11,064). At an end on the face's
///   boundary it takes the value and the derivative there (and the value at 0.64 inside, the
///   factor t^2 (t - 0.64) (t - 1), 0.37 of Hermite's), so that the face keeps its exact tangent
///   plane along its boundary and faces tangent along an edge stay tangent on the patches.
///   Neighbouring patches share their boundary curves (C0 inside a face).
struct FitScheme
{
  double T[4];
  bool Derivative[4];
};

/// The four schemes, by whether the patch's low and high ends lie on the face's boundary.
const FitScheme& SchemeFor(bool lowOnBoundary, bool highOnBoundary)
{
  static const FitScheme schemes[4] = {
    { { 0.0, 0.29289321881345248, 0.70710678118654752, 1.0 }, { false, false, false, false } },
    { { 0.0, 0.0, 0.64, 1.0 }, { false, true, false, false } },
    { { 0.0, 0.36, 1.0, 1.0 }, { false, false, false, true } },
    { { 0.0, 0.0, 1.0, 1.0 }, { false, true, false, true } }, // Hermite
  };
  return schemes[(lowOnBoundary ? 1 : 0) + (highOnBoundary ? 2 : 0)];
}

/// The inverse of the 4 x 4 matrix of the scheme's conditions on the cubic Bernstein basis
/// (row k: B_i(T[k]) or B_i'(T[k])): control points = inverse * conditions' values.
std::array<std::array<double, 4>, 4> InverseConditions(const FitScheme& scheme)
{
  std::array<std::array<double, 4>, 4> inverse{};
  for (int column = 0; column < 4; ++column) // the conditions' matrix against each unit vector
  {
    double a[4][5];
    for (int k = 0; k < 4; ++k)
    {
      const Bernstein3 b(scheme.T[k]);
      for (int c = 0; c < 4; ++c)
        a[k][c] = scheme.Derivative[k] ? b.D[c] : b.B[c];
      a[k][4] = k == column ? 1.0 : 0.0;
    }
    SolveNormalEquations(a); // the schemes' matrices are regular (distinct nodes or orders)
    for (int r = 0; r < 4; ++r)
      inverse[r][column] = a[r][4] / a[r][r];
  }
  return inverse;
}

/// InverseConditions of SchemeFor(low, high), computed once.
const std::array<std::array<double, 4>, 4>& InverseFor(bool lowOnBoundary, bool highOnBoundary)
{
  static const std::array<std::array<double, 4>, 4> inverses[4] = {
    InverseConditions(SchemeFor(false, false)), InverseConditions(SchemeFor(true, false)),
    InverseConditions(SchemeFor(false, true)), InverseConditions(SchemeFor(true, true)) };
  return inverses[(lowOnBoundary ? 1 : 0) + (highOnBoundary ? 2 : 0)];
}

/// The bicubic patch on [u0,u1]x[v0,v1] that meets the tensor product of the two directions'
/// schemes (SchemeFor: whether each end lies on the face's boundary). It keeps the surface's own
/// (u,v) parametrisation: the trims, in that parameter space, stay valid on the patches. The
/// surface is evaluated once at each distinct node pair, to the order its conditions ask there
/// (a Hermite patch: D2 at its four corners, as the Hermite fit always did).
BezierPatch FittedPatch(const Handle(Geom_Surface)& s, double u0, double u1, double v0, double v1,
  bool uLow, bool uHigh, bool vLow, bool vHigh)
{
  const FitScheme &su = SchemeFor(uLow, uHigh), &sv = SchemeFor(vLow, vHigh);
  const std::array<std::array<double, 4>, 4>&iu = InverseFor(uLow, uHigh),
                                             &iv = InverseFor(vLow, vHigh);
  // Each condition's node, as an index into the direction's distinct nodes, and whether a
  // derivative is asked at that node.
  struct Nodes
  {
    int Count = 0, Of[4] = {};
    double T[4] = {};
    bool Derivative[4] = {};
  };
  auto nodesOf = [](const FitScheme& scheme) {
    Nodes n;
    for (int k = 0; k < 4; ++k)
    {
      int at = 0;
      while (at < n.Count && n.T[at] != scheme.T[k])
        ++at;
      if (at == n.Count)
        n.T[n.Count++] = scheme.T[k];
      n.Of[k] = at;
      n.Derivative[at] = n.Derivative[at] || scheme.Derivative[k];
    }
    return n;
  };
  const Nodes nu = nodesOf(su), nv = nodesOf(sv);
  // Derivatives with respect to the local parameters: d/dt = (u1 - u0) d/du.
  const double hu = u1 - u0, hv = v1 - v0;
  gp_XYZ P[4][4], Su[4][4], Sv[4][4], Suv[4][4];
  for (int a = 0; a < nu.Count; ++a)
    for (int b = 0; b < nv.Count; ++b)
    {
      const double u = u0 + hu * nu.T[a], v = v0 + hv * nv.T[b];
      gp_Pnt p;
      gp_Vec du, dv, duu, dvv, duv;
      if (nu.Derivative[a] && nv.Derivative[b])
      {
        s->D2(u, v, p, du, dv, duu, dvv, duv);
        Suv[a][b] = (hu * hv) * duv.XYZ();
      }
      else if (nu.Derivative[a] || nv.Derivative[b])
        s->D1(u, v, p, du, dv);
      else
        p = s->Value(u, v);
      P[a][b] = p.XYZ();
      Su[a][b] = hu * du.XYZ();
      Sv[a][b] = hv * dv.XYZ();
    }
  gp_XYZ values[4][4];
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b)
    {
      const int x = nu.Of[a], y = nv.Of[b];
      values[a][b] = su.Derivative[a] ? (sv.Derivative[b] ? Suv[x][y] : Su[x][y])
                                      : (sv.Derivative[b] ? Sv[x][y] : P[x][y]);
    }
  BezierPatch p;
  p.Domain = { u0, u1, v0, v1 };
  for (int i = 0; i < 4; ++i)
  {
    for (int j = 0; j < 4; ++j)
    {
      gp_XYZ q(0.0, 0.0, 0.0);
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b)
          q += (iu[i][a] * iv[j][b]) * values[a][b];
      double* c = &p.ControlPoints[(4 * i + j) * 3];
      c[0] = q.X();
      c[1] = q.Y();
      c[2] = q.Z();
    }
  }
  return p;
}

/// Max |patch - S| of one patch on an n x n grid of interior points, and along its u-edges
/// (v fixed, where only the u-interpolation errs) and v-edges.
struct PatchError
{
  double All = 0.0, AlongU = 0.0, AlongV = 0.0;
};
PatchError MeasureOne(const Handle(Geom_Surface)& s, const BezierPatch& p, int n)
{
  PatchError e;
  const auto& d = p.Domain;
  auto err = [&](double a, double b) {
    const double u = d[0] + (d[1] - d[0]) * a, v = d[2] + (d[3] - d[2]) * b;
    const PatchEval pe = EvaluatePatchLocal(p.ControlPoints, a, b);
    const gp_Pnt q = s->Value(u, v);
    return std::hypot(pe.P[0] - q.X(), pe.P[1] - q.Y(), pe.P[2] - q.Z());
  };
  for (int i = 1; i < n; ++i)
  {
    const double a = double(i) / n;
    e.AlongU = std::max({ e.AlongU, err(a, 0.0), err(a, 1.0) });
    e.AlongV = std::max({ e.AlongV, err(0.0, a), err(1.0, a) });
    for (int j = 1; j < n; ++j)
      e.All = std::max(e.All, err(a, double(j) / n));
  }
  e.All = std::max({ e.All, e.AlongU, e.AlongV });
  return e;
}

/// The knots strictly inside (a, b) of a curve's B-spline, through trims and offsets (an offset
/// curve keeps its basis's parameter).
void CurveKnots(Handle(Geom_Curve) c, double a, double b, std::vector<double>& out)
{
  for (;;)
  {
    if (auto t = Handle(Geom_TrimmedCurve)::DownCast(c))
      c = t->BasisCurve();
    else if (auto o = Handle(Geom_OffsetCurve)::DownCast(c))
      c = o->BasisCurve();
    else
      break;
  }
  if (auto bc = Handle(Geom_BSplineCurve)::DownCast(c))
    for (int i = 1; i <= bc->NbKnots(); ++i)
      if (bc->Knot(i) > a && bc->Knot(i) < b)
        out.push_back(bc->Knot(i));
}

/// The knots strictly inside (a, b) of one direction of a surface: a B-spline's own; through
/// trims and offsets (which keep their basis's parameters), the basis's; an extrusion's along
/// its curve (u), a revolution's along its meridian (v). A patch that straddled such a knot,
/// where the surface is less smooth, had its error outside the fit's measuring grid (forty-ninth
/// session: AnalysisSitus's 204211, 98 extrusions, 7.8e-5 measured by random points where the
/// fit's grids found half the tolerance).
void SurfaceKnots(Handle(Geom_Surface) s, bool uDir, double a, double b, std::vector<double>& out)
{
  for (;;)
  {
    if (auto t = Handle(Geom_RectangularTrimmedSurface)::DownCast(s))
      s = t->BasisSurface();
    else if (auto o = Handle(Geom_OffsetSurface)::DownCast(s))
      s = o->BasisSurface();
    else
      break;
  }
  if (auto bs = Handle(Geom_BSplineSurface)::DownCast(s))
  {
    const int n = uDir ? bs->NbUKnots() : bs->NbVKnots();
    for (int i = 1; i <= n; ++i)
    {
      const double k = uDir ? bs->UKnot(i) : bs->VKnot(i);
      if (k > a && k < b)
        out.push_back(k);
    }
  }
  else if (auto e = Handle(Geom_SurfaceOfLinearExtrusion)::DownCast(s))
  {
    if (uDir)
      CurveKnots(e->BasisCurve(), a, b, out);
  }
  else if (auto r = Handle(Geom_SurfaceOfRevolution)::DownCast(s))
  {
    if (!uDir)
      CurveKnots(r->BasisCurve(), a, b, out);
  }
}

/// Initial grid lines of one direction: the domain ends, the surface's interior knots (where it
/// may be less smooth; SurfaceKnots), and splits so that periodic (angular) directions span at
/// most pi/4.
std::vector<double> InitialBreaks(const Handle(Geom_Surface)& surface, bool uDir, double a,
  double b)
{
  std::vector<double> breaks{ a, b };
  const Handle(Geom_Surface) s = Unwrap(surface);
  SurfaceKnots(s, uDir, a, b, breaks);
  std::sort(breaks.begin(), breaks.end());
  const bool periodic = uDir ? s->IsUPeriodic() : s->IsVPeriodic();
  const double span = uDir ? (periodic ? s->UPeriod() : 0.0) : (periodic ? s->VPeriod() : 0.0);
  // Angular directions of analytic surfaces (period 2 pi) get pieces of at most pi/4.
  const bool angular = periodic && std::fabs(span - 2.0 * M_PI) < 1e-9;
  const bool sphereLat = !uDir && s->IsKind(STANDARD_TYPE(Geom_SphericalSurface));
  if (angular || sphereLat)
  {
    std::vector<double> fine;
    for (size_t i = 0; i + 1 < breaks.size(); ++i)
    {
      const int pieces = std::max(1, int(std::ceil((breaks[i + 1] - breaks[i]) / (M_PI / 4) - 1e-9)));
      for (int k = 0; k < pieces; ++k)
        fine.push_back(breaks[i] + (breaks[i + 1] - breaks[i]) * k / pieces);
    }
    fine.push_back(breaks.back());
    breaks.swap(fine);
  }
  breaks.erase(std::unique(breaks.begin(), breaks.end(),
                 [](double x, double y) { return std::fabs(x - y) < 1e-12; }),
    breaks.end());
  return breaks;
}

/// Fitted patches (FitScheme: Hermite, or interpolating where `interpolate`) on a tensor grid
/// refined until every patch is within `tol` (or the patch budget runs out): an interval is
/// halved when the error along its direction is too large. (Split instead into as many parts
/// as the error's fourth root says, faces came out no fewer: docs/Design.md, item 3.)
PatchGrid FittedPatches(const Handle(Geom_Surface)& s, const std::array<double, 4>& d, double tol,
  int maxPatches, bool interpolate)
{
  std::vector<double> us = InitialBreaks(s, true, d[0], d[1]);
  std::vector<double> vs = InitialBreaks(s, false, d[2], d[3]);
  PatchGrid grid;
  for (int round = 0; round < 16; ++round)
  {
    grid.NU = static_cast<int>(us.size()) - 1;
    grid.NV = static_cast<int>(vs.size()) - 1;
    grid.Patches.clear();
    std::vector<char> splitU(grid.NU, 0), splitV(grid.NV, 0);
    bool any = false;
    for (int j = 0; j < grid.NV; ++j)
    {
      for (int i = 0; i < grid.NU; ++i)
      {
        grid.Patches.push_back(FittedPatch(s, us[i], us[i + 1], vs[j], vs[j + 1],
          !interpolate || i == 0, !interpolate || i + 1 == grid.NU, !interpolate || j == 0,
          !interpolate || j + 1 == grid.NV));
        const PatchError e = MeasureOne(s, grid.Patches.back(), 6);
        if (e.All <= tol)
          continue;
        any = true;
        const bool u = e.AlongU > 0.25 * e.All, v = e.AlongV > 0.25 * e.All;
        if (u || !v)
          splitU[i] = 1;
        if (v || !u)
          splitV[j] = 1;
      }
    }
    const size_t nu = us.size() - 1 + std::count(splitU.begin(), splitU.end(), 1);
    const size_t nv = vs.size() - 1 + std::count(splitV.begin(), splitV.end(), 1);
    if (!any || nu * nv > static_cast<size_t>(maxPatches))
      break;
    auto refine = [](const std::vector<double>& b, const std::vector<char>& split) {
      std::vector<double> out{ b[0] };
      for (size_t i = 0; i + 1 < b.size(); ++i)
      {
        if (split[i])
          out.push_back(0.5 * (b[i] + b[i + 1]));
        out.push_back(b[i + 1]);
      }
      return out;
    };
    us = refine(us, splitU);
    vs = refine(vs, splitV);
  }
  return grid;
}

/// Splits a cubic (4 control points of `dim` doubles, stride `stride`) at tau by de Casteljau;
/// the first half goes to a, the second to b.
void SplitCubic(const double* c, int stride, int dim, double tau, double* a, double* b)
{
  for (int k = 0; k < dim; ++k)
  {
    const double p0 = c[k], p1 = c[stride + k], p2 = c[2 * stride + k], p3 = c[3 * stride + k];
    const double p01 = p0 + tau * (p1 - p0), p12 = p1 + tau * (p2 - p1), p23 = p2 + tau * (p3 - p2);
    const double p012 = p01 + tau * (p12 - p01), p123 = p12 + tau * (p23 - p12);
    const double m = p012 + tau * (p123 - p012);
    a[k] = p0;
    a[stride + k] = p01;
    a[2 * stride + k] = p012;
    a[3 * stride + k] = m;
    b[k] = m;
    b[stride + k] = p123;
    b[2 * stride + k] = p23;
    b[3 * stride + k] = p3;
  }
}

/// Splits a patch along u (dir 0) or v (dir 1) into `pieces` equal parameter parts, exactly.
std::vector<BezierPatch> SplitPatch(const BezierPatch& p, int dir, int pieces)
{
  std::vector<BezierPatch> out;
  BezierPatch rest = p;
  for (int k = 0; k < pieces - 1; ++k)
  {
    const double tau = 1.0 / (pieces - k);
    BezierPatch a = rest, b = rest;
    for (int line = 0; line < 4; ++line)
    {
      // dir 0: the cubic along u for fixed j = line (stride 12); dir 1: along v, fixed i.
      const int offset = dir == 0 ? 3 * line : 12 * line;
      const int stride = dir == 0 ? 12 : 3;
      SplitCubic(&rest.ControlPoints[offset], stride, 3, tau, &a.ControlPoints[offset],
        &b.ControlPoints[offset]);
    }
    const int lo = dir == 0 ? 0 : 2;
    const double mid = rest.Domain[lo] + tau * (rest.Domain[lo + 1] - rest.Domain[lo]);
    a.Domain[lo + 1] = mid;
    b.Domain[lo] = mid;
    out.push_back(a);
    rest = b;
  }
  out.push_back(rest);
  return out;
}

/// Length of the control polygon of a patch along u (dir 0) or v (dir 1), max over its lines.
double NetLength(const BezierPatch& p, int dir)
{
  double worst = 0.0;
  for (int line = 0; line < 4; ++line)
  {
    double l = 0.0;
    for (int k = 0; k < 3; ++k)
    {
      const int a = dir == 0 ? (4 * k + line) : (4 * line + k);
      const int b = dir == 0 ? (4 * (k + 1) + line) : (4 * line + k + 1);
      l += std::hypot(p.ControlPoints[3 * b] - p.ControlPoints[3 * a],
        p.ControlPoints[3 * b + 1] - p.ControlPoints[3 * a + 1],
        p.ControlPoints[3 * b + 2] - p.ControlPoints[3 * a + 2]);
    }
    worst = std::max(worst, l);
  }
  return worst;
}

/// Splits grid columns (and rows) whose patches are longer than maxSize, exactly (de Casteljau),
/// so that no patch is much larger than maxSize: small patches keep float evaluation accurate.
PatchGrid LimitPatchSize(const PatchGrid& g, double maxSize, int maxPatches)
{
  if (g.Patches.empty() || maxSize <= 0.0)
    return g;
  // Pieces along a net of that length, at most maxPatches + 1 (then no split is made): a face
  // without bounds spans 2e100 mm, whose count no int holds (UndefinedBehaviorSanitizer, the
  // mutation corpus); a NaN length gives 1.
  auto pieces = [&](double length) {
    const double k = std::ceil(length / maxSize);
    if (k > static_cast<double>(maxPatches))
      return maxPatches + 1;
    return k >= 1.0 ? static_cast<int>(k) : 1;
  };
  std::vector<int> cu(g.NU, 1), cv(g.NV, 1);
  for (int j = 0; j < g.NV; ++j)
    for (int i = 0; i < g.NU; ++i)
    {
      const BezierPatch& p = g.Patches[i + j * g.NU];
      cu[i] = std::max(cu[i], pieces(NetLength(p, 0)));
      cv[j] = std::max(cv[j], pieces(NetLength(p, 1)));
    }
  const long nu = std::accumulate(cu.begin(), cu.end(), 0L), nv = std::accumulate(cv.begin(), cv.end(), 0L);
  if ((nu == g.NU && nv == g.NV) || nu * nv > maxPatches)
    return g;
  PatchGrid out;
  out.NU = static_cast<int>(nu);
  out.NV = static_cast<int>(nv);
  out.Patches.resize(static_cast<size_t>(nu * nv));
  int row = 0;
  for (int j = 0; j < g.NV; ++j)
  {
    int col = 0;
    for (int i = 0; i < g.NU; ++i)
    {
      const std::vector<BezierPatch> strips = SplitPatch(g.Patches[i + j * g.NU], 0, cu[i]);
      for (int a = 0; a < cu[i]; ++a)
      {
        const std::vector<BezierPatch> cells = SplitPatch(strips[a], 1, cv[j]);
        for (int b = 0; b < cv[j]; ++b)
          out.Patches[(col + a) + (row + b) * nu] = cells[b];
      }
      col += cu[i];
    }
    row += cv[j];
  }
  return out;
}

/// Max |patch(u,v) - S(u,v)| over n random (u,v) plus the patch corners.
double MeasurePatches(const Handle(Geom_Surface)& s, const PatchGrid& grid,
  const std::array<double, 4>& d, int n, unsigned seed)
{
  if (grid.Patches.empty())
    return 0.0;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(d[0], d[1]), V(d[2], d[3]);
  auto find = [&](double u, double v) -> const BezierPatch& {
    int iu = 0, iv = 0;
    for (int i = 0; i < grid.NU - 1; ++i)
      if (u >= grid.Patches[i].Domain[1])
        iu = i + 1;
    for (int j = 0; j < grid.NV - 1; ++j)
      if (v >= grid.Patches[j * grid.NU].Domain[3])
        iv = j + 1;
    return grid.Patches[iu + iv * grid.NU];
  };
  double worst = 0.0;
  auto check = [&](double u, double v) {
    const PatchEval e = EvaluatePatch(find(u, v), u, v);
    const gp_Pnt q = s->Value(u, v);
    worst = std::max(worst, std::hypot(e.P[0] - q.X(), e.P[1] - q.Y(), e.P[2] - q.Z()));
  };
  for (int k = 0; k < n; ++k)
    check(U(rng), V(rng));
  for (const auto& p : grid.Patches)
  {
    check(p.Domain[0], p.Domain[2]);
    check(p.Domain[1], p.Domain[3]);
  }
  return worst;
}

// ---------------------------------------------------------------------------------------------
// Curves
// ---------------------------------------------------------------------------------------------
template <int N>
struct CurveSegment
{
  std::array<double, 4 * N> ControlPoints{};
  double T0 = 0.0, T1 = 0.0;
};
using Segment2 = CurveSegment<2>;
using Segment3 = CurveSegment<3>;

inline void Store(const gp_Pnt2d& p, double* c)
{
  c[0] = p.X();
  c[1] = p.Y();
}
inline void Store(const gp_Pnt& p, double* c)
{
  c[0] = p.X();
  c[1] = p.Y();
  c[2] = p.Z();
}

/// Converts a curve over [f,l] into cubic Bezier segments that keep the curve's parameter.
/// CurveT: Geom2d_Curve or Geom_Curve and their B-spline/Bezier/line/trimmed/approx types.
template <int N, class CurveT, class BSplineT, class BezierT, class LineT, class TrimmedT,
  class ToBezierT, class ApproxT>
std::vector<CurveSegment<N>> ConvertCurve(const Handle(CurveT)& curve, double f, double l,
  double tol)
{
  std::vector<CurveSegment<N>> out;
  Handle(CurveT) basis = curve;
  while (auto t = Handle(TrimmedT)::DownCast(basis))
    basis = t->BasisCurve();

  auto fromBezier = [&](Handle(BezierT) bz, double t0, double t1) {
    if (bz->Degree() < 3)
    {
      bz = Handle(BezierT)::DownCast(bz->Copy());
      bz->Increase(3);
    }
    CurveSegment<N> seg;
    seg.T0 = t0;
    seg.T1 = t1;
    for (int i = 0; i < 4; ++i)
      Store(bz->Pole(i + 1), &seg.ControlPoints[i * N]);
    out.push_back(seg);
  };
  auto fromBSpline = [&](const Handle(BSplineT)& bs) {
    ToBezierT conv(bs);
    TColStd_Array1OfReal knots(1, conv.NbArcs() + 1);
    conv.Knots(knots);
    for (int i = 1; i <= conv.NbArcs(); ++i)
      fromBezier(conv.Arc(i), knots(i), knots(i + 1));
  };

  if (basis->IsKind(STANDARD_TYPE(LineT)))
  {
    CurveSegment<N> seg;
    seg.T0 = f;
    seg.T1 = l;
    for (int i = 0; i < 4; ++i)
      Store(basis->Value(f + (l - f) * i / 3.0), &seg.ControlPoints[i * N]);
    out.push_back(seg);
    return out;
  }
  if (auto bs = Handle(BSplineT)::DownCast(basis))
  {
    if (!bs->IsRational() && bs->Degree() <= 3 && !bs->IsPeriodic() &&
      f >= bs->FirstParameter() - 1e-12 && l <= bs->LastParameter() + 1e-12)
    {
      Handle(BSplineT) copy = Handle(BSplineT)::DownCast(bs->Copy());
      copy->Segment(std::max(f, bs->FirstParameter()), std::min(l, bs->LastParameter()));
      fromBSpline(copy);
      return out;
    }
  }
  Handle(TrimmedT) trimmed = new TrimmedT(curve, f, l);
  ApproxT approx(trimmed, tol, GeomAbs_C1, 2000, 3);
  if (approx.HasResult())
  {
    fromBSpline(approx.Curve());
  }
  // A trimmed periodic curve may come back with its parameters moved by whole periods: put them
  // back into [f, l] so that segments and pcurves share the edge's parameter.
  if (!out.empty() && basis->IsPeriodic())
  {
    const double period = basis->Period();
    const double shift = std::round((f - out.front().T0) / period) * period;
    for (auto& seg : out)
    {
      seg.T0 += shift;
      seg.T1 += shift;
    }
  }
  return out;
}

std::vector<Segment2> ConvertCurve2d(const Handle(Geom2d_Curve)& c, double f, double l, double tol)
{
  return ConvertCurve<2, Geom2d_Curve, Geom2d_BSplineCurve, Geom2d_BezierCurve, Geom2d_Line,
    Geom2d_TrimmedCurve, Geom2dConvert_BSplineCurveToBezierCurve, Geom2dConvert_ApproxCurve>(
    c, f, l, tol);
}

std::vector<Segment3> ConvertCurve3d(const Handle(Geom_Curve)& c, double f, double l, double tol)
{
  return ConvertCurve<3, Geom_Curve, Geom_BSplineCurve, Geom_BezierCurve, Geom_Line,
    Geom_TrimmedCurve, GeomConvert_BSplineCurveToBezierCurve, GeomConvert_ApproxCurve>(
    c, f, l, tol);
}

double Distance(const gp_Pnt& p, const double* c)
{
  return std::hypot(p.X() - c[0], p.Y() - c[1], p.Z() - c[2]);
}

/// Max distance between the segments and the curve at the same parameter (8 points a segment).
template <int N, class CurveT>
double MeasureCurve(const Handle(CurveT)& c, const std::vector<CurveSegment<N>>& segs)
{
  double worst = 0.0;
  for (const auto& s : segs)
  {
    for (int k = 0; k <= 8; ++k)
    {
      const double r = k / 8.0;
      const auto e = EvaluateCubic<N>(s.ControlPoints.data(), r);
      worst = std::max(worst, Distance(c->Value(s.T0 + (s.T1 - s.T0) * r), e.P.data()));
    }
  }
  return worst;
}

template <int N>
void ReverseSegment(CurveSegment<N>& s)
{
  for (int i = 0; i < 2; ++i)
    for (int k = 0; k < N; ++k)
      std::swap(s.ControlPoints[i * N + k], s.ControlPoints[(3 - i) * N + k]);
  std::swap(s.T0, s.T1);
}

/// Signed area of a closed loop of cubic 2D segments (polyline with 16 points a segment).
double SignedArea(const std::vector<TrimSegment>& segs, size_t first, size_t count)
{
  double a = 0.0;
  for (size_t s = first; s < first + count; ++s)
  {
    const double* cp = segs[s].ControlPoints.data();
    auto prev = EvaluateCubic<2>(cp, 0.0).P;
    for (int k = 1; k <= 16; ++k)
    {
      const auto p = EvaluateCubic<2>(cp, k / 16.0).P;
      a += prev[0] * p[1] - p[0] * prev[1];
      prev = p;
    }
  }
  return 0.5 * a;
}

// ---------------------------------------------------------------------------------------------
// Display mesh
// ---------------------------------------------------------------------------------------------
struct BoundaryChord
{
  TopoDS_Edge Edge; ///< oriented as in the face
  double P0 = 0.0, P1 = 0.0;
};
using ChordKey = std::pair<int, int>;

/// Hash of a chord key (two vertex indices) for the refiner's edge maps, which are only looked
/// up, never walked in order.
struct ChordKeyHash
{
  size_t operator()(const ChordKey& k) const
  {
    return std::hash<uint64_t>()((static_cast<uint64_t>(static_cast<uint32_t>(k.first)) << 32) |
      static_cast<uint32_t>(k.second));
  }
};

ChordKey Key(int a, int b)
{
  return a < b ? ChordKey(a, b) : ChordKey(b, a);
}

/// The triangles on one edge of the refiner's mesh, in the order they were added: two at most
/// on a manifold mesh, held in place (a vector per edge was a heap block per edge, most of the
/// mesh step's allocations on a part of long strips); more, should a face's mesh have them, in
/// More.
struct EdgeTriangles
{
  std::array<int, 2> First{ -1, -1 };
  int Count = 0;
  std::vector<int> More;

  size_t size() const { return static_cast<size_t>(Count); }
  bool empty() const { return Count == 0; }
  int operator[](size_t i) const { return i < 2 ? First[i] : More[i - 2]; }
  void push_back(int t)
  {
    if (Count < 2)
      First[static_cast<size_t>(Count)] = t;
    else
      More.push_back(t);
    ++Count;
  }
  /// Removes every entry equal to t, keeping the others' order.
  void remove(int t)
  {
    int kept = 0;
    for (int i = 0; i < Count; ++i)
    {
      const int v = (*this)[static_cast<size_t>(i)];
      if (v == t)
        continue;
      if (kept < 2)
        First[static_cast<size_t>(kept)] = v;
      else
        More[static_cast<size_t>(kept - 2)] = v;
      ++kept;
    }
    Count = kept;
    More.resize(static_cast<size_t>(std::max(0, Count - 2)));
  }
};

/// One face's triangulation in UV, refined by conforming longest-edge bisection (Rivara's
/// LEPP): a triangle is split across its longest edge together with the neighbour that shares
/// that edge, after the neighbour's own longer edges have been split, so no T-junction appears.
/// Midpoints of boundary chords are put on the edge's pcurve, so they stay on the trimming curves.
/// An inner edge whose midpoint falls outside the face is not split, nor are its two triangles
/// after: on a face narrower than the coarse mesh's deflection (a crescent between two arcs
/// 0.0025 mm apart, joined by chords 1.7 mm long) such midpoints lay up to 0.047 mm off the
/// face, and their samples' spheres started in the air (docs/Design.md, "Display mesh").
/// With ConversionOptions::DelaunayRefinement, after each split the new triangles' edges are made
/// Delaunay on the surface (Lawson's flips, angles measured in 3D, a flip kept only where both new
/// triangles keep the orientation in UV and the new edge keeps the chordal and angular
/// deflection): bisection alone keeps the shape of the slivers the coarse mesh starts from (a
/// plane's fan of boundary vertices, a cylinder's strips along its length), and halving a
/// sliver's long diagonal halves its short side too, so the side of a rod of radius 1 mm and 1 m
/// long gets 26,345 vertices, its shortest edges 0.003 mm, where the flipped mesh has 1,374
/// (docs/Design.md, "Display mesh").
class FaceRefiner
{
public:
  /// `side`: the face's side test, shared by the face's refinements (made on first use).
  FaceRefiner(const Handle(Geom_Surface)& s, const TopoDS_Face& face, bool delaunay,
    double deflection, double angular, std::shared_ptr<FaceSide>& side)
    : Surface(s)
    , TheFace(face)
    , Delaunay(delaunay)
    , Deflection(deflection)
    , Angular(angular)
    , Side(&side)
  {
  }

  int AddVertex(const gp_Pnt2d& uv)
  {
    UV.push_back(uv);
    XYZ.push_back(Surface->Value(uv.X(), uv.Y()));
    if (Delaunay)
    {
      // The surface normal (unnormalised), which the flips' turn test reads many times.
      gp_Pnt p;
      gp_Vec du, dv;
      Surface->D1(uv.X(), uv.Y(), p, du, dv);
      Normal.push_back(du.Crossed(dv));
    }
    return static_cast<int>(UV.size()) - 1;
  }
  void AddTriangle(int a, int b, int c)
  {
    const int id = static_cast<int>(Tris.size());
    Tris.push_back({ a, b, c });
    Alive.push_back(1);
    Frozen.push_back(0);
    for (int k = 0; k < 3; ++k)
      EdgeTris[Key(Tris[id][k], Tris[id][(k + 1) % 3])].push_back(id);
  }
  void AddChord(int a, int b, const TopoDS_Edge& e, double pa, double pb)
  {
    // (An edge's polygon on a damaged face's triangulation may name no node of it: node 0 on
    // a torus whose edge the file turned round, in the mutation corpus; valgrind saw the
    // boundary marks written before their array.)
    const int n = static_cast<int>(UV.size());
    if (a < 0 || b < 0 || a >= n || b >= n)
      return;
    Chords[Key(a, b)] = { e, a < b ? pa : pb, a < b ? pb : pa };
  }

  /// Moves the coarse mesh's inner nodes that lie outside the face onto it. BRepMesh keeps a
  /// node inside its polygon of the boundary, whose chords cut across the face where a pcurve
  /// curves away from them: on the SO-ARM101 wrist (a torus of tube radius 1.2 mm, an edge whose
  /// pcurve bows 0.023 in UV off its one chord) a node of the torus's grid lay 0.03 mm off its
  /// face, and its sample's sphere started where no wall is. Such a node goes to the nearest
  /// point of the face's pcurves, 1e-2 of its distance further on (into the face), or less where
  /// that is not inside, or onto the pcurve itself; a move that would turn one of its triangles
  /// over in UV is not made, and the node stays (docs/Design.md, "Every vertex on its face").
  /// Call before Refine.
  void KeepNodesOnTheFace()
  {
    std::vector<char> onBoundary(UV.size(), 0);
    for (const auto& c : Chords)
    {
      onBoundary[static_cast<size_t>(c.first.first)] = 1;
      onBoundary[static_cast<size_t>(c.first.second)] = 1;
    }
    for (size_t i = 0; i < UV.size(); ++i)
    {
      if (onBoundary[i] || !Outside(UV[i]))
        continue;
      gp_Pnt2d foot;
      if (!NearestOnTheTrim(UV[i], foot))
        continue;
      const gp_Vec2d on(UV[i], foot);
      std::vector<int> around;
      for (size_t t = 0; t < Tris.size(); ++t)
        if (Alive[t] && (Tris[t][0] == int(i) || Tris[t][1] == int(i) || Tris[t][2] == int(i)))
          around.push_back(static_cast<int>(t));
      std::vector<double> before;
      for (const int t : around)
        before.push_back(AreaUV(Tris[t][0], Tris[t][1], Tris[t][2]));
      const gp_Pnt2d from = UV[i];
      for (const double s : { 1e-2, 1e-3, 1e-4, 0.0 })
      {
        const gp_Pnt2d q = foot.Translated(s * on);
        if (s > 0.0 && Outside(q))
          continue;
        UV[i] = q;
        bool kept = true;
        for (size_t k = 0; k < around.size() && kept; ++k)
        {
          const int t = around[k];
          kept = AreaUV(Tris[t][0], Tris[t][1], Tris[t][2]) * before[k] > 0.0;
        }
        if (!kept)
        {
          UV[i] = from;
          continue;
        }
        gp_Pnt p;
        gp_Vec du, dv;
        Surface->D1(q.X(), q.Y(), p, du, dv);
        XYZ[i] = p;
        if (Delaunay)
          Normal[i] = du.Crossed(dv);
        break;
      }
    }
  }

  /// Splits edges longest first until none is longer than maxEdge (or the vertex cap is hit).
  void Refine(double maxEdge, size_t maxVertices)
  {
    using Item = std::pair<double, int>;
    std::priority_queue<Item> queue;
    auto push = [&](int t) {
      const double l = Length(LongestKey(t));
      if (l > maxEdge)
        queue.emplace(l, t);
    };
    for (size_t i = 0; i < Tris.size(); ++i)
      push(static_cast<int>(i));
    while (!queue.empty() && UV.size() < maxVertices)
    {
      // The side test's budget for the face, its refinements together (SideTestBudget).
      if (*Side && OverBudget((*Side)->Asked(), UV.size()))
      {
        Stopped = true;
        break;
      }
      const int t = queue.top().second;
      queue.pop();
      if (!Alive[t] || Frozen[t])
        continue;
      const size_t before = Tris.size();
      Bisect(t, 0);
      if (Delaunay)
        MakeDelaunay(before);
      for (size_t i = before; i < Tris.size(); ++i)
        push(static_cast<int>(i));
      if (Alive[t] && !Frozen[t])
        push(t);
    }
  }

  std::vector<gp_Pnt2d> UV;
  std::vector<gp_Pnt> XYZ;
  std::vector<gp_Vec> Normal; ///< per vertex, with Delaunay only
  std::vector<std::array<int, 3>> Tris;
  std::vector<char> Alive;
  std::vector<char> Frozen; ///< not split again: an edge's midpoint would leave the face
  /// The refinement stopped at the side test's budget (SideTestBudget).
  bool Stopped = false;
  /// How many times a face's refinements may ask OpenCASCADE's classifier (FaceSide) for the
  /// side of a midpoint whose cell has no kept answer: SideTestBudget times, or SideTestFloor
  /// times where that is more than SideTestsPerVertex a vertex of the mesh so far. Over 227 real
  /// files the most a face asked is 9,985 (150 vertices: a cone of LeRobot's leader gripper
  /// trigger, once its endless split was mended, Midpoint), and otherwise 6,303 for 875 vertices
  /// (7.2 a vertex). A B-spline face that a mutation distorted (a weight of NIST_MBE_PMI_11
  /// doubled and a point moved 40 mm, found by libFuzzer) asked 408,315 times at 0.3 ms each for
  /// a few hundred vertices, and held the reader two minutes; Thor's gear cylinder, whose loop
  /// winds round it 19 times, 401,721 (36 a vertex).
  static constexpr long SideTestBudget = 50000, SideTestFloor = 20000, SideTestsPerVertex = 20;
  static bool OverBudget(long asked, size_t vertices)
  {
    return asked >= SideTestBudget ||
      (asked >= SideTestFloor && asked > SideTestsPerVertex * static_cast<long>(vertices));
  }

private:
  double Length(const ChordKey& k) const { return XYZ[k.first].Distance(XYZ[k.second]); }
  /// The angle at c of the triangle (a, b, c) in 3D; -1 where an edge at c has no length (a
  /// pole's vertices).
  double AngleAt(int c, int a, int b) const
  {
    const gp_Vec u(XYZ[c], XYZ[a]), v(XYZ[c], XYZ[b]);
    const double lu = u.Magnitude(), lv = v.Magnitude();
    if (!(lu > 0.0) || !(lv > 0.0))
      return -1.0;
    return std::atan2(u.Crossed(v).Magnitude(), u.Dot(v));
  }
  /// How far the surface's point at the UV midpoint of (a, b) lies from the chord's midpoint: a
  /// flip must not cut across the surface (a rod's chord across its diameter is short in 3D, and
  /// Delaunay's angles would take it).
  double Sag(int a, int b) const
  {
    const gp_Pnt m = Surface->Value(0.5 * (UV[a].X() + UV[b].X()), 0.5 * (UV[a].Y() + UV[b].Y()));
    return m.Distance(gp_Pnt(0.5 * (XYZ[a].XYZ() + XYZ[b].XYZ())));
  }
  /// The angle between the surface's normals at a and b (-1 where one is not defined: a pole).
  double Turn(int a, int b) const
  {
    const gp_Vec &na = Normal[size_t(a)], &nb = Normal[size_t(b)];
    if (!(na.Magnitude() > 0.0) || !(nb.Magnitude() > 0.0))
      return -1.0;
    return na.Angle(nb);
  }
  /// Whether (a, b) is an edge of a live triangle (EdgeTris keeps emptied entries).
  bool IsEdge(int a, int b) const
  {
    const auto it = EdgeTris.find(Key(a, b));
    return it != EdgeTris.end() && !it->second.empty();
  }
  /// Twice the signed area of (a, b, c) in UV.
  double AreaUV(int a, int b, int c) const
  {
    return (UV[b].X() - UV[a].X()) * (UV[c].Y() - UV[a].Y()) -
      (UV[b].Y() - UV[a].Y()) * (UV[c].X() - UV[a].X());
  }
  /// Lawson's flips from the edges of the triangles made since `first`: an inner edge (never a
  /// boundary chord) whose two opposite angles sum to more than pi is replaced by the other
  /// diagonal of its quad, where both new triangles have the old ones' orientation in UV and an
  /// area above rounding; the quad's outer edges are checked again. At most 64 flips per
  /// triangle made (on a curved surface the 3D angles need not settle as in the plane).
  void MakeDelaunay(size_t first)
  {
    std::vector<ChordKey> stack;
    for (size_t t = first; t < Tris.size(); ++t)
      if (Alive[t])
        for (int k = 0; k < 3; ++k)
          stack.push_back(Key(Tris[t][k], Tris[t][(k + 1) % 3]));
    size_t budget = 64 * (Tris.size() - first) + 64;
    while (!stack.empty() && budget > 0)
    {
      const ChordKey e = stack.back();
      stack.pop_back();
      if (Chords.count(e))
        continue;
      const auto it = EdgeTris.find(e);
      if (it == EdgeTris.end() || it->second.size() != 2)
        continue;
      const int t1 = it->second[0], t2 = it->second[1];
      // t1 = (a, b, c) with the edge as a -> b; t2 must hold it as b -> a (one orientation).
      const auto v1 = Tris[t1], v2 = Tris[t2];
      int k1 = 0;
      while (Key(v1[k1], v1[(k1 + 1) % 3]) != e)
        ++k1;
      const int a = v1[k1], b = v1[(k1 + 1) % 3], c = v1[(k1 + 2) % 3];
      int k2 = 0;
      while (Key(v2[k2], v2[(k2 + 1) % 3]) != e)
        ++k2;
      if (v2[k2] != b || v2[(k2 + 1) % 3] != a)
        continue;
      const int d = v2[(k2 + 2) % 3];
      if (c == d)
        continue;
      const double ac = AngleAt(c, a, b), ad = AngleAt(d, b, a);
      if (ac < 0.0 || ad < 0.0 || !(ac + ad > M_PI * (1.0 + 1e-9)))
        continue;
      // Both new triangles on the old ones' side in UV, clearly (a flat quad's corner).
      const double sense = AreaUV(a, b, c), floor = 1e-12 * sense * sense;
      if (!(AreaUV(a, d, c) * sense > floor) || !(AreaUV(d, b, c) * sense > floor) || IsEdge(c, d))
        continue;
      // The new edge within the mesh's limits, or within what the quad's edges already span
      // (its sides and the old diagonal): its chordal deviation within the linear deflection and
      // the turn of the surface's normal along it within the angular deflection (a pole's
      // vertex, where the normal is not defined, gets no new edge).
      const double sag = Sag(c, d), turn = Turn(c, d);
      if (!(sag <= std::max({ Deflection, Sag(a, b), Sag(a, d), Sag(d, b), Sag(b, c), Sag(c, a) })) ||
        !(turn >= 0.0) ||
        !(turn <= std::max({ Angular, Turn(a, b), Turn(a, d), Turn(d, b), Turn(b, c), Turn(c, a) })))
        continue;
      Remove(t1);
      Remove(t2);
      AddTriangle(a, d, c);
      AddTriangle(d, b, c);
      --budget;
      for (const ChordKey& o : { Key(a, d), Key(d, b), Key(b, c), Key(c, a) })
        stack.push_back(o);
    }
  }
  /// The longest edge, ties broken by vertex ids so both triangles of an edge agree.
  ChordKey LongestKey(int t) const
  {
    ChordKey best = Key(Tris[t][0], Tris[t][1]);
    for (int k = 1; k < 3; ++k)
    {
      const ChordKey c = Key(Tris[t][k], Tris[t][(k + 1) % 3]);
      const double lc = Length(c), lb = Length(best);
      if (lc > lb || (lc == lb && c > best))
        best = c;
    }
    return best;
  }
  void Remove(int t)
  {
    Alive[t] = 0;
    for (int k = 0; k < 3; ++k)
    {
      EdgeTris[Key(Tris[t][k], Tris[t][(k + 1) % 3])].remove(t);
    }
  }
  int Neighbour(int t, const ChordKey& k) const
  {
    auto it = EdgeTris.find(k);
    if (it == EdgeTris.end())
      return -1;
    for (size_t i = 0; i < it->second.size(); ++i)
      if (it->second[i] != t)
        return it->second[i];
    return -1;
  }
  /// Whether p lies outside the face (FaceSide, made on first use and kept for the face's other
  /// refinements).
  bool Outside(const gp_Pnt2d& p)
  {
    if (!*Side)
      *Side = std::make_shared<FaceSide>(TheFace);
    return (*Side)->Outside(p);
  }
  /// The nearest point to p of the face's pcurves (both of a seam's); false where there is none.
  bool NearestOnTheTrim(const gp_Pnt2d& p, gp_Pnt2d& foot) const
  {
    double best = std::numeric_limits<double>::infinity();
    for (TopExp_Explorer ex(TheFace, TopAbs_EDGE); ex.More(); ex.Next())
    {
      const TopoDS_Edge& e = TopoDS::Edge(ex.Current());
      for (const TopAbs_Orientation o : { e.Orientation(), TopAbs::Reverse(e.Orientation()) })
      {
        double f = 0.0, l = 0.0;
        const Handle(Geom2d_Curve) pc =
          BRep_Tool::CurveOnSurface(TopoDS::Edge(e.Oriented(o)), TheFace, f, l);
        if (pc.IsNull())
          continue;
        auto take = [&](const gp_Pnt2d& q) {
          const double d = q.Distance(p);
          if (d < best)
          {
            best = d;
            foot = q;
          }
        };
        try
        {
          take(pc->Value(f));
          take(pc->Value(l));
          Geom2dAPI_ProjectPointOnCurve pr(p, pc, f, l);
          if (pr.NbPoints() > 0)
            take(pr.NearestPoint());
        }
        catch (const Standard_Failure&)
        {
          // (a pcurve OpenCASCADE cannot project on: its ends, where taken, or none of it; a
          // node left without a foot stays where it is)
        }
      }
    }
    return best < std::numeric_limits<double>::infinity();
  }
  /// The new vertex at the middle of (a, b): on a boundary chord on its pcurve, on an inner
  /// edge at the UV midpoint; -1 where that lies outside the face.
  int Midpoint(int a, int b)
  {
    const ChordKey k = Key(a, b);
    // A chord split before and back again (Lawson's flips brought the diagonal back) is not
    // split again: its triangle is frozen. On LeRobot's leader gripper trigger a cone's chord
    // was split and flipped back without end, each split adding a vertex at its midpoint, until
    // the face had its 200,000 vertices (99,955 at one point): 91% of the part's samples and
    // 2.7 s of display mesh.
    if (!Split.insert(k).second)
      return -1;
    const gp_Pnt2d& pa = UV[a];
    const gp_Pnt2d& pb = UV[b];
    gp_Pnt2d m((pa.X() + pb.X()) / 2, (pa.Y() + pb.Y()) / 2);
    auto ch = Chords.find(k);
    if (ch == Chords.end())
      return Outside(m) ? -1 : AddVertex(m);
    const BoundaryChord c = ch->second;
    const double pm = 0.5 * (c.P0 + c.P1);
    // The pcurve that passes nearest to the chord's ends, within half the chord: a seam edge has
    // two, a period apart. The ends need not lie on it exactly: a vertex's node lies within its
    // tolerance of the pcurve's end (1.2e-4 in UV on the Original Prusa i3's extruder cover,
    // where a test within 1e-6 of the chord left the midpoint on the chord, 0.033 mm off the
    // face). With none, the chord's midpoint, unless it lies outside the face.
    double nearest = 0.5 * pa.Distance(pb);
    bool onCurve = false;
    for (const TopAbs_Orientation o : { c.Edge.Orientation(), TopAbs::Reverse(c.Edge.Orientation()) })
    {
      double f, l;
      Handle(Geom2d_Curve) pc =
        BRep_Tool::CurveOnSurface(TopoDS::Edge(c.Edge.Oriented(o)), TheFace, f, l);
      if (pc.IsNull())
        continue;
      const double off =
        std::max(pc->Value(c.P0).Distance(UV[k.first]), pc->Value(c.P1).Distance(UV[k.second]));
      if (off <= nearest)
      {
        nearest = off;
        m = pc->Value(pm);
        onCurve = true;
      }
    }
    if (!onCurve && Outside(m))
      return -1;
    Chords.erase(k);
    const int id = AddVertex(m);
    const int lo = k.first, hi = k.second;
    AddChord(lo, id, c.Edge, c.P0, pm);
    AddChord(id, hi, c.Edge, pm, c.P1);
    return id;
  }
  /// false where t cannot be split (its edge's midpoint, or its neighbour's, leaves the face):
  /// t is then frozen.
  bool Bisect(int t, int depth)
  {
    for (int guard = 0; guard < 64 && Alive[t]; ++guard)
    {
      const ChordKey e = LongestKey(t);
      const int n = Neighbour(t, e);
      if (n >= 0 && LongestKey(n) != e && depth < 200)
      {
        // Split the neighbour's longer edge first.
        if (!Bisect(n, depth + 1))
        {
          Frozen[t] = 1;
          return false;
        }
        continue;
      }
      const auto split = [&](int tri, int m) {
        const auto v = Tris[tri];
        int k = 0;
        while (Key(v[k], v[(k + 1) % 3]) != e)
          ++k;
        const int a = v[k], b = v[(k + 1) % 3], c = v[(k + 2) % 3];
        Remove(tri);
        AddTriangle(a, m, c);
        AddTriangle(m, b, c);
      };
      const int m = Midpoint(e.first, e.second);
      if (m < 0)
      {
        Frozen[t] = 1;
        if (n >= 0)
          Frozen[n] = 1;
        return false;
      }
      split(t, m);
      if (n >= 0)
        split(n, m);
      return true;
    }
    return true;
  }

  Handle(Geom_Surface) Surface;
  TopoDS_Face TheFace;
  bool Delaunay = false; ///< ConversionOptions::DelaunayRefinement
  double Deflection = 0.0, Angular = 0.0; ///< the display mesh's limits, which a flip keeps
  std::unordered_map<ChordKey, EdgeTriangles, ChordKeyHash> EdgeTris;
  std::unordered_map<ChordKey, BoundaryChord, ChordKeyHash> Chords;
  std::unordered_set<ChordKey, ChordKeyHash> Split; ///< chords split once (Midpoint)
  std::shared_ptr<FaceSide>* Side; ///< the face's, shared by its refinements
};

/// Solids, and shells outside solids (a surface model's), that are open only where two of their
/// faces' edges run together without being one edge (an unsewn seam: I-DEAS's exports of
/// CAx-IF's k1 part, a shell of 46 faces with two coincident edges 2.59 mm long, each bounding
/// one face): sewn within `tol` where that leaves no free edge, no edge of more than two faces
/// and one closed shell (a solid's: a valid solid), and replaced; left as they are otherwise
/// (the closure check then refuses them). A warning for each one sewn.
TopoDS_Shape SewNearlyClosedShells(const TopoDS_Shape& shape, double tol,
  std::vector<std::string>& warnings)
{
  BRepTools_ReShape reshape;
  bool any = false;
  auto freeEdges = [](const TopoDS_Shape& s) {
    TopTools_IndexedDataMapOfShapeListOfShape edgeFaces;
    TopExp::MapShapesAndUniqueAncestors(s, TopAbs_EDGE, TopAbs_FACE, edgeFaces);
    int free = 0;
    for (int i = 1; i <= edgeFaces.Extent(); ++i)
    {
      const TopoDS_Edge& e = TopoDS::Edge(edgeFaces.FindKey(i));
      if (!BRep_Tool::Degenerated(e) && edgeFaces(i).Extent() == 1 &&
        !BRep_Tool::IsClosed(e, TopoDS::Face(edgeFaces(i).First()))) // not a seam
        ++free;
    }
    return free;
  };
  // The closed shell sewn from the faces of `s`; null where the sewing leaves it open.
  auto sew = [&](const TopoDS_Shape& s) {
    TopoDS_Shell none;
    BRepBuilderAPI_Sewing sewing(tol);
    for (TopExp_Explorer fx(s, TopAbs_FACE); fx.More(); fx.Next())
      sewing.Add(fx.Current());
    sewing.Perform();
    if (sewing.NbFreeEdges() != 0 || sewing.NbMultipleEdges() != 0)
      return none;
    TopExp_Explorer hx(sewing.SewedShape(), TopAbs_SHELL);
    if (!hx.More())
      return none;
    const TopoDS_Shell shell = TopoDS::Shell(hx.Current());
    hx.Next();
    if (hx.More() || !BRep_Tool::IsClosed(shell) || freeEdges(shell) != 0)
      return none;
    return shell;
  };
  auto note = [&](const char* what, int index, int free) {
    std::ostringstream w;
    w << what << " " << index << " was open along " << free
      << " edge(s) that run together with others within " << tol
      << " mm without being one edge; sewn, it is closed";
    warnings.push_back(w.str());
  };
  int index = 0;
  for (TopExp_Explorer sx(shape, TopAbs_SOLID); sx.More(); sx.Next(), ++index)
  {
    const int free = freeEdges(sx.Current());
    if (free == 0)
      continue;
    try
    {
      const TopoDS_Shell shell = sew(sx.Current());
      if (shell.IsNull())
        continue;
      BRepBuilderAPI_MakeSolid make(shell);
      if (!make.IsDone())
        continue;
      TopoDS_Solid sewn = make.Solid();
      BRepLib::OrientClosedSolid(sewn);
      if (!BRepCheck_Analyzer(sewn).IsValid())
        continue;
      reshape.Replace(sx.Current(), sewn);
      any = true;
      note("solid", index, free);
    }
    catch (const Standard_Failure&)
    {
      continue; // left open: the closure check refuses it
    }
  }
  index = 0;
  for (TopExp_Explorer hx(shape, TopAbs_SHELL, TopAbs_SOLID); hx.More(); hx.Next(), ++index)
  {
    const int free = freeEdges(hx.Current());
    if (free == 0)
      continue;
    try
    {
      const TopoDS_Shell shell = sew(hx.Current());
      if (shell.IsNull() || !BRepCheck_Analyzer(shell).IsValid())
        continue;
      reshape.Replace(hx.Current(), shell);
      any = true;
      note("shell (outside the solids)", index, free);
    }
    catch (const Standard_Failure&)
    {
      continue;
    }
  }
  return any ? reshape.Apply(shape) : shape;
}

/// A face that a solid or shell bounds besides the one it was given to first (ConvertShapeImpl's
/// faceSolid): the model face it is, that solid, and the face's orientation there.
struct SharedFaceUse
{
  int Face = -1, Solid = -1;
  bool Reversed = false;
};

/// Appends, for each use, a copy of its face for that solid: the face (oriented as that solid
/// holds it), its patches, loops and trimming segments (on the same edges), its exact surface,
/// and its display mesh (normals and triangles turned where the orientation differs). Each copy
/// gets its own samples, measured in its own solid.
void AddSharedFaceCopies(BRepModel& m, const std::vector<SharedFaceUse>& uses)
{
  if (uses.empty())
    return;
  DisplayMesh& M = m.Mesh;
  const size_t faces = m.Faces.size();
  std::vector<std::vector<int>> vertices(faces), triangles(faces);
  for (size_t v = 0; v < M.FaceIds.size(); ++v)
    if (M.FaceIds[v] >= 0 && static_cast<size_t>(M.FaceIds[v]) < faces)
      vertices[static_cast<size_t>(M.FaceIds[v])].push_back(static_cast<int>(v));
  for (size_t t = 0; t < M.TriangleFace.size(); ++t)
    if (M.TriangleFace[t] >= 0 && static_cast<size_t>(M.TriangleFace[t]) < faces)
      triangles[static_cast<size_t>(M.TriangleFace[t])].push_back(static_cast<int>(t));
  for (const SharedFaceUse& u : uses)
  {
    const size_t f = static_cast<size_t>(u.Face);
    const int copy = static_cast<int>(m.Faces.size());
    Face F = m.Faces[f];
    const bool turned = F.Reversed != u.Reversed;
    F.Solid = u.Solid;
    F.Reversed = u.Reversed;
    F.FirstPatch = static_cast<int>(m.Patches.size());
    for (int p = m.Faces[f].FirstPatch; p < m.Faces[f].FirstPatch + m.Faces[f].PatchCount; ++p)
    {
      BezierPatch P = m.Patches[static_cast<size_t>(p)];
      P.Face = copy;
      m.Patches.push_back(P);
    }
    // (The loops run with the material on their left whatever the face's orientation.)
    F.FirstLoop = static_cast<int>(m.Loops.size());
    for (int l = m.Faces[f].FirstLoop; l < m.Faces[f].FirstLoop + m.Faces[f].LoopCount; ++l)
    {
      TrimLoop L = m.Loops[static_cast<size_t>(l)];
      const int first = L.FirstSegment;
      L.Face = copy;
      L.FirstSegment = static_cast<int>(m.TrimSegments.size());
      for (int k = first; k < first + L.SegmentCount; ++k)
      {
        TrimSegment T = m.TrimSegments[static_cast<size_t>(k)];
        T.Face = copy;
        T.Loop = static_cast<int>(m.Loops.size());
        m.TrimSegments.push_back(T);
      }
      m.Loops.push_back(L);
    }
    m.Faces.push_back(F);
    if (m.FaceExact.size() + 1 == m.Faces.size())
      m.FaceExact.push_back(m.FaceExact[f]);
    const double sign = turned ? -1.0 : 1.0;
    const bool withUV = M.UV.size() == 2 * M.FaceIds.size();
    const bool withCurvatures = M.Curvatures.size() == 2 * M.FaceIds.size();
    std::map<int, int> renumbered;
    for (const int v : vertices[f])
    {
      renumbered[v] = static_cast<int>(M.FaceIds.size());
      for (int k = 0; k < 3; ++k)
      {
        M.Points.push_back(M.Points[3 * static_cast<size_t>(v) + static_cast<size_t>(k)]);
        M.Normals.push_back(sign * M.Normals[3 * static_cast<size_t>(v) + static_cast<size_t>(k)]);
      }
      for (int k = 0; k < 2 && withUV; ++k)
        M.UV.push_back(M.UV[2 * static_cast<size_t>(v) + static_cast<size_t>(k)]);
      if (withCurvatures)
      {
        double c[2] = { M.Curvatures[2 * static_cast<size_t>(v)],
          M.Curvatures[2 * static_cast<size_t>(v) + 1] };
        if (turned)
          TurnCurvatures(c);
        M.Curvatures.insert(M.Curvatures.end(), { c[0], c[1] });
      }
      M.FaceIds.push_back(copy);
    }
    for (const int t : triangles[f])
    {
      const int* a = &M.Triangles[3 * static_cast<size_t>(t)];
      const int t0 = renumbered[a[0]], t1 = renumbered[a[1]], t2 = renumbered[a[2]];
      if (turned)
        M.Triangles.insert(M.Triangles.end(), { t0, t2, t1 });
      else
        M.Triangles.insert(M.Triangles.end(), { t0, t1, t2 });
      M.TriangleFace.push_back(copy);
    }
    if (std::find(m.LooseFaces.begin(), m.LooseFaces.end(), u.Face) != m.LooseFaces.end())
      m.LooseFaces.push_back(copy);
    const auto& o = m.OverlappingFaces;
    if (std::find(o.begin(), o.end(), u.Face) != o.end())
      m.OverlappingFaces.push_back(copy);
  }
}

/// Gives each solid its own copy of an edge whose faces (by the trimming segments along it) lie
/// in several solids, with that solid's faces, so that an edge bounds the faces of one solid:
/// the closure check, the edges' own splitting (SplitNonManifoldEdges) and the solver's scope
/// (a solid's certification searches the edges of its own faces) then see each solid whole.
/// Returns the number of edges split.
int SplitEdgesAcrossSolids(BRepModel& m)
{
  std::vector<std::vector<int>> along(m.Edges.size());
  for (size_t s = 0; s < m.TrimSegments.size(); ++s)
  {
    const int e = m.TrimSegments[s].Edge;
    if (e >= 0 && static_cast<size_t>(e) < m.Edges.size())
      along[static_cast<size_t>(e)].push_back(static_cast<int>(s));
  }
  int split = 0;
  const size_t edges = m.Edges.size();
  for (size_t e = 0; e < edges; ++e)
  {
    std::vector<int> solids;
    for (const int s : along[e])
    {
      const int solid = m.Faces[static_cast<size_t>(m.TrimSegments[static_cast<size_t>(s)].Face)].Solid;
      if (std::find(solids.begin(), solids.end(), solid) == solids.end())
        solids.push_back(solid);
    }
    if (solids.size() < 2)
      continue;
    ++split;
    for (size_t k = 0; k < solids.size(); ++k)
    {
      const int target = k == 0 ? static_cast<int>(e) : CopyEdge(m, static_cast<int>(e));
      std::vector<int> faces;
      for (const int s : along[e])
      {
        TrimSegment& ts = m.TrimSegments[static_cast<size_t>(s)];
        if (m.Faces[static_cast<size_t>(ts.Face)].Solid != solids[k])
          continue;
        ts.Edge = target;
        if (std::find(faces.begin(), faces.end(), ts.Face) == faces.end())
          faces.push_back(ts.Face);
      }
      Edge& to = m.Edges[static_cast<size_t>(target)];
      to.FaceCount = static_cast<int>(faces.size());
      if (to.Seam && faces.size() == 1)
        to.Faces = { faces[0], faces[0] };
      else
        to.Faces = { faces[0], faces.size() > 1 ? faces[1] : -1 };
    }
  }
  return split;
}

} // namespace

// ---------------------------------------------------------------------------------------------
namespace
{
BRepModel ConvertShapeImpl(const TopoDS_Shape& input, const ConversionOptions& options,
  std::vector<TopoDS_Face>* faces, bool healedOnRead)
{
  BRepModel model;
  model.Tolerance = options.Tolerance;
  ConversionStatistics& stats = model.Stats;
  auto warn = [&](const std::string& w) { stats.Warnings.push_back(w); };
  auto progress = [&](double f) {
    if (options.Progress && !options.Progress(f))
      throw std::runtime_error("conversion aborted");
  };

  // --- heal -------------------------------------------------------------------------------
  auto t0 = Clock::now();
  TopoDS_Shape shape = input;
  // Bodies touching face to face in one solid, joined as the file's solid says they are one
  // (TouchingBodies.h): before the healing, which would make each body a solid of its own.
  try
  {
    shape = JoinBodiesTouchingFaceToFace(shape, options.Tolerance, stats.Warnings).Shape;
  }
  catch (const Standard_Failure& e)
  {
    warn(std::string("looking for bodies touching face to face failed: ") +
      e.GetMessageString());
    shape = input;
  }
  // Shells open only along unsewn seams, sewn: before the healing, which may split such a
  // solid's faces apart.
  if (options.Heal)
  {
    try
    {
      shape = SewNearlyClosedShells(shape, options.Tolerance, stats.Warnings);
    }
    catch (const Standard_Failure& e)
    {
      warn(std::string("sewing open shells failed: ") + e.GetMessageString());
    }
  }
  // A shape from a STEP file was healed by OpenCASCADE's transfer already (its FixShape, the
  // STEP resource's FromSTEP sequence, with the file's precision): ShapeFix_Shape on it again
  // changed 1 of 50 files' models and took 0.02-1.5 s a file, a quarter of their reading and
  // conversion (docs/Design.md, "Healing"). Where the joining or the sewing above changed it, it
  // is healed.
  if (options.Heal && !(healedOnRead && shape.IsEqual(input)))
  {
    const TopoDS_Shape unhealed = shape;
    try
    {
      ShapeFix_Shape fixer(shape);
      fixer.Perform();
      shape = fixer.Shape();
    }
    catch (const Standard_Failure& e)
    {
      warn(std::string("healing failed, converting the shape as read: ") + e.GetMessageString());
      shape = unhealed;
    }
  }
  BRepLib::BuildCurves3d(shape);
  stats.HealSeconds = Since(t0);
  progress(0.05);

  // --- topology: solids, faces, edges -------------------------------------------------------
  t0 = Clock::now();
  TopTools_IndexedMapOfShape faceMap;
  std::vector<int> faceSolid;
  // A face that bounds several solids or shells (a compound solid's, or a surface model's shells
  // written with the faces where their bodies meet shared): each after the first it bounds gets
  // a copy of its own (SharedFaceUse, AddSharedFaceCopies), so that every solid keeps all its
  // faces. A solid or shell whose faces are all, and only, those of one read before it is that
  // body again (a file that lists one body twice: OpenCASCADE's AP209 samples) and gets none.
  std::vector<SharedFaceUse> sharedUses;
  auto addBody = [&](const TopoDS_Shape& body, int solidIndex) {
    std::vector<TopoDS_Shape> bodyFaces;
    for (TopExp_Explorer fx(body, TopAbs_FACE); fx.More(); fx.Next())
      bodyFaces.push_back(fx.Current());
    // Every face of this body already read, and all of one body read before: the same again.
    bool allSeen = !bodyFaces.empty();
    std::set<int> indices;
    for (const TopoDS_Shape& f : bodyFaces)
    {
      const int index = faceMap.FindIndex(f);
      if (index == 0)
      {
        allSeen = false;
        break;
      }
      indices.insert(index - 1);
    }
    if (allSeen)
    {
      std::map<int, std::set<int>> ownedBy; // solid -> its faces
      for (size_t i = 0; i < faceSolid.size(); ++i)
        ownedBy[faceSolid[i]].insert(static_cast<int>(i));
      for (const SharedFaceUse& u : sharedUses)
        ownedBy[u.Solid].insert(u.Face);
      for (const auto& o : ownedBy)
        if (o.second == indices)
          return; // the same body again
    }
    for (const TopoDS_Shape& f : bodyFaces)
    {
      const int index = faceMap.Add(f);
      if (index > static_cast<int>(faceSolid.size()))
      {
        faceSolid.push_back(solidIndex);
        continue;
      }
      bool seen = faceSolid[static_cast<size_t>(index - 1)] == solidIndex;
      for (const SharedFaceUse& u : sharedUses)
        seen = seen || (u.Face == index - 1 && u.Solid == solidIndex);
      if (!seen)
        sharedUses.push_back({ index - 1, solidIndex, f.Orientation() == TopAbs_REVERSED });
    }
  };
  int solid = 0;
  for (TopExp_Explorer sx(shape, TopAbs_SOLID); sx.More(); sx.Next(), ++solid)
    addBody(sx.Current(), solid);
  // Shells outside solids: a surface model's (SHELL_BASED_SURFACE_MODEL; FreeCAD writes a shape
  // that is a shell so), each given a SolidId of its own. A closed one bounds a volume and is
  // measured as a solid; an open one is flagged by the closure check (CheckSolids).
  int looseShells = 0, closedLooseShells = 0;
  for (TopExp_Explorer hx(shape, TopAbs_SHELL, TopAbs_SOLID); hx.More(); hx.Next(), ++solid)
  {
    if (BRep_Tool::IsClosed(hx.Current()))
      ++closedLooseShells;
    else
      ++looseShells;
    addBody(hx.Current(), solid);
  }
  int looseFaces = 0;
  for (TopExp_Explorer fx(shape, TopAbs_FACE, TopAbs_SHELL); fx.More(); fx.Next())
  {
    if (faceMap.Add(fx.Current()) > static_cast<int>(faceSolid.size()))
    {
      faceSolid.push_back(solid);
      ++looseFaces;
    }
  }
  if (looseFaces > 0)
    ++solid;
  if (closedLooseShells > 0)
    warn(std::to_string(closedLooseShells) + " closed shell(s) are not written as solids (a "
      "surface model): each is measured as the solid it bounds");
  if (looseShells > 0 || looseFaces > 0)
  {
    std::ostringstream w;
    w << looseShells << " open shell(s) and " << looseFaces
      << " loose face(s) belong to no solid: each keeps its own SolidId, but thickness is only "
         "meaningful inside closed solids";
    warn(w.str());
  }
  if (faceMap.Extent() == 0)
    throw std::runtime_error("the shape holds no face");
  stats.Solids = solid;

  // Curves of edges on faces that miss their edge, projected again (CurvesOnFaces.h): before
  // anything reads the faces' parameter bounds or trims. Also without the healing: the trims are
  // these curves, wrong for every use of the model.
  {
    std::vector<TopoDS_Face> faceList;
    for (int i = 1; i <= faceMap.Extent(); ++i)
      faceList.push_back(TopoDS::Face(faceMap(i)));
    try
    {
      RepairCurvesOnFaces(faceList, options.Tolerance, stats.Warnings);
    }
    catch (const Standard_Failure& e)
    {
      warn(std::string("checking the edges' curves on faces failed: ") + e.GetMessageString());
    }
  }
  TopTools_IndexedMapOfShape edgeMap;
  for (int i = 1; i <= faceMap.Extent(); ++i)
    for (TopExp_Explorer ex(faceMap(i), TopAbs_EDGE); ex.More(); ex.Next())
      if (!BRep_Tool::Degenerated(TopoDS::Edge(ex.Current())))
        edgeMap.Add(ex.Current());
  TopTools_IndexedDataMapOfShapeListOfShape edgeFaces;
  TopExp::MapShapesAndUniqueAncestors(shape, TopAbs_EDGE, TopAbs_FACE, edgeFaces);

  Bnd_Box box;
  BRepBndLib::Add(shape, box);
  const double diagonal = box.IsVoid() ? 1.0 : std::sqrt(box.SquareExtent());
  const double tol = options.Tolerance;
  // A vertex whose tolerance is a good part of the part: the file's faces and edges miss each
  // other there by up to that much, and the translation and the healing covered it by growing
  // the tolerance (a plane moved 22 mm off its face's edges, a vertex moved 41 mm: mutated
  // Voron parts and the L-bracket, read without a word before the forty-first session). Real
  // files' largest, over 365 on disk: 0.0555 mm on a 123 mm part, 0.025 mm on an 11 mm screw,
  // within 2.3e-3 of the diagonal (a KiCad model refused as open aside). Warned of once per
  // vertex (the loops' bridges below skip those).
  TopTools_MapOfShape gapVertices; // vertices warned of (once each)
  {
    const double loose = std::max(100.0 * tol, 5e-3 * diagonal);
    TopTools_IndexedMapOfShape vertices;
    TopExp::MapShapes(shape, TopAbs_VERTEX, vertices);
    int more = 0;
    double moreTol = 0.0;
    for (int i = 1; i <= vertices.Extent(); ++i)
    {
      const TopoDS_Vertex v = TopoDS::Vertex(vertices(i));
      const double vt = BRep_Tool::Tolerance(v);
      if (!(vt > loose))
        continue;
      gapVertices.Add(v);
      const gp_Pnt vp = BRep_Tool::Pnt(v);
      model.LooseVertices.push_back({ vp.X(), vp.Y(), vp.Z(), vt });
      if (gapVertices.Extent() > 3) // a moved face takes all of its vertices along
      {
        ++more;
        moreTol = std::max(moreTol, vt);
        continue;
      }
      std::ostringstream w;
      w << "the vertex at (" << vp.X() << ", " << vp.Y() << ", " << vp.Z() << ") has a tolerance of "
        << vt << " mm: the file's faces and edges miss each other there by up to that much; the "
           "thickness near there is not reliable";
      warn(w.str());
    }
    if (more > 0)
    {
      std::ostringstream w;
      w << more << " more vertices have tolerances above " << loose << " mm (up to " << moreTol
        << " mm)";
      warn(w.str());
    }
    // The faces around them whose surface lies off most of their own vertices by more than that:
    // a face whose surface was moved off its edges is wrong all over, not only near a vertex.
    if (!gapVertices.IsEmpty())
    {
      TopTools_IndexedDataMapOfShapeListOfShape vertexFaces;
      TopExp::MapShapesAndUniqueAncestors(shape, TopAbs_VERTEX, TopAbs_FACE, vertexFaces);
      TopTools_MapOfShape seen;
      for (TopTools_MapOfShape::Iterator it(gapVertices); it.More(); it.Next())
      {
        const int vi = vertexFaces.FindIndex(it.Key());
        if (vi == 0)
          continue;
        for (const TopoDS_Shape& fs : vertexFaces(vi))
        {
          const int fi = faceMap.FindIndex(fs);
          if (fi == 0 || !seen.Add(fs))
            continue;
          const TopoDS_Face face = TopoDS::Face(fs);
          const Handle(Geom_Surface) surface = BRep_Tool::Surface(face);
          if (surface.IsNull())
            continue;
          TopTools_IndexedMapOfShape own;
          TopExp::MapShapes(face, TopAbs_VERTEX, own);
          int off = 0;
          try
          {
            for (int k = 1; k <= own.Extent(); ++k)
            {
              GeomAPI_ProjectPointOnSurf proj(BRep_Tool::Pnt(TopoDS::Vertex(own(k))), surface);
              off += proj.NbPoints() > 0 && proj.LowerDistance() > loose;
            }
          }
          catch (const Standard_Failure&)
          {
            off = 0; // not judged: its vertices stay named, the face is not
          }
          if (off >= 2 && 2 * off > own.Extent())
          {
            model.LooseFaces.push_back(fi - 1);
            warn("face " + std::to_string(fi - 1) + ": " + std::to_string(off) + " of its " +
              std::to_string(own.Extent()) + " vertices lie more than " + std::to_string(loose) +
              " mm off its surface: its samples, and the spheres touching it, are flagged failed");
          }
        }
      }
    }
  }
  const double maxPatchSize =
    options.MaxPatchSize > 0.0 ? options.MaxPatchSize : diagonal / 8.0;

  // --- faces: patches (in parallel) --------------------------------------------------------
  // Each face's Bezier patches, refined until the measured deviation is within the tolerance,
  // and that deviation: the conversion's cost on large parts (a 1 m storage part of 251 faces,
  // tori, offset and rational B-spline faces, makes 133,000 patches in 40 s on one core), made
  // on every core, face by face, as the display meshes are below. Offset and swept surfaces
  // evaluate through adaptors that cache their basis, which two threads must not share: such a
  // face works on a copy of its surface (the same geometry, so the same patches). The rest of the
  // face (trimming loops, kind, recognition) follows in order in the loop after.
  struct FacePatches
  {
    PatchGrid Grid;
    double Deviation = 0.0;
    double Measured = 0.0; ///< -1: not measured (Face::MaxDeviation)
    std::string Failure;   ///< OpenCASCADE's message where the conversion failed
    /// A B-spline or Bezier face's analytic surface (RecogniseAnalytic), null where none.
    Handle(Geom_Surface) Analytic;
  };
  const int faceTotal = faceMap.Extent();
  std::vector<FacePatches> facePatches(static_cast<size_t>(faceTotal));
  auto patchFace = [&](int fi) {
    const TopoDS_Face ff = TopoDS::Face(TopoDS::Face(faceMap(fi + 1)).Oriented(TopAbs_FORWARD));
    Handle(Geom_Surface) surface = BRep_Tool::Surface(ff);
    if (surface.IsNull())
      return; // warned in the loop below
    const Handle(Geom_Surface) basis = Unwrap(surface);
    if (basis->IsKind(STANDARD_TYPE(Geom_OffsetSurface)) ||
      basis->IsKind(STANDARD_TYPE(Geom_SurfaceOfRevolution)) ||
      basis->IsKind(STANDARD_TYPE(Geom_SurfaceOfLinearExtrusion)))
      surface = Handle(Geom_Surface)::DownCast(surface->Copy());
    double u0, u1, v0, v1;
    BRepTools::UVBounds(ff, u0, u1, v0, v1);
    const std::array<double, 4> domain{ u0, u1, v0, v1 };
    FacePatches& out = facePatches[static_cast<size_t>(fi)];
    PatchGrid grid;
    double deviation = 0.0;
    // A B-spline or Bezier face that is an analytic surface within a thousandth of the tolerance
    // (recognised here, on every core; taken as the face's exact surface in the loop below).
    if (basis->IsKind(STANDARD_TYPE(Geom_BSplineSurface)) ||
      basis->IsKind(STANDARD_TYPE(Geom_BezierSurface)))
      out.Analytic = RecogniseAnalytic(basis, domain, 1e-3 * tol);
    const bool freeForm = !basis->IsKind(STANDARD_TYPE(Geom_ElementarySurface)) &&
      out.Analytic.IsNull();
    try
    {
      if (basis->IsKind(STANDARD_TYPE(Geom_Plane)))
        grid = PlanePatches(surface, domain);
      else
        grid = ExactPatches(surface, domain);
      if (!grid.Patches.empty())
        deviation = MeasurePatches(surface, grid, domain, options.DeviationSamples, fi + 1);
      if (grid.Patches.empty() || deviation > tol)
      {
        grid = FittedPatches(surface, domain, 0.5 * tol, options.MaxPatchesPerFace, freeForm);
        deviation = MeasurePatches(surface, grid, domain, options.DeviationSamples, fi + 1);
      }
    }
    catch (const Standard_Failure& e)
    {
      out.Failure = e.GetMessageString();
    }
    grid = LimitPatchSize(grid, maxPatchSize, options.MaxPatchesPerFace);
    // The face's deviation, which the certification's bound on analytic faces takes as the
    // patches' distance from the exact surface (exact_gap in the kernel source): the random points
    // above and a grid on every patch (MeasureOne's 7 x 7 without its corners, which the random
    // measure takes). A 33 x 33 grid on every patch found at most 1% more on ten parts.
    double measured = deviation;
    try
    {
      for (const auto& p : grid.Patches)
        measured = std::max(measured, MeasureOne(surface, p, 6).All);
    }
    catch (const Standard_Failure&)
    {
      measured = -1.0; // not measured: the solver takes the conversion tolerance instead
    }
    out.Grid = std::move(grid);
    out.Deviation = deviation;
    out.Measured = measured;
  };
  OnEveryCore(faceTotal, patchFace,
    [&](int finished) { progress(0.05 + 0.5 * finished / faceTotal); });

  // --- faces: kinds and trimming loops ------------------------------------------------------
  model.Faces.resize(faceMap.Extent());
  model.FaceExact.assign(model.Faces.size(), {});
  for (int fi = 0; fi < faceMap.Extent(); ++fi)
  {
    const TopoDS_Face face = TopoDS::Face(faceMap(fi + 1));
    const TopoDS_Face ff = TopoDS::Face(face.Oriented(TopAbs_FORWARD));
    Face& F = model.Faces[fi];
    F.Solid = faceSolid[fi];
    F.Reversed = face.Orientation() == TopAbs_REVERSED;
    Handle(Geom_Surface) surface = BRep_Tool::Surface(ff);
    if (surface.IsNull())
    {
      warn("face " + std::to_string(fi) + ": has no surface, skipped");
      continue;
    }
    Classify(surface, F, model.FaceExact[fi]);
    double u0, u1, v0, v1;
    BRepTools::UVBounds(ff, u0, u1, v0, v1);
    F.Domain = { u0, u1, v0, v1 };
    if (surface->IsUPeriodic() && std::fabs((u1 - u0) - surface->UPeriod()) < 1e-9 * surface->UPeriod())
      F.Period[0] = surface->UPeriod();
    if (surface->IsVPeriodic() && std::fabs((v1 - v0) - surface->VPeriod()) < 1e-9 * surface->VPeriod())
      F.Period[1] = surface->VPeriod();
    const std::string where = "face " + std::to_string(fi) + " (" + SurfaceKindName(F.Kind) + ")";
    // A face whose trim spans no width in one parameter (its wire lies on one parameter line:
    // a face of no area, as in one of OpenCASCADE's own test files, where a plane's loop runs
    // out and back along a line): nothing to measure on it, and a patch of no width is no patch.
    // Kept without patches or loops, so that its edges still close the solid.
    if (!(u0 < u1) || !(v0 < v1))
    {
      warn(where + ": its trim spans no area (parameters " + std::to_string(u0) + " to " +
        std::to_string(u1) + " by " + std::to_string(v0) + " to " + std::to_string(v1) +
        "): kept without patches");
      F.Domain = { 0.0, 0.0, 0.0, 0.0 };
      continue;
    }

    // The patches, made in parallel before this loop (FacePatches).
    FacePatches& made = facePatches[static_cast<size_t>(fi)];
    if (!made.Failure.empty())
      warn(where + ": surface conversion failed: " + made.Failure);
    PatchGrid grid = std::move(made.Grid);
    double deviation = made.Deviation;
    const double measured = made.Measured;
    deviation = std::max(deviation, measured);
    if (grid.Patches.empty())
      warn(where + ": no Bezier patches could be made; the face takes no part in the solve");
    else if (deviation > tol)
    {
      std::ostringstream w;
      w << where << ": patches deviate " << deviation << " > tolerance " << tol;
      warn(w.str());
    }
    F.MaxDeviation = measured;
    // A B-spline or Bezier face that is an analytic surface within a thousandth of the
    // tolerance takes that surface as its exact one (Face::Kind; the degrees stay the file's):
    // the solver's exact finish and bounds then work on it as on a face written as a cylinder
    // or torus. Its patches stay those of the file's surface.
    if ((F.Kind == SurfaceKind::BSplineSurface || F.Kind == SurfaceKind::BezierSurface) &&
      !grid.Patches.empty())
    {
      const Handle(Geom_Surface)& analytic = facePatches[static_cast<size_t>(fi)].Analytic;
      if (!analytic.IsNull())
      {
        Face recognised;
        std::array<double, 8> exact{};
        Classify(analytic, recognised, exact);
        if (recognised.Kind <= SurfaceKind::Torus)
        {
          F.Kind = recognised.Kind;
          model.FaceExact[fi] = exact;
          ++stats.AnalyticFromSpline;
        }
      }
    }
    F.FirstPatch = static_cast<int>(model.Patches.size());
    F.PatchCount = static_cast<int>(grid.Patches.size());
    F.PatchesU = grid.NU;
    F.PatchesV = grid.NV;
    for (auto& p : grid.Patches)
    {
      p.Face = fi;
      model.Patches.push_back(p);
    }
    stats.MaxPatchDeviation = std::max(stats.MaxPatchDeviation, deviation);

    // Trimming loops.
    BRepAdaptor_Surface adaptor(ff, Standard_False);
    const double uvExtent = std::max(u1 - u0, v1 - v0);
    double tol2d = std::min(adaptor.UResolution(tol), adaptor.VResolution(tol));
    tol2d = std::clamp(tol2d, 1e-10 * uvExtent, 1e-3 * uvExtent);
    F.UVTolerance = tol2d;
    F.FirstLoop = static_cast<int>(model.Loops.size());
    const TopoDS_Wire outerWire = BRepTools::OuterWire(ff);
    for (TopoDS_Iterator wi(ff); wi.More(); wi.Next())
    {
      if (wi.Value().ShapeType() != TopAbs_WIRE)
        continue;
      const TopoDS_Wire wire = TopoDS::Wire(wi.Value());
      std::vector<TopoDS_Edge> edges;
      for (BRepTools_WireExplorer we(wire, ff); we.More(); we.Next())
        edges.push_back(we.Current());
      int stored = 0;
      for (TopoDS_Iterator ei(wire); ei.More(); ei.Next())
        ++stored;
      if (static_cast<int>(edges.size()) != stored)
      {
        warn(where + ": wire edges could not be ordered, using their stored order");
        edges.clear();
        for (TopoDS_Iterator ei(wire); ei.More(); ei.Next())
          edges.push_back(TopoDS::Edge(ei.Value()));
      }
      TrimLoop loop;
      loop.Face = fi;
      loop.FirstSegment = static_cast<int>(model.TrimSegments.size());
      loop.Outer = wire.IsSame(outerWire);
      const int loopIndex = static_cast<int>(model.Loops.size());
      std::vector<int> edgeStarts;
      std::vector<TopoDS_Edge> edgeOf; // the edge behind each entry of edgeStarts
      for (const TopoDS_Edge& e : edges)
      {
        double f, l;
        Handle(Geom2d_Curve) pc = BRep_Tool::CurveOnSurface(e, ff, f, l);
        if (pc.IsNull())
        {
          warn(where + ": an edge has no curve on the face; its loop stays open");
          continue;
        }
        std::vector<Segment2> segs;
        try
        {
          segs = ConvertCurve2d(pc, f, l, tol2d);
        }
        catch (const Standard_Failure& ex)
        {
          warn(where + ": trimming curve conversion failed: " + ex.GetMessageString());
        }
        if (segs.empty())
          continue;
        const bool reversed = e.Orientation() == TopAbs_REVERSED;
        if (reversed)
        {
          std::reverse(segs.begin(), segs.end());
          for (auto& s : segs)
            ReverseSegment(s);
        }
        const int edgeIndex = BRep_Tool::Degenerated(e) ? -1 : edgeMap.FindIndex(e) - 1;
        edgeStarts.push_back(static_cast<int>(model.TrimSegments.size()));
        edgeOf.push_back(e);
        for (const auto& s : segs)
        {
          TrimSegment ts;
          ts.ControlPoints = s.ControlPoints;
          ts.Face = fi;
          ts.Loop = loopIndex;
          ts.Edge = edgeIndex;
          ts.Reversed = reversed;
          ts.T0 = s.T0;
          ts.T1 = s.T1;
          model.TrimSegments.push_back(ts);
        }
      }
      loop.SegmentCount = static_cast<int>(model.TrimSegments.size()) - loop.FirstSegment;
      if (loop.SegmentCount == 0)
        continue;
      // Pcurves written in different periods of a periodic surface (an edge's curve on the face
      // a whole period away from the one before it, where both meet in 3D): each is moved by
      // whole periods to start where the one before it ends, as ShapeFix_Wire::FixShifted does
      // for seams. Welded as they stood, the two ends met half a period from both, and the trim
      // was a different face.
      const double periodU = surface->IsUPeriodic() ? surface->UPeriod() : 0.0;
      const double periodV = surface->IsVPeriodic() ? surface->VPeriod() : 0.0;
      bool shifted = false, winds = false;
      if (periodU > 0.0 || periodV > 0.0)
      {
        auto wholePeriods = [](double d, double period) {
          return period > 0.0 ? std::round(d / period) * period : 0.0;
        };
        auto meetInSpace = [&](const std::array<double, 8>& ca, const std::array<double, 8>& cb,
                             const TopoDS_Edge& before) {
          const TopoDS_Vertex vtx = TopExp::LastVertex(before, Standard_True);
          const double vtxTol = vtx.IsNull() ? 0.0 : BRep_Tool::Tolerance(vtx);
          return surface->Value(ca[6], ca[7]).Distance(surface->Value(cb[0], cb[1])) <=
            std::max(tol, 2.0 * vtxTol);
        };
        // Moves the loop's segments from `first` on by (su, sv).
        auto shiftFrom = [&](int first, double su, double sv) {
          for (int s = first; s < loop.FirstSegment + loop.SegmentCount; ++s)
            for (int i = 0; i < 4; ++i)
            {
              model.TrimSegments[s].ControlPoints[2 * i] += su;
              model.TrimSegments[s].ControlPoints[2 * i + 1] += sv;
            }
        };
        for (size_t k = 1; k < edgeStarts.size(); ++k)
        {
          const int b = edgeStarts[k];
          const auto& ca = model.TrimSegments[b - 1].ControlPoints;
          const auto& cb = model.TrimSegments[b].ControlPoints;
          const double su = wholePeriods(ca[6] - cb[0], periodU);
          const double sv = wholePeriods(ca[7] - cb[1], periodV);
          if ((su != 0.0 || sv != 0.0) && meetInSpace(ca, cb, edgeOf[k - 1]))
          {
            shiftFrom(b, su, sv);
            shifted = true;
          }
        }
        // The loop's end a whole period from its start: it winds.
        if (!edgeStarts.empty())
        {
          const auto& ca = model.TrimSegments[loop.FirstSegment + loop.SegmentCount - 1].ControlPoints;
          const auto& cb = model.TrimSegments[edgeStarts[0]].ControlPoints;
          winds = (wholePeriods(ca[6] - cb[0], periodU) != 0.0 ||
                    wholePeriods(ca[7] - cb[1], periodV) != 0.0) &&
            meetInSpace(ca, cb, edgeOf.back());
        }
        if (shifted && !winds)
        {
          // The whole loop by whole periods to where the face's patches are.
          double lo[2] = { 1e300, 1e300 }, hi[2] = { -1e300, -1e300 };
          for (int s = loop.FirstSegment; s < loop.FirstSegment + loop.SegmentCount; ++s)
            for (int i = 0; i < 8; ++i)
            {
              lo[i % 2] = std::min(lo[i % 2], model.TrimSegments[s].ControlPoints[i]);
              hi[i % 2] = std::max(hi[i % 2], model.TrimSegments[s].ControlPoints[i]);
            }
          shiftFrom(loop.FirstSegment, wholePeriods(0.5 * (u0 + u1 - lo[0] - hi[0]), periodU),
            wholePeriods(0.5 * (v0 + v1 - lo[1] - hi[1]), periodV));
        }
      }
      // Gaps between consecutive pcurves, where the model itself says the two ends are one
      // point (the 3D gap within the shared vertex's tolerance or the conversion tolerance).
      // Within the conversion tolerance they are welded (both ends moved to their middle): that
      // moves the trim by at most half of it. A wider gap is bridged by a straight segment of
      // its own instead, the pcurves left as they are: welding tilts the ends of both segments,
      // and a trim moved by half a gap of 0.0146 mm (a vertex of tolerance 7.3e-3) left a face's
      // point 3.6e-3 mm inside a sphere classified outside its face (OpenCASCADE's
      // trj3_s1-al-214.stp, sample 5718). The bridge stands for the vertex: it belongs to the
      // edge before it, at that edge's end (a parameter range of one point).
      std::vector<char> bridge(edgeStarts.size(), 0);
      for (size_t k = 0; k < edgeStarts.size(); ++k)
      {
        const int b = edgeStarts[k];
        const size_t prev = k == 0 ? edgeStarts.size() - 1 : k - 1;
        const int a = (k == 0 ? loop.FirstSegment + loop.SegmentCount : edgeStarts[k]) - 1;
        auto& ca = model.TrimSegments[a].ControlPoints;
        auto& cb = model.TrimSegments[b].ControlPoints;
        const double gap = std::hypot(ca[6] - cb[0], ca[7] - cb[1]);
        if (gap == 0.0 || (k == 0 && winds))
          continue;
        const double gap3d = surface->Value(ca[6], ca[7]).Distance(surface->Value(cb[0], cb[1]));
        const TopoDS_Vertex vtx = TopExp::LastVertex(edgeOf[prev], Standard_True);
        const double vtxTol = vtx.IsNull() ? 0.0 : BRep_Tool::Tolerance(vtx);
        loop.RawGap = std::max(loop.RawGap, gap);
        loop.RawGap3D = std::max(loop.RawGap3D, gap3d);
        if (gap3d <= tol)
        {
          const double mu = 0.5 * (ca[6] + cb[0]), mv = 0.5 * (ca[7] + cb[1]);
          ca[4] += mu - ca[6];
          ca[5] += mv - ca[7];
          cb[2] += mu - cb[0];
          cb[3] += mv - cb[1];
          ca[6] = cb[0] = mu;
          ca[7] = cb[1] = mv;
        }
        else if (gap3d <= 2.0 * vtxTol)
        {
          bridge[k] = 1;
          // A gap the healing covered by growing the vertex's tolerance to it: the file's
          // edges miss each other there. Real files' gaps stay within hundredths of a
          // millimetre (0.07 mm at most, on a KiCad resistor 1 mm long, over 368 files); a
          // moved vertex (a mutated Voron part) left gaps of 1.6-24 mm, bridged silently.
          if (gap3d > std::max(100.0 * tol, 1e-3 * diagonal) && gapVertices.Add(vtx))
          {
            const gp_Pnt at = BRep_Tool::Pnt(vtx);
            model.LooseVertices.push_back({ at.X(), at.Y(), at.Z(), std::max(vtxTol, gap3d) });
            std::ostringstream w;
            w << where << ": trimming loop " << model.Loops.size()
              << " closes only within its vertex's tolerance " << vtxTol << " at (" << at.X()
              << ", " << at.Y() << ", " << at.Z() << "): its edges miss each other by " << gap3d
              << " mm in 3D; the thickness near there is not reliable";
            warn(w.str());
          }
        }
        else
        {
          std::ostringstream w;
          w << where << ": trimming loop " << model.Loops.size() << " does not close: gap "
            << gap << " in UV, " << gap3d << " in 3D, beyond the vertex tolerance " << vtxTol;
          warn(w.str());
          loop.Open = true;
        }
      }
      if (std::find(bridge.begin(), bridge.end(), 1) != bridge.end())
      {
        const auto first = model.TrimSegments.begin() + loop.FirstSegment;
        const std::vector<TrimSegment> old(first, model.TrimSegments.end());
        model.TrimSegments.erase(first, model.TrimSegments.end());
        for (size_t k = 0; k < edgeStarts.size(); ++k)
        {
          const int b = edgeStarts[k] - loop.FirstSegment;
          const int end = (k + 1 < edgeStarts.size() ? edgeStarts[k + 1] - loop.FirstSegment
                                                     : static_cast<int>(old.size()));
          if (bridge[k])
          {
            const TrimSegment& sa = old[static_cast<size_t>(
              (k == 0 ? static_cast<int>(old.size()) : b) - 1)];
            const TrimSegment& sb = old[static_cast<size_t>(b)];
            TrimSegment br = sa;
            for (int i = 0; i < 4; ++i)
              for (int c = 0; c < 2; ++c)
                br.ControlPoints[2 * i + c] = sa.ControlPoints[6 + c] +
                  (sb.ControlPoints[c] - sa.ControlPoints[6 + c]) * i / 3.0;
            br.T0 = sa.T1;
            model.TrimSegments.push_back(br);
          }
          model.TrimSegments.insert(model.TrimSegments.end(), old.begin() + b, old.begin() + end);
        }
        loop.SegmentCount = static_cast<int>(model.TrimSegments.size()) - loop.FirstSegment;
      }
      if (winds)
      {
        // The loop ends a whole period from where it starts: it winds round the surface (a
        // cylinder's axis) instead of enclosing a region, and no shift of its pcurves closes it
        // (AngelLM/Thor's FreeCAD exports: a half-cylinder whose arc at the foot is the other
        // half of the circle). OpenCASCADE's check calls such a face invalid, and which region
        // it bounds is a guess. A straight segment across the period closes the loop where it
        // was written (OpenCASCADE's classifier reads it so too), and the face is loose.
        const TrimSegment& last = model.TrimSegments.back();
        TrimSegment br = last;
        const auto& first = model.TrimSegments[loop.FirstSegment].ControlPoints;
        for (int i = 0; i < 4; ++i)
          for (int c = 0; c < 2; ++c)
            br.ControlPoints[2 * i + c] =
              last.ControlPoints[6 + c] + (first[c] - last.ControlPoints[6 + c]) * i / 3.0;
        br.Edge = -1;
        br.T0 = br.T1 = 0.0;
        model.TrimSegments.push_back(br);
        loop.SegmentCount = static_cast<int>(model.TrimSegments.size()) - loop.FirstSegment;
        if (std::find(model.LooseFaces.begin(), model.LooseFaces.end(), fi) ==
          model.LooseFaces.end())
        {
          model.LooseFaces.push_back(fi);
          warn(where + ": its boundary's curves on the surface end a whole period from where "
            "they start: the loop winds round the surface instead of enclosing a region "
            "(OpenCASCADE's check calls such a face invalid), so where the face lies is not "
            "known: its samples, and the spheres reaching it, are flagged failed");
        }
      }
      loop.Area = SignedArea(model.TrimSegments, loop.FirstSegment, loop.SegmentCount);
      stats.MaxLoopGap = std::max(stats.MaxLoopGap, loop.RawGap);
      stats.MaxLoopGap3D = std::max(stats.MaxLoopGap3D, loop.RawGap3D);
      stats.OpenLoops += loop.Open ? 1 : 0;
      model.Loops.push_back(loop);
    }
    F.LoopCount = static_cast<int>(model.Loops.size()) - F.FirstLoop;
    // The outer loop: the one that encloses the others, so the largest in (u, v). OpenCASCADE's
    // BRepTools::OuterWire is a guess, and it named the D-shaped hole of a long plane strip the
    // outer wire (Creality's Ender-3 4040 profile, face 169): the strip, reversed into a hole,
    // was measured as the hole alone, and spheres 1.4 mm into the strip passed. Its choice stands
    // where another loop is not larger (loops side by side on a periodic surface).
    int outer = -1;
    for (int l = F.FirstLoop; l < F.FirstLoop + F.LoopCount; ++l)
      if (model.Loops[l].Outer)
        outer = l;
    for (int l = F.FirstLoop; l < F.FirstLoop + F.LoopCount; ++l)
      if (outer < 0 ||
        std::abs(model.Loops[l].Area) > (1.0 + 1e-6) * std::abs(model.Loops[outer].Area))
        outer = l;
    for (int loopIndex = F.FirstLoop; loopIndex < F.FirstLoop + F.LoopCount; ++loopIndex)
    {
      TrimLoop& loop = model.Loops[loopIndex];
      loop.Outer = loopIndex == outer;
      if ((loop.Outer && loop.Area < 0.0) || (!loop.Outer && loop.Area > 0.0))
      {
        warn(where + ": trimming loop " + std::to_string(loopIndex) +
          " had the wrong orientation for its role and was reversed");
        std::reverse(model.TrimSegments.begin() + loop.FirstSegment,
          model.TrimSegments.begin() + loop.FirstSegment + loop.SegmentCount);
        for (int s = loop.FirstSegment; s < loop.FirstSegment + loop.SegmentCount; ++s)
        {
          TrimSegment& ts = model.TrimSegments[s];
          for (int i = 0; i < 2; ++i)
          {
            std::swap(ts.ControlPoints[2 * i], ts.ControlPoints[2 * (3 - i)]);
            std::swap(ts.ControlPoints[2 * i + 1], ts.ControlPoints[2 * (3 - i) + 1]);
          }
          std::swap(ts.T0, ts.T1);
          ts.Reversed = !ts.Reversed;
        }
        loop.Area = -loop.Area;
      }
    }
    progress(0.55 + 0.1 * (fi + 1) / faceMap.Extent());
  }

  // --- edges --------------------------------------------------------------------------------
  model.Edges.resize(edgeMap.Extent());
  for (int ei = 0; ei < edgeMap.Extent(); ++ei)
  {
    const TopoDS_Edge edge = TopoDS::Edge(edgeMap(ei + 1));
    Edge& E = model.Edges[ei];
    if (edgeFaces.Contains(edge))
    {
      for (TopTools_ListOfShape::Iterator it(edgeFaces.FindFromKey(edge)); it.More(); it.Next())
      {
        const int f = faceMap.FindIndex(it.Value()) - 1;
        if (f < 0)
          continue;
        if (E.FaceCount < 2)
          E.Faces[E.FaceCount] = f;
        ++E.FaceCount;
        if (BRep_Tool::IsClosed(edge, TopoDS::Face(it.Value())))
        {
          E.Seam = true;
          E.Faces = { f, f };
        }
      }
    }
    // (An edge of more than two faces: CheckConvertedModel splits it where its faces pair into
    // wedges, and warns of the solid as non-manifold where they do not.)
    double f, l;
    Handle(Geom_Curve) c = BRep_Tool::Curve(edge, f, l);
    E.T0 = f;
    E.T1 = l;
    E.FirstSegment = static_cast<int>(model.EdgeSegments.size());
    if (c.IsNull())
    {
      warn("edge " + std::to_string(ei) + " has no 3D curve");
      continue;
    }
    std::vector<Segment3> segs;
    try
    {
      segs = ConvertCurve3d(c, f, l, 0.5 * tol);
      E.MaxDeviation = MeasureCurve<3>(c, segs);
    }
    catch (const Standard_Failure& ex)
    {
      warn("edge " + std::to_string(ei) + ": conversion failed: " + ex.GetMessageString());
    }
    for (const auto& s : segs)
    {
      EdgeSegment es;
      es.ControlPoints = s.ControlPoints;
      es.Edge = ei;
      es.T0 = s.T0;
      es.T1 = s.T1;
      model.EdgeSegments.push_back(es);
    }
    E.SegmentCount = static_cast<int>(segs.size());
    stats.MaxEdgeDeviation = std::max(stats.MaxEdgeDeviation, E.MaxDeviation);
  }
  stats.ConvertSeconds = Since(t0);
  progress(0.75);

  // --- display mesh -------------------------------------------------------------------------
  t0 = Clock::now();
  const double deflection =
    options.LinearDeflection > 0.0 ? options.LinearDeflection : 1e-3 * diagonal;
  const double maxEdge = options.MaxEdgeLength > 0.0 ? options.MaxEdgeLength : diagonal / 50.0;
  BRepMesh_IncrementalMesh mesher(shape, deflection, Standard_False, options.AngularDeflection,
    Standard_True);
  stats.RemeshedFaces =
    MeshFacesLeftWithoutTriangulation(faceMap, deflection, options.AngularDeflection);
  DisplayMesh& M = model.Mesh;
  // Each face is refined on its own (FaceRefiner), on every core, faces taken in turn; their
  // meshes are then joined in the faces' order, as one loop over them gives them. The calling
  // thread refines too and reports the progress between its faces; a failure or an abort stops
  // the others and is rethrown here.
  struct FaceMesh
  {
    bool Made = false, Flipped = false, Stopped = false;
    std::vector<gp_Pnt2d> UV;
    std::vector<std::array<int, 3>> Tris; ///< the refined mesh's live triangles
    /// Per vertex, the principal curvatures (PrincipalConvexity), zeros at a singular point; on
    /// the face's boundary taken just inside it (below).
    std::vector<std::array<double, 2>> Curvatures;
  };
  const int faceCount = faceMap.Extent();
  std::vector<TopoDS_Face> forwardFaces(static_cast<size_t>(faceCount));
  for (int fi = 0; fi < faceCount; ++fi)
    forwardFaces[static_cast<size_t>(fi)] =
      TopoDS::Face(TopoDS::Face(faceMap(fi + 1)).Oriented(TopAbs_FORWARD));
  std::vector<FaceMesh> faceMeshes(static_cast<size_t>(faceCount));
  auto refineFace = [&](int fi) {
    const TopoDS_Face& ff = forwardFaces[static_cast<size_t>(fi)];
    TopLoc_Location loc;
    Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(ff, loc);
    Handle(Geom_Surface) surface = BRep_Tool::Surface(ff);
    if (tri.IsNull() || !tri->HasUVNodes() || surface.IsNull())
      return; // warned below
    // Offset and swept surfaces evaluate through adaptors that cache their basis (a B-spline's
    // spans), which two threads must not share: faces that share such a surface each refine on
    // a copy of their own (the same geometry, so the same mesh).
    Handle(Geom_Surface) basis = surface;
    if (Handle(Geom_RectangularTrimmedSurface) rt =
          Handle(Geom_RectangularTrimmedSurface)::DownCast(surface))
      basis = rt->BasisSurface();
    if (basis->IsKind(STANDARD_TYPE(Geom_OffsetSurface)) ||
      basis->IsKind(STANDARD_TYPE(Geom_SurfaceOfRevolution)) ||
      basis->IsKind(STANDARD_TYPE(Geom_SurfaceOfLinearExtrusion)))
      surface = Handle(Geom_Surface)::DownCast(surface->Copy());
    // The side test's kept answers serve each refinement of the face (bisection, flipped).
    std::shared_ptr<FaceSide> side;
    auto meshFace = [&](bool delaunay, size_t cap) {
      FaceRefiner fm(surface, ff, delaunay, deflection, options.AngularDeflection, side);
      for (int i = 1; i <= tri->NbNodes(); ++i)
        fm.AddVertex(tri->UVNode(i));
      for (int i = 1; i <= tri->NbTriangles(); ++i)
      {
        int n[3];
        tri->Triangle(i).Get(n[0], n[1], n[2]);
        fm.AddTriangle(n[0] - 1, n[1] - 1, n[2] - 1);
      }
      for (TopExp_Explorer ex(ff, TopAbs_EDGE); ex.More(); ex.Next())
      {
        const TopoDS_Edge e = TopoDS::Edge(ex.Current());
        Handle(Poly_PolygonOnTriangulation) poly = BRep_Tool::PolygonOnTriangulation(e, tri, loc);
        if (poly.IsNull() || !poly->HasParameters())
          continue;
        for (int k = 1; k < poly->NbNodes(); ++k)
          fm.AddChord(poly->Node(k) - 1, poly->Node(k + 1) - 1, e, poly->Parameter(k),
            poly->Parameter(k + 1));
      }
      fm.KeepNodesOnTheFace();
      fm.Refine(maxEdge, cap);
      return fm;
    };
    // Bisection keeps the coarse mesh's slivers; where that would end far denser than the
    // limits ask and large (more than SliverRatio times the vertices of the flipped mesh and
    // than SliverVertices), the flipped mesh is taken. Each bisection stops at its budget, so a
    // long cylinder's side costs no more than that, and a face that stays within SliverVertices
    // is meshed once, as without the guard.
    FaceMesh& out = faceMeshes[static_cast<size_t>(fi)];
    const size_t cap = static_cast<size_t>(options.MaxVerticesPerFace);
    const bool guard = !options.DelaunayRefinement && options.SliverRatio > 0.0;
    const size_t floor = static_cast<size_t>(std::max(0, options.SliverVertices));
    FaceRefiner fm = meshFace(options.DelaunayRefinement, guard ? std::min(cap, floor + 1) : cap);
    if (guard && fm.UV.size() > floor)
    {
      FaceRefiner flipped = meshFace(true, cap);
      const size_t budget = std::max(
        floor, static_cast<size_t>(options.SliverRatio * static_cast<double>(flipped.UV.size())));
      bool bisectionFits = false;
      if (budget > floor)
      {
        // Over the floor but perhaps within the ratio: bisection again, up to the ratio's budget.
        FaceRefiner bisected = meshFace(false, std::min(cap, budget + 1));
        bisectionFits = bisected.UV.size() <= budget;
        if (bisectionFits)
          fm = std::move(bisected);
      }
      if (!bisectionFits)
      {
        fm = std::move(flipped);
        out.Flipped = true;
      }
    }
    out.Stopped = fm.Stopped;
    out.UV = std::move(fm.UV);
    for (size_t ti = 0; ti < fm.Tris.size(); ++ti)
      if (fm.Alive[ti])
        out.Tris.push_back(fm.Tris[ti]);
    // The principal curvatures of each vertex (on every core, on this face's own surface).
    const bool reversed = model.Faces[static_cast<size_t>(fi)].Reversed;
    auto convexityAt = [&](double u, double v) {
      gp_Pnt q;
      gp_Vec du, dv, duu, dvv, duv;
      surface->D2(u, v, q, du, dv, duu, dvv, duv);
      gp_Vec n = du.Crossed(dv);
      if (!(n.Magnitude() >= 1e-12 * std::max(1.0, du.Magnitude() * dv.Magnitude())))
        return std::array<double, 2>{ 0.0, 0.0 }; // a singular point (pole, apex): none
      n.Normalize();
      if (reversed)
        n.Reverse();
      return PrincipalConvexity(du, dv, duu, dvv, duv, n);
    };
    // Vertices on the face's boundary (on a triangle edge used once): there the curvatures are
    // taken just inside the face, 1e-2 of the way to each of the vertex's triangles' centroids
    // (where the solver moves such a sample, SamplesFromMesh), the smallest largest and the
    // largest smallest of them. At the boundary itself the surface's second derivatives may be
    // the next span's, beyond the face (a knot there: Hammond's 1590T's fillet read 7e-4 more
    // curved on its edge than 0.0014 inside it).
    std::vector<std::pair<int, int>> edges;
    edges.reserve(3 * out.Tris.size());
    for (const auto& t : out.Tris)
      for (int k = 0; k < 3; ++k)
        edges.push_back(std::minmax(t[k], t[(k + 1) % 3]));
    std::sort(edges.begin(), edges.end());
    std::vector<char> onBoundary(out.UV.size(), 0);
    for (size_t k = 0; k < edges.size();)
    {
      size_t e = k + 1;
      while (e < edges.size() && edges[e] == edges[k])
        ++e;
      if (e - k == 1)
        onBoundary[static_cast<size_t>(edges[k].first)] =
          onBoundary[static_cast<size_t>(edges[k].second)] = 1;
      k = e;
    }
    out.Curvatures.assign(out.UV.size(),
      { std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity() });
    for (const auto& t : out.Tris)
    {
      double cu = 0.0, cv = 0.0;
      for (int k = 0; k < 3; ++k)
      {
        cu += out.UV[static_cast<size_t>(t[k])].X() / 3.0;
        cv += out.UV[static_cast<size_t>(t[k])].Y() / 3.0;
      }
      for (int k = 0; k < 3; ++k)
      {
        const size_t vi = static_cast<size_t>(t[k]);
        if (!onBoundary[vi])
          continue;
        const gp_Pnt2d& uv = out.UV[vi];
        const std::array<double, 2> inside =
          convexityAt(uv.X() + 1e-2 * (cu - uv.X()), uv.Y() + 1e-2 * (cv - uv.Y()));
        auto& c = out.Curvatures[vi];
        c[0] = std::min(c[0], inside[0]);
        c[1] = std::max(c[1], inside[1]);
      }
    }
    for (size_t vi = 0; vi < out.UV.size(); ++vi)
      if (!onBoundary[vi] || !std::isfinite(out.Curvatures[vi][0]))
        out.Curvatures[vi] = convexityAt(out.UV[vi].X(), out.UV[vi].Y());
    out.Made = true;
  };
  OnEveryCore(faceCount, refineFace,
    [&](int finished) { progress(0.75 + 0.2 * finished / faceCount); });
  for (int fi = 0; fi < faceCount; ++fi)
  {
    const FaceMesh& fm = faceMeshes[static_cast<size_t>(fi)];
    if (!fm.Made)
    {
      // Its area, so that a user can tell a sliver (the surveyed files' six left are at most
      // 6e-4 mm^2) from a hole in the map that matters.
      std::ostringstream w;
      w << "face " << fi << ": no display mesh could be made";
      try
      {
        GProp_GProps props;
        BRepGProp::SurfaceProperties(forwardFaces[static_cast<size_t>(fi)], props);
        w << " (area " << std::setprecision(3) << props.Mass() << " mm^2)";
      }
      catch (const Standard_Failure&)
      {
      }
      w << "; it has no samples";
      warn(w.str());
      continue;
    }
    stats.FlippedFaces += fm.Flipped ? 1 : 0;
    if (fm.Stopped)
      warn("face " + std::to_string(fi) + ": its display mesh was refined only in part (" +
        std::to_string(fm.UV.size()) + " vertices): its refinement asked which side of the trim "
        "a point lies on more often than a sound face does; the face may be damaged, and its "
        "samples are coarse");
    Handle(Geom_Surface) surface = BRep_Tool::Surface(forwardFaces[static_cast<size_t>(fi)]);
    const int base = static_cast<int>(M.FaceIds.size());
    for (size_t vi = 0; vi < fm.UV.size(); ++vi)
    {
      const gp_Pnt2d& uv = fm.UV[vi];
      gp_Pnt p;
      gp_Vec du, dv;
      surface->D1(uv.X(), uv.Y(), p, du, dv);
      gp_Vec n = du.Crossed(dv);
      if (n.Magnitude() < 1e-12 * std::max(1.0, du.Magnitude() * dv.Magnitude()))
      {
        // Singular point (pole, apex): take the normal a little way into the face.
        const auto& d = model.Faces[fi].Domain;
        const double cu = 0.5 * (d[0] + d[1]), cv = 0.5 * (d[2] + d[3]);
        gp_Pnt q;
        surface->D1(uv.X() + 1e-6 * (cu - uv.X()), uv.Y() + 1e-6 * (cv - uv.Y()), q, du, dv);
        n = du.Crossed(dv);
      }
      if (n.Magnitude() > 0.0)
        n.Normalize();
      if (model.Faces[fi].Reversed)
        n.Reverse();
      const std::array<double, 2>& c = fm.Curvatures[vi];
      M.Points.insert(M.Points.end(), { p.X(), p.Y(), p.Z() });
      M.Normals.insert(M.Normals.end(), { n.X(), n.Y(), n.Z() });
      M.Curvatures.insert(M.Curvatures.end(), { c[0], c[1] });
      M.UV.insert(M.UV.end(), { uv.X(), uv.Y() });
      M.FaceIds.push_back(fi);
    }
    for (const auto& t : fm.Tris)
    {
      if (model.Faces[fi].Reversed)
        M.Triangles.insert(M.Triangles.end(), { base + t[0], base + t[2], base + t[1] });
      else
        M.Triangles.insert(M.Triangles.end(), { base + t[0], base + t[1], base + t[2] });
      M.TriangleFace.push_back(fi);
    }
    progress(0.95 + 0.05 * (fi + 1) / faceCount);
  }
  // Faces of one solid lying on one another, their outer sides the same way: named, and their
  // samples flagged (BRepModel::OverlappingFaces).
  {
    std::map<int, std::set<int>> bySolid;
    for (const auto& ab : FindCoincidentFaces(model, forwardFaces, tol, deflection))
      for (int f : { ab.first, ab.second })
        bySolid[model.Faces[static_cast<size_t>(f)].Solid].insert(f);
    for (const auto& sf : bySolid)
    {
      model.OverlappingFaces.insert(
        model.OverlappingFaces.end(), sf.second.begin(), sf.second.end());
      std::ostringstream w;
      w << "solid " << sf.first << ": faces ";
      int named = 0;
      for (int f : sf.second)
      {
        if (named == 6)
        {
          w << " and " << sf.second.size() - 6 << " more";
          break;
        }
        w << (named == 0 ? "" : (named + 1 == static_cast<int>(sf.second.size()) ? " and " : ", "))
          << f << " (" << SurfaceKindName(model.Faces[static_cast<size_t>(f)].Kind) << ")";
        ++named;
      }
      w << " lie on one another with their outer sides the same way (a face written twice, or "
           "faces overlapping): which of them bounds the part there is not known, so their "
           "samples are flagged failed";
      warn(w.str());
    }
  }
  stats.MeshSeconds = Since(t0);

  // Faces that bound several solids or shells: a copy for each (sharedUses), and each edge then
  // given to one solid.
  AddSharedFaceCopies(model, sharedUses);
  if (!sharedUses.empty())
  {
    SplitEdgesAcrossSolids(model);
    // Where: a display vertex of the first such face (else its first patch's corner).
    const int first = sharedUses[0].Face;
    std::array<double, 3> at{};
    const auto& ids = model.Mesh.FaceIds;
    const auto hit = std::find(ids.begin(), ids.end(), first);
    if (hit != ids.end())
      for (int k = 0; k < 3; ++k)
        at[static_cast<size_t>(k)] =
          model.Mesh.Points[3 * static_cast<size_t>(hit - ids.begin()) + static_cast<size_t>(k)];
    else if (model.Faces[static_cast<size_t>(first)].PatchCount > 0)
      for (int k = 0; k < 3; ++k)
        at[static_cast<size_t>(k)] =
          model.Patches[static_cast<size_t>(model.Faces[static_cast<size_t>(first)].FirstPatch)]
            .ControlPoints[static_cast<size_t>(k)];
    std::ostringstream w;
    w << sharedUses.size() << " face(s) bound more than one solid or shell (bodies written with "
      << "the faces where they meet shared, the first at (" << at[0] << ", " << at[1] << ", "
      << at[2] << ")): each body has a copy of its own, measured in that body";
    warn(w.str());
  }
  if (faces)
  {
    faces->clear();
    for (int i = 1; i <= faceMap.Extent(); ++i)
      faces->push_back(TopoDS::Face(faceMap(i)));
    for (const SharedFaceUse& u : sharedUses)
      faces->push_back(TopoDS::Face(
        faceMap(u.Face + 1).Oriented(u.Reversed ? TopAbs_REVERSED : TopAbs_FORWARD)));
  }
  stats.Faces = static_cast<int>(model.Faces.size());
  stats.Patches = static_cast<int>(model.Patches.size());
  stats.Loops = static_cast<int>(model.Loops.size());
  stats.TrimSegments = static_cast<int>(model.TrimSegments.size());
  stats.Edges = static_cast<int>(model.Edges.size());
  stats.EdgeSegments = static_cast<int>(model.EdgeSegments.size());
  return model;
}

} // namespace

BRepModel ConvertShape(const TopoDS_Shape& input, const ConversionOptions& options,
  std::vector<TopoDS_Face>* faces)
{
  try
  {
    return ConvertShapeImpl(input, options, faces, false);
  }
  catch (const Standard_Failure& e)
  {
    throw std::runtime_error(std::string("OpenCASCADE failed during conversion: ") +
      e.GetMessageString());
  }
}

void CheckConvertedModel(const std::string& path, BRepModel& model)
{
  auto Square = [](double x) { return x * x; };
  auto fail = [&](const std::string& why) { throw InputError("STEP file '" + path + "': " + why); };
  try
  {
    ValidateModel(model);
  }
  catch (const std::runtime_error& e)
  {
    fail(std::string("the conversion produced an unusable model (") + e.what() + ")");
  }
  // A face (its patches) beyond the text check's bound on coordinates: a face with no bound (a
  // plane's natural bounds in OpenCASCADE reach 1e85 mm, in a mutation of the plate whose face
  // lost its bound list; the mesh leaves such a face out) or a damaged one.
  {
    double far = 0.0;
    int farFace = -1;
    for (const BezierPatch& b : model.Patches)
      for (const double c : b.ControlPoints)
        if (!(std::fabs(c) <= far))
        {
          far = std::fabs(c);
          farFace = b.Face;
        }
    if (!(far <= MaxCoordinateMillimetres))
    {
      std::ostringstream w;
      w << "face " << farFace << " reaches " << far
        << " mm from the origin, beyond 1,000 km: a face without a bound on an unbounded "
           "surface (a plane, cylinder or cone), or a damaged one";
      fail(w.str());
    }
  }
  // Size against the tolerance: a part a few tolerances across has no wall the patches keep.
  const auto& pts = model.Mesh.Points;
  std::array<double, 6> box{ 1e300, -1e300, 1e300, -1e300, 1e300, -1e300 };
  for (size_t i = 0; i < pts.size(); ++i)
  {
    box[2 * (i % 3)] = std::min(box[2 * (i % 3)], pts[i]);
    box[2 * (i % 3) + 1] = std::max(box[2 * (i % 3) + 1], pts[i]);
  }
  const double diagonal = pts.empty() ? 0.0
                                      : std::sqrt(Square(box[1] - box[0]) +
                                          Square(box[3] - box[2]) + Square(box[5] - box[4]));
  if (diagonal < MinSizeInTolerances * model.Tolerance)
  {
    std::ostringstream w;
    w << "the part is only " << diagonal << " mm across, less than " << MinSizeInTolerances
      << " times the conversion tolerance " << model.Tolerance
      << " mm: its walls would vanish within the tolerance (lower the reader's Tolerance to "
      << diagonal / 1e4 << " or less)";
    fail(w.str());
  }
  // Edges where bodies of a solid touch, one per pair of faces (their wedges from the faces'
  // orientation, which the volume's sign tells before OrientSolids turns it).
  std::vector<int> faceCounts;
  for (const Edge& e : model.Edges)
    faceCounts.push_back(e.FaceCount);
  for (const int e : SplitNonManifoldEdges(model, CheckSolids(model)))
    model.Stats.Warnings.push_back("edge " + std::to_string(e) + " bounds " +
      std::to_string(faceCounts[static_cast<size_t>(e)]) +
      " faces where bodies of its solid touch along it: split into one edge per pair of faces "
      "(the thickness goes to 0 along it)");
  const std::vector<SolidCheck> checks = CheckSolids(model);
  int closed = 0;
  std::string firstBad;
  for (size_t s = 0; s < checks.size(); ++s)
  {
    const SolidCheck& c = checks[s];
    if (c.Faces == 0)
      continue;
    if (c.Closed())
    {
      ++closed;
      continue;
    }
    std::ostringstream w;
    w << "solid " << s << " (" << c.Faces << " faces) ";
    if (c.FreeEdges > 0)
      w << "is open: " << c.FreeEdges << " edges bound only one face";
    if (c.FreeEdges > 0 && c.NonManifoldEdges > 0)
      w << ", and ";
    if (c.NonManifoldEdges > 0)
      w << "is non-manifold: " << c.NonManifoldEdges << " edges are shared by more than two faces";
    w << " (one at " << c.FreeEdgeAt[0] << ", " << c.FreeEdgeAt[1] << ", " << c.FreeEdgeAt[2]
      << ")";
    if (firstBad.empty())
      firstBad = w.str();
    model.Stats.Warnings.push_back(w.str() + "; its samples are flagged failed");
  }
  if (closed == 0)
    fail("holds no closed solid: " + firstBad +
      ". A thickness needs a closed, manifold solid; repair the model in CAD");
  // Faces without display triangles: the volume is the display mesh's, and leaves them out.
  std::vector<char> meshed(model.Faces.size(), 0);
  for (const int f : model.Mesh.TriangleFace)
    if (f >= 0 && static_cast<size_t>(f) < meshed.size())
      meshed[static_cast<size_t>(f)] = 1;
  for (size_t s = 0; s < checks.size(); ++s)
    if (checks[s].Closed() && checks[s].Outward != 0 &&
      (checks[s].Outward < 0) != (checks[s].Volume < 0.0))
    {
      int meshless = 0;
      for (size_t f = 0; f < model.Faces.size(); ++f)
        meshless += model.Faces[f].Solid == static_cast<int>(s) && !meshed[f];
      std::ostringstream w;
      w << "solid " << s << ": its outermost faces face " << (checks[s].Outward > 0 ? "out" : "in")
        << "wards, but its faces enclose a " << (checks[s].Volume < 0.0 ? "negative" : "positive")
        << " volume (" << checks[s].Volume << " mm^3";
      if (meshless > 0)
        w << ", without its " << meshless
          << (meshless > 1 ? " faces that have" : " face that has") << " no display mesh";
      w << "): a face's loops or geometry are damaged; its orientation is taken from the "
           "outermost faces";
      model.Stats.Warnings.push_back(w.str());
    }
  for (int s : OrientSolids(model, checks))
    model.Stats.Warnings.push_back("solid " + std::to_string(s) +
      " was inside out (its face normals pointed inwards); its orientation was reversed");
}

BRepModel ConvertStepFile(const std::string& path, const ConversionOptions& options,
  std::vector<TopoDS_Face>* faces)
{
  StepReadResult info;
  const TopoDS_Shape shape = ReadStepFile(path, &info);
  BRepModel model;
  try
  {
    model = ConvertShapeImpl(shape, options, faces, true);
  }
  catch (const Standard_Failure& e)
  {
    throw InputError("STEP file '" + path + "': OpenCASCADE failed during conversion: " +
      e.GetMessageString());
  }
  catch (const std::runtime_error& e)
  {
    throw InputError("STEP file '" + path + "': " + e.what());
  }
  model.SourceFile = path;
  model.LengthUnit = info.LengthUnit;
  model.Stats.ReadSeconds = info.Seconds;
  model.Schema = info.Schema;
  auto& warnings = model.Stats.Warnings;
  warnings.insert(warnings.begin(), info.Warnings.begin(), info.Warnings.end());
  try
  {
    CheckConvertedModel(path, model);
  }
  catch (const InputError& e)
  {
    // A face lost with its B-spline surface leaves its solid open: the refusal names the
    // B-splines OpenCASCADE read nothing from (the text check's), the likely cause.
    const std::string unread = DescribeUnreadGeometry(info.Scan);
    if (unread.empty())
      throw;
    const std::string why = e.what() + unread;
    throw InputError(why);
  }
  return model;
}

namespace
{
/// The oriented edge's direction where it starts (or ends, atEnd) in its wire's sense.
gp_Vec WireTangent(const TopoDS_Edge& e, bool atEnd)
{
  BRepAdaptor_Curve c(e);
  const bool reversed = e.Orientation() == TopAbs_REVERSED;
  gp_Pnt p;
  gp_Vec d;
  c.D1((atEnd != reversed) ? c.LastParameter() : c.FirstParameter(), p, d);
  return reversed ? -d : d;
}

/// A copy of `longer` (an edge of `face`, oriented as in its wire) that keeps its start in the
/// wire's sense (keepStart) or its end, and ends (starts) at `to`, a vertex on its curve.
TopoDS_Edge TrimmedTo(const TopoDS_Edge& longer, bool keepStart, const TopoDS_Vertex& to,
  const TopoDS_Face& face)
{
  double f, l;
  const Handle(Geom_Curve) c = BRep_Tool::Curve(longer, f, l);
  gp_Pnt proj;
  double param = f;
  ShapeAnalysis_Curve().Project(c, BRep_Tool::Pnt(to), Precision::Confusion(), proj, param, f, l,
    Standard_False);
  // In the edge's own sense its first vertex lies at f; reversed in the wire, the wire's start
  // is its last vertex.
  const bool keepFirst = keepStart != (longer.Orientation() == TopAbs_REVERSED);
  const TopoDS_Edge forward = TopoDS::Edge(longer.Oriented(TopAbs_FORWARD));
  TopoDS_Vertex vf, vl;
  TopExp::Vertices(forward, vf, vl);
  ShapeBuild_Edge sbe;
  const TopoDS_Edge e = keepFirst
    ? sbe.CopyReplaceVertices(forward, vf, TopoDS::Vertex(to.Oriented(TopAbs_REVERSED)))
    : sbe.CopyReplaceVertices(forward, TopoDS::Vertex(to.Oriented(TopAbs_FORWARD)), vl);
  const double a = keepFirst ? f : param, b = keepFirst ? param : l;
  sbe.SetRange3d(e, a, b);
  BRep_Builder().Range(e, face, a, b);
  return TopoDS::Edge(e.Oriented(longer.Orientation()));
}

/// `face` without the notches of its wires: two edges in a row on one curve, the second turning
/// back along the first (a boundary that goes out and comes back the same way, enclosing
/// nothing: the headbands' planes, written so by SolidWorks). The longer edge is trimmed to where
/// the shorter one ends and the shorter one goes. BRepMesh fails on such a face; without the
/// notch it meshes, and the face's area is the same. The edges that went or changed are added to
/// `changed` (the face's own ones); none where the face has no notch.
TopoDS_Face WithoutNotches(const TopoDS_Face& face, TopTools_MapOfShape& changed)
{
  BRep_Builder b;
  TopoDS_Face out = TopoDS::Face(face.EmptyCopied());
  for (TopExp_Explorer w(face, TopAbs_WIRE); w.More(); w.Next())
  {
    std::vector<TopoDS_Edge> edges;
    for (BRepTools_WireExplorer e(TopoDS::Wire(w.Current()), face); e.More(); e.Next())
      edges.push_back(e.Current());
    bool again = true;
    while (again && edges.size() > 2)
    {
      again = false;
      for (size_t i = 0; i < edges.size() && !again; ++i)
      {
        const size_t j = (i + 1) % edges.size();
        const TopoDS_Edge a = edges[i], c = edges[j];
        if (BRep_Tool::Degenerated(a) || BRep_Tool::Degenerated(c))
          continue;
        const gp_Vec ta = WireTangent(a, true), tc = WireTangent(c, false);
        if (ta.Magnitude() < 1e-12 || tc.Magnitude() < 1e-12 ||
          ta.Normalized().Dot(tc.Normalized()) > -0.9999)
          continue;
        // The shorter edge must lie on the longer's curve: its far end within the tolerances.
        const double la = GCPnts_AbscissaPoint::Length(BRepAdaptor_Curve(a));
        const double lc = GCPnts_AbscissaPoint::Length(BRepAdaptor_Curve(c));
        const bool aShorter = la < lc;
        const TopoDS_Edge& longer = aShorter ? c : a;
        const TopoDS_Vertex far = aShorter ? TopExp::FirstVertex(a, Standard_True)
                                           : TopExp::LastVertex(c, Standard_True);
        double f, l;
        const Handle(Geom_Curve) curve = BRep_Tool::Curve(longer, f, l);
        if (curve.IsNull())
          continue;
        gp_Pnt proj;
        double param;
        const double gap = ShapeAnalysis_Curve().Project(curve, BRep_Tool::Pnt(far),
          Precision::Confusion(), proj, param, f, l, Standard_False);
        if (gap > BRep_Tool::Tolerance(a) + BRep_Tool::Tolerance(c) + BRep_Tool::Tolerance(far))
          continue;
        changed.Add(a);
        changed.Add(c);
        const TopoDS_Edge merged = TrimmedTo(longer, !aShorter, far, face);
        if (aShorter)
        {
          edges[j] = merged;
          edges.erase(edges.begin() + static_cast<std::ptrdiff_t>(i));
        }
        else
        {
          edges[i] = merged;
          edges.erase(edges.begin() + static_cast<std::ptrdiff_t>(j));
        }
        again = true;
      }
    }
    TopoDS_Wire wire;
    b.MakeWire(wire);
    for (const TopoDS_Edge& e : edges)
      b.Add(wire, e);
    wire.Orientation(w.Current().Orientation());
    b.Add(out, wire);
  }
  return changed.IsEmpty() ? face : out;
}

/// One face of MeshFacesLeftWithoutTriangulation: true where it got a triangulation.
/// Puts `tri` on `face` (at the face's location `loc`) and each polygon on its edge: the two of
/// a seam as BRep_Tool reads them, its forward use's first.
void InstallTriangulation(const TopoDS_Face& face, const TopLoc_Location& loc,
  const Handle(Poly_Triangulation)& tri, const std::vector<EdgePolygons>& polygons)
{
  BRep_Builder b;
  b.UpdateFace(face, tri);
  for (const auto& [e, p] : polygons)
  {
    if (p[1].IsNull())
      b.UpdateEdge(e, p[0], tri, loc);
    else
      b.UpdateEdge(e, p[0], p[1], tri, loc);
  }
}

bool MeshFaceAgain(
  const TopoDS_Face& face, const TopLoc_Location& loc, double deflection, double angularDeflection)
{
  // Coarser first, with the algorithm that meshed most of such faces, then the other; finer
  // only for a small face: on a large face a try that fails took seconds.
  Bnd_Box box;
  BRepBndLib::Add(face, box);
  const bool small = !box.IsVoid() && std::sqrt(box.SquareExtent()) < 10.0 * deflection;
  // Every try meshes a copy without the notches of its wires; a face that has any is tried
  // first at the deflection asked for. The notch's edges get no polygon (the refinement splits
  // their chords in UV).
  TopTools_MapOfShape notched;
  {
    BRepBuilderAPI_Copy probe(face, Standard_True, Standard_False);
    (void)WithoutNotches(TopoDS::Face(probe.Shape()), notched);
  }
  std::vector<std::pair<double, IMeshTools_MeshAlgoType>> tries;
  if (!notched.IsEmpty())
    tries.emplace_back(1.0, IMeshTools_MeshAlgoType_Watson);
  tries.emplace_back(4.0, IMeshTools_MeshAlgoType_Delabella);
  tries.emplace_back(4.0, IMeshTools_MeshAlgoType_Watson);
  if (small)
    tries.emplace_back(0.25, IMeshTools_MeshAlgoType_Watson);
  for (const auto& [k, algo] : tries)
  {
    BRepBuilderAPI_Copy copier(face, Standard_True, Standard_False);
    TopTools_MapOfShape changed;
    const TopoDS_Face copy = WithoutNotches(TopoDS::Face(copier.Shape()), changed);
    IMeshTools_Parameters p;
    p.Deflection = k * deflection;
    p.Angle = angularDeflection;
    p.MeshAlgo = algo;
    try
    {
      BRepMesh_IncrementalMesh m(copy, p);
    }
    catch (const Standard_Failure&)
    {
      continue;
    }
    TopLoc_Location cl;
    const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(copy, cl);
    if (tri.IsNull() || !tri->HasUVNodes())
      continue;
    // Each edge of the face (but a notch's) needs its copy's polygon on the triangulation.
    std::vector<EdgePolygons> polygons;
    bool complete = true;
    for (TopExp_Explorer ex(face, TopAbs_EDGE); ex.More() && complete; ex.Next())
    {
      const TopoDS_Edge& e = TopoDS::Edge(ex.Current());
      if (BRep_Tool::Degenerated(e))
        continue;
      const TopoDS_Edge c = TopoDS::Edge(copier.ModifiedShape(e));
      if (changed.Contains(c))
        continue;
      const bool seam = BRep_Tool::IsClosed(c, copy);
      const Handle(Poly_PolygonOnTriangulation) first = BRep_Tool::PolygonOnTriangulation(
        seam ? TopoDS::Edge(c.Oriented(TopAbs_FORWARD)) : c, tri, cl);
      const Handle(Poly_PolygonOnTriangulation) second = seam
        ? BRep_Tool::PolygonOnTriangulation(TopoDS::Edge(c.Oriented(TopAbs_REVERSED)), tri, cl)
        : Handle(Poly_PolygonOnTriangulation)();
      complete = !first.IsNull() && (!seam || !second.IsNull());
      polygons.push_back({ e, { first, second } });
    }
    if (!complete)
      continue;
    InstallTriangulation(face, loc, tri, polygons);
    return true;
  }
  // Last, a B-spline copy, mapped back onto the face.
  std::vector<EdgePolygons> polygons;
  const Handle(Poly_Triangulation) tri =
    MeshThroughBSplines(face, deflection, angularDeflection, polygons);
  if (tri.IsNull())
    return false;
  InstallTriangulation(face, loc, tri, polygons);
  return true;
}

} // namespace

// Doc in BRepConverter.h.
Handle(Poly_Triangulation) MeshThroughBSplines(const TopoDS_Face& face, double deflection,
  double angularDeflection, std::vector<EdgePolygons>& polygons)
{
  polygons.clear();
  // An edge without a curve on the face (a seam whose circle the file moved off its torus, in the
  // mutation corpus): OpenCASCADE 7.6's NURBS conversion dereferences the missing pcurve and
  // crashes (BRepTools_NurbsConvertModification::NewCurve2d). Such a face is left unmeshed.
  for (TopExp_Explorer ex(face, TopAbs_EDGE); ex.More(); ex.Next())
  {
    double f = 0.0, l = 0.0;
    if (BRep_Tool::CurveOnSurface(TopoDS::Edge(ex.Current()), face, f, l).IsNull())
      return nullptr;
  }
  BRepBuilderAPI_NurbsConvert converter(face, Standard_True);
  if (!converter.IsDone())
    return nullptr;
  const TopoDS_Face copy = TopoDS::Face(converter.Shape());
  BRepMesh_IncrementalMesh(copy, deflection, Standard_False, angularDeflection, Standard_False);
  TopLoc_Location cl, fl;
  const Handle(Poly_Triangulation) ct = BRep_Tool::Triangulation(copy, cl);
  const Handle(Geom_Surface) surface = BRep_Tool::Surface(face, fl);
  if (ct.IsNull() || !ct->HasUVNodes() || surface.IsNull() || !(cl == fl))
    return nullptr;
  double u0, u1, v0, v1, cu0, cu1, cv0, cv1;
  BRepTools::UVBounds(face, u0, u1, v0, v1);
  BRepTools::UVBounds(copy, cu0, cu1, cv0, cv1);
  Bnd_Box box;
  BRepBndLib::Add(face, box);
  const double size = box.IsVoid() ? 1.0 : std::sqrt(box.SquareExtent());
  ShapeAnalysis_Surface sas(surface);
  const int n = ct->NbNodes();
  Handle(Poly_Triangulation) tri = new Poly_Triangulation(n, ct->NbTriangles(), Standard_True);
  auto unwrap = [](double x, double guide, bool periodic, double period) {
    return periodic ? x + period * std::round((guide - x) / period) : x;
  };
  for (int i = 1; i <= n; ++i)
  {
    const gp_Pnt p = ct->Node(i);
    const gp_Pnt2d c = ct->UVNode(i);
    const gp_Pnt2d uv = sas.ValueOfUV(p, 1e-7 * size);
    if (!(sas.Gap() <= 1e-6 * size))
      return nullptr;
    const double gu = u0 + (cu1 > cu0 ? (c.X() - cu0) / (cu1 - cu0) : 0.0) * (u1 - u0);
    const double gv = v0 + (cv1 > cv0 ? (c.Y() - cv0) / (cv1 - cv0) : 0.0) * (v1 - v0);
    tri->SetNode(i, p);
    const bool pu = surface->IsUPeriodic(), pv = surface->IsVPeriodic();
    tri->SetUVNode(i,
      gp_Pnt2d(unwrap(uv.X(), gu, pu, pu ? surface->UPeriod() : 0.0),
        unwrap(uv.Y(), gv, pv, pv ? surface->VPeriod() : 0.0)));
  }
  auto cross = [](const gp_Pnt2d& a, const gp_Pnt2d& b, const gp_Pnt2d& c) {
    return (b.X() - a.X()) * (c.Y() - a.Y()) - (b.Y() - a.Y()) * (c.X() - a.X());
  };
  for (int i = 1; i <= ct->NbTriangles(); ++i)
  {
    int a, b, c;
    ct->Triangle(i).Get(a, b, c);
    // The copy's winding in (u, v), whatever the directions of the face's parameters.
    const bool flip = (cross(ct->UVNode(a), ct->UVNode(b), ct->UVNode(c)) > 0.0) !=
      (cross(tri->UVNode(a), tri->UVNode(b), tri->UVNode(c)) > 0.0);
    tri->SetTriangle(i, flip ? Poly_Triangle(a, c, b) : Poly_Triangle(a, b, c));
  }
  // Polygons: the copy's nodes, with parameters on the face's edges.
  for (TopExp_Explorer ex(face, TopAbs_EDGE); ex.More(); ex.Next())
  {
    const TopoDS_Edge& e = TopoDS::Edge(ex.Current());
    if (BRep_Tool::Degenerated(e))
      continue;
    const TopoDS_Edge ce = TopoDS::Edge(converter.ModifiedShape(e));
    double f, l;
    const Handle(Geom_Curve) curve = BRep_Tool::Curve(e, f, l);
    if (curve.IsNull())
      return nullptr;
    std::array<Handle(Poly_PolygonOnTriangulation), 2> both;
    const bool seam = BRep_Tool::IsClosed(ce, copy);
    for (int side = 0; side < (seam ? 2 : 1); ++side)
    {
      const TopoDS_Edge oriented =
        seam ? TopoDS::Edge(ce.Oriented(side == 0 ? TopAbs_FORWARD : TopAbs_REVERSED)) : ce;
      const Handle(Poly_PolygonOnTriangulation) cp =
        BRep_Tool::PolygonOnTriangulation(oriented, ct, cl);
      if (cp.IsNull() || !cp->HasParameters())
        return nullptr;
      TColStd_Array1OfInteger nodes(1, cp->NbNodes());
      TColStd_Array1OfReal params(1, cp->NbNodes());
      // The nearest point of the edge's curve; a closed edge's ends go to its first and last
      // parameters (the polygon runs along the edge).
      const bool closed = curve->Value(f).Distance(curve->Value(l)) <= BRep_Tool::Tolerance(e);
      const int count = cp->NbNodes();
      for (int k = 1; k <= count; ++k)
      {
        nodes(k) = cp->Node(k);
        gp_Pnt proj;
        double t = f;
        ShapeAnalysis_Curve().Project(curve, ct->Node(cp->Node(k)), 1e-7 * size, proj, t, f, l,
          Standard_False);
        if (closed && (k == 1 || k == count))
          t = k == 1 ? f : l;
        params(k) = std::min(l, std::max(f, t));
      }
      both[static_cast<size_t>(side)] = new Poly_PolygonOnTriangulation(nodes, params);
    }
    polygons.emplace_back(e, both);
  }
  return tri;
}

// Doc in BRepConverter.h. Measured on Ploopy's parts (docs/Robustness.md, "Faces BRepMesh leaves").
int MeshFacesLeftWithoutTriangulation(
  const TopTools_IndexedMapOfShape& faceMap, double deflection, double angularDeflection)
{
  int meshed = 0;
  for (int i = 1; i <= faceMap.Extent(); ++i)
  {
    const TopoDS_Face& face = TopoDS::Face(faceMap(i));
    TopLoc_Location loc;
    if (!BRep_Tool::Triangulation(face, loc).IsNull())
      continue;
    try
    {
      meshed += MeshFaceAgain(face, loc, deflection, angularDeflection) ? 1 : 0;
    }
    catch (const Standard_Failure&)
    {
      // Left without a mesh, and warned of, as before.
    }
  }
  return meshed;
}

} // namespace brt
