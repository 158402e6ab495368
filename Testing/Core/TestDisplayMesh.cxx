// The display mesh's refinement with Delaunay flips (ConversionOptions::DelaunayRefinement): the
// same surface, the same limits, well-shaped triangles and far fewer vertices where bisection
// alone keeps OpenCASCADE's slivers (docs/Design.md, "Display mesh").
#include "AnalyticShapes.h"
#include "BRepConverter.h"
#include "FaceSide.h"
#include "SolverTestHelpers.h"
#include "StepFile.h"
#include "TestHelpers.h"
#include "TrimClassifier.h"

#include <gtest/gtest.h>

#include <map>
#include <tuple>

#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Poly_PolygonOnTriangulation.hxx>
#include <Poly_Triangulation.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRepPrimAPI_MakeCone.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepBuilderAPI_Copy.hxx>
#include <BRepTools.hxx>
#include <BRepTopAdaptor_FClass2d.hxx>
#include <BndLib_Add2dCurve.hxx>
#include <Bnd_Box2d.hxx>
#include <Geom2d_BSplineCurve.hxx>
#include <Geom2d_Line.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <Geom_Plane.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array1OfPnt2d.hxx>
#include <TopoDS_Vertex.hxx>
#include <TopoDS_Wire.hxx>
#include <memory>
#include <gp_Circ.hxx>
#include <gp_Pln.hxx>
#include <Geom_Surface.hxx>
#include <Geom_Curve.hxx>
#include <BRepPrimAPI_MakePrism.hxx>
#include <GC_MakeArcOfCircle.hxx>
#include <TopoDS_Face.hxx>

#include <array>
#include <cmath>
#include <cstdio>
#include <map>

namespace
{
using brt::BRepModel;
using V3 = std::array<double, 3>;

V3 Vertex(const BRepModel& m, int v)
{
  return { m.Mesh.Points[3 * size_t(v)], m.Mesh.Points[3 * size_t(v) + 1],
    m.Mesh.Points[3 * size_t(v) + 2] };
}

V3 Sub(const V3& a, const V3& b)
{
  return { a[0] - b[0], a[1] - b[1], a[2] - b[2] };
}

V3 Cross(const V3& a, const V3& b)
{
  return { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0] };
}

double Dot(const V3& a, const V3& b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

double Norm(const V3& a)
{
  return std::sqrt(Dot(a, a));
}

/// What the checks below measure on a display mesh.
struct MeshFigures
{
  size_t Vertices = 0;
  double LongestEdge = 0.0;
  double Area = 0.0;
  /// Triangles whose normal (from their vertex order) points against the surface normals of
  /// their vertices (the reader's Normals): a fold.
  int Folded = 0;
  /// Triangles whose height is below a tenth of their longest edge.
  int Slivers = 0;
};

MeshFigures Measure(const BRepModel& m)
{
  MeshFigures f;
  f.Vertices = m.Mesh.Points.size() / 3;
  for (size_t t = 0; t < m.Mesh.Triangles.size() / 3; ++t)
  {
    const int* v = &m.Mesh.Triangles[3 * t];
    const V3 a = Vertex(m, v[0]), b = Vertex(m, v[1]), c = Vertex(m, v[2]);
    const V3 n = Cross(Sub(b, a), Sub(c, a));
    const double area = 0.5 * Norm(n);
    f.Area += area;
    const double longest = std::max({ Norm(Sub(b, a)), Norm(Sub(c, b)), Norm(Sub(a, c)) });
    f.LongestEdge = std::max(f.LongestEdge, longest);
    if (2.0 * area / longest < 0.1 * longest)
      ++f.Slivers;
    double along = 0.0;
    for (int k = 0; k < 3; ++k)
      along += Dot(n, { m.Mesh.Normals[3 * size_t(v[k])], m.Mesh.Normals[3 * size_t(v[k]) + 1],
                          m.Mesh.Normals[3 * size_t(v[k]) + 2] });
    if (!(along > 0.0))
      ++f.Folded;
  }
  return f;
}

/// "Plain" is bisection on every face (SliverRatio 0), "flipped" the flips on every face.
BRepModel Convert(const TopoDS_Shape& shape, bool delaunay, double maxEdge = 0.0)
{
  brt::ConversionOptions o;
  o.DelaunayRefinement = delaunay;
  o.SliverRatio = 0.0;
  o.MaxEdgeLength = maxEdge;
  return brt::ConvertShape(shape, o);
}

/// A shape meshed both ways with edges of at most 2 mm, and the figures of both, printed.
struct BothWays
{
  BRepModel Plain, Flipped;
  MeshFigures P, F;
};

BothWays MeshBothWays(const TopoDS_Shape& shape, const char* name)
{
  BothWays b{ Convert(shape, false, 2.0), Convert(shape, true, 2.0), {}, {} };
  b.P = Measure(b.Plain);
  b.F = Measure(b.Flipped);
  std::printf("%s: bisection %zu vertices (%d slivers, area %.6f), flips %zu vertices (%d slivers, "
              "area %.6f, longest edge %.3f)\n",
    name, b.P.Vertices, b.P.Slivers, b.P.Area, b.F.Vertices, b.F.Slivers, b.F.Area,
    b.F.LongestEdge);
  return b;
}
} // namespace

