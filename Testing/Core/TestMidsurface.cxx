// The midsurface of thin parts against closed forms: the mid-plane of a plate, the mid-cylinder of
// a tube, the mid-planes of L, T and cross profiles meeting at their junction lines.
#include "AnalyticShapes.h"
#include "Midsurface.h"
#include "SolverTestHelpers.h"
#include "Statistics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <unordered_map>

namespace
{
brt::MidsurfaceInput InputOf(const brt::test::Solved& s)
{
  brt::MidsurfaceInput in;
  const auto& M = s.Model.Mesh;
  in.Points = M.Points;
  in.Normals = M.Normals;
  in.FaceIds = M.FaceIds;
  in.Triangles = M.Triangles;
  for (size_t i = 0; i < s.Results.size(); ++i)
  {
    const brt::SampleResult& r = s.Results[i];
    const double O[3] = { M.Points[3 * i], M.Points[3 * i + 1], M.Points[3 * i + 2] };
    const bool ok = r.Type != brt::ContactType::Failed;
    in.Thickness.push_back(ok ? r.Thickness : std::nan(""));
    in.ContactType.push_back(int(r.Type));
    in.OppositeFace.push_back(r.OppositeFace);
    in.ContactAngle.push_back(ok ? brt::ContactAngle(O, r) : std::nan(""));
    in.EdgeZone.push_back(ok && brt::IsEdgeZone(O, r) ? 1 : 0);
  }
  return in;
}

brt::Midsurface Build(const TopoDS_Shape& shape)
{
  const auto solved = brt::test::SolveShape(shape, 1e-4);
  return brt::BuildMidsurface(InputOf(solved));
}

std::array<double, 3> Point(const brt::Midsurface& m, size_t i)
{
  return { m.Points[3 * i], m.Points[3 * i + 1], m.Points[3 * i + 2] };
}

double LongestEdge(const brt::Midsurface& m)
{
  double l = 0.0;
  for (size_t t = 0; t < m.Triangles.size() / 3; ++t)
    for (int k = 0; k < 3; ++k)
    {
      const auto a = Point(m, size_t(m.Triangles[3 * t + k]));
      const auto b = Point(m, size_t(m.Triangles[3 * t + (k + 1) % 3]));
      l = std::max(l, std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]));
    }
  return l;
}

/// Every edge (smaller id first) with the sheets of its triangles, one entry per triangle.
std::map<std::pair<int, int>, std::vector<int>> EdgeSheets(const brt::Midsurface& m)
{
  std::map<std::pair<int, int>, std::vector<int>> edges;
  for (size_t t = 0; t < m.Triangles.size() / 3; ++t)
    for (int k = 0; k < 3; ++k)
    {
      const int a = m.Triangles[3 * t + k], b = m.Triangles[3 * t + (k + 1) % 3];
      edges[{ std::min(a, b), std::max(a, b) }].push_back(m.TriangleSheet[t]);
    }
  return edges;
}

/// Edges whose triangles belong to more than one sheet: the junctions.
std::vector<std::pair<int, int>> SheetJunctionEdges(const brt::Midsurface& m)
{
  std::vector<std::pair<int, int>> out;
  for (const auto& e : EdgeSheets(m))
  {
    bool mixed = false;
    for (int s : e.second)
      mixed = mixed || s != e.second[0];
    if (mixed)
      out.push_back(e.first);
  }
  return out;
}

void Describe(const char* name, const brt::Midsurface& m)
{
  std::printf("%s: %zu sheets, %zu triangles, %zu points, sample %d other side %d extended %d junction %d pruned %d in %d branches, "
              "boundary %d non-manifold %d junctions %d open %d, not thin %zu faces\n",
    name, m.Sheets.size(), m.Triangles.size() / 3, m.Points.size() / 3, m.SheetSamples,
    m.OppositeSideSamples, m.ExtendedVertices, m.JunctionVertices, m.PrunedSamples, m.PrunedBranches, m.BoundaryEdges, m.NonManifoldEdges,
    m.Junctions, m.OpenJunctionEdges, m.NotThinFaces.size());
  EXPECT_EQ(m.FoldEdges, 0) << name;
}
} // namespace

