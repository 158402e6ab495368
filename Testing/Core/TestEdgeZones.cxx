// Edge zones (docs/Solver.md, "Edge zones") against their closed form on the analytic solids: next
// to a convex right-angled edge of a wall of thickness h, the maximal sphere at a sample x away
// from the edge has radius x and touches the other face of the edge (contact angle 90 degrees)
// while x < h / 2; farther away it touches the opposite wall (contact angle 180). So a sample is
// in an edge zone exactly when its distance to the nearest convex edge is below h / 2.
#include "AnalyticShapes.h"
#include "SolverTestHelpers.h"
#include "Statistics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>

namespace
{
using namespace brt;

std::array<double, 3> Bezier(const std::array<double, 12>& c, double s)
{
  const double b[4] = { (1 - s) * (1 - s) * (1 - s), 3 * s * (1 - s) * (1 - s), 3 * s * s * (1 - s),
    s * s * s };
  std::array<double, 3> p{};
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 3; ++k)
      p[k] += b[i] * c[3 * i + k];
  return p;
}

/// Distance from each sample to the nearest edge that `convex` accepts (edges sampled finely).
std::vector<double> EdgeDistances(const BRepModel& m, const std::vector<Sample>& samples,
  const std::function<bool(const std::array<double, 3>&, const std::array<double, 3>&)>& convex)
{
  std::vector<std::array<double, 3>> points;
  for (const Edge& e : m.Edges)
  {
    if (e.Seam || e.SegmentCount == 0)
      continue;
    const auto& first = m.EdgeSegments[e.FirstSegment].ControlPoints;
    const auto& last = m.EdgeSegments[e.FirstSegment + e.SegmentCount - 1].ControlPoints;
    if (!convex(Bezier(first, 0.0), Bezier(last, 1.0)))
      continue;
    for (int s = e.FirstSegment; s < e.FirstSegment + e.SegmentCount; ++s)
      for (int j = 0; j <= 400; ++j)
        points.push_back(Bezier(m.EdgeSegments[s].ControlPoints, j / 400.0));
  }
  std::vector<double> out(samples.size(), std::numeric_limits<double>::infinity());
  for (size_t i = 0; i < samples.size(); ++i)
    for (const auto& p : points)
    {
      const double dx = p[0] - samples[i].Point[0], dy = p[1] - samples[i].Point[1],
                   dz = p[2] - samples[i].Point[2];
      out[i] = std::min(out[i], std::sqrt(dx * dx + dy * dy + dz * dz));
    }
  return out;
}

struct Band
{
  size_t Checked = 0, Inside = 0, Wrong = 0, Failed = 0;
};

/// Checks every sample that `use` accepts: edge zone <=> distance < h / 2, samples within
/// `margin` of the band's border left out (there the sphere touches both: a tie).
Band CheckBand(const char* name, const test::Solved& s, const std::vector<double>& distance,
  double h, double margin, const std::function<bool(const Sample&)>& use)
{
  Band b;
  for (size_t i = 0; i < s.Samples.size(); ++i)
  {
    if (!use(s.Samples[i]) || std::fabs(distance[i] - h / 2) < margin)
      continue;
    const SampleResult& r = s.Results[i];
    if (r.Type == ContactType::Failed)
    {
      ++b.Failed;
      continue;
    }
    ++b.Checked;
    const bool expected = distance[i] < h / 2;
    const bool zone = IsEdgeZone(s.Samples[i].Point.data(), r);
    b.Inside += zone ? 1 : 0;
    if (zone != expected)
    {
      if (b.Wrong < 5)
        std::printf("[edge zones] %s: sample %zu at (%.4f, %.4f, %.4f), %.4f from a convex edge: "
                    "contact angle %.2f, 2t %.6f, %s\n",
          name, i, s.Samples[i].Point[0], s.Samples[i].Point[1], s.Samples[i].Point[2],
          distance[i], ContactAngle(s.Samples[i].Point.data(), r), r.Thickness,
          zone ? "edge zone, expected none" : "no edge zone, expected one");
      ++b.Wrong;
    }
  }
  std::printf("[edge zones] %s: %zu samples checked, %zu in edge zones, %zu wrong, %zu failed\n",
    name, b.Checked, b.Inside, b.Wrong, b.Failed);
  return b;
}

