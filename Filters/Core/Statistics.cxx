#include "Statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace brt
{

std::vector<double> VertexAreas(const std::vector<double>& points, const std::vector<int>& triangles)
{
  std::vector<double> area(points.size() / 3, 0.0);
  for (size_t t = 0; t + 2 < triangles.size(); t += 3)
  {
    const double* p[3];
    for (int k = 0; k < 3; ++k)
      p[k] = &points[3 * static_cast<size_t>(triangles[t + k])];
    const double a[3] = { p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2] };
    const double b[3] = { p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2] };
    const double c[3] = { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
      a[0] * b[1] - a[1] * b[0] };
    const double third = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) / 6.0;
    for (int k = 0; k < 3; ++k)
      area[triangles[t + k]] += third;
  }
  return area;
}

double ThicknessStatistics::Mean() const
{
  return Sums[SolvedArea] > 0.0 ? Sums[AreaThickness] / Sums[SolvedArea]
                                : std::numeric_limits<double>::quiet_NaN();
}

void ThicknessStatistics::Combine(const ThicknessStatistics& other)
{
  for (size_t k = 0; k < Sums.size(); ++k)
    Sums[k] += other.Sums[k];
  for (size_t k = 0; k < ResidualHistogram.size(); ++k)
    ResidualHistogram[k] += other.ResidualHistogram[k];
  Min = std::min(Min, other.Min);
  Max = std::max(Max, other.Max);
}

ThicknessStatistics Accumulate(const std::vector<SampleResult>& results,
  const std::vector<double>& area, double minimum, double maximum)
{
  using S = ThicknessStatistics;
  S s;
  s.Sums[S::SolvingProcesses] = results.empty() ? 0.0 : 1.0;
  for (size_t i = 0; i < results.size(); ++i)
  {
    const SampleResult& r = results[i];
    s.Sums[S::Samples] += 1;
    s.Sums[S::TotalArea] += area[i];
    s.Sums[S::PerType + static_cast<int>(r.Type)] += 1;
    if (r.Type == ContactType::Failed)
    {
      s.Sums[S::PerReason + static_cast<int>(r.Reason)] += 1;
      continue;
    }
    s.Sums[S::SolvedArea] += area[i];
    s.Sums[S::AreaThickness] += area[i] * r.Thickness;
    if (minimum > 0.0 && r.Thickness < minimum)
      s.Sums[S::AreaBelow] += area[i];
    if (maximum > 0.0 && r.Thickness > maximum)
      s.Sums[S::AreaAbove] += area[i];
    s.Min = std::min(s.Min, r.Thickness);
    s.Max = std::max(s.Max, r.Thickness);
    const double l = r.Residual > 0.0 ? std::log10(r.Residual) : S::ResidualLow;
    const int bin = std::clamp(static_cast<int>(std::floor((l - S::ResidualLow) /
                                 (S::ResidualHigh - S::ResidualLow) * S::ResidualBins)),
      0, S::ResidualBins - 1);
    s.ResidualHistogram[static_cast<int>(r.Type) * S::ResidualBins + bin] += 1;
  }
  return s;
}

std::vector<double> AreaHistogram(const std::vector<SampleResult>& results,
  const std::vector<double>& area, int bins, double top)
{
  std::vector<double> hist(static_cast<size_t>(std::max(bins, 0)), 0.0);
  if (bins <= 0 || !(top > 0.0))
    return hist;
  for (size_t i = 0; i < results.size(); ++i)
    if (results[i].Type != ContactType::Failed)
      hist[std::clamp(static_cast<int>(results[i].Thickness / top * bins), 0, bins - 1)] += area[i];
  return hist;
}

} // namespace brt