TEST(Midsurface, PlateIsItsMidPlaneToTheOutline)
{
  const auto m = Build(brt::analytic::Plate(100, 60, 5));
  Describe("plate 100x60x5", m);
  ASSERT_EQ(m.Sheets.size(), 1u);
  ASSERT_GT(m.Triangles.size(), 300u);
  double worstZ = 0.0, worstH = 0.0;
  std::array<double, 4> box{ 1e9, -1e9, 1e9, -1e9 };
  for (size_t i = 0; i < m.Points.size() / 3; ++i)
  {
    const auto p = Point(m, i);
    worstZ = std::max(worstZ, std::fabs(p[2] - 2.5));
    worstH = std::max(worstH, std::fabs(m.Thickness[i] - 5.0) / 5.0);
    box = { std::min(box[0], p[0]), std::max(box[1], p[0]), std::min(box[2], p[1]),
      std::max(box[3], p[1]) };
  }
  EXPECT_LE(worstZ, 1e-6);
  EXPECT_LE(worstH, 1e-6);
  // The sheet reaches the outline: its boundary is the plate's rectangle at mid-height.
  EXPECT_NEAR(box[0], 0.0, 1e-9);
  EXPECT_NEAR(box[1], 100.0, 1e-9);
  EXPECT_NEAR(box[2], 0.0, 1e-9);
  EXPECT_NEAR(box[3], 60.0, 1e-9);
  EXPECT_NEAR(m.Sheets[0].Area, 6000.0, 6000.0 * 1e-9);
  const double edge = LongestEdge(m);
  const brt::EdgeCounts c = brt::CountEdges(m.Triangles);
  EXPECT_EQ(c.NonManifold, 0);
  // Every boundary vertex lies on the outline (within one mesh edge: here exactly).
  double worstOutline = 0.0;
  for (const auto& e : EdgeSheets(m))
    if (e.second.size() == 1)
      for (int v : { e.first.first, e.first.second })
      {
        const auto p = Point(m, size_t(v));
        worstOutline = std::max(worstOutline,
          std::min({ std::fabs(p[0]), std::fabs(p[0] - 100), std::fabs(p[1]), std::fabs(p[1] - 60) }));
      }
  EXPECT_LE(worstOutline, 1e-9) << "longest edge " << edge;
  EXPECT_EQ(m.OpenJunctionEdges, 0);
}

TEST(Midsurface, TubeIsItsMidCylinder)
{
  const auto m = Build(brt::analytic::Tube(20, 15, 50));
  Describe("tube R20 r15", m);
  ASSERT_EQ(m.Sheets.size(), 1u);
  double worstR = 0.0, worstH = 0.0;
  for (size_t i = 0; i < m.Points.size() / 3; ++i)
  {
    const auto p = Point(m, i);
    worstR = std::max(worstR, std::fabs(std::hypot(p[0], p[1]) - 17.5) / 17.5);
    worstH = std::max(worstH, std::fabs(m.Thickness[i] - 5.0) / 5.0);
  }
  EXPECT_LE(worstR, 1e-6);
  EXPECT_LE(worstH, 1e-6);
  // Closed around: the seam is welded, only the two end circles are boundary.
  const brt::EdgeCounts c = brt::CountEdges(m.Triangles);
  EXPECT_EQ(c.NonManifold, 0);
  for (const auto& e : EdgeSheets(m))
    if (e.second.size() == 1)
      for (int v : { e.first.first, e.first.second })
      {
        const double z = Point(m, size_t(v))[2];
        EXPECT_TRUE(std::fabs(z) < 1e-9 || std::fabs(z - 50) < 1e-9) << "boundary at z " << z;
      }
}

