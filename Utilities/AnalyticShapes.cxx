#include "AnalyticShapes.h"

#include <vector>

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepBuilderAPI_NurbsConvert.hxx>
#include <Geom_BezierCurve.hxx>
#include <GC_MakeArcOfEllipse.hxx>
#include <Geom_TrimmedCurve.hxx>
#include <gp_Elips.hxx>
#include <algorithm>
#include <TColgp_Array1OfPnt.hxx>
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeSolid.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <Geom_ConicalSurface.hxx>
#include <Geom_ToroidalSurface.hxx>
#include <ShapeFix_Solid.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Wire.hxx>
#include <gp_Ax3.hxx>
#include <gp_Circ.hxx>
#include <gp_Pln.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepBuilderAPI_Transform.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRep_Builder.hxx>
#include <TopoDS_Compound.hxx>
#include <gp_Trsf.hxx>
#include <BRepPrimAPI_MakeCone.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakePrism.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepPrimAPI_MakeTorus.hxx>
#include <BRep_Tool.hxx>
#include <Geom_Curve.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <gp_Ax2.hxx>
#include <gp_Pnt.hxx>

#include <cmath>

namespace brt::analytic
{
TopoDS_Shape Plate(double lx, double ly, double h)
{
  return BRepPrimAPI_MakeBox(lx, ly, h).Shape();
}

TopoDS_Shape Tube(double R, double r, double length)
{
  const gp_Ax2 axis(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1));
  return BRepAlgoAPI_Cut(BRepPrimAPI_MakeCylinder(axis, R, length).Shape(),
    BRepPrimAPI_MakeCylinder(axis, r, length).Shape())
    .Shape();
}

TopoDS_Shape SphericalShell(double R, double r)
{
  return BRepAlgoAPI_Cut(BRepPrimAPI_MakeSphere(R).Shape(), BRepPrimAPI_MakeSphere(r).Shape())
    .Shape();
}

TopoDS_Shape ConicalShell(double R1, double R2, double height, double h)
{
  const gp_Ax2 axis(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1));
  // Coaxial cones of one semi-angle a (tan a = (R1 - R2) / height), radii apart by h / cos a.
  const double a = std::atan2(R1 - R2, height), inset = h / std::cos(a);
  return BRepAlgoAPI_Cut(BRepPrimAPI_MakeCone(axis, R1, R2, height).Shape(),
    BRepPrimAPI_MakeCone(axis, R1 - inset, R2 - inset, height).Shape())
    .Shape();
}

namespace
{
/// The planar annulus at height z between radii `outer` and `inner` around the z axis.
TopoDS_Face Annulus(double z, double outer, double inner)
{
  auto circle = [&](double r) {
    return BRepBuilderAPI_MakeWire(
      BRepBuilderAPI_MakeEdge(gp_Circ(gp_Ax2(gp_Pnt(0, 0, z), gp_Dir(0, 0, 1)), r)).Edge())
      .Wire();
  };
  BRepBuilderAPI_MakeFace f(gp_Pln(gp_Pnt(0, 0, z), gp_Dir(0, 0, 1)), circle(outer));
  f.Add(TopoDS::Wire(circle(inner).Reversed()));
  return f.Face();
}

/// The solid bounded by `faces`, sewn into one shell.
TopoDS_Shape SewnSolid(const std::vector<TopoDS_Face>& faces)
{
  BRepBuilderAPI_Sewing sew(1e-6);
  for (const TopoDS_Face& f : faces)
    sew.Add(f);
  sew.Perform();
  BRepBuilderAPI_MakeSolid solid(TopoDS::Shell(sew.SewedShape()));
  ShapeFix_Solid fix(solid.Solid());
  fix.Perform();
  return fix.Solid();
}
} // namespace

TopoDS_Shape ConicalShellPastApex(double angle, double drop, double top, double bottom)
{
  // Cones of radius 0 at their apexes: a point at height z below the apex has v = z / cos(angle)
  // < 0, radius v sin(angle) < 0, so it lies on the nappe opposite the axis's direction.
  auto side = [&](double apex) {
    return BRepBuilderAPI_MakeFace(
      new Geom_ConicalSurface(gp_Ax3(gp_Pnt(0, 0, apex), gp_Dir(0, 0, 1)), angle, 0.0), 0.0,
      2.0 * M_PI, (top - apex) / std::cos(angle), (bottom - apex) / std::cos(angle), 1e-7)
      .Face();
  };
  auto annulus = [&](double z) {
    return Annulus(z, -z * std::tan(angle), -(z + drop) * std::tan(angle));
  };
  return SewnSolid({ side(0.0), side(-drop), annulus(top), annulus(bottom) });
}

