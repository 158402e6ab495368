// The trim test (eq. 6 and the corner rule) on hand-made loops whose inside is known exactly.
#include "TrimClassifier.h"

#include "NativeSolver.h"
#include "Solver.h"

#include "BRepConverter.h"
#include "Bezier.h"
#include "TestHelpers.h"

#include <gtest/gtest.h>

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepPrimAPI_MakePrism.hxx>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

namespace
{
using namespace brt;

/// A model of one face over `domain`, the plane z = 0 (one flat patch, ten times the domain's
/// size: the kernel needs a patch per face), whose one outer loop is `segments`.
BRepModel OneFaceModel(const std::array<double, 4>& domain,
  const std::vector<std::array<double, 8>>& segments, double uvTolerance = 1e-9)
{
  BRepModel m;
  m.Faces.resize(1);
  Face& F = m.Faces[0];
  F.Domain = domain;
  F.PatchCount = 1;
  F.PatchesU = F.PatchesV = 1;
  F.LoopCount = 1;
  F.UVTolerance = uvTolerance;
  BezierPatch patch;
  patch.Face = 0;
  patch.Domain = domain;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
    {
      patch.ControlPoints[(4 * i + j) * 3] = 10.0 * (domain[0] + (domain[1] - domain[0]) * i / 3.0);
      patch.ControlPoints[(4 * i + j) * 3 + 1] =
        10.0 * (domain[2] + (domain[3] - domain[2]) * j / 3.0);
    }
  m.Patches.push_back(patch);
  TrimLoop loop;
  loop.Face = 0;
  loop.Outer = true;
  loop.SegmentCount = static_cast<int>(segments.size());
  for (const auto& c : segments)
  {
    TrimSegment t;
    t.Face = 0;
    t.Loop = 0;
    t.ControlPoints = c;
    m.TrimSegments.push_back(t);
  }
  m.Loops.push_back(loop);
  return m;
}

/// A straight segment from (x0, y0) to (x1, y1), its control points evenly spaced.
std::array<double, 8> LineSegment(double x0, double y0, double x1, double y1)
{
  std::array<double, 8> c{};
  for (int k = 0; k < 4; ++k)
  {
    c[2 * k] = x0 + (x1 - x0) * k / 3.0;
    c[2 * k + 1] = y0 + (y1 - y0) * k / 3.0;
  }
  return c;
}

struct Probe
{
  double u, v;
  bool inside;
};

/// Each probe's side by the crossing parity, by the kernel's classify and by the reader's
/// ClassifyPoint (given the face's TrimLoopsCross; with `loopsCross` false, as though its loops
/// did not cross, so that the other rules decide alone).
void ExpectSides(const BRepModel& m, const std::vector<Probe>& probes, bool loopsCross = true)
{
  SolverData data = PrepareSolver(m, SolverOptions());
  if (!loopsCross)
    data.FaceLoopsCross.assign(data.FaceLoopsCross.size(), -1.0);
  const NativeSolver native(m, data);
  for (const Probe& p : probes)
  {
    EXPECT_EQ(InsideByCrossings(m, 0, p.u, p.v), p.inside) << "(" << p.u << ", " << p.v << ")";
    const TrimProjection r = ClassifyPoint(m, 0, p.u, p.v, data.FaceLoopsCross[0]);
    EXPECT_EQ(r.Inside, p.inside) << "ClassifyPoint (" << p.u << ", " << p.v << "): segment "
                                  << r.Segment << " t " << r.Parameter << ", corner " << r.Corner;
    bool inside = false;
    int segment = -1;
    double parameter = 0.0, distance = 0.0;
    native.Classify(0, p.u, p.v, inside, segment, parameter, distance);
    EXPECT_EQ(inside, p.inside) << "kernel classify (" << p.u << ", " << p.v << "): segment "
                                << segment << " t " << parameter;
  }
}

/// Adds a closed polygon loop (straight cubic segments) to face 0 of `m`.
void AddPolygon(BRepModel& m, const std::vector<std::array<double, 2>>& pts, bool outer)
{
  TrimLoop loop;
  loop.Face = 0;
  loop.Outer = outer;
  loop.FirstSegment = static_cast<int>(m.TrimSegments.size());
  for (size_t i = 0; i < pts.size(); ++i)
  {
    const auto& a = pts[i];
    const auto& b = pts[(i + 1) % pts.size()];
    TrimSegment s;
    s.Face = 0;
    s.Loop = static_cast<int>(m.Loops.size());
    for (int k = 0; k < 4; ++k)
    {
      s.ControlPoints[2 * k] = a[0] + (b[0] - a[0]) * k / 3.0;
      s.ControlPoints[2 * k + 1] = a[1] + (b[1] - a[1]) * k / 3.0;
    }
    m.TrimSegments.push_back(s);
  }
  loop.SegmentCount = static_cast<int>(pts.size());
  m.Loops.push_back(loop);
  m.Faces[0].LoopCount = static_cast<int>(m.Loops.size());
}

bool InPolygon(const std::vector<std::array<double, 2>>& p, double x, double y)
{
  bool in = false;
  for (size_t i = 0, j = p.size() - 1; i < p.size(); j = i++)
    if ((p[i][1] > y) != (p[j][1] > y) &&
      x < (p[j][0] - p[i][0]) * (y - p[i][1]) / (p[j][1] - p[i][1]) + p[i][0])
      in = !in;
  return in;
}

TEST(TrimClassifier, LShapeWithSquareHoleMatchesExactPolygonTest)
{
  // L-shaped outer loop (counter-clockwise, one concave corner) and a clockwise square hole.
  const std::vector<std::array<double, 2>> outer{ { 0, 0 }, { 4, 0 }, { 4, 1 }, { 1, 1 },
    { 1, 4 }, { 0, 4 } };
  const std::vector<std::array<double, 2>> hole{ { 0.3, 2 }, { 0.3, 3 }, { 0.7, 3 }, { 0.7, 2 } };
  BRepModel m;
  m.Faces.resize(1);
  AddPolygon(m, outer, true);
  AddPolygon(m, hole, false);
  int corners = 0;
  const int n = 200;
  for (int i = 0; i <= n; ++i)
  {
    for (int j = 0; j <= n; ++j)
    {
      // A grid offset from every vertex so no point sits exactly on the boundary.
      const double x = -0.5 + 5.0 * (i + 0.37) / n, y = -0.5 + 5.0 * (j + 0.61) / n;
      const bool expected = InPolygon(outer, x, y) && !InPolygon(hole, x, y);
      const TrimProjection r = ClassifyPoint(m, 0, x, y);
      corners += r.Corner;
      ASSERT_EQ(r.Inside, expected) << "(" << x << ", " << y << ") distance " << r.Distance;
    }
  }
  std::printf("[trim] %d of %d points decided by the corner rule\n", corners, (n + 1) * (n + 1));
}

TEST(TrimClassifier, CornerRuleConcaveInsideConvexOutside)
{
  BRepModel m;
  m.Faces.resize(1);
  AddPolygon(m, { { 0, 0 }, { 4, 0 }, { 4, 1 }, { 1, 1 }, { 1, 4 }, { 0, 4 } }, true);
  // Beyond the convex corner (4,0): nearest point is the vertex, outside.
  TrimProjection r = ClassifyPoint(m, 0, 4.2, -0.3);
  EXPECT_FALSE(r.Inside);
  EXPECT_NEAR(r.Distance, std::hypot(0.2, 0.3), 1e-12);
  // In the wedge of the concave corner (1,1): nearest point is the vertex, inside.
  r = ClassifyPoint(m, 0, 0.8, 0.8);
  EXPECT_TRUE(r.Inside);
  // Exactly on the bisector near the concave corner the two tangents disagree: corner rule.
  r = ClassifyPoint(m, 0, 1.0 + 1e-3, 1.0 + 1e-3);
  EXPECT_FALSE(r.Inside);
}

/// A loop that turns back on itself at a cusp: two arcs meet at the tip of a spike with
/// tangents opposite but for a millionth (the control_arm's face 102 has such a spike). Below
/// the tip, where the nearest trimming point is the tip and the two tangents disagree, the
/// corner's turn is rounding: the corner rule took such points for inside. ClassifyPoint must
/// give the crossing parity's answer there (outside: the loop lies above the tip), and keep the
/// tangent's answer inside the spike.
TEST(TrimClassifier, CuspTakesTheCrossingParity)
{
  const double eps = 1e-6;
  const BRepModel m = OneFaceModel({ 0.0, 10.0, 0.0, 10.0 },
    { { 3, 10, 3.5, 6, 5 + eps, 4, 5, 2 }, // down to the tip, from the left
      { 5, 2, 5, 4, 6.5, 6, 7, 10 },       // back up, to the right
      { 7, 10, 17.0 / 3, 10, 13.0 / 3, 10, 3, 10 } });
  // The tangents at the tip: (-eps, -2) in, (0, 2) out; their turn -2 eps says "concave".
  EXPECT_LT(TrimLoopsCross(m, 0), 0.0); // the cusp's rule alone decides
  ExpectSides(m, { { 5.01, 1.9, false }, { 4.99, 1.95, false }, { 5.3, 1.0, false },
                   { 4.6, 1.2, false }, { 5.0, 2.3, true }, { 5.0, 6.0, true } });
  // Below the tip the nearest point is the tip, decided as a corner.
  const TrimProjection below = ClassifyPoint(m, 0, 5.01, 1.9);
  EXPECT_TRUE(below.Corner);
}

/// Beside the tip of a sliver face, where its two edges run together: the tip of face 68 of the
/// Ploopy headband (Headband-Triangle-SMALL, a rational B-spline face 8.8e-4 by 0.29 in its
/// parameters, whose two edges lie within 3e-7 of each other and cross near the tip, so that its
/// loop is a figure of eight there), its first segment down from the tip, a short closing segment,
/// and its last segment back up to the tip, as the file's conversion gives them (to the last bit).
/// At (2.96e-4, 0.289028), 2.1e-4 to the side of the tip, both edges' nearest points lie just
/// below the tip at distances equal within 1.1e-9 (relative), and each edge's tangent puts the
/// point on its own side: the nearer said inside, and a contact there, 0.27 mm outside the face,
/// gave a sphere 2t = 0.547 where the exact is 0.696. The reader's ClassifyPoint and the kernel's
/// classify must give the crossing parity's answer (outside) there.
TEST(TrimClassifier, TiedEdgesBesideASliverTakeTheCrossingParity)
{
  const std::array<double, 8> down = { 8.8056931890676562e-05, 0.28902804582399244,
    0.00010396923458925021, 0.28711742477597607, 0.00011979854110764232, 0.28506940260125591,
    0.0001355369605204197, 0.28288861905085111 };
  const std::array<double, 8> up = { 0.00013575764462472493, 0.28286013593856885,
    0.00011995237339327605, 0.28505016667621208, 0.00010404967833121704, 0.28710773524542577,
    8.8056931890676562e-05, 0.28902804582399244 };
  const BRepModel m = OneFaceModel({ 0.0, 1e-3, 0.0, 0.3 },
    { down, LineSegment(down[6], down[7], up[0], up[1]), up }, 4e-8);
  const std::vector<Probe> probes = { { 0.000296, 0.289028, false }, { 0.000296, 0.2889, false },
    { 0.0002, 0.289028, false }, { 0.00012, 0.2855, false } };
  // The case is a tie: at the first probe both edges lie as near within 1e-8, their nearest
  // points inside the segments.
  double dDown = 0.0, dUp = 0.0;
  const double tDown = ProjectOnSegment(down, probes[0].u, probes[0].v, &dDown);
  const double tUp = ProjectOnSegment(up, probes[0].u, probes[0].v, &dUp);
  EXPECT_NEAR(dDown, dUp, 1e-8 * dDown);
  EXPECT_GT(tDown, 0.0);
  EXPECT_LT(tUp, 1.0);
  // The two edges cross near the tip (TrimLoopsCross), which alone would take the parity there
  // too: the tie's rule is tested as though they did not, and then with it.
  EXPECT_GE(TrimLoopsCross(m, 0), 0.0);
  ExpectSides(m, probes, false);
  ExpectSides(m, probes);
}

/// A spike's tip whose sides are not next to each other on the loop: the triangle (0, 0),
/// (10.3, 5), (-9.3, 9) traversed counter-clockwise, its tip rounded by a short fillet that turns
/// right by 38 degrees (ending 1.4e-3 rad short of the way back), then a sliver 1e-4 long turning
/// left, then the way back (the classic Ploopy trackball's secondary buttons, face 10, have such a
/// tip). The loop turns left by 180.08 degrees at the tip, the fillet's end and the way back alone
/// say right by 179.92: with the sliver left out as a side, the corner rule put points 5 away
/// outside the spike's tip inside the face (37 spheres of that part too small, 2t 0.027 against
/// the exact 2.0). There the crossing parity decides, in the reader and in the kernel.
TEST(TrimClassifier, CornerAcrossASliverTakesTheCrossingParity)
{
  // The way back: the fillet's end direction (0.98, -0.2) reversed, turned right by 1.4e-3 rad.
  const double bx = -0.98 - 0.2 * 1.4e-3, by = 0.2 - 0.98 * 1.4e-3;
  const double sx = 10.3 + 1e-4 * 0.2, sy = 5.0 + 1e-4 * 0.98; // the sliver's end
  const double ex = sx + 20.0 * bx, ey = sy + 20.0 * by;
  const BRepModel m = OneFaceModel({ -12.0, 14.0, -4.0, 12.0 },
    { LineSegment(0, 0, 10, 5), { 10, 5, 10.0894, 5.0447, 10.202, 5.02, 10.3, 5.0 }, // fillet
      LineSegment(10.3, 5.0, sx, sy), LineSegment(sx, sy, ex, ey), LineSegment(ex, ey, 0, 0) });
  EXPECT_LT(TrimLoopsCross(m, 0), 0.0); // the corner's rule alone decides
  // Beyond the tip (its nearest loop point the fillet's end), and inside the triangle.
  ExpectSides(m, { { 12.0, 0.0, false }, { 13.0, 2.0, false }, { 11.5, -2.0, false },
                   { 11.0, 3.0, false }, { 3.0, 4.0, true }, { 8.0, 5.0, true } });
  // The first probe's nearest loop point is the fillet's end, and the sliver is left out there.
  const TrimProjection tip = ClassifyPoint(m, 0, 12.0, 0.0);
  EXPECT_TRUE(tip.Corner);
  EXPECT_TRUE(tip.Segment == 1 || tip.Segment == 2) << tip.Segment;
}

/// A loop that crosses itself: the unit square whose top edge runs on past the corner (0, 1) to
/// (-0.005, 0.999), hooks back above itself to (0, 0.9993), and only then turns down the left side,
/// which crosses the top edge at (0, 0.999): a small lobe there runs clockwise (the classic
/// Ploopy trackball's secondary buttons, face 88, a B-spline face whose top edge hooks so at its
/// domain's corner: 6 contacts at the corner above the hook, spheres of 2t 0.146 against the exact
/// 0.234). Above the corner, (0, 1.0008), the nearest loop point is the hook's end, whose sides say
/// inside. TrimLoopsCross finds the crossing (and none on the plain square), and the kernel's
/// classify, and the reader's ClassifyPoint given the face's TrimLoopsCross, take the crossing
/// parity on such a face: outside.
TEST(TrimClassifier, LoopThatCrossesItselfTakesTheCrossingParity)
{
  const std::array<double, 4> domain = { -0.1, 1.1, -0.1, 1.1 };
  const BRepModel square = OneFaceModel(domain, { LineSegment(0, 0, 1, 0),
    LineSegment(1, 0, 1, 1), LineSegment(1, 1, 0, 1), LineSegment(0, 1, 0, 0) });
  EXPECT_LT(TrimLoopsCross(square, 0), 0.0);
  const BRepModel m = OneFaceModel(domain, { LineSegment(0, 0, 1, 0), LineSegment(1, 0, 1, 1),
    LineSegment(1, 1, -0.005, 0.999), LineSegment(-0.005, 0.999, 0, 0.9993),
    LineSegment(0, 0.9993, 0, 0) });
  EXPECT_GE(TrimLoopsCross(m, 0), 0.0);
  ExpectSides(m, { { 0.0, 1.0008, false }, { 0.0005, 1.0006, false }, { -0.02, 0.5, false },
                   { 0.5, 0.5, true }, { 0.01, 0.99, true } });
  // Without the face's TrimLoopsCross, the reader's test keeps the nearer curve's answer above
  // the corner, which the parity replaces.
  EXPECT_TRUE(ClassifyPoint(m, 0, 0.0, 1.0008).Inside);
}

TEST(TrimClassifier, NewtonProjectionOnCurvedSegment)
{
  // Quarter circle of radius 1 as a cubic (standard kappa); projection of points on rays.
  const double k = 0.5522847498;
  const std::array<double, 8> cp{ 1, 0, 1, k, k, 1, 0, 1 };
  for (double a : { 0.1, 0.4, 0.785, 1.2, 1.5 })
  {
    for (double rad : { 0.5, 1.3, 3.0 })
    {
      double d = 0.0;
      ProjectOnSegment(cp, rad * std::cos(a), rad * std::sin(a), &d);
      EXPECT_NEAR(d, std::fabs(rad - 1.0), 3e-4) << a << " " << rad; // cubic arc error 2.7e-4
    }
  }
}
// A loop whose corner carries a sliver that turns back, as a bridged gap or a pcurve's tail leaves
// one (the Framework logo cover's face 11: a bridge 3.7e-4 long pointing backwards at a concave
// corner put a point 0.67 away inside the face outside it, and a sphere held that face 0.35 deep).
// The top face of an L-shaped prism (the L of CornerRuleConcaveInsideConvexOutside ten times as
// large, 2 high), its loop given such a bridge at the concave corner (10, 10): a segment 4e-4 long
// back along the side it came along, the next side starting at its end. Every point of the face's
// parameter plane 0.5 or more from the loop (a thousand times the sliver's length: nearer, the
// sliver's tangent still decides) must be classified as the exact polygon test of the L says, by
// the reader's ClassifyPoint and the kernel's classify alike. Before the sliver rule the points
// in the corner's wedge whose nearest loop point was the sliver's end were put outside (the corner
// rule took the sliver's backward tangent). A sliver a hundredth of the distance (tried) moved six
// spheres of OpenCASCADE's trj3_s1-md-214.stp into its faces, 0.024 deep.
TEST(TrimClassifier, BackwardSliverAtACornerSaysNothing)
{
  const std::vector<std::array<double, 2>> shape{ { 0, 0 }, { 40, 0 }, { 40, 10 }, { 10, 10 },
    { 10, 40 }, { 0, 40 } };
  BRepBuilderAPI_MakePolygon polygon;
  for (const auto& p : shape)
    polygon.Add(gp_Pnt(p[0], p[1], 0));
  polygon.Close();
  BRepModel m = ConvertShape(
    BRepPrimAPI_MakePrism(BRepBuilderAPI_MakeFace(polygon.Wire(), true).Face(), gp_Vec(0, 0, 2))
      .Shape(),
    ConversionOptions());
  int face = -1;
  for (int f = 0; f < static_cast<int>(m.Faces.size()); ++f)
  {
    const std::array<double, 8>& e = m.FaceExact[static_cast<size_t>(f)];
    if (m.Faces[f].Kind == SurfaceKind::Plane && std::fabs(std::fabs(e[5]) - 1.0) < 1e-9 &&
      std::fabs(e[2] - 2.0) < 1e-9)
      face = f;
  }
  ASSERT_GE(face, 0);
  Face& F = m.Faces[face];
  ASSERT_EQ(F.LoopCount, 1);
  const int loopIndex = F.FirstLoop;
  auto at = [&](double u, double v) {
    int patch = F.FirstPatch;
    for (int p = F.FirstPatch; p < F.FirstPatch + F.PatchCount; ++p)
    {
      const std::array<double, 4>& pd = m.Patches[static_cast<size_t>(p)].Domain;
      if (u >= pd[0] && u <= pd[1] && v >= pd[2] && v <= pd[3])
        patch = p;
    }
    return EvaluatePatch(m.Patches[static_cast<size_t>(patch)], u, v).P;
  };
  // The segment that ends at the concave corner (1, 1, 2), and the bridge after it.
  TrimLoop& loop = m.Loops[static_cast<size_t>(loopIndex)];
  int corner = -1;
  for (int k = loop.FirstSegment; k < loop.FirstSegment + loop.SegmentCount; ++k)
  {
    const auto& c = m.TrimSegments[static_cast<size_t>(k)].ControlPoints;
    const auto p = at(c[6], c[7]);
    if (std::hypot(p[0] - 10.0, p[1] - 10.0) < 1e-9)
      corner = k;
  }
  ASSERT_GE(corner, 0);
  const int next = corner + 1 < loop.FirstSegment + loop.SegmentCount ? corner + 1 : loop.FirstSegment;
  TrimSegment bridge = m.TrimSegments[static_cast<size_t>(corner)];
  {
    const auto& c = bridge.ControlPoints;
    const double du = c[6] - c[0], dv = c[7] - c[1], len = std::hypot(du, dv);
    const double eu = c[6], ev = c[7], bu = eu - 4e-4 * du / len, bv = ev - 4e-4 * dv / len;
    for (int k = 0; k < 4; ++k)
    {
      bridge.ControlPoints[2 * k] = eu + (bu - eu) * k / 3.0;
      bridge.ControlPoints[2 * k + 1] = ev + (bv - ev) * k / 3.0;
    }
    bridge.T0 = bridge.T1;
    TrimSegment& n = m.TrimSegments[static_cast<size_t>(next)];
    const double nu = n.ControlPoints[6], nv = n.ControlPoints[7];
    for (int k = 0; k < 4; ++k)
    {
      n.ControlPoints[2 * k] = bu + (nu - bu) * k / 3.0;
      n.ControlPoints[2 * k + 1] = bv + (nv - bv) * k / 3.0;
    }
  }
  m.TrimSegments.insert(m.TrimSegments.begin() + corner + 1, bridge);
  loop.SegmentCount += 1;
  for (TrimLoop& l : m.Loops)
    if (l.FirstSegment > corner && &l != &loop)
      l.FirstSegment += 1;
  const SolverData data = PrepareSolver(m, SolverOptions());
  const NativeSolver native(m, data);
  size_t checked = 0, nearCorner = 0, wrongHost = 0, wrongKernel = 0;
  const int n = 120;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j)
    {
      const double u = F.Domain[0] - 1.0 + (F.Domain[1] - F.Domain[0] + 2.0) * (i + 0.37) / n;
      const double v = F.Domain[2] - 1.0 + (F.Domain[3] - F.Domain[2] + 2.0) * (j + 0.61) / n;
      const TrimProjection host = ClassifyPoint(m, face, u, v);
      if (!(host.Distance >= 0.5))
        continue; // 1,000 times the sliver's length or more
      const auto p = at(u, v); // a plane's patch continues the plane past its domain
      const bool expected = InPolygon(shape, p[0], p[1]);
      bool inside = false;
      int segment = -1;
      double parameter = 0.0, distance = 0.0;
      native.Classify(face, u, v, inside, segment, parameter, distance);
      ++checked;
      nearCorner += std::hypot(p[0] - 10.0, p[1] - 10.0) < 6.0;
      if (host.Inside != expected && ++wrongHost <= 5)
        ADD_FAILURE() << "ClassifyPoint at (" << p[0] << ", " << p[1] << "): " << host.Inside;
      if (inside != expected && ++wrongKernel <= 5)
        ADD_FAILURE() << "kernel classify at (" << p[0] << ", " << p[1] << "): " << inside;
    }
  std::printf("[trim] sliver at a corner: %zu points (%zu within 6 of the corner), %zu and %zu "
              "misjudged (reader, kernel)\n",
    checked, nearCorner, wrongHost, wrongKernel);
  EXPECT_GT(nearCorner, 100u);
  EXPECT_EQ(wrongHost, 0u);
  EXPECT_EQ(wrongKernel, 0u);
}

} // namespace

