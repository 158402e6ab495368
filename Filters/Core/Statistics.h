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

/// Per-vertex area of a triangle mesh: a third of every adjacent triangle. points: xyz per
/// vertex; triangles: 3 vertex ids per triangle.
std::vector<double> VertexAreas(const std::vector<double>& points, const std::vector<int>& triangles);

struct ThicknessStatistics
{
  static constexpr int ContactTypes = 4; ///< brt::ContactType values 0..3
  static constexpr int FailReasons = 11; ///< brt::FailReason values 0..10
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
    AreaBelow, ///< solved area with 2t below the minimum (when the minimum is > 0)
    AreaAbove, ///< solved area with 2t above the maximum (when the maximum is > 0)
    SolvingProcesses,
    PerType,                            ///< ContactTypes counts, indexed by ContactType
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
/// the thickness limits (<= 0: unset).
ThicknessStatistics Accumulate(const std::vector<SampleResult>& results,
  const std::vector<double>& area, double minimum, double maximum);

/// Solved area per thickness bin: bins equal bins over [0, top] (thicknesses at or above top go
/// to the last bin).
std::vector<double> AreaHistogram(const std::vector<SampleResult>& results,
  const std::vector<double>& area, int bins, double top);

} // namespace brt