// A rod 1 m long and 1 mm in radius: OpenCASCADE meshes its side as one strip of 72 slivers the
// rod's length long, which bisection alone refines to 26,345 vertices (its diagonals' midpoints
// add columns around the rod as well as rows along it, down to edges of 0.003 mm). With the flips
// the side needs rows 20 mm apart (the limit: 1/50 of the diagonal) of the 36 points around that
// the angular deflection asks for: about 2 x 51 x 37 vertices at most. The mesh stays on the
// cylinder, unfolded, within the limit, with the polygon's area.
TEST(DisplayMesh, DelaunayRefinementOnALongRod)
{
  const double r = 1.0, L = 1000.0;
  const TopoDS_Shape rod = BRepPrimAPI_MakeCylinder(r, L).Shape();
  const BRepModel plain = Convert(rod, false), flipped = Convert(rod, true);
  const MeshFigures p = Measure(plain), f = Measure(flipped);
  std::printf("rod r 1 L 1000: bisection %zu vertices (%d slivers), flips %zu vertices (longest edge "
              "%.3f, area %.2f, exact %.2f)\n",
    p.Vertices, p.Slivers, f.Vertices, f.LongestEdge, f.Area, 2 * M_PI * r * (r + L));
  EXPECT_LE(f.Vertices, size_t(2 * 51 * 37 + 2 * 37));
  EXPECT_EQ(f.Folded, 0);
  const double maxEdge = std::hypot(L, 2 * r) / 50.0;
  EXPECT_LE(f.LongestEdge, maxEdge * (1 + 1e-9));
  // The 36-gon's area (the caps' and the side's), which a valid mesh of these vertices has too.
  const double polygon = 36 * std::sin(2 * M_PI / 36) / (2 * M_PI);
  EXPECT_NEAR(f.Area, 2 * M_PI * r * (r + L) * polygon, 2e-3 * 2 * M_PI * r * (r + L));
  // Every vertex on the cylinder or a cap.
  double worst = 0.0;
  for (size_t v = 0; v < f.Vertices; ++v)
  {
    const V3 q = Vertex(flipped, int(v));
    const double side = std::fabs(std::hypot(q[0], q[1]) - r);
    const double cap = std::min(std::fabs(q[2]), std::fabs(q[2] - L));
    worst = std::max(worst, std::min(side, cap));
  }
  EXPECT_LE(worst, 1e-9);
}

// The tube of the closed forms (R 20, r 15, 80 long), with the flips: fewer vertices, no fold, no
// edge over the limit (2 mm here), the area of the bisection's mesh (the same boundary polygons,
// the same surfaces), and the closed form 2t = R - r = 5 within 1e-6 relative at every sample
// more than a thickness from the rims (the solve of the reader's defaults, docs/Solver.md).
TEST(DisplayMesh, DelaunayRefinementKeepsTheTubesClosedForm)
{
  const BothWays b = MeshBothWays(brt::analytic::Tube(20, 15, 80), "tube");
  const MeshFigures &p = b.P, &f = b.F;
  const BRepModel& flipped = b.Flipped;
  EXPECT_LT(f.Vertices, p.Vertices / 2);
  EXPECT_EQ(f.Folded, 0);
  EXPECT_EQ(f.Slivers, 0);
  EXPECT_LE(f.LongestEdge, 2.0);
  EXPECT_NEAR(f.Area, p.Area, 1e-3 * p.Area);

  brt::SolverOptions options;
  const brt::SolverData data = brt::PrepareSolver(flipped, options);
  const std::vector<brt::Sample> samples = brt::SamplesFromMesh(flipped, data);
  std::vector<brt::SampleResult> results;
  brt::SolveReference(flipped, data, options, samples, results);
  const std::vector<double> rim = brt::test::RimDistances(flipped, samples);
  int checked = 0, failed = 0;
  double worst = 0.0;
  for (size_t i = 0; i < samples.size(); ++i)
  {
    if (!(rim[i] > 5.0))
      continue;
    ++checked;
    if (results[i].Type == brt::ContactType::Failed)
    {
      ++failed;
      continue;
    }
    worst = std::max(worst, std::fabs(results[i].Thickness - 5.0) / 5.0);
  }
  std::printf("tube, flips: %d samples away from the rims, %d failed, max |2t - 5| / 5 = %.2e\n",
    checked, failed, worst);
  EXPECT_GE(checked, 1000);
  EXPECT_EQ(failed, 0);
  EXPECT_LE(worst, 1e-6);
}

// The hole plate (planes and the hole's cylinder) with the flips: fewer vertices, no fold, no
// edge over the limit (2 mm here), no more slivers, and the bisection's area to 1e-4 (the planes'
// to rounding: the same boundary; the hole's side differs by its chords).
TEST(DisplayMesh, DelaunayRefinementOnAPlateWithAHole)
{
  const BothWays b = MeshBothWays(brt::analytic::HolePlate(80, 6, 10), "hole plate");
  const MeshFigures &p = b.P, &f = b.F;
  EXPECT_LT(f.Vertices, p.Vertices);
  EXPECT_EQ(f.Folded, 0);
  EXPECT_LE(f.Slivers, p.Slivers);
  EXPECT_LE(f.LongestEdge, 2.0);
  EXPECT_NEAR(f.Area, p.Area, 1e-4 * p.Area);
}