TEST(EdgeZones, HolePlateBandIsHalfTheThickness)
{
  // 80 x 80 x 6 with a hole of radius 10: every edge is convex and right-angled (the hole's
  // circles included), so the band is 3 wide along all of them; the side faces and the hole's
  // wall, 6 high, lie entirely within 3 of an edge.
  const test::Solved s = test::SolveShape(analytic::HolePlate(80, 6, 10), 1e-4);
  const auto distance = EdgeDistances(s.Model, s.Samples, [](auto&, auto&) { return true; });
  const Band b = CheckBand("hole plate", s, distance, 6.0, 0.02, [](const Sample&) { return true; });
  EXPECT_GT(b.Checked, s.Samples.size() * 9 / 10);
  EXPECT_GT(b.Inside, 0u);
  EXPECT_EQ(b.Wrong, 0u);
}

TEST(EdgeZones, LBracketBandAndNoneAtTheFilletedInnerCorner)
{
  // Profile (0,0) (60,0) (60,8) (8,8) (8,60) (0,60), 40 deep, inner corner filleted with r = 5:
  // the fillet's two tangent edges (x = 13 or y = 13 at the inner faces) are smooth, every other
  // edge convex and right-angled. The outer corner block (x, y < 2h + r) is left out: there the
  // sphere is bounded by the two outer faces and the fillet together, no closed form.
  const double h = 8, r = 5, corner = 2 * h + r;
  const test::Solved s = test::SolveShape(analytic::LBracket(60, h, 40, r), 1e-4);
  const auto smooth = [&](const std::array<double, 3>& a, const std::array<double, 3>& b) {
    const bool vertical = std::fabs(a[0] - b[0]) < 1e-6 && std::fabs(a[1] - b[1]) < 1e-6;
    return vertical && ((std::fabs(a[0] - (h + r)) < 1e-6 && std::fabs(a[1] - h) < 1e-6) ||
                         (std::fabs(a[0] - h) < 1e-6 && std::fabs(a[1] - (h + r)) < 1e-6));
  };
  const auto distance =
    EdgeDistances(s.Model, s.Samples, [&](auto& a, auto& b) { return !smooth(a, b); });
  const Band b = CheckBand("L-bracket", s, distance, h, 0.02,
    [&](const Sample& p) { return p.Point[0] > corner || p.Point[1] > corner; });
  EXPECT_GT(b.Checked, s.Samples.size() / 2);
  EXPECT_GT(b.Inside, 0u);
  EXPECT_EQ(b.Wrong, 0u);
  // The filleted inner corner is concave: its samples (on the fillet, away from the caps) span
  // the wall to the outer faces and are never edge zones.
  size_t fillet = 0, zones = 0;
  for (size_t i = 0; i < s.Samples.size(); ++i)
  {
    const auto& p = s.Samples[i].Point;
    const double dx = p[0] - (h + r), dy = p[1] - (h + r);
    if (p[0] < h + r && p[1] < h + r && std::fabs(std::sqrt(dx * dx + dy * dy) - r) < 1e-3 &&
      p[2] > h && p[2] < 40 - h && s.Results[i].Type != ContactType::Failed)
    {
      ++fillet;
      zones += IsEdgeZone(p.data(), s.Results[i]) ? 1 : 0;
    }
  }
  std::printf("[edge zones] L-bracket fillet: %zu samples, %zu in edge zones\n", fillet, zones);
  EXPECT_GT(fillet, 10u);
  EXPECT_EQ(zones, 0u);
}

TEST(EdgeZones, ContactAngleAndCornerAngle)
{
  // Sphere of radius 1 centred at the origin, sample O at the top.
  SampleResult r;
  r.Type = ContactType::SurfaceSurface;
  r.Radius = 1;
  r.Thickness = 2;
  const double O[3] = { 0, 0, 1 };
  r.Foot = { 0, 0, -1 }; // a wall: the contact opposite O
  EXPECT_NEAR(ContactAngle(O, r), 180.0, 1e-9);
  EXPECT_FALSE(IsEdgeZone(O, r));
  r.Foot = { 1, 0, 0 }; // a right-angled corner
  EXPECT_NEAR(ContactAngle(O, r), 90.0, 1e-9);
  EXPECT_TRUE(IsEdgeZone(O, r));
  // A wedge of material angle a puts the contact at 180 - a: 40 degrees is a knife edge (thin
  // material) at the default corner angle of 60, 80 degrees a corner.
  for (double a : { 40.0, 80.0 })
  {
    const double phi = (180.0 - a) * 3.14159265358979323846 / 180.0;
    r.Foot = { std::sin(phi), 0, std::cos(phi) };
    EXPECT_NEAR(ContactAngle(O, r), 180.0 - a, 1e-9);
    EXPECT_EQ(IsEdgeZone(O, r), a >= 60.0) << a;
    EXPECT_TRUE(IsEdgeZone(O, r, 30.0)) << a;
  }
  SampleResult failed;
  EXPECT_TRUE(std::isnan(ContactAngle(O, failed)));
  EXPECT_FALSE(IsEdgeZone(O, failed));
}
} // namespace
