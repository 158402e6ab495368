#include "Statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace brt
{

const char* SampleClassName(SampleClass c)
{
  switch (c)
  {
    case SampleClass::Failed:
      return "failed";
    case SampleClass::Thin:
      return "thin";
    case SampleClass::Ok:
      return "ok";
    case SampleClass::Thick:
      return "thick";
    case SampleClass::EdgeZone:
      return "edge zone";
  }
  return "?";
}

double ContactAngle(const double O[3], const SampleResult& r)
{
  if (r.Type == ContactType::Failed)
    return std::numeric_limits<double>::quiet_NaN();
  if (r.Type == ContactType::Osculating)
    return 0.0; // the sphere touches at O itself
  double a[3], b[3], aa = 0.0, bb = 0.0, ab = 0.0;
  for (int k = 0; k < 3; ++k)
  {
    a[k] = O[k] - r.Center[k];
    b[k] = r.Foot[k] - r.Center[k];
    aa += a[k] * a[k];
    bb += b[k] * b[k];
    ab += a[k] * b[k];
  }
  if (!(aa > 0.0) || !(bb > 0.0))
    return 0.0; // a sphere of radius 0, or the contact at the centre: a corner
  const double c = std::clamp(ab / std::sqrt(aa * bb), -1.0, 1.0);
  return std::acos(c) * (180.0 / 3.14159265358979323846);
}

bool IsEdgeZone(const double O[3], const SampleResult& r, double cornerAngle)
{
  const double angle = ContactAngle(O, r);
  return angle == angle && angle <= 180.0 - cornerAngle;
}

SampleClass Classify(const SampleResult& r, bool edgeZone, double minimum, double maximum,
  bool countEdgeZones)
{
  if (r.Type == ContactType::Failed)
    return SampleClass::Failed;
  if (edgeZone && !countEdgeZones)
    return SampleClass::EdgeZone;
  if (minimum > 0.0 && r.Thickness < minimum)
    return SampleClass::Thin;
  if (maximum > 0.0 && r.Thickness > maximum)
    return SampleClass::Thick;
  return SampleClass::Ok;
}

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
  const std::vector<double>& area, double minimum, double maximum,
  const std::vector<unsigned char>* edgeZone, bool countEdgeZones)
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
    const bool zone = edgeZone && (*edgeZone)[i] != 0;
    s.Sums[S::ClassArea +
      static_cast<int>(Classify(r, zone, minimum, maximum, countEdgeZones))] += area[i];
    if (r.Type == ContactType::Failed)
    {
      s.Sums[S::PerReason + static_cast<int>(r.Reason)] += 1;
      continue;
    }
    s.Sums[S::SolvedArea] += area[i];
    s.Sums[S::AreaThickness] += area[i] * r.Thickness;
    const bool below = minimum > 0.0 && r.Thickness < minimum;
    const bool above = maximum > 0.0 && r.Thickness > maximum;
    if (zone)
      s.Sums[S::EdgeZoneArea] += area[i];
    s.Sums[S::AreaBelowAll] += below ? area[i] : 0.0;
    s.Sums[S::AreaAboveAll] += above ? area[i] : 0.0;
    s.Sums[S::AreaBelowWalls] += below && !zone ? area[i] : 0.0;
    s.Sums[S::AreaAboveWalls] += above && !zone ? area[i] : 0.0;
    if (below && (countEdgeZones || !zone))
      s.Sums[S::AreaBelow] += area[i];
    if (above && (countEdgeZones || !zone))
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

GapStatistics AccumulateGap(const std::vector<SampleResult>& results,
  const std::vector<unsigned char>& infinite, const std::vector<double>& area, double minimum,
  double maximum)
{
  using G = GapStatistics;
  G s;
  const size_t n = results.size();
  s.Value.assign(n, std::numeric_limits<double>::quiet_NaN());
  s.Infinite.assign(n, 0);
  for (size_t i = 0; i < n; ++i)
  {
    const SampleResult& g = results[i];
    const bool solved = g.Type != ContactType::Failed;
    if ((i < infinite.size() && infinite[i]) || (solved && maximum > 0.0 && g.Thickness > maximum))
    {
      s.Infinite[i] = 1;
      s.Value[i] = std::numeric_limits<double>::infinity();
      s.Sums[G::AreaWithGap] += area[i];
      s.Sums[G::InfiniteArea] += area[i];
      continue;
    }
    if (!solved)
    {
      s.Sums[G::Failed] += 1.0;
      continue;
    }
    s.Value[i] = g.Thickness;
    if (g.Type == ContactType::OtherSolid)
      s.Sums[G::OtherSolidArea] += area[i];
    s.Sums[G::AreaWithGap] += area[i];
    s.Sums[G::FiniteArea] += area[i];
    s.Sums[G::AreaGap] += area[i] * g.Thickness;
    if (minimum > 0.0 && g.Thickness < minimum)
      s.Sums[G::AreaBelow] += area[i];
    s.Min = std::min(s.Min, g.Thickness);
    s.Max = std::max(s.Max, g.Thickness);
  }
  return s;
}

double GroupStatistics::Mean(int g) const
{
  const double a = Get(g, SolvedArea);
  return a > 0.0 ? Get(g, AreaThickness) / a : std::numeric_limits<double>::quiet_NaN();
}

void GroupStatistics::Combine(const GroupStatistics& other)
{
  for (size_t k = 0; k < Sums.size() && k < other.Sums.size(); ++k)
    Sums[k] += other.Sums[k];
  for (size_t g = 0; g < Min.size() && g < other.Min.size(); ++g)
  {
    Min[g] = std::min(Min[g], other.Min[g]);
    Max[g] = std::max(Max[g], other.Max[g]);
  }
}

GroupStatistics AccumulateGroups(const std::vector<SampleResult>& results,
  const std::vector<double>& area, const std::vector<int>& group, int groups, double minimum,
  const std::vector<unsigned char>* edgeZone, bool countEdgeZones)
{
  using G = GroupStatistics;
  G s;
  s.Groups = std::max(groups, 0);
  s.Sums.assign(static_cast<size_t>(s.Groups) * G::SumCount, 0.0);
  s.Min.assign(s.Groups, std::numeric_limits<double>::max());
  s.Max.assign(s.Groups, -std::numeric_limits<double>::max());
  for (size_t i = 0; i < results.size() && i < group.size(); ++i)
  {
    const int g = group[i];
    if (g < 0 || g >= s.Groups)
      continue;
    double* sum = &s.Sums[static_cast<size_t>(g) * G::SumCount];
    const SampleResult& r = results[i];
    sum[G::Samples] += 1;
    sum[G::TotalArea] += area[i];
    if (r.Type == ContactType::Failed)
    {
      sum[G::Failed] += 1;
      continue;
    }
    const bool zone = edgeZone && (*edgeZone)[i] != 0;
    sum[G::SolvedArea] += area[i];
    sum[G::AreaThickness] += area[i] * r.Thickness;
    if (zone)
      sum[G::EdgeZoneArea] += area[i];
    if (minimum > 0.0 && r.Thickness < minimum && (countEdgeZones || !zone))
      sum[G::AreaBelow] += area[i];
    s.Min[g] = std::min(s.Min[g], r.Thickness);
    s.Max[g] = std::max(s.Max[g], r.Thickness);
  }
  return s;
}

} // namespace brt