// The reader's default (SliverRatio 4, SliverVertices 10,000): each face keeps its bisection mesh
// unless that holds more than 4 times the vertices of its flipped mesh and more than 10,000, where
// the flipped mesh is taken. Checked face by face against both meshes made on their own, on the
// rod (its side: 26,345 bisection vertices), the tube (its cylinders' strips) and the hole plate,
// the latter also with edges of 1.5 mm, where its plane faces' bisection meshes pass the floor
// but stay within the ratio (the guard meshes them a second time and keeps them); every branch
// must occur.
TEST(DisplayMesh, SliverRatioTakesTheFlippedMeshOnlyWhereBisectionExplodes)
{
  int kept = 0, keptOverFloor = 0, flippedFaces = 0;
  const std::pair<TopoDS_Shape, double> cases[] = {
    { BRepPrimAPI_MakeCylinder(1.0, 1000.0).Shape(), 0.0 },
    { brt::analytic::Tube(20, 15, 80), 0.0 },
    { brt::analytic::HolePlate(80, 6, 10), 0.0 },
    { brt::analytic::HolePlate(80, 6, 10), 1.5 },
  };
  for (const auto& c : cases)
  {
    const TopoDS_Shape& shape = c.first;
    brt::ConversionOptions o;
    o.MaxEdgeLength = c.second;
    // The default last, after the two it is compared with: the first conversion of a shape
    // meshes it, later ones start from the triangulation BRepMesh stored on it, which differed by
    // 2 of the tube's 5,135 vertices on one face.
    const BRepModel plain = Convert(shape, false, c.second), flipped = Convert(shape, true, c.second);
    const BRepModel def = brt::ConvertShape(shape, o);
    auto perFace = [](const BRepModel& m) {
      std::map<int, size_t> n;
      for (int f : m.Mesh.FaceIds)
        ++n[f];
      return n;
    };
    const auto nd = perFace(def), np = perFace(plain), nf = perFace(flipped);
    int expectFlipped = 0;
    for (const auto& f : np)
    {
      const bool explodes = double(f.second) > o.SliverRatio * double(nf.at(f.first)) &&
        f.second > size_t(o.SliverVertices);
      expectFlipped += explodes ? 1 : 0;
      EXPECT_EQ(nd.at(f.first), explodes ? nf.at(f.first) : f.second) << "face " << f.first;
      (explodes ? flippedFaces : kept) += 1;
      keptOverFloor += !explodes && f.second > size_t(o.SliverVertices) ? 1 : 0;
    }
    EXPECT_EQ(def.Stats.FlippedFaces, expectFlipped);
    std::printf("default mesh: %zu vertices (bisection %zu, flips %zu), %d faces flipped\n",
      def.Mesh.NumberOfPoints(), plain.Mesh.NumberOfPoints(), flipped.Mesh.NumberOfPoints(),
      def.Stats.FlippedFaces);
  }
  EXPECT_GT(kept, 0);
  EXPECT_GT(keptOverFloor, 0);
  EXPECT_GT(flippedFaces, 0);
}

// A face narrower than the coarse mesh's deflection: a crescent 20 mm across between two arcs
// whose sagittas differ by 0.01 mm, extruded 1 mm. OpenCASCADE joins its two arcs by chords
// whose midpoints lie outside it, the farther the longer the chord; bisection put vertices
// there, and their samples' spheres started in the air (the Original Prusa i3's extruder motor
// plate: 0.035 mm off its face, a sphere of 2t = 0.07 centred outside the part). Every vertex
// lies on its face, within the tolerance, as bisection and as the flips make the mesh.
TEST(DisplayMesh, VerticesStayOnAFaceNarrowerThanTheDeflection)
{
  const gp_Pnt p1(-10, 0, 0), p2(10, 0, 0);
  const TopoDS_Edge outer = BRepBuilderAPI_MakeEdge(GC_MakeArcOfCircle(p1, gp_Pnt(0, -5, 0), p2).Value());
  const TopoDS_Edge inner = BRepBuilderAPI_MakeEdge(GC_MakeArcOfCircle(p2, gp_Pnt(0, -4.99, 0), p1).Value());
  const TopoDS_Face crescent = BRepBuilderAPI_MakeFace(BRepBuilderAPI_MakeWire(outer, inner).Wire());
  const TopoDS_Shape solid = BRepPrimAPI_MakePrism(crescent, gp_Vec(0, 0, 1)).Shape();
  for (const bool delaunay : { false, true })
  {
    brt::ConversionOptions o;
    o.DelaunayRefinement = delaunay;
    o.MaxEdgeLength = 0.5;
    std::vector<TopoDS_Face> faces;
    const BRepModel m = brt::ConvertShape(solid, o, &faces);
    ASSERT_EQ(faces.size(), m.Faces.size());
    double worst = 0.0;
    size_t far = 0;
    for (size_t v = 0; v < m.Mesh.NumberOfPoints(); ++v)
    {
      const V3 p = Vertex(m, static_cast<int>(v));
      BRepExtrema_DistShapeShape d(BRepBuilderAPI_MakeVertex(gp_Pnt(p[0], p[1], p[2])).Vertex(),
        faces[static_cast<size_t>(m.Mesh.FaceIds[v])]);
      ASSERT_TRUE(d.IsDone());
      worst = std::max(worst, d.Value());
      far += d.Value() > m.Tolerance;
    }
    std::printf("crescent (%s): %zu vertices, the farthest %.3g from its face\n",
      delaunay ? "flips" : "bisection", m.Mesh.NumberOfPoints(), worst);
    EXPECT_EQ(far, 0u);
  }
}

// A mesh vertex on a face's boundary is solved from a point nudged 1e-2 of the way to an
// adjacent triangle's centroid (SamplesFromMesh). That centroid lies inside the mesh's polygon,
// which leaves the face where its boundary curves away from a long chord: 52 of the
// ExpansionCard's nudged samples and 11 of the hinge's lay more than 1e-5 outside their face's
// trim in UV (one 8.1e-4), and on the Original Prusa i3's extruder body a sphere started so was
// centred outside the part. On every Data/ model, every sample lies inside its face's trim by the
// solver's own classifier, or outside by less than the conversion tolerance (in UV): a boundary
// vertex itself may lie that far outside the trim, which bridges its pcurves' gaps (64 of the
// ExpansionCard's, 7.3e-5 at most, after the change).
TEST(DisplayMesh, NudgedBoundarySamplesStayInTheirFace)
{
  for (const auto& name : brt::test::DataModels())
  {
    const BRepModel m = brt::ConvertStepFile(brt::test::DataFile(name), brt::ConversionOptions());
    const brt::SolverData data = brt::PrepareSolver(m, brt::SolverOptions());
    const std::vector<brt::Sample> samples = brt::SamplesFromMesh(m, data);
    size_t nudged = 0, outside = 0;
    double farthest = 0.0;
    for (size_t i = 0; i < samples.size(); ++i)
    {
      const brt::Sample& s = samples[i];
      if (s.U == m.Mesh.UV[2 * i] && s.V == m.Mesh.UV[2 * i + 1])
        continue;
      ++nudged;
      const brt::TrimProjection p = brt::ClassifyPoint(m, s.Face, s.U, s.V);
      if (!p.Inside)
        farthest = std::max(farthest, p.Distance);
      outside += !p.Inside && p.Distance > m.Tolerance ? 1 : 0;
    }
    std::printf("%s: %zu samples nudged, %zu outside their face's trim by more than the tolerance "
      "(the farthest %.3g in UV)\n",
      name.c_str(), nudged, outside, farthest);
    EXPECT_EQ(outside, 0u) << name;
  }
}