// ClassifyPoint skips segments whose control box is farther than the best distance so far; the
// nearest segment (ties to the lowest index) must be the one a projection on every segment
// finds. Random points over every face's domain of a real part, inside and outside its trims.
TEST(TrimClassifier, BoxCullingFindsTheNearestSegment)
{
  const BRepModel m =
    ConvertStepFile(test::DataFile("ExpansionCard_SelfTapping.stp"), ConversionOptions());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-0.1, 1.1);
  size_t points = 0, mismatches = 0;
  for (int f = 0; f < static_cast<int>(m.Faces.size()); ++f)
  {
    const Face& F = m.Faces[f];
    for (int k = 0; k < 40 && F.LoopCount > 0; ++k)
    {
      const double u = F.Domain[0] + unit(rng) * (F.Domain[1] - F.Domain[0]);
      const double v = F.Domain[2] + unit(rng) * (F.Domain[3] - F.Domain[2]);
      double best = std::numeric_limits<double>::max();
      int bestSeg = -1;
      for (int l = F.FirstLoop; l < F.FirstLoop + F.LoopCount; ++l)
        for (int s = m.Loops[l].FirstSegment;
             s < m.Loops[l].FirstSegment + m.Loops[l].SegmentCount; ++s)
        {
          const auto& cp = m.TrimSegments[s].ControlPoints;
          if (cp[0] == cp[6] && cp[1] == cp[7] && cp[0] == cp[2] && cp[1] == cp[3] &&
            cp[0] == cp[4] && cp[1] == cp[5])
            continue; // zero length: ClassifyPoint skips it too
          double d = 0.0;
          ProjectOnSegment(cp, u, v, &d);
          if (d < best)
          {
            best = d;
            bestSeg = s;
          }
        }
      const TrimProjection p = ClassifyPoint(m, f, u, v);
      ++points;
      if (p.Segment != bestSeg || p.Distance != best)
      {
        ++mismatches;
        ADD_FAILURE() << "face " << f << " (" << u << ", " << v << "): segment " << p.Segment
                      << " at " << p.Distance << ", brute force " << bestSeg << " at " << best;
      }
    }
  }
  EXPECT_GT(points, 1000u);
  EXPECT_EQ(mismatches, 0u);
}

