// The ray thickness (the distance from O along the inward normal to the first point of the
// trimmed faces of its solid) against closed forms on the analytic solids, every sample: for
// these shapes the ray's exit point is known exactly everywhere, rims and holes included.
#include "AnalyticShapes.h"
#include "BRepConverter.h"
#include "ExactDistance.h"
#include "TestHelpers.h"
#include "NativeSolver.h"
#include "Solver.h"

#include <gtest/gtest.h>

#include <BRep_Builder.hxx>
#include <IntCurvesFace_ShapeIntersector.hxx>
#include <TopoDS_Compound.hxx>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <memory>

namespace
{
using namespace brt;

/// Distance from p along the unit direction d to the boundary of the box [0, L]^3 it is in.
double BoxExit(const std::array<double, 3>& p, const std::array<double, 3>& d,
  const std::array<double, 3>& L)
{
  double s = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k)
  {
    if (d[k] > 1e-12)
      s = std::min(s, (L[k] - p[k]) / d[k]);
    else if (d[k] < -1e-12)
      s = std::min(s, -p[k] / d[k]);
  }
  return s;
}

struct Case
{
  const char* Name;
  TopoDS_Shape Shape;
  /// The exact ray thickness of a sample (point and inward normal).
  std::function<double(const Sample&)> Exact;
};

TEST(RayThickness, ClosedFormsEverySample)
{
  const std::array<double, 3> plate{ 100, 60, 5 };
  const Case cases[] = {
    { "plate 100 x 60 x 5", analytic::Plate(100, 60, 5),
      [&](const Sample& s) { return BoxExit(s.Point, s.Direction, plate); } },
    { "tube R 20, r 15, length 80", analytic::Tube(20, 15, 80),
      [](const Sample& s) {
        // Caps: along the axis; cylinders: radial, from one wall to the other.
        return std::fabs(s.Direction[2]) > 0.5 ? 80.0 : 5.0;
      } },
    { "spherical shell R 25, r 20", analytic::SphericalShell(25, 20),
      [](const Sample&) { return 5.0; } },
    { "hole plate 80 x 80 x 6, hole r 10", analytic::HolePlate(80, 6, 10),
      [](const Sample& s) {
        const auto& p = s.Point;
        const auto& d = s.Direction;
        double exit = BoxExit(p, d, { 80, 80, 6 });
        // The hole (axis x = y = 40 along z, radius 10): the ray's first entry into it.
        const double px = p[0] - 40, py = p[1] - 40;
        const double a = d[0] * d[0] + d[1] * d[1], b = 2 * (px * d[0] + py * d[1]),
                     c = px * px + py * py - 100;
        const double disc = b * b - 4 * a * c;
        // A ray grazing the hole (within 1e-3 mm of tangent) meets its face at one point or
        // nowhere depending on the last bit: not a closed form, left out.
        if (a > 1e-12 && std::fabs(disc) <= 1e-6 * a)
          return std::numeric_limits<double>::quiet_NaN();
        if (a > 1e-12 && disc > 0)
        {
          const double s1 = (-b - std::sqrt(disc)) / (2 * a);
          if (s1 > 1e-6)
            exit = std::min(exit, s1);
        }
        return exit;
      } },
  };
  for (const Case& c : cases)
  {
    const BRepModel m = ConvertShape(c.Shape, ConversionOptions()); // the reader's defaults
    const SolverData data = PrepareSolver(m, SolverOptions());
    const std::vector<Sample> samples = SamplesFromMesh(m, data);
    std::vector<double> ray;
    NativeSolver(m, data).RayThickness(samples, ray);
    double worst = 0.0;
    size_t missed = 0, worstAt = 0, grazing = 0;
    for (size_t i = 0; i < samples.size(); ++i)
    {
      if (!std::isfinite(ray[i]))
      {
        ++missed;
        continue;
      }
      const double exact = c.Exact(samples[i]);
      if (std::isnan(exact))
      {
        ++grazing;
        continue;
      }
      const double rel = std::fabs(ray[i] - exact) / exact;
      if (rel > worst)
      {
        worst = rel;
        worstAt = i;
      }
    }
    std::printf("[ray thickness] %s: %zu samples, max |ray - exact| / exact = %.2e (sample %zu: "
                "%.9g against %.9g), %zu without a hit, %zu grazing left out\n",
      c.Name, samples.size(), worst, worstAt, ray[worstAt], c.Exact(samples[worstAt]), missed,
      grazing);
    EXPECT_EQ(missed, 0u) << c.Name;
    EXPECT_LE(worst, 1e-6) << c.Name;
  }
}