TEST(DisplayMesh, FaceLeftWithoutTriangulationIsMeshedAgain)
{
  // BRepMesh leaves some faces without a triangulation (Ploopy's parts: a cone whose top circle
  // is written in two arcs, one past 2 pi; SolidWorks's headbands). Such a face is stood in for
  // here by the tube's outer cylinder with its triangulation taken away: it is meshed again
  // alone, and its edges, the seam's two sides included, get their polygons on the new
  // triangulation, which the display mesh's refinement reads.
  const TopoDS_Shape tube = brt::analytic::Tube(20, 15, 80);
  BRepMesh_IncrementalMesh(tube, 0.1, Standard_False, 0.5, Standard_False);
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(tube, TopAbs_FACE, faces);
  int target = 0;
  for (int i = 1; i <= faces.Extent() && target == 0; ++i)
  {
    BRepAdaptor_Surface s(TopoDS::Face(faces(i)));
    if (s.GetType() == GeomAbs_Cylinder && std::fabs(s.Cylinder().Radius() - 20.0) < 1e-9)
      target = i;
  }
  ASSERT_GT(target, 0);
  const TopoDS_Face face = TopoDS::Face(faces(target));
  BRep_Builder().UpdateFace(face, Handle(Poly_Triangulation)());
  TopLoc_Location loc;
  ASSERT_TRUE(BRep_Tool::Triangulation(face, loc).IsNull());

  EXPECT_EQ(brt::MeshFacesLeftWithoutTriangulation(faces, 0.1, 0.5), 1);
  const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(face, loc);
  ASSERT_FALSE(tri.IsNull());
  EXPECT_TRUE(tri->HasUVNodes());
  EXPECT_GT(tri->NbTriangles(), 10);
  int seams = 0;
  for (TopExp_Explorer ex(face, TopAbs_EDGE); ex.More(); ex.Next())
  {
    const TopoDS_Edge& e = TopoDS::Edge(ex.Current());
    const Handle(Poly_PolygonOnTriangulation) poly = BRep_Tool::PolygonOnTriangulation(e, tri, loc);
    ASSERT_FALSE(poly.IsNull());
    // Its nodes are the triangulation's nodes on the edge.
    for (int k = 1; k <= poly->NbNodes(); ++k)
    {
      const gp_Pnt p = tri->Node(poly->Node(k));
      EXPECT_NEAR(std::hypot(p.X(), p.Y()), 20.0, 1e-9);
    }
    if (BRep_Tool::IsClosed(e, face))
    {
      ++seams;
      // The seam's two sides: the same points, at u = 0 and u = 2 pi.
      const Handle(Poly_PolygonOnTriangulation) other = BRep_Tool::PolygonOnTriangulation(
        TopoDS::Edge(e.Reversed()), tri, loc);
      ASSERT_FALSE(other.IsNull());
      ASSERT_EQ(other->NbNodes(), poly->NbNodes());
      EXPECT_NEAR(std::fabs(tri->UVNode(poly->Node(1)).X() - tri->UVNode(other->Node(1)).X()),
        2.0 * M_PI, 1e-9);
    }
  }
  EXPECT_EQ(seams, 2) << "the seam, once in each orientation";
  // The other faces keep theirs; a second call finds nothing to do.
  EXPECT_EQ(brt::MeshFacesLeftWithoutTriangulation(faces, 0.1, 0.5), 0);
}

TEST(DisplayMesh, NotchedFaceIsMeshedWithoutItsNotch)
{
  // A wire that goes out and comes back the same way, enclosing nothing (SolidWorks's headband
  // planes: a circle arc 2.8 mm out, 0.96 mm back along it), on which BRepMesh fails. Here a
  // sector of radius 10 from 0 to 45 degrees whose arc runs on to 60 degrees and back.
  const gp_Circ circle(gp_Ax2(gp::Origin(), gp::DZ()), 10.0);
  const double deg = M_PI / 180.0;
  const gp_Pnt p0(10, 0, 0), p45(10 * std::cos(45 * deg), 10 * std::sin(45 * deg), 0),
    p60(10 * std::cos(60 * deg), 10 * std::sin(60 * deg), 0);
  BRepBuilderAPI_MakeWire wire;
  wire.Add(BRepBuilderAPI_MakeEdge(gp::Origin(), p0).Edge());
  const TopoDS_Edge out = BRepBuilderAPI_MakeEdge(circle, 0.0, 60 * deg).Edge();
  wire.Add(out);
  const TopoDS_Edge back =
    TopoDS::Edge(BRepBuilderAPI_MakeEdge(circle, 45 * deg, 60 * deg).Edge().Reversed());
  wire.Add(back);
  wire.Add(BRepBuilderAPI_MakeEdge(p45, gp::Origin()).Edge());
  ASSERT_TRUE(wire.IsDone());
  const TopoDS_Face face = BRepBuilderAPI_MakeFace(wire.Wire(), Standard_True).Face();
  BRepMesh_IncrementalMesh mesher(face, 0.01, Standard_False, 0.5, Standard_False);
  TopLoc_Location loc;
  std::printf("[notch] BRepMesh alone: %s (status %d)\n",
    BRep_Tool::Triangulation(face, loc).IsNull() ? "no triangulation" : "a triangulation",
    mesher.GetStatusFlags());
  BRep_Builder().UpdateFace(face, Handle(Poly_Triangulation)());
  TopTools_IndexedMapOfShape faces;
  faces.Add(face);
  ASSERT_EQ(brt::MeshFacesLeftWithoutTriangulation(faces, 0.01, 0.5), 1);
  const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(face, loc);
  ASSERT_FALSE(tri.IsNull());
  // The sector, and nothing of the notch: nodes within 45 degrees, triangles covering the
  // sector's area but for the chords' segments (deflection 0.01).
  double area = 0.0;
  for (int i = 1; i <= tri->NbNodes(); ++i)
  {
    const gp_Pnt p = tri->Node(i);
    EXPECT_LE(std::atan2(p.Y(), p.X()), 45 * deg + 1e-9) << "a node on the notch";
    EXPECT_LE(std::hypot(p.X(), p.Y()), 10.0 + 1e-9);
  }
  for (int i = 1; i <= tri->NbTriangles(); ++i)
  {
    int a, b, c;
    tri->Triangle(i).Get(a, b, c);
    area += 0.5 *
      gp_Vec(tri->Node(a), tri->Node(b)).Crossed(gp_Vec(tri->Node(a), tri->Node(c))).Magnitude();
  }
  const double sector = 0.5 * 100.0 * 45 * deg;
  EXPECT_LT(area, sector);
  EXPECT_GT(area, sector - 0.01 * 10.0 * 45 * deg) << "more than the chords' segments missing";
  // The two lines have their polygons; the notch's two arcs have none.
  int withPolygon = 0;
  for (TopExp_Explorer ex(face, TopAbs_EDGE); ex.More(); ex.Next())
    withPolygon += !BRep_Tool::PolygonOnTriangulation(TopoDS::Edge(ex.Current()), tri, loc).IsNull();
  EXPECT_EQ(withPolygon, 2);
}