/// Checks that every vertex lies on one of the mid-planes, inside its part of the profile.
void ExpectOnMidPlanes(const brt::Midsurface& m,
  const std::function<bool(const std::array<double, 3>&)>& onPlanes)
{
  int off = 0;
  for (size_t i = 0; i < m.Points.size() / 3; ++i)
    if (!onPlanes(Point(m, i)))
    {
      if (off++ < 5)
        ADD_FAILURE() << "vertex off the mid-planes: " << Point(m, i)[0] << " " << Point(m, i)[1]
                      << " " << Point(m, i)[2];
    }
  EXPECT_EQ(off, 0);
}

TEST(Midsurface, LBracketIsTwoSheetsMeetingAtOneLine)
{
  for (double fillet : { 0.0, 3.0 })
  {
    SCOPED_TRACE(fillet);
    const auto m = Build(brt::analytic::LBracket(60, 5, 40, fillet));
    Describe(fillet > 0 ? "L 60x5, inner fillet 3" : "L 60x5, sharp", m);
    ASSERT_EQ(m.Sheets.size(), 2u);
    const double tol = 1e-6;
    // On y = 2.5 (x >= 2.5) or x = 2.5 (y >= 2.5): nothing towards the convex corner.
    ExpectOnMidPlanes(m, [&](const std::array<double, 3>& p) {
      return (std::fabs(p[1] - 2.5) <= tol && p[0] >= 2.5 - tol) ||
        (std::fabs(p[0] - 2.5) <= tol && p[1] >= 2.5 - tol);
    });
    const auto junction = SheetJunctionEdges(m);
    ASSERT_FALSE(junction.empty());
    double zmin = 1e9, zmax = -1e9;
    for (const auto& e : junction)
      for (int v : { e.first, e.second })
      {
        const auto p = Point(m, size_t(v));
        EXPECT_NEAR(p[0], 2.5, tol);
        EXPECT_NEAR(p[1], 2.5, tol);
        zmin = std::min(zmin, p[2]);
        zmax = std::max(zmax, p[2]);
      }
    // One line along the whole width.
    EXPECT_NEAR(zmin, 0.0, 1e-9);
    EXPECT_NEAR(zmax, 40.0, 1e-9);
    EXPECT_EQ(m.OpenJunctionEdges, 0);
    EXPECT_EQ(brt::CountEdges(m.Triangles).NonManifold, 0);
  }
}

TEST(Midsurface, TProfileIsThreeSheetsOnOneNonManifoldChain)
{
  // Flange 80 x 6, web 40 x 4, 30 deep.
  const auto m = Build(brt::analytic::TProfile(80, 6, 40, 4, 30));
  Describe("T 80x6 + 40x4", m);
  ASSERT_EQ(m.Sheets.size(), 3u);
  const double tol = 1e-6;
  ExpectOnMidPlanes(m, [&](const std::array<double, 3>& p) {
    return std::fabs(p[1] + 3.0) <= tol || (std::fabs(p[0]) <= tol && p[1] >= -3.0 - tol);
  });
  const brt::EdgeCounts c = brt::CountEdges(m.Triangles);
  EXPECT_GT(c.NonManifold, 0);
  EXPECT_EQ(c.NonManifoldChains, 1);
  EXPECT_EQ(m.Junctions, 1);
  // The chain is the line x = 0, y = -3 across the whole depth; each of its edges has exactly
  // three triangles, one per sheet.
  double length = 0.0;
  for (const auto& e : EdgeSheets(m))
    if (e.second.size() > 2)
    {
      EXPECT_EQ(e.second.size(), 3u);
      std::vector<int> s = e.second;
      std::sort(s.begin(), s.end());
      EXPECT_TRUE(s[0] != s[1] && s[1] != s[2]);
      const auto a = Point(m, size_t(e.first.first)), b = Point(m, size_t(e.first.second));
      for (const auto& p : { a, b })
      {
        EXPECT_NEAR(p[0], 0.0, tol);
        EXPECT_NEAR(p[1], -3.0, tol);
      }
      length += std::fabs(b[2] - a[2]);
    }
  EXPECT_NEAR(length, 30.0, 1e-9);
  EXPECT_EQ(m.OpenJunctionEdges, 0);
}