/// On real parts, at the reader's default tolerance: 400 random samples' rays against
/// OpenCASCADE's first intersection of the same line with the exact faces of the sample's solid
/// (IntCurvesFace_ShapeIntersector, beyond 4 tolerances as ours), classed by
/// brt::exact::CompareRay. Every ray both hit must agree within 1e-4 relative, or differ as the
/// two definitions do: the same hit at a glancing angle, a graze ours counts within twice the
/// tolerance of a face, OpenCASCADE's hit off the faces or a touch of its own. No other
/// difference, no hit of one alone. The per-patch box and slab tests of the rays' walk
/// (docs/Solver.md, item 15, "Speed") pass a patch over only where no hit can lie; this is their
/// check on free-form and analytic faces alike (brt_exact_check --ray measures more parts).
TEST(RayThickness, AgreesWithOpenCascadeOnRealParts)
{
  for (const char* file : { "FRAMEWORK_DESKTOP_BLANK_TILE.stp", "fw13_hinge_l_assy.stp",
         "NIST_MBE_PMI_11.stp", "ExpansionCard_SelfTapping.stp" })
  {
    std::vector<TopoDS_Face> faces;
    const BRepModel m = ConvertStepFile(test::DataFile(file), ConversionOptions(), &faces);
    const SolverData data = PrepareSolver(m, SolverOptions());
    const std::vector<Sample> all = SamplesFromMesh(m, data);
    std::vector<Sample> samples;
    for (size_t i = 0; i < all.size(); i += std::max<size_t>(1, all.size() / 400))
      samples.push_back(all[i]);
    NativeSolver native(m, data);
    std::vector<double> ours;
    native.RayThickness(samples, ours);
    // Each solid's faces, and the intersector over them.
    int solids = 0;
    for (const Face& f : m.Faces)
      solids = std::max(solids, f.Solid + 1);
    BRep_Builder b;
    std::vector<TopoDS_Compound> bySolid(static_cast<size_t>(solids) + 1);
    for (TopoDS_Compound& c : bySolid)
      b.MakeCompound(c);
    for (size_t f = 0; f < faces.size(); ++f)
      b.Add(bySolid[static_cast<size_t>(m.Faces[f].Solid + 1)], faces[f]);
    std::vector<std::unique_ptr<IntCurvesFace_ShapeIntersector>> in(bySolid.size());
    std::map<exact::RayAgreement, size_t> tally;
    for (size_t k = 0; k < samples.size(); ++k)
    {
      const Sample& s = samples[k];
      const size_t solid = static_cast<size_t>(m.Faces[static_cast<size_t>(s.Face)].Solid + 1);
      if (!in[solid])
      {
        in[solid] = std::make_unique<IntCurvesFace_ShapeIntersector>();
        in[solid]->Load(bySolid[solid], m.Tolerance);
      }
      double exactRay;
      const exact::RayAgreement a = exact::CompareRay(ours[k], *in[solid], bySolid[solid],
        gp_Pnt(s.Point[0], s.Point[1], s.Point[2]),
        gp_Dir(s.Direction[0], s.Direction[1], s.Direction[2]), 4.0 * m.Tolerance, m.Tolerance,
        &exactRay);
      ++tally[a];
      EXPECT_TRUE(a != exact::RayAgreement::Other && a != exact::RayAgreement::OursAlone &&
        a != exact::RayAgreement::ExactAlone && a != exact::RayAgreement::ExactFailed)
        << file << " sample " << k << ": ours " << ours[k] << ", OpenCASCADE " << exactRay << ": "
        << exact::RayAgreementName(a);
    }
    const size_t both = samples.size() - tally[exact::RayAgreement::Neither];
    std::printf("[ray thickness] %s: %zu rays, %zu within 1e-4 relative of OpenCASCADE's, %zu "
                "glancing, %zu grazing, %zu OpenCASCADE's off the faces, %zu its touches, %zu "
                "neither hit\n",
      file, samples.size(), tally[exact::RayAgreement::Within], tally[exact::RayAgreement::Glancing],
      tally[exact::RayAgreement::Grazing], tally[exact::RayAgreement::ExactOff],
      tally[exact::RayAgreement::ExactTouch], tally[exact::RayAgreement::Neither]);
    EXPECT_GE(tally[exact::RayAgreement::Within], (99 * both) / 100) << file;
  }
}
} // namespace