TEST(DisplayMesh, BSplineCopyMeshLiesOnTheFace)
{
  // The last try for a face BRepMesh leaves (Voron's power panel's cones): a mesh of its
  // B-spline copy, mapped back onto the face's own parameters. On a cone's side (a seam, a full
  // turn): every node at its (u, v) on the cone, within the face's range; triangles wound in
  // (u, v) as BRepMesh winds them on the face itself; polygon parameters on the edges' curves;
  // the seam's two polygons a period apart.
  const TopoDS_Shape cone = BRepPrimAPI_MakeCone(gp_Ax2(gp_Pnt(0, 0, 5), gp::DZ()), 4, 2, 3).Shape();
  TopoDS_Face face;
  for (TopExp_Explorer ex(cone, TopAbs_FACE); ex.More() && face.IsNull(); ex.Next())
    if (BRepAdaptor_Surface(TopoDS::Face(ex.Current())).GetType() == GeomAbs_Cone)
      face = TopoDS::Face(ex.Current());
  ASSERT_FALSE(face.IsNull());
  std::vector<brt::EdgePolygons> polygons;
  const Handle(Poly_Triangulation) tri = brt::MeshThroughBSplines(face, 0.01, 0.5, polygons);
  ASSERT_FALSE(tri.IsNull());
  ASSERT_TRUE(tri->HasUVNodes());
  TopLoc_Location loc;
  const Handle(Geom_Surface) surface = BRep_Tool::Surface(face, loc);
  double u0, u1, v0, v1;
  BRepTools::UVBounds(face, u0, u1, v0, v1);
  double worst = 0.0;
  for (int i = 1; i <= tri->NbNodes(); ++i)
  {
    const gp_Pnt2d uv = tri->UVNode(i);
    worst = std::max(worst, surface->Value(uv.X(), uv.Y()).Distance(tri->Node(i)));
    EXPECT_TRUE(uv.X() > u0 - 1e-9 && uv.X() < u1 + 1e-9 && uv.Y() > v0 - 1e-9 && uv.Y() < v1 + 1e-9)
      << "node " << i << " at (" << uv.X() << ", " << uv.Y() << ") outside the face's range";
  }
  EXPECT_LT(worst, 1e-9);
  // Winding: BRepMesh's own mesh of the face gives the sign.
  const TopoDS_Face own = TopoDS::Face(BRepBuilderAPI_Copy(face).Shape());
  BRepMesh_IncrementalMesh(own, 0.01, Standard_False, 0.5, Standard_False);
  TopLoc_Location ol;
  const Handle(Poly_Triangulation) ref = BRep_Tool::Triangulation(own, ol);
  ASSERT_FALSE(ref.IsNull());
  auto sign = [](const Handle(Poly_Triangulation)& t, int i) {
    int a, b, c;
    t->Triangle(i).Get(a, b, c);
    const gp_Pnt2d p = t->UVNode(a), q = t->UVNode(b), r = t->UVNode(c);
    return ((q.X() - p.X()) * (r.Y() - p.Y()) - (q.Y() - p.Y()) * (r.X() - p.X())) > 0.0;
  };
  for (int i = 1; i <= tri->NbTriangles(); ++i)
    ASSERT_EQ(sign(tri, i), sign(ref, 1)) << "triangle " << i << " wound the other way";
  int seams = 0;
  for (const auto& [edge, polys] : polygons)
  {
    ASSERT_FALSE(polys[0].IsNull());
    double f, l;
    const Handle(Geom_Curve) curve = BRep_Tool::Curve(edge, f, l);
    for (int k = 1; k <= polys[0]->NbNodes(); ++k)
      EXPECT_LT(curve->Value(polys[0]->Parameter(k)).Distance(tri->Node(polys[0]->Node(k))), 1e-7);
    if (!polys[1].IsNull())
    {
      ++seams;
      EXPECT_NEAR(std::fabs(tri->UVNode(polys[0]->Node(1)).X() - tri->UVNode(polys[1]->Node(1)).X()),
        2.0 * M_PI, 1e-9);
    }
  }
  EXPECT_GT(seams, 0);
}