TEST(Midsurface, CrossIsFourSheetsOnOneNonManifoldChain)
{
  const auto m = Build(brt::analytic::CrossProfile(60, 5, 20));
  Describe("cross 60x5", m);
  ASSERT_EQ(m.Sheets.size(), 4u);
  const double tol = 1e-6;
  ExpectOnMidPlanes(m, [&](const std::array<double, 3>& p) {
    return std::fabs(p[0]) <= tol || std::fabs(p[1]) <= tol;
  });
  const brt::EdgeCounts c = brt::CountEdges(m.Triangles);
  EXPECT_EQ(c.NonManifoldChains, 1);
  double length = 0.0;
  for (const auto& e : EdgeSheets(m))
    if (e.second.size() > 2)
    {
      EXPECT_EQ(e.second.size(), 4u);
      length += std::fabs(Point(m, size_t(e.first.second))[2] - Point(m, size_t(e.first.first))[2]);
    }
  EXPECT_NEAR(length, 20.0, 1e-9);
}

TEST(Midsurface, BlockIsReportedNotThin)
{
  const auto m = Build(brt::analytic::Plate(20, 20, 20));
  Describe("block 20^3", m);
  EXPECT_TRUE(m.Triangles.empty());
  EXPECT_FALSE(m.NotThinFaces.empty());
  EXPECT_GT(m.NotThinArea, 0.0);
}

// --- The skeleton of rods ------------------------------------------------------------------------
#include "Skeleton.h"

#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <gp_Ax2.hxx>

namespace
{
brt::Skeleton BuildSkeletonOf(const TopoDS_Shape& shape, const char* name)
{
  const auto solved = brt::test::SolveShape(shape, 1e-4);
  const brt::Skeleton s = brt::BuildSkeleton(InputOf(solved));
  std::printf("%s: %zu nodes, %zu polylines, rod samples %d, noise %d, cycles %d, spurs %d, "
              "junctions %d, ends %d\n",
    name, s.Radius.size(), s.Polylines.size(), s.RodSamples, s.NoiseClusters, s.ShortCycles,
    s.RemovedSpurs, s.JunctionNodes, s.EndNodes);
  return s;
}
} // namespace

TEST(Skeleton, RodIsItsAxis)
{
  const auto s = BuildSkeletonOf(
    brt::analytic::Rod(5.0, 100.0), "rod R5 L100");
  ASSERT_EQ(s.Polylines.size(), 1u);
  EXPECT_EQ(s.EndNodes, 2);
  EXPECT_EQ(s.JunctionNodes, 0);
  double zmin = 1e9, zmax = -1e9;
  for (size_t i = 0; i < s.Radius.size(); ++i)
  {
    // A rod's sphere touches its own cylinder across: the exact finish's closed form (the
    // sphere through the axis) makes it exact.
    EXPECT_LE(std::hypot(s.Points[3 * i], s.Points[3 * i + 1]), 1e-9);
    EXPECT_NEAR(s.Radius[i], 5.0, 5e-9);
    zmin = std::min(zmin, s.Points[3 * i + 2]);
    zmax = std::max(zmax, s.Points[3 * i + 2]);
  }
  // The axis between the end spheres (z = R .. L - R), to a cluster cell (R/2).
  EXPECT_NEAR(zmin, 5.0, 2.5);
  EXPECT_NEAR(zmax, 95.0, 2.5);
  EXPECT_EQ(s.Polylines[0].size(), s.Radius.size());
}

TEST(Skeleton, RingIsOneClosedCircle)
{
  const auto s = BuildSkeletonOf(
    brt::analytic::Ring(30.0, 4.0), "ring 30/4");
  ASSERT_EQ(s.Polylines.size(), 1u);
  EXPECT_EQ(s.Polylines[0].front(), s.Polylines[0].back());
  EXPECT_EQ(s.EndNodes + s.JunctionNodes, 0);
  for (size_t i = 0; i < s.Radius.size(); ++i)
  {
    // Cluster means of centres on the circle lie inside it by the cell's sagitta.
    EXPECT_NEAR(std::hypot(s.Points[3 * i], s.Points[3 * i + 1]), 30.0, 0.05);
    EXPECT_NEAR(s.Points[3 * i + 2], 0.0, 1e-6);
    EXPECT_NEAR(s.Radius[i], 4.0, 4e-9);
  }
}