/// Whether the kernel walks a segment tree on F: more than 8 trimming segments in its loops
/// (brt::PackTrimTrees).
static bool HasSegmentTree(const BRepModel& m, const Face& F)
{
  int segments = 0;
  for (int l = F.FirstLoop; l < F.FirstLoop + F.LoopCount; ++l)
    segments += m.Loops[l].SegmentCount;
  return segments > 8;
}

// The kernel's trim test walks a tree over the segments of a face with more than 8 of them
// (brt::PackTrimTrees); it must find what the reader's ClassifyPoint (a scan of every segment,
// checked against brute force above) finds: the same nearest segment, parameter, distance and
// side (the side but at a cusp, where the kernel takes the crossing parity). Random points over
// every such face's domain of the FRAMEWORK tile (faces of up to 178 segments), inside and
// outside its trims.
// Whether the corner ClassifyPoint decided by the corner rule (its nearest point at an end of
// host.Segment) has tangents within 1e-3 rad of each other or of opposite: the segment's end
// tangent and the neighbouring segment's (along the loop, past zero-length ones), from their
// control points.
static bool CornerIsNearlyStraightOrCusp(const BRepModel& m, const TrimProjection& host)
{
  const TrimSegment& seg = m.TrimSegments[static_cast<size_t>(host.Segment)];
  const TrimLoop& loop = m.Loops[static_cast<size_t>(seg.Loop)];
  const bool atEnd = host.Parameter > 0.5;
  auto tangent = [](const std::array<double, 8>& c, bool end) {
    // The first non-zero difference of control points from that end.
    for (int k = 0; k < 3; ++k)
    {
      const int a = end ? 6 - 2 * (k + 1) : 0, b = end ? 6 : 2 * (k + 1);
      const double du = c[b] - c[a], dv = c[b + 1] - c[a + 1];
      if (du != 0.0 || dv != 0.0)
        return std::array<double, 2>{ du, dv };
    }
    return std::array<double, 2>{ 0.0, 0.0 };
  };
  const int n = loop.SegmentCount, at = host.Segment - loop.FirstSegment;
  std::array<double, 2> other{ 0.0, 0.0 };
  for (int k = 1; k < n && other[0] == 0.0 && other[1] == 0.0; ++k)
  {
    const int j = loop.FirstSegment + ((at + (atEnd ? k : -k)) % n + n) % n;
    other = tangent(m.TrimSegments[static_cast<size_t>(j)].ControlPoints, !atEnd);
  }
  const std::array<double, 2> own = tangent(seg.ControlPoints, atEnd);
  const double la = std::hypot(own[0], own[1]), lb = std::hypot(other[0], other[1]);
  return la > 0.0 && lb > 0.0 && std::fabs(own[0] * other[1] - own[1] * other[0]) < 1e-3 * la * lb;
}

