#include "ResultCheck.h"

#include "ModelIO.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace brt
{
ResultCheckSummary CheckResults(
  const BRepModel& model, const std::vector<Sample>& samples, std::vector<SampleResult>& results)
{
  ResultCheckSummary summary;
  const std::vector<SolidCheck> solids = CheckSolids(model);
  // Bounding box of each solid's control points (a Bezier patch lies in their hull).
  std::vector<std::array<double, 6>> boxes(
    solids.size(), std::array<double, 6>{ 1e300, -1e300, 1e300, -1e300, 1e300, -1e300 });
  for (const BezierPatch& p : model.Patches)
  {
    const int s = p.Face >= 0 ? model.Faces[static_cast<size_t>(p.Face)].Solid : -1;
    if (s < 0)
      continue;
    auto& b = boxes[static_cast<size_t>(s)];
    for (int i = 0; i < 16; ++i)
      for (int k = 0; k < 3; ++k)
      {
        b[2 * k] = std::min(b[2 * k], p.ControlPoints[3 * i + k]);
        b[2 * k + 1] = std::max(b[2 * k + 1], p.ControlPoints[3 * i + k]);
      }
  }
  std::vector<double> diagonal(boxes.size(), 0.0);
  for (size_t s = 0; s < boxes.size(); ++s)
    if (boxes[s][0] <= boxes[s][1])
      diagonal[s] = std::sqrt(std::pow(boxes[s][1] - boxes[s][0], 2) +
        std::pow(boxes[s][3] - boxes[s][2], 2) + std::pow(boxes[s][5] - boxes[s][4], 2));

  const size_t n = std::min(samples.size(), results.size());
  for (size_t i = 0; i < n; ++i)
  {
    SampleResult& r = results[i];
    const int face = samples[i].Face;
    const int s = face >= 0 && static_cast<size_t>(face) < model.Faces.size()
      ? model.Faces[static_cast<size_t>(face)].Solid
      : -1;
    auto flag = [&](FailReason reason) {
      r.Type = ContactType::Failed;
      r.Reason = reason;
    };
    if (s >= 0 && solids[static_cast<size_t>(s)].FreeEdges > 0)
    {
      flag(FailReason::OpenShell);
      ++summary.OpenShell;
      continue;
    }
    if (s >= 0 && solids[static_cast<size_t>(s)].NonManifoldEdges > 0)
    {
      flag(FailReason::NonManifold);
      ++summary.NonManifold;
      continue;
    }
    if (r.Type == ContactType::Failed)
      continue;
    const double limit = (s >= 0 ? diagonal[static_cast<size_t>(s)] : 0.0) + model.Tolerance;
    const bool finite = std::isfinite(r.Thickness) && std::isfinite(r.Radius) &&
      std::isfinite(r.Center[0]) && std::isfinite(r.Center[1]) && std::isfinite(r.Center[2]);
    if (!finite || !(r.Thickness <= limit) || s < 0)
    {
      flag(FailReason::Unbounded);
      ++summary.Unbounded;
      continue;
    }
    // Where the file's faces and edges miss each other (a vertex or a face moved off its edges,
    // covered by a tolerance of millimetres): the faces there are not the part's, and neither is
    // a sphere at them or touching them.
    if (std::find(model.LooseFaces.begin(), model.LooseFaces.end(), face) != model.LooseFaces.end() ||
      std::find(model.LooseFaces.begin(), model.LooseFaces.end(), r.OppositeFace) !=
        model.LooseFaces.end())
    {
      flag(FailReason::FileGap);
      ++summary.FileGap;
      continue;
    }
    for (const auto& v : model.LooseVertices)
    {
      auto within = [&](const std::array<double, 3>& p) {
        const double dx = p[0] - v[0], dy = p[1] - v[1], dz = p[2] - v[2];
        return dx * dx + dy * dy + dz * dz <= v[3] * v[3];
      };
      if (within(samples[i].Point) || within(r.Foot))
      {
        flag(FailReason::FileGap);
        ++summary.FileGap;
        break;
      }
    }
  }
  return summary;
}

std::vector<std::size_t> MeasuredSamples(const BRepModel& model, const std::vector<Sample>& samples)
{
  // Which solids are closed (their edges), not their volumes: the display mesh's triangles took
  // most of this list's 0.14 ms on NIST_MBE_PMI_11, inside the solve's time.
  const std::vector<SolidCheck> solids = CheckSolids(model, false);
  std::vector<std::size_t> which;
  which.reserve(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i)
  {
    const int face = samples[i].Face;
    const int s = face >= 0 && static_cast<size_t>(face) < model.Faces.size()
      ? model.Faces[static_cast<size_t>(face)].Solid
      : -1;
    if (s < 0 || solids[static_cast<size_t>(s)].Closed())
      which.push_back(i);
  }
  return which;
}
} // namespace brt
