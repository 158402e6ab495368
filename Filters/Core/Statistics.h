// BRepThickness: the statistics of a thickness map (the filter's Summary and Residuals ports),
// free of VTK so that GoogleTest reaches them. Every quantity is a sum, a minimum or a maximum,
// so the partial statistics of several processes combine by addition (Combine) or by MPI
// reductions on the same arrays.
#pragma once

#include "Solver.h"

#include <limits>
#include <vector>

namespace brt
{

/// Pass/fail class of a sample (the filter's ThicknessClass array; docs/DataContract.md).
enum class SampleClass : int
{
  Failed = 0,  ///< the solve failed (FailReason says why)
  Thin = 1,    ///< 2t below the minimum
  Ok = 2,      ///< within the limits (or no limit set)
  Thick = 3,   ///< 2t above the maximum
  EdgeZone = 4 ///< the sphere is small because of a corner (IsEdgeZone), not counted as thin
};
constexpr int SampleClasses = 5;
const char* SampleClassName(SampleClass c);

/// Default of the edge-zone corner angle (degrees; IsEdgeZone).
constexpr double DefaultEdgeZoneAngle = 60.0;

/// The angle (degrees, 0..180) at the sphere's centre M between the sample point O and the
/// contact point P of a solved result: 180 where the sphere spans a wall (P opposite O), 180 - a
/// at a corner of material angle a (90 at a right-angled convex edge); 0 for an osculating sphere,
/// which touches at O itself (the end of a rounded wall: an edge zone). NaN for a failed sample.
double ContactAngle(const double O[3], const SampleResult& r);

/// Edge zone (docs/Solver.md, "Edge zones"): a solved sample whose sphere is bounded by boundary
/// that meets O's side of the part at a corner, not by the opposite wall: its contact angle is at
/// most 180 - cornerAngle. cornerAngle is the smallest material angle that counts as a corner
/// (default 60 degrees): sharper wedges (knife edges, tapering ribs) are real thin material.
bool IsEdgeZone(const double O[3], const SampleResult& r, double cornerAngle = DefaultEdgeZoneAngle);

/// Class of one sample. minimum, maximum: the thickness limits (<= 0: unset). countEdgeZones:
/// edge-zone samples are classified by their thickness like the others instead of EdgeZone.
SampleClass Classify(const SampleResult& r, bool edgeZone, double minimum, double maximum,
  bool countEdgeZones);

/// Per-vertex area of a triangle mesh: a third of every adjacent triangle. points: xyz per
/// vertex; triangles: 3 vertex ids per triangle.
std::vector<double> VertexAreas(const std::vector<double>& points, const std::vector<int>& triangles);

struct ThicknessStatistics
{
  static constexpr int ContactTypes = 6; ///< brt::ContactType values 0..5
  static constexpr int FailReasons = 13; ///< brt::FailReason values 0..12
  /// log10 |R| histogram: ResidualBins bins over [ResidualLow, ResidualHigh]; residuals outside
  /// (and 0) go to the end bins.
  static constexpr double ResidualLow = -16.0, ResidualHigh = 0.0;
  static constexpr int ResidualBins = 64;

  /// Layout of Sums.
  enum Sum
  {
    Samples,
    SolvedArea,    ///< area of the solved samples' vertices
    AreaThickness, ///< sum of area x 2t over the solved samples
    TotalArea,
    AreaBelow, ///< solved area with 2t below the minimum (when > 0), edge zones as the option says
    AreaAbove, ///< solved area with 2t above the maximum (when > 0), edge zones as the option says
    SolvingProcesses,
    EdgeZoneArea,   ///< solved area in edge zones
    AreaBelowAll,   ///< AreaBelow counting the edge zones
    AreaAboveAll,   ///< AreaAbove counting the edge zones
    AreaBelowWalls, ///< AreaBelow without the edge zones
    AreaAboveWalls, ///< AreaAbove without the edge zones
    ClassArea,      ///< SampleClasses areas, indexed by SampleClass
    PerType = ClassArea + SampleClasses, ///< ContactTypes counts, indexed by ContactType
    PerReason = PerType + ContactTypes, ///< FailReasons counts of the failed samples
    SumCount = PerReason + FailReasons
  };
  std::vector<double> Sums = std::vector<double>(SumCount, 0.0);
  /// Counts per contact type (rows) and log10 |R| bin, ContactTypes x ResidualBins.
  std::vector<double> ResidualHistogram = std::vector<double>(ContactTypes * ResidualBins, 0.0);
  double Min = std::numeric_limits<double>::max();  ///< over the solved samples
  double Max = -std::numeric_limits<double>::max(); ///< over the solved samples