TEST(TrimClassifier, KernelSegmentTreeFindsWhatTheScanFinds)
{
  const BRepModel m =
    ConvertStepFile(test::DataFile("FRAMEWORK_DESKTOP_BLANK_TILE.stp"), ConversionOptions());
  const SolverData data = PrepareSolver(m, SolverOptions());
  const NativeSolver native(m, data);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(-0.1, 1.1);
  size_t faces = 0, points = 0, mismatches = 0, cusps = 0;
  for (int f = 0; f < static_cast<int>(m.Faces.size()); ++f)
  {
    const Face& F = m.Faces[f];
    if (!HasSegmentTree(m, F))
      continue;
    ++faces;
    for (int k = 0; k < 60; ++k)
    {
      const double u = F.Domain[0] + unit(rng) * (F.Domain[1] - F.Domain[0]);
      const double v = F.Domain[2] + unit(rng) * (F.Domain[3] - F.Domain[2]);
      const TrimProjection host = ClassifyPoint(m, f, u, v);
      bool inside = false;
      int segment = -1;
      double parameter = 0.0, distance = 0.0;
      native.Classify(f, u, v, inside, segment, parameter, distance);
      ++points;
      // Where the two tangents at a corner lie within a thousandth of a radian of each other or
      // of opposite, both take the crossing parity instead of the corner rule (a cusp,
      // docs/Solver.md, Open items, "The corner rule at a cusp").
      if (host.Corner && CornerIsNearlyStraightOrCusp(m, host))
      {
        ++cusps;
        EXPECT_EQ(host.Inside, InsideByCrossings(m, f, u, v))
          << "face " << f << " (" << u << ", " << v << ")";
      }
      if (segment != host.Segment || inside != host.Inside ||
        std::fabs(distance - host.Distance) > 1e-12 * (1.0 + host.Distance) ||
        std::fabs(parameter - host.Parameter) > 1e-9)
      {
        ++mismatches;
        ADD_FAILURE() << "face " << f << " (" << u << ", " << v << "): kernel segment " << segment
                      << " at " << distance << " (t " << parameter << ", inside " << inside
                      << "), ClassifyPoint " << host.Segment << " at " << host.Distance << " (t "
                      << host.Parameter << ", inside " << host.Inside << ")";
      }
    }
  }
  EXPECT_GT(faces, 50u);
  EXPECT_EQ(mismatches, 0u);
  std::printf("[kernel trim tree] %zu faces, %zu points, %zu decided by the crossing parity\n",
    faces, points, cusps);
}