// FaceSide, the refinement's side test (docs/Design.md, "Every vertex on its face"): where it keeps
// an answer for a cell, every point of the cell gets the classifier's own. On a plate with 48
// round holes of three sizes (a 97 x 97 grid over its UV box, and 32 points on circles 1e-3
// outside and inside each hole's), and on every face of the FRAMEWORK tile (a 29 x 29 grid over
// each face's UV box, off the cells' lines): the same answer as BRepTopAdaptor_FClass2d at every
// point, and the answers kept on the plate and on most faces. Fails where the cells a pcurve
// crosses keep answers (each pcurve marking only its start's cell: 1,556 points of the plate).
TEST(DisplayMesh, FaceSideAgreesWithTheClassifier)
{
  auto check = [](const TopoDS_Face& face, const std::vector<gp_Pnt2d>& points,
                 const std::string& what) {
    brt::FaceSide side(face);
    const BRepTopAdaptor_FClass2d reference(face, 1e-9);
    long differ = 0;
    for (const gp_Pnt2d& p : points)
      differ += side.Outside(p) != (reference.Perform(p) == TopAbs_OUT);
    EXPECT_EQ(differ, 0) << what;
    return side.Cached();
  };
  auto grid = [](const TopoDS_Face& face, int n) {
    double u0, u1, v0, v1;
    BRepTools::UVBounds(face, u0, u1, v0, v1);
    std::vector<gp_Pnt2d> points;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        points.emplace_back(u0 + (u1 - u0) * (i + 0.37) / n, v0 + (v1 - v0) * (j + 0.61) / n);
    return points;
  };
  {
    BRepBuilderAPI_MakeFace plate(gp_Pln(gp::XOY()), -50.0, 50.0, -30.0, 30.0);
    std::vector<std::pair<gp_Pnt2d, double>> holes;
    for (int i = 0; i < 8; ++i)
      for (int j = 0; j < 6; ++j)
      {
        const gp_Pnt2d c(-42.0 + 12.0 * i, -25.0 + 10.0 * j);
        const double r = 1.5 + 0.75 * ((i + j) % 3);
        TopoDS_Wire w = BRepBuilderAPI_MakeWire(
          BRepBuilderAPI_MakeEdge(gp_Circ(gp_Ax2(gp_Pnt(c.X(), c.Y(), 0.0), gp::DZ()), r)));
        w.Reverse();
        plate.Add(w);
        holes.emplace_back(c, r);
      }
    ASSERT_TRUE(plate.IsDone());
    const TopoDS_Face face = plate.Face();
    std::vector<gp_Pnt2d> points = grid(face, 97);
    for (const auto& h : holes)
      for (int k = 0; k < 32; ++k)
        for (const double r : { h.second - 1e-3, h.second + 1e-3 })
          points.emplace_back(h.first.X() + r * std::cos(0.1 + k * M_PI / 16),
            h.first.Y() + r * std::sin(0.1 + k * M_PI / 16));
    EXPECT_TRUE(check(face, points, "the plate with 48 holes"));
  }
  for (const char* name : { "FRAMEWORK_DESKTOP_BLANK_TILE.stp" })
  {
    const TopoDS_Shape shape = brt::ReadStepFile(brt::test::DataFile(name));
    int faces = 0, cached = 0;
    for (TopExp_Explorer ex(shape, TopAbs_FACE); ex.More(); ex.Next(), ++faces)
    {
      const TopoDS_Face face = TopoDS::Face(TopoDS::Face(ex.Current()).Oriented(TopAbs_FORWARD));
      cached += check(face, grid(face, 29), std::string(name) + " face " + std::to_string(faces));
    }
    EXPECT_GT(cached, 9 * faces / 10) << name;
  }
}