  bool AnySolved() const { return Max >= Min; }
  /// Area-weighted mean thickness of the solved samples (NaN when none).
  double Mean() const;
  /// Adds another process's statistics.
  void Combine(const ThicknessStatistics& other);
};

/// Statistics of results[i] with the vertex area area[i] (equal sizes). minimum and maximum:
/// the thickness limits (<= 0: unset). edgeZone: per sample, nonzero in an edge zone (null: none);
/// countEdgeZones: whether AreaBelow/AreaAbove and the classes count edge-zone samples.
ThicknessStatistics Accumulate(const std::vector<SampleResult>& results,
  const std::vector<double>& area, double minimum, double maximum,
  const std::vector<unsigned char>* edgeZone = nullptr, bool countEdgeZones = false);

/// The exterior gap's per-sample values and statistics (docs/Solver.md item 17).
struct GapStatistics
{
  std::vector<double> Value;          ///< per sample: 2t, +inf where infinite, NaN where failed
  std::vector<unsigned char> Infinite; ///< per sample: 1 where the gap is infinite
  enum Sum
  {
    AreaWithGap,  ///< area of the samples with a gap, finite or infinite
    FiniteArea,   ///< area of the samples with a finite gap
    AreaGap,      ///< sum of area x gap over the finite gaps
    InfiniteArea, ///< area of the samples with an infinite gap
    Failed,       ///< samples whose gap solve failed
    AreaBelow,    ///< area with a finite gap below the minimum (when > 0)
    OtherSolidArea, ///< area where another solid touches or overlaps (gap 0, ContactType::OtherSolid)
    SumCount
  };
  std::vector<double> Sums = std::vector<double>(SumCount, 0.0);
  double Min = std::numeric_limits<double>::max();  ///< over the finite gaps
  double Max = -std::numeric_limits<double>::max(); ///< over the finite gaps
};

/// The gap of results[i] (the exterior solve) with area[i]: infinite where infinite[i] (no wall
/// faces the sample) or, when maximum > 0, where the gap exceeds it; minimum (> 0): the limit of
/// AreaBelow. Sums, Min and Max combine over processes by sum, min and max.
GapStatistics AccumulateGap(const std::vector<SampleResult>& results,
  const std::vector<unsigned char>& infinite, const std::vector<double>& area, double minimum,
  double maximum);

/// Statistics per group of samples (per solid, per face): group[i] is sample i's group in
/// [0, Groups) (others are skipped). Every field is a sum, a minimum or a maximum, so processes
/// combine them by reductions like ThicknessStatistics.
struct GroupStatistics
{
  enum Sum
  {
    Samples,
    Failed,
    TotalArea,
    SolvedArea,
    AreaThickness,
    AreaBelow,    ///< below the minimum, edge zones as the option says
    EdgeZoneArea,
    SumCount
  };
  int Groups = 0;
  std::vector<double> Sums; ///< Groups x SumCount, group-major
  std::vector<double> Min, Max; ///< per group, over the solved samples
  double Get(int g, Sum k) const { return Sums[static_cast<size_t>(g) * SumCount + k]; }
  double Mean(int g) const; ///< area-weighted mean thickness (NaN when none solved)
  void Combine(const GroupStatistics& other);
};
GroupStatistics AccumulateGroups(const std::vector<SampleResult>& results,
  const std::vector<double>& area, const std::vector<int>& group, int groups, double minimum,
  const std::vector<unsigned char>* edgeZone = nullptr, bool countEdgeZones = false);

/// Solved area per thickness bin: bins equal bins over [0, top] (thicknesses at or above top go
/// to the last bin).
std::vector<double> AreaHistogram(const std::vector<SampleResult>& results,
  const std::vector<double>& area, int bins, double top);

} // namespace brt