TopoDS_Shape LemonShell(double major, double inner, double outer, double half)
{
  // On a spindle torus (major radius below the minor) the points with major + minor cos(v) < 0
  // lie across the axis from their angle u: the lemon, around v = pi. Each band spans
  // |z| = minor |sin(v)| <= half.
  auto band = [&](double minor) {
    const double a = std::asin(half / minor);
    return BRepBuilderAPI_MakeFace(
      new Geom_ToroidalSurface(gp_Ax3(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), major, minor), 0.0,
      2.0 * M_PI, M_PI - a, M_PI + a, 1e-7)
      .Face();
  };
  auto annulus = [&](double z) {
    return Annulus(z, std::sqrt(outer * outer - half * half) - major,
      std::sqrt(inner * inner - half * half) - major);
  };
  return SewnSolid({ band(outer), band(inner), annulus(half), annulus(-half) });
}

TopoDS_Shape ToroidalShell(double major, double R, double r)
{
  return BRepAlgoAPI_Cut(
    BRepPrimAPI_MakeTorus(major, R).Shape(), BRepPrimAPI_MakeTorus(major, r).Shape())
    .Shape();
}

TopoDS_Shape HolePlate(double side, double h, double holeRadius)
{
  const TopoDS_Shape hole = BRepPrimAPI_MakeCylinder(
    gp_Ax2(gp_Pnt(side / 2, side / 2, -1), gp_Dir(0, 0, 1)), holeRadius, h + 2)
                              .Shape();
  return BRepAlgoAPI_Cut(BRepPrimAPI_MakeBox(side, side, h).Shape(), hole).Shape();
}

TopoDS_Shape CountersunkPlate(double side, double h, double holeRadius, double sink)
{
  const gp_Ax2 axis(gp_Pnt(side / 2, side / 2, -1), gp_Dir(0, 0, 1));
  const TopoDS_Shape hole = BRepPrimAPI_MakeCylinder(axis, holeRadius, h + 2).Shape();
  // The cone continues 1 above the top (radius grows 1 per 1 in z) so that it cuts cleanly.
  const gp_Ax2 coneAxis(gp_Pnt(side / 2, side / 2, h - sink), gp_Dir(0, 0, 1));
  const TopoDS_Shape cone =
    BRepPrimAPI_MakeCone(coneAxis, holeRadius, holeRadius + sink + 1, sink + 1).Shape();
  const TopoDS_Shape drilled =
    BRepAlgoAPI_Cut(BRepPrimAPI_MakeBox(side, side, h).Shape(), hole).Shape();
  return BRepAlgoAPI_Cut(drilled, cone).Shape();
}

TopoDS_Shape PocketBlock(double side, double h, double slotLength, double slotRadius,
  double depth, double holeRadius)
{
  const double cx = side / 2, cy = side / 2, z0 = h - depth;
  const TopoDS_Shape middle = BRepPrimAPI_MakeBox(gp_Pnt(cx - slotLength / 2, cy - slotRadius, z0),
    gp_Pnt(cx + slotLength / 2, cy + slotRadius, h + 1))
                                .Shape();
  const TopoDS_Shape left = BRepPrimAPI_MakeCylinder(
    gp_Ax2(gp_Pnt(cx - slotLength / 2, cy, z0), gp_Dir(0, 0, 1)), slotRadius, depth + 1)
                              .Shape();
  const TopoDS_Shape right = BRepPrimAPI_MakeCylinder(
    gp_Ax2(gp_Pnt(cx + slotLength / 2, cy, z0), gp_Dir(0, 0, 1)), slotRadius, depth + 1)
                               .Shape();
  const TopoDS_Shape hole = BRepPrimAPI_MakeCylinder(
    gp_Ax2(gp_Pnt(side / 4, side / 4, -1), gp_Dir(0, 0, 1)), holeRadius, h + 2)
                              .Shape();
  TopoDS_Shape block = BRepPrimAPI_MakeBox(side, side, h).Shape();
  for (const TopoDS_Shape& tool : { middle, left, right, hole })
    block = BRepAlgoAPI_Cut(block, tool).Shape();
  return block;
}

