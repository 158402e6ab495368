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

} // namespace