// The kernel's even-odd test (the second opinion far from the loops) counts, on a face with a
// segment tree, only the segments whose boxes the ray in +u meets; it must give the reader's
// InsideByCrossings (every segment's chords) on random points over every such face of the
// FRAMEWORK tile and the ExpansionCard, and on points placed on the ray through a segment's
// end, where a chord's end lies on the ray. So must the preparation's CrossingIndex (the
// segments listed in bands of v) on every face, and at the ends of its segments' boxes in v
// (its bands' edges).
TEST(TrimClassifier, KernelCrossingsThroughTheTreeGiveTheScansAnswer)
{
  size_t faces = 0, points = 0, mismatches = 0, inside = 0, indexPoints = 0, indexMismatches = 0;
  for (const char* name : { "FRAMEWORK_DESKTOP_BLANK_TILE.stp", "ExpansionCard_SelfTapping.stp" })
  {
    const BRepModel m = ConvertStepFile(test::DataFile(name), ConversionOptions());
    const SolverData data = PrepareSolver(m, SolverOptions());
    const NativeSolver native(m, data);
    const CrossingIndex index(m);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> unit(-0.1, 1.1);
    for (int f = 0; f < static_cast<int>(m.Faces.size()); ++f)
    {
      const Face& F = m.Faces[f];
      for (int k = 0; k < 40 && F.LoopCount > 0; ++k)
      {
        const double u = F.Domain[0] + unit(rng) * (F.Domain[1] - F.Domain[0]);
        double v = F.Domain[2] + unit(rng) * (F.Domain[3] - F.Domain[2]);
        if (k % 2 == 0)
        {
          // The lowest or highest control point in v of one of the face's segments.
          const TrimLoop& L = m.Loops[F.FirstLoop];
          const auto& cp = m.TrimSegments[L.FirstSegment + k % L.SegmentCount].ControlPoints;
          v = cp[1];
          for (int i = 1; i < 4; ++i)
            v = k % 4 == 0 ? std::min(v, cp[2 * i + 1]) : std::max(v, cp[2 * i + 1]);
        }
        ++indexPoints;
        const bool scan = InsideByCrossings(m, f, u, v);
        if (index.Inside(f, u, v) != scan)
        {
          ++indexMismatches;
          ADD_FAILURE() << name << " face " << f << " (" << u << ", " << v
                        << "): CrossingIndex " << !scan << ", InsideByCrossings " << scan;
        }
      }
      if (!HasSegmentTree(m, F))
        continue;
      ++faces;
      for (int k = 0; k < 80; ++k)
      {
        double u = F.Domain[0] + unit(rng) * (F.Domain[1] - F.Domain[0]);
        double v = F.Domain[2] + unit(rng) * (F.Domain[3] - F.Domain[2]);
        if (k % 4 == 0)
        {
          // v of a segment's first control point (on the loop), u anywhere.
          const TrimLoop& L = m.Loops[F.FirstLoop];
          v = m.TrimSegments[L.FirstSegment + k % L.SegmentCount].ControlPoints[1];
        }
        const bool host = InsideByCrossings(m, f, u, v);
        const bool kernel = native.InsideByCrossings(f, u, v);
        ++points;
        inside += host ? 1 : 0;
        if (host != kernel)
        {
          ++mismatches;
          ADD_FAILURE() << name << " face " << f << " (" << u << ", " << v << "): kernel "
                        << kernel << ", InsideByCrossings " << host;
        }
      }
    }
  }
  std::printf("crossings: %zu faces with a tree, %zu points (%zu inside), %zu disagree; "
              "CrossingIndex %zu points, %zu disagree\n",
    faces, points, inside, mismatches, indexPoints, indexMismatches);
  EXPECT_GT(faces, 60u);
  EXPECT_GT(inside, points / 10);
  EXPECT_EQ(mismatches, 0u);
  EXPECT_GT(indexPoints, 10000u);
  EXPECT_EQ(indexMismatches, 0u);
}

