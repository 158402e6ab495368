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
  auto grow = [](std::array<double, 6>& b, const BezierPatch& p) {
    for (int i = 0; i < 16; ++i)
      for (int k = 0; k < 3; ++k)
      {
        b[2 * k] = std::min(b[2 * k], p.ControlPoints[3 * i + k]);
        b[2 * k + 1] = std::max(b[2 * k + 1], p.ControlPoints[3 * i + k]);
      }
  };
  for (const BezierPatch& p : model.Patches)
  {
    const int s = p.Face >= 0 ? model.Faces[static_cast<size_t>(p.Face)].Solid : -1;
    if (s >= 0)
      grow(boxes[static_cast<size_t>(s)], p);
  }
  std::vector<double> diagonal(boxes.size(), 0.0);
  for (size_t s = 0; s < boxes.size(); ++s)
    if (boxes[s][0] <= boxes[s][1])
      diagonal[s] = std::sqrt(std::pow(boxes[s][1] - boxes[s][0], 2) +
        std::pow(boxes[s][3] - boxes[s][2], 2) + std::pow(boxes[s][5] - boxes[s][4], 2));

  // Where the file's faces and edges miss each other: the loose faces as flags, the loose
  // vertices sorted along x with their largest radius, so that a sample looks only at those
  // within that of it along x (a broken file may hold thousands of them).
  std::vector<char> looseFace(model.Faces.size(), 0);
  for (int f : model.LooseFaces)
    if (f >= 0 && static_cast<size_t>(f) < looseFace.size())
      looseFace[static_cast<size_t>(f)] = 1;
  std::vector<std::array<double, 4>> loose = model.LooseVertices;
  std::sort(loose.begin(), loose.end(),
    [](const std::array<double, 4>& a, const std::array<double, 4>& b) { return a[0] < b[0]; });
  double reach = 0.0;
  for (const auto& v : loose)
    reach = std::max(reach, v[3]);
  auto nearLoose = [&](const std::array<double, 3>& p) {
    auto it = std::lower_bound(loose.begin(), loose.end(), p[0] - reach,
      [](const std::array<double, 4>& v, double x) { return v[0] < x; });
    for (; it != loose.end() && (*it)[0] <= p[0] + reach; ++it)
    {
      const auto& v = *it;
      const double dx = p[0] - v[0], dy = p[1] - v[1], dz = p[2] - v[2];
      if (dx * dx + dy * dy + dz * dz <= v[3] * v[3])
        return true;
    }
    return false;
  };
  auto onLooseFace = [&](int f) {
    return f >= 0 && static_cast<size_t>(f) < looseFace.size() && looseFace[static_cast<size_t>(f)];
  };
  // Faces lying on another face of their solid, their outer sides the same way: which of them
  // bounds the part is not known, so the samples on them are flagged; the spheres touching them
  // are not, since where they overlap the faces agree on where the surface is.
  std::vector<char> overlapping(model.Faces.size(), 0);
  for (int f : model.OverlappingFaces)
    if (f >= 0 && static_cast<size_t>(f) < overlapping.size())
      overlapping[static_cast<size_t>(f)] = 1;
  auto onOverlappingFace = [&](int f) {
    return f >= 0 && static_cast<size_t>(f) < overlapping.size() &&
      overlapping[static_cast<size_t>(f)];
  };
  // A loose face's extent is not known (a surface off its edges, or a boundary that winds round
  // its surface instead of enclosing a region): a sphere reaching the box of its patches'
  // control points, which holds every region the face could be, may hold some of it.
  std::vector<std::array<double, 6>> looseBoxes;
  for (int f : model.LooseFaces)
  {
    if (f < 0 || static_cast<size_t>(f) >= model.Faces.size())
      continue;
    const Face& F = model.Faces[static_cast<size_t>(f)];
    std::array<double, 6> b{ 1e300, -1e300, 1e300, -1e300, 1e300, -1e300 };
    for (int p = F.FirstPatch; p < F.FirstPatch + F.PatchCount; ++p)
      grow(b, model.Patches[static_cast<size_t>(p)]);
    if (b[0] <= b[1])
      looseBoxes.push_back(b);
  }
  auto reachesLooseFace = [&](const SampleResult& r) {
    for (const auto& b : looseBoxes)
    {
      double d2 = 0.0;
      for (int k = 0; k < 3; ++k)
      {
        const double c = r.Center[k];
        const double d = c < b[2 * k] ? b[2 * k] - c : (c > b[2 * k + 1] ? c - b[2 * k + 1] : 0.0);
        d2 += d * d;
      }
      if (d2 <= r.Radius * r.Radius)
        return true;
    }
    return false;
  };

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
    {
      // A sample the solve failed where the file's faces and edges do not agree (on a loose
      // face or a face lying on another, or within a loose vertex's radius) is flagged for that,
      // its cause: the solve's reason there (not maximal, say) would send the user to the wrong
      // place.
      if (onLooseFace(face) || onOverlappingFace(face) ||
        (!loose.empty() && nearLoose(samples[i].Point)))
      {
        r.Reason = FailReason::FileGap;
        ++summary.FileGap;
      }
      continue;
    }
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
    if (onLooseFace(face) || onOverlappingFace(face) || onLooseFace(r.OppositeFace) ||
      reachesLooseFace(r) ||
      (!loose.empty() && (nearLoose(samples[i].Point) || nearLoose(r.Foot))))
    {
      flag(FailReason::FileGap);
      ++summary.FileGap;
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
