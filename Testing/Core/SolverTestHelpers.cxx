#include "SolverTestHelpers.h"

#include "Bezier.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace brt::test
{
Solved SolveShape(const TopoDS_Shape& shape, double tolerance, const SolverOptions& options)
{
  Solved s;
  ConversionOptions conv;
  conv.Tolerance = tolerance;
  s.Model = ConvertShape(shape, conv);
  s.Data = PrepareSolver(s.Model, options);
  s.Samples = SamplesFromMesh(s.Model, s.Data);
  SolveReference(s.Model, s.Data, options, s.Samples, s.Results);
  return s;
}

double FaceParameters(const BRepModel& model, int face, const std::array<double, 3>& point,
  double* u, double* v)
{
  const Face& F = model.Faces[static_cast<size_t>(face)];
  double best = std::numeric_limits<double>::infinity();
  for (int p = F.FirstPatch; p < F.FirstPatch + F.PatchCount; ++p)
  {
    const BezierPatch& patch = model.Patches[static_cast<size_t>(p)];
    const auto& D = patch.Domain;
    double pu = 0.5 * (D[0] + D[1]), pv = 0.5 * (D[2] + D[3]);
    for (int it = 0; it < 40; ++it)
    {
      const PatchEval e = EvaluatePatch(patch, pu, pv);
      double a00 = 0, a01 = 0, a11 = 0, b0 = 0, b1 = 0;
      for (int k = 0; k < 3; ++k)
      {
        const double r = point[k] - e.P[k];
        a00 += e.Du[k] * e.Du[k];
        a01 += e.Du[k] * e.Dv[k];
        a11 += e.Dv[k] * e.Dv[k];
        b0 += e.Du[k] * r;
        b1 += e.Dv[k] * r;
      }
      const double det = a00 * a11 - a01 * a01;
      if (!(det > 0.0))
        break;
      pu = std::clamp(pu + (a11 * b0 - a01 * b1) / det, D[0], D[1]);
      pv = std::clamp(pv + (a00 * b1 - a01 * b0) / det, D[2], D[3]);
    }
    const PatchEval e = EvaluatePatch(patch, pu, pv);
    const double d = std::hypot(e.P[0] - point[0], e.P[1] - point[1], e.P[2] - point[2]);
    if (d < best)
    {
      best = d;
      *u = pu;
      *v = pv;
    }
  }
  return best;
}

namespace
{
/// Distance from p to a cubic 3D segment: best of 17 samples, refined by Newton (clamped).
double SegmentDistance(const std::array<double, 12>& cp, const std::array<double, 3>& p)
{
  auto dist = [&](double t) {
    const auto e = EvaluateCubic<3>(cp.data(), t);
    return std::hypot(e.P[0] - p[0], e.P[1] - p[1], e.P[2] - p[2]);
  };
  double best = std::numeric_limits<double>::infinity(), bt = 0.0;
  for (int k = 0; k <= 16; ++k)
    if (dist(k / 16.0) < best)
    {
      best = dist(k / 16.0);
      bt = k / 16.0;
    }
  double t = bt;
  for (int it = 0; it < 20; ++it)
  {
    const auto e = EvaluateCubic<3>(cp.data(), t);
    double f = 0.0, df = 0.0;
    for (int k = 0; k < 3; ++k)
    {
      f += (e.P[k] - p[k]) * e.D1[k];
      df += e.D1[k] * e.D1[k] + (e.P[k] - p[k]) * e.D2[k];
    }
    if (df <= 0.0)
      break;
    t = std::clamp(t - f / df, 0.0, 1.0);
  }
  return std::min(best, dist(t));
}
} // namespace

std::vector<double> RimDistances(const BRepModel& m, const std::vector<Sample>& samples)
{
  std::vector<double> out(samples.size(), std::numeric_limits<double>::infinity());
  for (const Edge& e : m.Edges)
  {
    // A seam, or the line where two faces of one surface meet (a rod written as two half
    // cylinders), is no rim.
    if (e.Seam || (e.Faces[0] >= 0 && e.Faces[1] >= 0 && m.FaceExact.size() == m.Faces.size() &&
                    m.Faces[e.Faces[0]].Kind == m.Faces[e.Faces[1]].Kind &&
                    m.Faces[e.Faces[0]].Kind <= SurfaceKind::Torus &&
                    m.FaceExact[e.Faces[0]] == m.FaceExact[e.Faces[1]]))
      continue;
    for (int s = e.FirstSegment; s < e.FirstSegment + e.SegmentCount; ++s)
      for (size_t i = 0; i < samples.size(); ++i)
        out[i] = std::min(out[i], SegmentDistance(m.EdgeSegments[s].ControlPoints, samples[i].Point));
  }
  return out;
}

void PrintResidualSummary(const std::string& name, const std::vector<SampleResult>& results)
{
  size_t failed = 0;
  std::vector<double> ss, se;
  for (const auto& r : results)
  {
    if (r.Type == ContactType::Failed)
      ++failed;
    else if (r.Type == ContactType::SurfaceSurface)
      ss.push_back(r.Residual);
    else
      se.push_back(r.Residual);
  }
  std::printf("[solve] %s: %zu samples, %zu failed (%.3f%%), %zu surface/surface, %zu surface/edge "
              "or vertex\n",
    name.c_str(), results.size(), failed, results.empty() ? 0.0 : 100.0 * failed / results.size(),
    ss.size(), se.size());
  for (auto* v : { &ss, &se })
  {
    if (v->empty())
      continue;
    std::sort(v->begin(), v->end());
    std::printf("[residual] %s %s: median %.2e, p99 %.2e, max %.2e\n", name.c_str(),
      v == &ss ? "surface/surface" : "surface/edge", (*v)[v->size() / 2],
      (*v)[std::min(v->size() - 1, v->size() * 99 / 100)], v->back());
  }
  for (size_t i = 0, shown = 0; i < results.size() && shown < 10; ++i)
    if (results[i].Type == ContactType::Failed)
    {
      std::printf("[failed] %s sample %zu: %s (residual %.2e, %d iterations)\n", name.c_str(), i,
        FailReasonName(results[i].Reason), results[i].Residual, results[i].Iterations);
      ++shown;
    }
}
} // namespace brt::test