// The preparation classifies s1's grid points among the segments that can be nearest to some
// point of their patch's domain or of a block of it (TrimCandidatesFor): the answer must be
// ClassifyPoint's over every segment, exactly. Boxes of every size over every face of the
// FRAMEWORK tile (faces of up to 178 segments), boxes within boxes as the preparation takes
// them, and random points inside each, its corners among them.
TEST(TrimClassifier, CandidatesOfABoxGiveTheScansAnswer)
{
  const BRepModel m =
    ConvertStepFile(test::DataFile("FRAMEWORK_DESKTOP_BLANK_TILE.stp"), ConversionOptions());
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  size_t points = 0, mismatches = 0, segments = 0, kept = 0;
  auto check = [&](int f, const std::array<double, 4>& box,
                 const std::vector<TrimCandidate>& near) {
    for (int k = 0; k < 12; ++k)
    {
      const double u = k < 4 ? box[(k & 1) ? 2 : 0] : box[0] + unit(rng) * (box[2] - box[0]);
      const double v = k < 4 ? box[(k & 2) ? 3 : 1] : box[1] + unit(rng) * (box[3] - box[1]);
      const TrimProjection all = ClassifyPoint(m, f, u, v);
      const TrimProjection among = ClassifyPointAmong(m, u, v, near);
      ++points;
      if (all.Segment != among.Segment || all.Inside != among.Inside ||
        all.Distance != among.Distance || all.Parameter != among.Parameter ||
        all.Corner != among.Corner)
      {
        ++mismatches;
        ADD_FAILURE() << "face " << f << " (" << u << ", " << v << "): among " << near.size()
                      << " candidates segment " << among.Segment << " at " << among.Distance
                      << ", over all " << all.Segment << " at " << all.Distance;
      }
    }
  };
  for (int f = 0; f < static_cast<int>(m.Faces.size()); ++f)
  {
    const Face& F = m.Faces[f];
    if (F.LoopCount <= 0)
      continue;
    int count = 0;
    for (int l = F.FirstLoop; l < F.FirstLoop + F.LoopCount; ++l)
      count += m.Loops[l].SegmentCount;
    const double wu = F.Domain[1] - F.Domain[0], wv = F.Domain[3] - F.Domain[2];
    for (int k = 0; k < 8; ++k)
    {
      // Boxes from the whole domain (and beyond it) down to a thousandth of it.
      const double size = std::pow(10.0, -3.0 * unit(rng));
      const double u0 = F.Domain[0] + (unit(rng) * 1.1 - 0.05) * wu;
      const double v0 = F.Domain[2] + (unit(rng) * 1.1 - 0.05) * wv;
      const std::array<double, 4> box{ u0, v0, u0 + size * wu, v0 + size * wv };
      const std::vector<TrimCandidate> near = TrimCandidatesFor(m, f, box);
      segments += static_cast<size_t>(count);
      kept += near.size();
      check(f, box, near);
      // A block of it, among the box's candidates.
      const std::array<double, 4> inner{ box[0] + 0.25 * (box[2] - box[0]),
        box[1] + 0.5 * (box[3] - box[1]), box[0] + 0.5 * (box[2] - box[0]),
        box[1] + 0.625 * (box[3] - box[1]) };
      check(f, inner, TrimCandidatesFor(m, near, inner));
    }
  }
  std::printf("FRAMEWORK tile: %zu points, candidates %.1f%% of the faces' segments\n", points,
    100.0 * static_cast<double>(kept) / static_cast<double>(segments));
  EXPECT_GT(points, 5000u);
  EXPECT_EQ(mismatches, 0u);
  EXPECT_LT(kept, segments / 2); // the candidates are a real cut, not every segment
}
