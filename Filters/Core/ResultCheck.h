// BRepThickness: the checks every solve's results pass before they reach the user.
#pragma once

#include "Solver.h"

#include <cstddef>
#include <vector>

namespace brt
{
struct ResultCheckSummary
{
  std::size_t OpenShell = 0;   ///< samples flagged because their solid is open
  std::size_t NonManifold = 0; ///< samples flagged because their solid is non-manifold
  std::size_t Unbounded = 0;   ///< solved samples whose thickness was not finite or too large
  std::size_t FileGap = 0;     ///< samples flagged where the file's faces and edges miss each other
};

/// Flags as failed, with the reason, the samples of open and non-manifold solids (CheckSolids,
/// ModelIO.h) and every solved sample whose thickness, radius or centre is not finite or whose
/// thickness exceeds the bounding-box diagonal of its solid (the Bezier control points' box,
/// which holds the solid) by more than the conversion tolerance: nothing infinite, NaN or
/// impossible is ever reported as solved. Then every sample not failed already that lies on one of
/// the model's loose faces or within the radius of one of its loose vertices, or whose sphere
/// touches there (where the file's faces and edges miss each other, BRepModel::LooseVertices and
/// LooseFaces), or that lies on a face lying on another of its solid (BRepModel::
/// OverlappingFaces): FailReason::FileGap.
ResultCheckSummary CheckResults(const BRepModel& model, const std::vector<Sample>& samples,
  std::vector<SampleResult>& results);

/// The samples worth solving, in order: all but those on open or non-manifold solids, which
/// CheckResults flags failed whatever the solve gives them (and whose solve is the slowest of
/// all: on a part with an open surface model beside its solid, most of the time went there).
std::vector<std::size_t> MeasuredSamples(const BRepModel& model, const std::vector<Sample>& samples);
} // namespace brt