TEST(Skeleton, CrossedRodsMeetAtOneJunction)
{
  const TopoDS_Shape a =
    BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(-50, 0, 0), gp_Dir(1, 0, 0)), 4.0, 100.0).Shape();
  const TopoDS_Shape b =
    BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, -50, 0), gp_Dir(0, 1, 0)), 3.0, 100.0).Shape();
  const auto s = BuildSkeletonOf(BRepAlgoAPI_Fuse(a, b).Shape(), "rods crossed");
  EXPECT_EQ(s.JunctionNodes, 1);
  EXPECT_EQ(s.EndNodes, 4);
  ASSERT_EQ(s.Polylines.size(), 4u);
  // The four branches start at one node, at the crossing of the axes (within a cluster cell),
  // and each runs along one half-axis.
  std::map<int, int> starts;
  for (const auto& l : s.Polylines)
  {
    ++starts[l.front()];
    ++starts[l.back()];
  }
  int junction = -1;
  for (const auto& st : starts)
    if (st.second == 4)
      junction = st.first;
  ASSERT_GE(junction, 0);
  EXPECT_LE(std::hypot(s.Points[3 * junction], s.Points[3 * junction + 1], s.Points[3 * junction + 2]), 2.0);
  for (size_t i = 0; i < s.Radius.size(); ++i)
  {
    const double x = s.Points[3 * i], y = s.Points[3 * i + 1], z = s.Points[3 * i + 2];
    EXPECT_TRUE((std::hypot(y, z) < 1e-4 && std::fabs(s.Radius[i] - 4.0) < 4e-4) ||
      (std::hypot(x, z) < 1e-4 && std::fabs(s.Radius[i] - 3.0) < 3e-4) || int(i) == junction)
      << x << " " << y << " " << z << " r " << s.Radius[i];
  }
}

TEST(Midsurface, BadInputIsOneClearError)
{
  brt::MidsurfaceInput in;
  in.Points = { 0, 0, 0, 1, 0, 0, 0, 1, 0 };
  in.Normals = { 0, 0, 1, 0, 0, 1, 0, 0, 1 };
  in.FaceIds = { 0, 0, 0 };
  in.Thickness = { 1, 1, 1 };
  in.ContactType = { 1, 1, 1 };
  in.OppositeFace = { 1, 1, 1 };
  in.ContactAngle = { 180, 180, 180 };
  in.EdgeZone = { 0, 0, 0 };
  in.Triangles = { 0, 1, 2 };
  EXPECT_NO_THROW(brt::BuildMidsurface(in));
  EXPECT_NO_THROW(brt::BuildSkeleton(in));
  auto bad = in;
  bad.Thickness.pop_back();
  EXPECT_THROW(brt::BuildMidsurface(bad), std::invalid_argument);
  EXPECT_THROW(brt::BuildSkeleton(bad), std::invalid_argument);
  bad = in;
  bad.Triangles = { 0, 1, 3 };
  EXPECT_THROW(brt::BuildMidsurface(bad), std::invalid_argument);
  // NaN thickness everywhere (all samples failed): no sheet, no crash.
  bad = in;
  bad.Thickness = { std::nan(""), std::nan(""), std::nan("") };
  bad.ContactType = { 0, 0, 0 };
  EXPECT_TRUE(brt::BuildMidsurface(bad).Triangles.empty());
  EXPECT_TRUE(brt::BuildSkeleton(bad).Polylines.empty());
  // An empty input.
  EXPECT_TRUE(brt::BuildMidsurface(brt::MidsurfaceInput{}).Triangles.empty());
  EXPECT_TRUE(brt::BuildSkeleton(brt::MidsurfaceInput{}).Polylines.empty());
}
