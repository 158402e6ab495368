// The thickness-map statistics behind the filter's Summary and Residuals ports, on hand-made
// results whose sums are known.
#include "Statistics.h"

#include <gtest/gtest.h>

#include <cmath>

namespace
{
using namespace brt;
using S = ThicknessStatistics;

SampleResult Solved(ContactType type, double thickness, double residual)
{
  SampleResult r;
  r.Type = type;
  r.Thickness = thickness;
  r.Radius = thickness / 2;
  r.Residual = residual;
  return r;
}

SampleResult Failed(FailReason reason)
{
  SampleResult r;
  r.Reason = reason;
  return r;
}

TEST(Statistics, VertexAreasShareEachTriangleInThirds)
{
  // Unit square as two triangles: the diagonal's ends touch both.
  const std::vector<double> points = { 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0 };
  const std::vector<double> area = VertexAreas(points, { 0, 1, 2, 0, 2, 3 });
  ASSERT_EQ(area.size(), 4u);
  EXPECT_DOUBLE_EQ(area[0], 1.0 / 3);
  EXPECT_DOUBLE_EQ(area[1], 1.0 / 6);
  EXPECT_DOUBLE_EQ(area[2], 1.0 / 3);
  EXPECT_DOUBLE_EQ(area[3], 1.0 / 6);
}

TEST(Statistics, SumsCountsLimitsAndHistograms)
{
  const std::vector<SampleResult> results = { Solved(ContactType::SurfaceSurface, 1.0, 1e-8),
    Solved(ContactType::SurfaceSurface, 3.0, 0.0), Failed(FailReason::NotMaximal),
    Solved(ContactType::SurfaceEdge, 2.0, 1e-3) };
  const std::vector<double> area = { 1.0, 3.0, 2.0, 2.0 };
  const S s = Accumulate(results, area, 1.5, 2.5);
  EXPECT_EQ(s.Sums[S::Samples], 4);
  EXPECT_EQ(s.Sums[S::TotalArea], 8);
  EXPECT_EQ(s.Sums[S::SolvedArea], 6);
  EXPECT_EQ(s.Sums[S::AreaThickness], 1 + 9 + 4);
  EXPECT_DOUBLE_EQ(s.Mean(), 14.0 / 6);
  EXPECT_EQ(s.Sums[S::AreaBelow], 1); // 2t = 1 < 1.5
  EXPECT_EQ(s.Sums[S::AreaAbove], 3); // 2t = 3 > 2.5
  EXPECT_EQ(s.Sums[S::SolvingProcesses], 1);
  EXPECT_EQ(s.Sums[S::PerType + 0], 1);
  EXPECT_EQ(s.Sums[S::PerType + 1], 2);
  EXPECT_EQ(s.Sums[S::PerType + 2], 1);
  EXPECT_EQ(s.Sums[S::PerType + 3], 0);
  EXPECT_EQ(s.Sums[S::PerReason + static_cast<int>(FailReason::NotMaximal)], 1);
  EXPECT_EQ(s.Min, 1.0);
  EXPECT_EQ(s.Max, 3.0);
  // log10 |R|: -8 is bin 32 of 64 over [-16, 0]; 0 goes to the first bin; -3 to bin 52.
  const auto bin = [&](ContactType t, int b) {
    return s.ResidualHistogram[static_cast<int>(t) * S::ResidualBins + b];
  };
  EXPECT_EQ(bin(ContactType::SurfaceSurface, 32), 1);
  EXPECT_EQ(bin(ContactType::SurfaceSurface, 0), 1);
  EXPECT_EQ(bin(ContactType::SurfaceEdge, 52), 1);
  double total = 0;
  for (double v : s.ResidualHistogram)
    total += v;
  EXPECT_EQ(total, 3); // the failed sample has no residual bin
  // Thickness bins over [0, 3]: 1 -> bin 1, 2 -> bin 2, 3 (the top) -> the last bin.
  EXPECT_EQ(AreaHistogram(results, area, 3, 3.0), (std::vector<double>{ 0.0, 1.0, 5.0 }));
  // Limits unset: no area below or above.
  const S u = Accumulate(results, area, 0.0, 0.0);
  EXPECT_EQ(u.Sums[S::AreaBelow], 0);
  EXPECT_EQ(u.Sums[S::AreaAbove], 0);
}

TEST(Statistics, PartsCombineToTheWhole)
{
  const std::vector<SampleResult> results = { Solved(ContactType::SurfaceSurface, 1.0, 1e-8),
    Solved(ContactType::SurfaceVertex, 0.5, 1e-12), Failed(FailReason::LeftModel),
    Solved(ContactType::SurfaceEdge, 2.0, 1e-3) };
  const std::vector<double> area = { 1.0, 0.5, 2.0, 2.0 };
  const S whole = Accumulate(results, area, 0.8, 1.5);
  S part = Accumulate({ results[0], results[1] }, { area[0], area[1] }, 0.8, 1.5);
  part.Combine(Accumulate({ results[2], results[3] }, { area[2], area[3] }, 0.8, 1.5));
  for (int k = 0; k < S::SumCount; ++k)
  {
    if (k == S::SolvingProcesses)
      continue;
    EXPECT_DOUBLE_EQ(part.Sums[k], whole.Sums[k]) << "sum " << k;
  }
  EXPECT_EQ(part.Sums[S::SolvingProcesses], 2);
  EXPECT_EQ(part.ResidualHistogram, whole.ResidualHistogram);
  EXPECT_EQ(part.Min, whole.Min);
  EXPECT_EQ(part.Max, whole.Max);
  // Nothing solved: no minimum, no mean, an empty histogram.
  const S none = Accumulate({ Failed(FailReason::NoOppositePoint) }, { 1.0 }, 0.0, 0.0);
  EXPECT_FALSE(none.AnySolved());
  EXPECT_TRUE(std::isnan(none.Mean()));
  EXPECT_EQ(AreaHistogram({}, {}, 4, 1.0), (std::vector<double>{ 0, 0, 0, 0 }));
}

TEST(Statistics, EdgeZonesClassesAndTheOption)
{
  // 2t = 0.5 (edge zone), 0.7 (thin wall), 2 (ok), 5 (thick), failed; limits 1 and 3.
  const std::vector<SampleResult> results = { Solved(ContactType::SurfaceSurface, 0.5, 0),
    Solved(ContactType::SurfaceSurface, 0.7, 0), Solved(ContactType::SurfaceEdge, 2.0, 0),
    Solved(ContactType::SurfaceSurface, 5.0, 0), Failed(FailReason::NotMaximal) };
  const std::vector<double> area = { 1.0, 2.0, 4.0, 8.0, 16.0 };
  const std::vector<unsigned char> zone = { 1, 0, 0, 0, 0 };
  const S off = Accumulate(results, area, 1.0, 3.0, &zone, false);
  EXPECT_EQ(off.Sums[S::EdgeZoneArea], 1);
  EXPECT_EQ(off.Sums[S::AreaBelow], 2); // the edge zone is not counted
  EXPECT_EQ(off.Sums[S::AreaBelowAll], 3);
  EXPECT_EQ(off.Sums[S::AreaBelowWalls], 2);
  EXPECT_EQ(off.Sums[S::AreaAbove], 8);
  EXPECT_EQ(off.Sums[S::ClassArea + static_cast<int>(SampleClass::EdgeZone)], 1);
  EXPECT_EQ(off.Sums[S::ClassArea + static_cast<int>(SampleClass::Thin)], 2);
  EXPECT_EQ(off.Sums[S::ClassArea + static_cast<int>(SampleClass::Ok)], 4);
  EXPECT_EQ(off.Sums[S::ClassArea + static_cast<int>(SampleClass::Thick)], 8);
  EXPECT_EQ(off.Sums[S::ClassArea + static_cast<int>(SampleClass::Failed)], 16);
  const S on = Accumulate(results, area, 1.0, 3.0, &zone, true);
  EXPECT_EQ(on.Sums[S::AreaBelow], 3);
  EXPECT_EQ(on.Sums[S::ClassArea + static_cast<int>(SampleClass::EdgeZone)], 0);
  EXPECT_EQ(on.Sums[S::ClassArea + static_cast<int>(SampleClass::Thin)], 3);
  EXPECT_EQ(Classify(results[0], true, 1.0, 3.0, false), SampleClass::EdgeZone);
  EXPECT_EQ(Classify(results[0], true, 1.0, 3.0, true), SampleClass::Thin);
  EXPECT_EQ(Classify(results[2], false, 0.0, 0.0, false), SampleClass::Ok);
  EXPECT_EQ(Classify(results[4], true, 1.0, 3.0, false), SampleClass::Failed);
}

TEST(Statistics, GroupsSumAndCombine)
{
  const std::vector<SampleResult> results = { Solved(ContactType::SurfaceSurface, 1.0, 0),
    Solved(ContactType::SurfaceSurface, 3.0, 0), Failed(FailReason::NotMaximal),
    Solved(ContactType::SurfaceEdge, 0.5, 0) };
  const std::vector<double> area = { 1.0, 3.0, 2.0, 2.0 };
  const std::vector<int> group = { 0, 0, 1, 1 };
  const std::vector<unsigned char> zone = { 0, 0, 0, 1 };
  using G = GroupStatistics;
  const G g = AccumulateGroups(results, area, group, 3, 2.0, &zone, false);
  EXPECT_EQ(g.Get(0, G::Samples), 2);
  EXPECT_DOUBLE_EQ(g.Mean(0), (1.0 + 9.0) / 4.0);
  EXPECT_EQ(g.Min[0], 1.0);
  EXPECT_EQ(g.Max[0], 3.0);
  EXPECT_EQ(g.Get(0, G::AreaBelow), 1);
  EXPECT_EQ(g.Get(1, G::Failed), 1);
  EXPECT_EQ(g.Get(1, G::TotalArea), 4);
  EXPECT_EQ(g.Get(1, G::AreaBelow), 0); // its thin sample is an edge zone
  EXPECT_EQ(g.Get(1, G::EdgeZoneArea), 2);
  EXPECT_TRUE(std::isnan(g.Mean(2)));
  G part = AccumulateGroups({ results[0], results[1] }, { area[0], area[1] }, { 0, 0 }, 3, 2.0);
  part.Combine(AccumulateGroups({ results[2], results[3] }, { area[2], area[3] }, { 1, 1 }, 3,
    2.0, nullptr, false));
  const G whole = AccumulateGroups(results, area, group, 3, 2.0);
  EXPECT_EQ(part.Sums, whole.Sums);
  EXPECT_EQ(part.Min, whole.Min);
  EXPECT_EQ(part.Max, whole.Max);
}

TEST(Statistics, GapValuesSharesAndCap)
{
  // Gaps 2 and 6, one infinite (no wall), one failed; areas 1, 2, 4, 8; minimum 3.
  const std::vector<SampleResult> results = { Solved(ContactType::SurfaceSurface, 2.0, 0),
    Solved(ContactType::SurfaceEdge, 6.0, 0), Failed(FailReason::NoOppositePoint),
    Failed(FailReason::NotMaximal) };
  const std::vector<unsigned char> infinite = { 0, 0, 1, 0 };
  const std::vector<double> area = { 1.0, 2.0, 4.0, 8.0 };
  using G = GapStatistics;
  const G g = AccumulateGap(results, infinite, area, 3.0, 0.0);
  EXPECT_EQ(g.Value[0], 2.0);
  EXPECT_EQ(g.Value[1], 6.0);
  EXPECT_TRUE(std::isinf(g.Value[2]) && g.Infinite[2] == 1);
  EXPECT_TRUE(std::isnan(g.Value[3]) && g.Infinite[3] == 0);
  EXPECT_EQ(g.Sums[G::AreaWithGap], 7);
  EXPECT_EQ(g.Sums[G::FiniteArea], 3);
  EXPECT_EQ(g.Sums[G::AreaGap], 2 + 12);
  EXPECT_EQ(g.Sums[G::InfiniteArea], 4);
  EXPECT_EQ(g.Sums[G::Failed], 1);
  EXPECT_EQ(g.Sums[G::AreaBelow], 1);
  EXPECT_EQ(g.Min, 2.0);
  EXPECT_EQ(g.Max, 6.0);
  // A cap of 5: the 6 mm gap counts as infinite.
  const G c = AccumulateGap(results, infinite, area, 3.0, 5.0);
  EXPECT_TRUE(std::isinf(c.Value[1]) && c.Infinite[1] == 1);
  EXPECT_EQ(c.Sums[G::InfiniteArea], 6);
  EXPECT_EQ(c.Max, 2.0);
}

} // namespace