// A face whose boundary holds an edge a few nanometres long on a cubic B-spline pcurve, at the
// end of the curve's parameter range (an Onshape part, Armchair Heavy Industries' Xol extruder
// mount for the VZ-Hex: its face 9's pcurve spans 3.1e-9 of 1.1e-3). OpenCASCADE 7.6's
// BndLib_Add2dCurve throws NCollection_Array1::Create on eighths of so short a range, and that
// stopped the whole conversion of the part ("OpenCASCADE failed during conversion"). FaceSide
// keeps no answers on such a face and asks the classifier, which agrees (a 41 x 41 grid over the
// triangle's box). Fails (throws) where FaceSide bounds the pieces unguarded.
TEST(DisplayMesh, FaceSideWithAnUnboundablePcurve)
{
  // The pcurve: 8 poles, knots 0, 0.2, ..., 1 (the ends of multiplicity 4); its edge the range
  // [1 - 3e-9, 1], a triangle in the plane's (u, v) closed by three lines.
  TColgp_Array1OfPnt2d poles(1, 8);
  for (int i = 1; i <= 8; ++i)
    poles(i) = gp_Pnt2d(0.1 * i, 0.01 * i * i);
  TColStd_Array1OfReal knots(1, 6);
  TColStd_Array1OfInteger mults(1, 6);
  for (int i = 1; i <= 6; ++i)
  {
    knots(i) = (i - 1) / 5.0;
    mults(i) = i == 1 || i == 6 ? 4 : 1;
  }
  const Handle(Geom2d_BSplineCurve) spline = new Geom2d_BSplineCurve(poles, knots, mults, 3);
  const double f = 1.0 - 3e-9, l = 1.0;
  {
    // (The OpenCASCADE behaviour this guards against, so that the test means something.)
    Bnd_Box2d box;
    EXPECT_THROW(
      BndLib_Add2dCurve::Add(spline, f + (l - f) * 6 / 8, f + (l - f) * 7 / 8, 0.0, box),
      Standard_Failure);
  }
  const Handle(Geom_Plane) plane = new Geom_Plane(gp::XOY());
  const gp_Pnt2d a = spline->Value(f), b = spline->Value(l);
  const gp_Pnt2d c(b.X() + 10.0, b.Y()), d(b.X() + 5.0, b.Y() + 10.0);
  BRep_Builder builder;
  auto vertex = [&](const gp_Pnt2d& p) {
    TopoDS_Vertex v;
    builder.MakeVertex(v, gp_Pnt(p.X(), p.Y(), 0.0), 1e-7);
    return v;
  };
  const TopoDS_Vertex va = vertex(a), vb = vertex(b), vc = vertex(c), vd = vertex(d);
  auto edge = [&](const Handle(Geom2d_Curve)& pc, double p0, double p1, const TopoDS_Vertex& v0,
                const TopoDS_Vertex& v1) {
    TopoDS_Edge e;
    builder.MakeEdge(e);
    builder.UpdateEdge(e, pc, plane, TopLoc_Location(), 1e-7);
    builder.Range(e, p0, p1);
    builder.Add(e, v0.Oriented(TopAbs_FORWARD));
    builder.Add(e, v1.Oriented(TopAbs_REVERSED));
    return e;
  };
  auto segment = [&](const gp_Pnt2d& p, const gp_Pnt2d& q, const TopoDS_Vertex& vp,
                   const TopoDS_Vertex& vq) {
    const Handle(Geom2d_Line) line = new Geom2d_Line(p, gp_Dir2d(q.X() - p.X(), q.Y() - p.Y()));
    return edge(line, 0.0, p.Distance(q), vp, vq);
  };
  TopoDS_Wire wire;
  builder.MakeWire(wire);
  builder.Add(wire, edge(spline, f, l, va, vb));
  builder.Add(wire, segment(b, c, vb, vc));
  builder.Add(wire, segment(c, d, vc, vd));
  builder.Add(wire, segment(d, a, vd, va));
  TopoDS_Face face;
  builder.MakeFace(face, plane, 1e-7);
  builder.Add(face, wire);
  std::unique_ptr<brt::FaceSide> side;
  ASSERT_NO_THROW(side = std::make_unique<brt::FaceSide>(face));
  EXPECT_FALSE(side->Cached());
  const BRepTopAdaptor_FClass2d reference(face, 1e-9);
  int differ = 0, inside = 0;
  for (int i = 0; i <= 40; ++i)
    for (int j = 0; j <= 40; ++j)
    {
      const gp_Pnt2d p(b.X() - 0.5 + 11.0 * (i + 0.37) / 40, b.Y() - 0.5 + 11.0 * (j + 0.61) / 40);
      const bool out = reference.Perform(p) == TopAbs_OUT;
      differ += side->Outside(p) != out;
      inside += !out;
    }
  EXPECT_EQ(differ, 0);
  EXPECT_GT(inside, 300); // (the triangle holds about a third of the grid)
}

