// The skeleton of rod-like regions: a graph of polylines through the maximal spheres' centres with
// their radii, simplified after Ferley et al. 1996 (docs/Midsurface.md). Free of VTK:
// vtkSkeletonFilter is its adapter.
#pragma once

#include "Midsurface.h"

#include <vector>

namespace brt
{
struct SkeletonOptions
{
  /// A sample is on a wall when its sphere touches one opposite face with at least this contact
  /// angle (degrees), as for the midsurface.
  double SheetAngle = 150.0;
  /// A wall sample belongs to a rod when the images of its face triangles on the medial axis keep
  /// less than this share of their area on average: the centres converge on a curve.
  double MaximumAreaRatio = 0.2;
  /// Centres are clustered in cells of this many times the median rod radius (noise filter).
  double ClusterSize = 0.5;
  /// Clusters of fewer samples are dropped as noise.
  int MinimumSamples = 3;
  /// A branch from a free end to a junction shorter than this many times the junction's radius is
  /// a spur and removed.
  double MinimumBranchLength = 2.0;
  /// A cycle of the cluster graph longer than this many median radii is a real loop (a ring);
  /// shorter ones are the band of neighbouring clusters and are broken.
  double LoopLength = 10.0;
  /// Free ends within this many radii of a common point, running towards it, meet there: the
  /// junction of rods, whose own samples touch several rods and are not rod samples.
  double JunctionReach = 3.0;
};

struct Skeleton
{
  std::vector<double> Points;  ///< xyz per node
  std::vector<double> Radius;  ///< per node: the mean sphere radius t of its samples
  std::vector<int> Samples;    ///< per node: the number of samples it stands for
  /// Node ids per polyline; a closed loop repeats its first node at the end.
  std::vector<std::vector<int>> Polylines;
  int RodSamples = 0;     ///< samples whose centres make the skeleton
  int NoiseClusters = 0;  ///< clusters dropped as noise (MinimumSamples)
  int ShortCycles = 0;    ///< edges left out to break short cycles of neighbouring clusters
  int RemovedSpurs = 0;   ///< branches removed as spurs
  int JunctionNodes = 0;  ///< nodes where three or more branches meet
  int EndNodes = 0;       ///< free ends
};

Skeleton BuildSkeleton(const MidsurfaceInput& input, const SkeletonOptions& options = {});
} // namespace brt