TopoDS_Shape CubicRidge(double H, double a, double c, double L, double W, double stepAt,
  double stepHeight, bool nurbs)
{
  // z(x) = H - a x^2 - c x^3 on [-L, e] (e = stepAt, or L without a step) as a cubic Bezier curve
  // in x = -L + (e + L) s: its control points from the polynomial's values and derivatives at
  // the ends (the Bezier form of a cubic).
  auto z = [&](double x) { return H - a * x * x - c * x * x * x; };
  auto dz = [&](double x) { return -2.0 * a * x - 3.0 * c * x * x; };
  const bool step = stepHeight > 0.0 && stepAt > -L && stepAt < L;
  const double e = step ? stepAt : L;
  const double h = (e + L) / 3.0; // dx/ds / 3
  TColgp_Array1OfPnt poles(1, 4);
  poles(1) = gp_Pnt(-L, 0, z(-L));
  poles(2) = gp_Pnt(-L + h, 0, z(-L) + h * dz(-L));
  poles(3) = gp_Pnt(e - h, 0, z(e) - h * dz(e));
  poles(4) = gp_Pnt(e, 0, z(e));
  Handle(Geom_BezierCurve) top = new Geom_BezierCurve(poles);
  BRepBuilderAPI_MakeWire wire;
  wire.Add(BRepBuilderAPI_MakeEdge(top).Edge());
  double zr = z(e);
  if (step)
  {
    // A wall up from the ridge's end, then a plateau to x = L.
    zr = z(e) + stepHeight;
    wire.Add(BRepBuilderAPI_MakeEdge(gp_Pnt(e, 0, z(e)), gp_Pnt(e, 0, zr)).Edge());
    wire.Add(BRepBuilderAPI_MakeEdge(gp_Pnt(e, 0, zr), gp_Pnt(L, 0, zr)).Edge());
  }
  wire.Add(BRepBuilderAPI_MakeEdge(gp_Pnt(L, 0, zr), gp_Pnt(L, 0, 0)).Edge());
  wire.Add(BRepBuilderAPI_MakeEdge(gp_Pnt(L, 0, 0), gp_Pnt(-L, 0, 0)).Edge());
  wire.Add(BRepBuilderAPI_MakeEdge(gp_Pnt(-L, 0, 0), gp_Pnt(-L, 0, z(-L))).Edge());
  const TopoDS_Face profile = BRepBuilderAPI_MakeFace(wire.Wire(), true);
  const TopoDS_Shape prism = BRepPrimAPI_MakePrism(profile, gp_Vec(0, W, 0));
  return nurbs ? BRepBuilderAPI_NurbsConvert(prism).Shape() : prism;
}

TopoDS_Shape EllipticEndPlate(double L, double h, double b, double W)
{
  // The ellipse in the plane y = 0: centre (0, 0, h/2), major axis along x where b > h/2.
  const double a = 0.5 * h;
  const gp_Ax2 frame(gp_Pnt(0, 0, a), gp_Dir(0, -1, 0), b >= a ? gp_Dir(1, 0, 0) : gp_Dir(0, 0, 1));
  const gp_Elips ellipse(frame, std::max(a, b), std::min(a, b));
  Handle(Geom_TrimmedCurve) arc = GC_MakeArcOfEllipse(ellipse, gp_Pnt(0, 0, 0), gp_Pnt(0, 0, h), true);
  BRepBuilderAPI_MakeWire wire;
  wire.Add(BRepBuilderAPI_MakeEdge(gp_Pnt(-L, 0, 0), gp_Pnt(0, 0, 0)).Edge());
  wire.Add(BRepBuilderAPI_MakeEdge(arc).Edge());
  wire.Add(BRepBuilderAPI_MakeEdge(gp_Pnt(0, 0, h), gp_Pnt(-L, 0, h)).Edge());
  wire.Add(BRepBuilderAPI_MakeEdge(gp_Pnt(-L, 0, h), gp_Pnt(-L, 0, 0)).Edge());
  const TopoDS_Face profile = BRepBuilderAPI_MakeFace(wire.Wire(), true);
  const TopoDS_Shape prism = BRepPrimAPI_MakePrism(profile, gp_Vec(0, W, 0));
  return BRepBuilderAPI_NurbsConvert(prism).Shape();
}

