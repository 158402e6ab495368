// The double-precision reference against closed forms: plates (0.1 to 50, one of aspect
// 1:1000), a coaxial tube, spherical and toroidal shells.
#include "AnalyticShapes.h"
#include "SolverTestHelpers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace
{
using namespace brt;

struct ClosedForm
{
  std::string Name;
  TopoDS_Shape Shape;
  double Thickness;
};

std::vector<ClosedForm> Shapes()
{
  std::vector<ClosedForm> v;
  for (double h : { 0.1, 1.0, 5.0, 50.0 })
    v.push_back({ "plate h=" + std::to_string(h), analytic::Plate(20 * h, 15 * h, h), h });
  v.push_back({ "plate 100x100x0.1 (aspect 1:1000)", analytic::Plate(100, 100, 0.1), 0.1 });
  v.push_back({ "tube R20 r15", analytic::Tube(20, 15, 80), 5.0 });
  v.push_back({ "spherical shell R25 r20", analytic::SphericalShell(25, 20), 5.0 });
  v.push_back({ "toroidal shell 40 R10 r6", analytic::ToroidalShell(40, 10, 6), 4.0 });
  return v;
}

TEST(SolverReference, ClosedForms)
{
  for (const ClosedForm& c : Shapes())
  {
    SCOPED_TRACE(c.Name);
    // Curved faces converted within 1e-6 so that the patches do not limit the accuracy.
    const test::Solved s = test::SolveShape(c.Shape, 1e-6);
    const std::vector<double> rim = test::RimDistances(s.Model, s.Samples);
    double worst = 0.0;
    size_t interior = 0, failed = 0;
    for (size_t i = 0; i < s.Results.size(); ++i)
    {
      const SampleResult& r = s.Results[i];
      failed += r.Type == ContactType::Failed;
      if (rim[i] < c.Thickness)
        continue;
      ++interior;
      ASSERT_EQ(r.Type, ContactType::SurfaceSurface)
        << "sample " << i << ": " << FailReasonName(r.Reason);
      worst = std::max(worst, std::fabs(r.Thickness - c.Thickness) / c.Thickness);
    }
    std::printf("[closed form] %s: %zu samples (%zu farther than h from every rim), s1 %zu, "
                "max |2t-h|/h = %.2e\n",
      c.Name.c_str(), s.Samples.size(), interior, s.Data.S1.size(), worst);
    test::PrintResidualSummary(c.Name, s.Results);
    EXPECT_GT(interior, 100u);
    EXPECT_LE(worst, 1e-6);
    EXPECT_EQ(failed, 0u);
  }
}
} // namespace
