// The exterior gap (issue 16; docs/Solver.md, "Exterior gap"): the same solver with the outward
// normal and the sphere in the air (SolverOptions::Exterior), against closed forms on generated
// solids: the slot of a U-channel, the hole of the hole plate, two parallel plates as two solids
// (SolverOptions::AllSolids), and a plain plate whose gap is infinite everywhere.
#include "AnalyticShapes.h"
#include "BRepConverter.h"
#include "NativeSolver.h"
#include "OpenCLSolver.h"
#include "Solver.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>

namespace
{
using namespace brt;

struct GapRun
{
  BRepModel Model;
  SolverData Data;
  std::vector<Sample> Samples; ///< Direction: the outward normal
  std::vector<SampleResult> Results;
};

GapRun SolveGap(const TopoDS_Shape& shape, bool allSolids, OpenCLSolver* cl = nullptr)
{
  GapRun g;
  ConversionOptions conv;
  conv.Tolerance = 1e-6;
  g.Model = ConvertShape(shape, conv);
  SolverOptions options;
  options.Exterior = true;
  options.AllSolids = allSolids;
  g.Data = PrepareSolver(g.Model, options);
  g.Samples = SamplesFromMesh(g.Model, g.Data);
  for (Sample& s : g.Samples)
    ReverseSample(s);
  if (cl)
  {
    cl->Upload(g.Model, g.Data);
    cl->Solve(g.Model, g.Data, options, g.Samples, g.Results);
  }
  else
    NativeSolver(g.Model, g.Data).Solve(options, g.Samples, g.Results);
  return g;
}

/// Checks every sample: `expected` gives its gap (infinity: no wall faces it; 0: another solid
/// touches or overlaps it there; NaN: no closed form, left out). A finite gap must be solved
/// within `rel`; an infinite one must fail with NoOppositePoint (nothing in front of it) and never
/// carry a value; a zero one must be typed OtherSolid with gap 0.
void Check(const char* name, const GapRun& g, const std::function<double(const Sample&)>& expected,
  double rel)
{
  size_t finite = 0, infinite = 0, zero = 0, wrong = 0, skipped = 0;
  double worst = 0.0;
  for (size_t i = 0; i < g.Samples.size(); ++i)
  {
    const double e = expected(g.Samples[i]);
    const SampleResult& r = g.Results[i];
    if (std::isnan(e))
    {
      ++skipped;
      continue;
    }
    if (std::isinf(e))
    {
      ++infinite;
      const bool ok = r.Type == ContactType::Failed && r.Reason == FailReason::NoOppositePoint;
      if (!ok && wrong++ < 5)
        std::printf("[gap] %s: sample %zu at (%.4f, %.4f, %.4f) dir (%.3f, %.3f, %.3f): expected "
                    "infinite, got type %d reason %d gap %.9g\n",
          name, i, g.Samples[i].Point[0], g.Samples[i].Point[1], g.Samples[i].Point[2],
          g.Samples[i].Direction[0], g.Samples[i].Direction[1], g.Samples[i].Direction[2],
          static_cast<int>(r.Type), static_cast<int>(r.Reason), r.Thickness);
      continue;
    }
    if (e == 0.0)
    {
      ++zero;
      const bool ok = r.Type == ContactType::OtherSolid && r.Thickness == 0.0;
      if (!ok && wrong++ < 5)
        std::printf("[gap] %s: sample %zu at (%.4f, %.4f, %.4f) dir (%.3f, %.3f, %.3f): expected "
                    "0 on another solid, got type %d reason %d gap %.9g\n",
          name, i, g.Samples[i].Point[0], g.Samples[i].Point[1], g.Samples[i].Point[2],
          g.Samples[i].Direction[0], g.Samples[i].Direction[1], g.Samples[i].Direction[2],
          static_cast<int>(r.Type), static_cast<int>(r.Reason), r.Thickness);
      continue;
    }
    ++finite;
    const double err =
      r.Type == ContactType::Failed ? std::numeric_limits<double>::infinity() : std::fabs(r.Thickness - e) / e;
    worst = std::max(worst, err);
    if (!(err <= rel) && wrong++ < 5)
      std::printf("[gap] %s: sample %zu at (%.4f, %.4f, %.4f): gap %.9g (type %d reason %d), "
                  "expected %.9g\n",
        name, i, g.Samples[i].Point[0], g.Samples[i].Point[1], g.Samples[i].Point[2], r.Thickness,
        static_cast<int>(r.Type), static_cast<int>(r.Reason), e);
  }
  std::printf("[gap] %s: %zu samples: %zu with a finite closed form (max relative error %.2e), "
              "%zu infinite, %zu on another solid (0), %zu without a closed form left out, %zu "
              "wrong\n",
    name, g.Samples.size(), finite, worst, infinite, zero, skipped, wrong);
  EXPECT_EQ(wrong, 0u) << name;
  EXPECT_GT(finite + infinite + zero, 0u) << name;
}

TEST(Gap, UChannelSlotWidth)
{
  // 40 wide, 30 high, legs 5, floor 6, 80 long: the slot is 30 wide. On the legs' inner faces
  // higher than half the slot above the floor the gap is the slot's width; every outer face
  // faces nothing. The floor's top and the legs' lower parts are bounded by the concave corner
  // (the gap's own "edge zones"): no simple closed form there, left out.
  const double w = 40, h = 30, lt = 5, ft = 6, l = 80, slot = w - 2 * lt;
  const GapRun g = SolveGap(analytic::UChannel(w, h, lt, ft, l), false);
  const double inf = std::numeric_limits<double>::infinity(), nan = std::nan("");
  Check("U-channel 40 x 30, slot 30", g,
    [&](const Sample& s) {
      const auto& p = s.Point;
      const auto& d = s.Direction;
      const bool innerLeg = (std::fabs(p[0] - lt) < 1e-6 && d[0] > 0.99) ||
        (std::fabs(p[0] - (w - lt)) < 1e-6 && d[0] < -0.99);
      if (innerLeg)
        return p[2] > ft + slot / 2 + 0.05 ? slot : nan;
      const bool floorTop = std::fabs(p[2] - ft) < 1e-6 && d[2] > 0.99;
      if (floorTop)
        return nan;
      return inf; // outer faces, leg tops, ends
    },
    1e-6);
}

TEST(Gap, HoleDiameterAndInfiniteOutside)
{
  // 80 x 80 x 6 with a hole of radius 10: on the hole's wall the gap is the diameter (the sphere
  // spans the hole, its caps above and below the plate in the air); the outer faces face nothing.
  // Within 0.05 of the hole's rims the sphere grazes the rim circle, and the trim test's
  // tolerance band lets points of the top or bottom face up to ~6e-5 inside the circle count:
  // 3e-6 relative there, checked at 1e-5.
  const GapRun g = SolveGap(analytic::HolePlate(80, 6, 10), false);
  const double inf = std::numeric_limits<double>::infinity(), nan = std::nan("");
  const auto hole = [](const Sample& s) {
    return std::fabs(std::hypot(s.Point[0] - 40, s.Point[1] - 40) - 10) < 1e-3;
  };
  const auto rim = [](const Sample& s) { return s.Point[2] < 0.05 || s.Point[2] > 5.95; };
  Check("hole plate, hole r 10, away from the rims", g,
    [&](const Sample& s) { return hole(s) ? (rim(s) ? nan : 20.0) : inf; }, 1e-6);
  Check("hole plate, hole r 10, rims", g,
    [&](const Sample& s) { return hole(s) && rim(s) ? 20.0 : nan; }, 1e-5);
}

TEST(Gap, TwoPlatesAllSolidsAndSameSolid)
{
  // Two 60 x 40 x 4 plates 3 apart: with AllSolids the facing faces are 3 apart everywhere (the
  // sphere's sides stick out into the air at the rims); with the sample's own solid only, nothing
  // faces anything.
  const double inf = std::numeric_limits<double>::infinity();
  const auto facing = [&](const Sample& s) {
    const bool aTop = std::fabs(s.Point[2] - 4) < 1e-6 && s.Direction[2] > 0.99;
    const bool bBottom = std::fabs(s.Point[2] - 7) < 1e-6 && s.Direction[2] < -0.99;
    return aTop || bBottom ? 3.0 : inf;
  };
  Check("two plates, all solids", SolveGap(analytic::TwoPlates(60, 40, 4, 3), true), facing, 1e-9);
  Check("two plates, own solid", SolveGap(analytic::TwoPlates(60, 40, 4, 3), false),
    [&](const Sample&) { return inf; }, 0.0);
}

TEST(Gap, TouchingAndOverlappingSolidsAreZero)
{
  // Two 60 x 40 x 4 plates as two solids. Stacked (gap 0): with AllSolids the touching faces get
  // the gap 0 (ContactType::OtherSolid), every other face faces nothing. Overlapping by 1 (the
  // upper plate from z = 3 to 7): A's top and B's bottom lie inside the other plate (0); the side
  // faces between z = 3 and 4 lie on the other plate's coplanar side faces, facing the air
  // (infinite); the samples within 0.05 of the lines z = 3 and 4 on the sides are left out.
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto stacked = [&](const Sample& s) {
    return std::fabs(s.Point[2] - 4) < 1e-6 && std::fabs(s.Direction[2]) > 0.99 ? 0.0 : inf;
  };
  Check("stacked plates, all solids", SolveGap(analytic::TwoPlates(60, 40, 4, 0), true), stacked, 0.0);
  Check("stacked plates, own solid", SolveGap(analytic::TwoPlates(60, 40, 4, 0), false),
    [&](const Sample&) { return inf; }, 0.0);
  const auto overlapping = [&](const Sample& s) {
    const double z = s.Point[2];
    if (std::fabs(z - 3) < 0.05 || std::fabs(z - 4) < 0.05)
      return std::fabs(s.Direction[2]) > 0.99 ? 0.0 : nan; // the faces inside; rims left out
    return inf;
  };
  Check("overlapping plates, all solids", SolveGap(analytic::TwoPlates(60, 40, 4, -1), true),
    overlapping, 0.0);
}

TEST(Gap, PlainPlateIsInfiniteEverywhere)
{
  const GapRun g = SolveGap(analytic::Plate(100, 60, 5), false);
  Check("plate 100 x 60 x 5", g, [](const Sample&) { return std::numeric_limits<double>::infinity(); }, 0.0);
}
TEST(Gap, OpenCLFloatAgreesWithTheNativeDevice)
{
  // The same kernel source in float on an OpenCL device (PoCL here), finished in double: the
  // same samples face nothing, and the finite gaps agree with the native device's within 1e-6.
  if (OpenCLSolver::ListDevices().empty())
    GTEST_SKIP() << "no OpenCL device";
  OpenCLSolver cl("any", false);
  struct Case
  {
    const char* Name;
    TopoDS_Shape Shape;
    bool AllSolids;
  };
  const Case cases[] = { { "U-channel", analytic::UChannel(40, 30, 5, 6, 80), false },
    { "stacked plates, all solids", analytic::TwoPlates(60, 40, 4, 0), true } };
  for (const Case& c : cases)
  {
    const GapRun native = SolveGap(c.Shape, c.AllSolids);
    const GapRun device = SolveGap(c.Shape, c.AllSolids, &cl);
    ASSERT_EQ(native.Results.size(), device.Results.size());
    size_t differ = 0, finite = 0, zero = 0;
    double worst = 0.0;
    for (size_t i = 0; i < native.Results.size(); ++i)
    {
      const SampleResult &a = native.Results[i], &b = device.Results[i];
      const bool fa = a.Type != ContactType::Failed, fb = b.Type != ContactType::Failed;
      if (fa != fb || (!fa && a.Reason != b.Reason) ||
        (a.Type == ContactType::OtherSolid) != (b.Type == ContactType::OtherSolid))
      {
        ++differ;
        continue;
      }
      if (a.Type == ContactType::OtherSolid)
        ++zero;
      else if (fa)
      {
        ++finite;
        worst = std::max(worst, std::fabs(a.Thickness - b.Thickness) / a.Thickness);
      }
    }
    std::printf("[gap] %s on %s (float): %zu samples, %zu finite, %zu on another solid, %zu differ "
                "from the native device in kind, max relative difference %.2e\n",
      c.Name, cl.DeviceName().c_str(), native.Results.size(), finite, zero, differ, worst);
    EXPECT_EQ(differ, 0u) << c.Name;
    EXPECT_LE(worst, 1e-6) << c.Name;
  }
}
} // namespace