TopoDS_Shape LBracket(double leg, double h, double width, double filletRadius)
{
  BRepBuilderAPI_MakePolygon poly;
  poly.Add(gp_Pnt(0, 0, 0));
  poly.Add(gp_Pnt(leg, 0, 0));
  poly.Add(gp_Pnt(leg, h, 0));
  poly.Add(gp_Pnt(h, h, 0));
  poly.Add(gp_Pnt(h, leg, 0));
  poly.Add(gp_Pnt(0, leg, 0));
  poly.Close();
  const TopoDS_Face profile = BRepBuilderAPI_MakeFace(poly.Wire());
  const TopoDS_Shape prism = BRepPrimAPI_MakePrism(profile, gp_Vec(0, 0, width));
  if (filletRadius <= 0.0)
    return prism;
  BRepFilletAPI_MakeFillet fillet(prism);
  for (TopExp_Explorer ex(prism, TopAbs_EDGE); ex.More(); ex.Next())
  {
    const TopoDS_Edge e = TopoDS::Edge(ex.Current());
    double f, l;
    Handle(Geom_Curve) c = BRep_Tool::Curve(e, f, l);
    const gp_Pnt a = c->Value(f), b = c->Value(l);
    // The inner corner edge runs along z through (h, h).
    if (std::fabs(a.X() - h) < 1e-9 && std::fabs(a.Y() - h) < 1e-9 &&
      std::fabs(b.X() - h) < 1e-9 && std::fabs(b.Y() - h) < 1e-9)
      fillet.Add(filletRadius, e);
  }
  return fillet.Shape();
}

namespace
{
TopoDS_Shape ExtrudedPolygon(const std::vector<gp_Pnt>& points, double depth)
{
  BRepBuilderAPI_MakePolygon poly;
  for (const gp_Pnt& p : points)
    poly.Add(p);
  poly.Close();
  const TopoDS_Face profile = BRepBuilderAPI_MakeFace(poly.Wire());
  return BRepPrimAPI_MakePrism(profile, gp_Vec(0, 0, depth));
}
} // namespace

TopoDS_Shape Rod(double R, double length)
{
  return BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), R, length).Shape();
}

TopoDS_Shape Ball(double R)
{
  return BRepPrimAPI_MakeSphere(gp_Pnt(0, 0, 0), R).Shape();
}

TopoDS_Shape Ring(double major, double minor)
{
  return BRepPrimAPI_MakeTorus(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), major, minor).Shape();
}

TopoDS_Shape TProfile(double fw, double ft, double wh, double wt, double depth)
{
  return ExtrudedPolygon({ gp_Pnt(-fw / 2, -ft, 0), gp_Pnt(fw / 2, -ft, 0), gp_Pnt(fw / 2, 0, 0),
                           gp_Pnt(wt / 2, 0, 0), gp_Pnt(wt / 2, wh, 0), gp_Pnt(-wt / 2, wh, 0),
                           gp_Pnt(-wt / 2, 0, 0), gp_Pnt(-fw / 2, 0, 0) },
    depth);
}

TopoDS_Shape CrossProfile(double len, double h, double depth)
{
  const double a = len / 2, b = h / 2;
  return ExtrudedPolygon({ gp_Pnt(-a, -b, 0), gp_Pnt(-b, -b, 0), gp_Pnt(-b, -a, 0), gp_Pnt(b, -a, 0),
                           gp_Pnt(b, -b, 0), gp_Pnt(a, -b, 0), gp_Pnt(a, b, 0), gp_Pnt(b, b, 0),
                           gp_Pnt(b, a, 0), gp_Pnt(-b, a, 0), gp_Pnt(-b, b, 0), gp_Pnt(-a, b, 0) },
    depth);
}

TopoDS_Shape UChannel(double w, double h, double lt, double ft, double l)
{
  // The profile in the xz plane, extruded along +y.
  BRepBuilderAPI_MakePolygon poly;
  poly.Add(gp_Pnt(0, 0, 0));
  poly.Add(gp_Pnt(w, 0, 0));
  poly.Add(gp_Pnt(w, 0, h));
  poly.Add(gp_Pnt(w - lt, 0, h));
  poly.Add(gp_Pnt(w - lt, 0, ft));
  poly.Add(gp_Pnt(lt, 0, ft));
  poly.Add(gp_Pnt(lt, 0, h));
  poly.Add(gp_Pnt(0, 0, h));
  poly.Close();
  const TopoDS_Face profile = BRepBuilderAPI_MakeFace(poly.Wire());
  return BRepPrimAPI_MakePrism(profile, gp_Vec(0, l, 0)).Shape();
}

TopoDS_Shape TwoPlates(double lx, double ly, double h, double gap)
{
  const TopoDS_Shape a = BRepPrimAPI_MakeBox(lx, ly, h).Shape();
  gp_Trsf up;
  up.SetTranslation(gp_Vec(0, 0, h + gap));
  return CompoundOf(a, BRepBuilderAPI_Transform(a, up, true).Shape());
}

TopoDS_Shape CompoundOf(const TopoDS_Shape& a, const TopoDS_Shape& b)
{
  BRep_Builder builder;
  TopoDS_Compound c;
  builder.MakeCompound(c);
  builder.Add(c, a);
  builder.Add(c, b);
  return c;
}
} // namespace brt::analytic