// A node of OpenCASCADE's own mesh inside its polygon of the face but outside the face: the
// polygon's chords cut across the face where a pcurve curves away from them (on the SO-ARM101
// wrist a torus's grid node lay 0.03 mm off its face, in the lune between a pcurve and its one
// chord, and its sample's sphere started where no wall is). Here a plate with a hole is meshed
// coarsely (the hole an octagon), and a node is put into the top face's mesh halfway between a
// chord of the hole and its arc: inside the hole. The converter keeps a face's triangulation
// made at its deflection, so that node is the coarse mesh's; it must end on the face, as every
// other vertex, by bisection and by the flips.
TEST(DisplayMesh, CoarseMeshNodeInsideAHoleIsMovedOntoTheFace)
{
  const double side = 20.0, h = 2.0, r = 5.0;
  const TopoDS_Shape plate = brt::analytic::HolePlate(side, h, r);
  brt::ConversionOptions o;
  o.LinearDeflection = 1.0;
  o.AngularDeflection = 1.2;
  o.Heal = false; // (the healing may rebuild faces, without their triangulation)
  o.MaxEdgeLength = 4.0;
  for (const bool delaunay : { false, true })
  {
    const TopoDS_Shape shape = BRepBuilderAPI_Copy(plate).Shape();
    BRepMesh_IncrementalMesh(shape, o.LinearDeflection, Standard_False, o.AngularDeflection);
    // The top face (a plane at z = h) and its hole's edge (a circle).
    TopoDS_Face top;
    for (TopExp_Explorer ex(shape, TopAbs_FACE); ex.More(); ex.Next())
    {
      const BRepAdaptor_Surface s(TopoDS::Face(ex.Current()));
      if (s.GetType() == GeomAbs_Plane && std::abs(s.Plane().Location().Z() - h) < 1e-9 &&
        std::abs(std::abs(s.Plane().Axis().Direction().Z()) - 1.0) < 1e-9)
        top = TopoDS::Face(ex.Current());
    }
    ASSERT_FALSE(top.IsNull());
    TopLoc_Location loc;
    const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(top, loc);
    ASSERT_FALSE(tri.IsNull());
    ASSERT_TRUE(tri->HasUVNodes());
    // A chord of the hole: two consecutive nodes of the circle's polygon on this face.
    TopoDS_Edge hole;
    for (TopExp_Explorer ex(top, TopAbs_EDGE); ex.More(); ex.Next())
      if (BRepAdaptor_Curve(TopoDS::Edge(ex.Current())).GetType() == GeomAbs_Circle)
        hole = TopoDS::Edge(ex.Current());
    ASSERT_FALSE(hole.IsNull());
    const Handle(Poly_PolygonOnTriangulation) poly =
      BRep_Tool::PolygonOnTriangulation(hole, tri, loc);
    ASSERT_FALSE(poly.IsNull());
    ASSERT_GE(poly->NbNodes(), 5);
    ASSERT_LE(poly->NbNodes(), 12); // coarse: the lune is 0.2-0.7 mm deep
    const int na = poly->Node(1), nb = poly->Node(2);
    // The triangle on that chord, and the node halfway between the chord and the arc.
    int t0 = 0;
    for (int t = 1; t <= tri->NbTriangles() && t0 == 0; ++t)
    {
      int n[3];
      tri->Triangle(t).Get(n[0], n[1], n[2]);
      for (int k = 0; k < 3; ++k)
        if ((n[k] == na && n[(k + 1) % 3] == nb) || (n[k] == nb && n[(k + 1) % 3] == na))
          t0 = t;
    }
    ASSERT_GT(t0, 0);
    const gp_Pnt2d ua = tri->UVNode(na), ub = tri->UVNode(nb);
    const gp_Pnt2d mid((ua.X() + ub.X()) / 2, (ua.Y() + ub.Y()) / 2);
    const gp_Pnt pm = BRep_Tool::Surface(top)->Value(mid.X(), mid.Y());
    const gp_Vec out(pm.X() - side / 2, pm.Y() - side / 2, 0.0); // from the hole's axis
    const double lune = r - out.Magnitude();
    ASSERT_GT(lune, 0.1);
    gp_Pnt pn = pm.Translated(out.Normalized() * (0.5 * lune));
    double un = 0.0, vn = 0.0;
    GeomAPI_ProjectPointOnSurf(pn, BRep_Tool::Surface(top)).LowerDistanceParameters(un, vn);
    EXPECT_EQ(BRepTopAdaptor_FClass2d(top, 1e-9).Perform(gp_Pnt2d(un, vn)), TopAbs_OUT);
    // The triangulation again, with the node and its three triangles in place of t0 (each with
    // t0's orientation), and the edges' polygons on it.
    const int nodes = tri->NbNodes() + 1, tris = tri->NbTriangles() + 2;
    const Handle(Poly_Triangulation) more = new Poly_Triangulation(nodes, tris, Standard_True);
    for (int i = 1; i < nodes; ++i)
    {
      more->SetNode(i, tri->Node(i));
      more->SetUVNode(i, tri->UVNode(i));
    }
    more->SetNode(nodes, pn);
    more->SetUVNode(nodes, gp_Pnt2d(un, vn));
    int at = 1;
    for (int t = 1; t <= tri->NbTriangles(); ++t)
    {
      int n[3];
      tri->Triangle(t).Get(n[0], n[1], n[2]);
      if (t != t0)
      {
        more->SetTriangle(at++, tri->Triangle(t));
        continue;
      }
      for (int k = 0; k < 3; ++k)
      {
        int m[3] = { n[0], n[1], n[2] };
        m[k] = nodes;
        more->SetTriangle(at++, Poly_Triangle(m[0], m[1], m[2]));
      }
    }
    more->Deflection(tri->Deflection());
    BRep_Builder builder;
    for (TopExp_Explorer ex(top, TopAbs_EDGE); ex.More(); ex.Next())
    {
      const TopoDS_Edge& e = TopoDS::Edge(ex.Current());
      const Handle(Poly_PolygonOnTriangulation) p = BRep_Tool::PolygonOnTriangulation(e, tri, loc);
      ASSERT_FALSE(p.IsNull());
      builder.UpdateEdge(e, p, more, loc);
    }
    builder.UpdateFace(top, more);
    o.DelaunayRefinement = delaunay;
    std::vector<TopoDS_Face> faces;
    const BRepModel m = brt::ConvertShape(shape, o, &faces);
    ASSERT_EQ(faces.size(), m.Faces.size());
    // The coarse mesh kept: a vertex where the node was put or where it was moved to.
    double nearest = 1e9, worst = 0.0;
    size_t far = 0;
    for (size_t v = 0; v < m.Mesh.NumberOfPoints(); ++v)
    {
      const V3 p = Vertex(m, static_cast<int>(v));
      const gp_Pnt q(p[0], p[1], p[2]);
      if (std::abs(q.Z() - h) < 1e-9)
        nearest = std::min(nearest, q.Distance(pn));
      BRepExtrema_DistShapeShape d(BRepBuilderAPI_MakeVertex(q).Vertex(),
        faces[static_cast<size_t>(m.Mesh.FaceIds[v])]);
      ASSERT_TRUE(d.IsDone());
      worst = std::max(worst, d.Value());
      far += d.Value() > m.Tolerance;
    }
    std::printf("plate with a node inside its hole (%s): the lune %.3f deep, the nearest vertex "
                "%.3g from the node, the farthest vertex %.3g off its face\n",
      delaunay ? "flips" : "bisection", lune, nearest, worst);
    EXPECT_LE(nearest, 0.6 * lune); // (the node was kept, and moved by half the lune at most)
    EXPECT_EQ(far, 0u);
  }
}

TEST(DisplayMesh, SplitChordIsNotSplitAgain)
{
  // LeRobot's leader gripper trigger (low_cost_robot, MIT): on its cone (face 3, 36 mm^2) the
  // refinement split a chord, Lawson's flips brought the chord back, and it was split again,
  // each time adding a vertex at the same midpoint, until the face had its 200,000 vertices
  // (99,955 at one point; the part 219,979, now about 20,000). A chord is split once.
  const BRepModel m = brt::ConvertStepFile(
    std::string(BRT_TESTING_DATA_DIR) + "/lcr_leader_gripper_trigger.step", brt::ConversionOptions());
  const brt::DisplayMesh& mesh = m.Mesh;
  EXPECT_LT(mesh.FaceIds.size(), 40000u);
  std::map<int, size_t> perFace;
  for (const int f : mesh.FaceIds)
    ++perFace[f];
  ASSERT_GT(perFace[3], 20u);
  // No two vertices of one face at one (u, v) (a seam's two sides are apart in (u, v)).
  std::map<std::tuple<int, double, double>, int> seen;
  size_t repeated = 0;
  for (size_t v = 0; v < mesh.FaceIds.size(); ++v)
    repeated += seen[std::make_tuple(mesh.FaceIds[v], mesh.UV[2 * v], mesh.UV[2 * v + 1])]++ > 0;
  EXPECT_EQ(repeated, 0u);
  for (const std::string& w : m.Stats.Warnings)
    EXPECT_EQ(w.find("refined only in part"), std::string::npos) << w;
}
