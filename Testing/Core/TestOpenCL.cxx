// The OpenCL kernels (PoCL here, any device elsewhere) against the double-precision reference,
// and the no-device path. Skipped, with the reason, when no OpenCL device exists.
#include "AnalyticShapes.h"
#include "NativeSolver.h"
#include "OpenCLSolver.h"
#include "ResultCheck.h"
#include "SolverTestHelpers.h"
#include "TestHelpers.h"

#include "Bezier.h"

#include <gtest/gtest.h>

#include <BRepBuilderAPI_NurbsConvert.hxx>
#include <BRepPrimAPI_MakeCone.hxx>
#include <ShapeUpgrade_ShapeDivideClosed.hxx>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace
{
using namespace brt;

/// The device to test on; null (skip, with the reason) only when there is no OpenCL device at
/// all or it lacks double precision. A kernel that does not build on a present device throws,
/// and the test fails.
std::unique_ptr<OpenCLSolver> Device(bool useDouble, std::string* why)
{
  if (OpenCLSolver::ListDevices().empty())
  {
    *why = "no OpenCL device";
    return nullptr;
  }
  const char* want = std::getenv("BRT_OPENCL_DEVICE");
  try
  {
    return std::make_unique<OpenCLSolver>(want ? want : "any", useDouble);
  }
  catch (const OpenCLError& e)
  {
    if (useDouble && std::string(e.what()).find("cl_khr_fp64") != std::string::npos)
    {
      *why = e.what();
      return nullptr;
    }
    throw;
  }
}

/// How far `foot` is from the surface of the sphere of `r` (positive: inside).
double DepthIn(const SampleResult& r, const std::array<double, 3>& foot)
{
  const double dx = foot[0] - r.Center[0], dy = foot[1] - r.Center[1], dz = foot[2] - r.Center[2];
  return r.Radius - std::sqrt(dx * dx + dy * dy + dz * dz);
}

/// Disagreements between kernel and reference results.
struct Disagreements
{
  size_t Count = 0;      ///< not the same contact type within `rel` (the issue's criterion)
  size_t Different = 0;  ///< of those, not the same sphere up to the solver's accuracy
};

/// Compares kernel and reference results; lists the disagreements. Agreement: the same contact
/// type and |2t_kernel - 2t_ref| <= rel * max(2t_ref, 1e-3 * scale). The floor matters only for
/// walls thinner than 1e-3 of the model size, which float resolves to about 1e-7 of the model
/// size in absolute terms, so a purely relative test would be noise there.
/// A disagreement is an equivalent sphere when both are solved and each one's foot lies within
/// `accuracy` of the other's sphere: both spheres touch both feet as closely as the solver can
/// tell (it ignores what lies less than the clearance inside a sphere, on patches within the
/// conversion tolerance of the faces). Such pairs are ties between two contacts of one sphere
/// (a vertex and the face next to it, the two far ends of the arc a sphere touches in a round)
/// whose radii differ by less than the patches' error amplified by the contact's flatness, so
/// rounding decides which one a path reports; the others are listed as different. Every sphere
/// tangent at O passes through O, so a foot next to O proves nothing (closer than 10x that
/// accuracy and a tenth of the smaller radius): such pairs count as different.
Disagreements Compare(const std::string& name, const std::vector<Sample>& samples,
  const std::vector<SampleResult>& ref, const std::vector<SampleResult>& cl, double rel,
  double scale, double accuracy, std::vector<std::string>* listed)
{
  auto awayFromO = [&](size_t i, const std::array<double, 3>& foot) {
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k)
      d2 += (foot[k] - samples[i].Point[k]) * (foot[k] - samples[i].Point[k]);
    const double near = std::min(10.0 * accuracy, 0.1 * std::min(ref[i].Radius, cl[i].Radius));
    return d2 > near * near;
  };
  Disagreements out;
  for (size_t i = 0; i < ref.size(); ++i)
  {
    const bool sameType = ref[i].Type == cl[i].Type;
    const bool bothFailed = ref[i].Type == ContactType::Failed && sameType;
    const double err = std::fabs(cl[i].Thickness - ref[i].Thickness) /
      std::max(ref[i].Thickness, 1e-3 * scale);
    if (bothFailed || (sameType && err <= rel))
      continue;
    ++out.Count;
    const bool solved = ref[i].Type != ContactType::Failed && cl[i].Type != ContactType::Failed;
    const double inRef = solved ? DepthIn(ref[i], cl[i].Foot) : 0.0;
    const double inCl = solved ? DepthIn(cl[i], ref[i].Foot) : 0.0;
    const bool equivalent = solved && std::fabs(inRef) <= accuracy &&
      std::fabs(inCl) <= accuracy && awayFromO(i, ref[i].Foot) && awayFromO(i, cl[i].Foot);
    out.Different += !equivalent;
    char line[640];
    std::snprintf(line, sizeof line,
      "%s sample %zu: reference %s 2t=%.9g (face %d, residual %.1e, %s) | kernel %s 2t=%.9g "
      "(face %d, residual %.1e, %d it, %s) | %s (kernel foot %.1e inside the reference "
      "sphere, reference foot %.1e inside the kernel's)",
      name.c_str(), i, ContactTypeName(ref[i].Type), ref[i].Thickness, ref[i].OppositeFace,
      ref[i].Residual, FailReasonName(ref[i].Reason), ContactTypeName(cl[i].Type),
      cl[i].Thickness, cl[i].OppositeFace, cl[i].Residual, cl[i].Iterations,
      FailReasonName(cl[i].Reason), equivalent ? "equivalent" : "DIFFERENT", inRef, inCl);
    if (listed)
      listed->push_back(line);
  }
  return out;
}

/// Surface/surface contacts whose foot is not where their FootParameter says on their patch
/// (the parameters come back from the kernels with the foot; the second look reads them). An
/// edge contact typed surface/surface at a tangent edge takes the trimming curve's point at the
/// edge parameter, which the trimming cubic's own parametrisation puts up to about 5e-3 mm along
/// the edge from the foot (measured on the ExpansionCard): hence 1e-3 of the model size.
size_t FootParameterMismatches(const BRepModel& m, const SolverData& data,
  const std::vector<SampleResult>& res, double tol)
{
  size_t bad = 0;
  for (const SampleResult& r : res)
  {
    if (r.Type != ContactType::SurfaceSurface)
      continue;
    const int patch = FindPatchFast(m, data, r.OppositeFace, r.FootParameter[0], r.FootParameter[1]);
    const auto P = EvaluatePatch(m.Patches[patch], r.FootParameter[0], r.FootParameter[1]).P;
    const double dx = P[0] - r.Foot[0], dy = P[1] - r.Foot[1], dz = P[2] - r.Foot[2];
    bad += !(std::sqrt(dx * dx + dy * dy + dz * dz) <= tol);
  }
  return bad;
}

/// Solved samples whose foot is the sample itself: within the patches' accuracy (2x the
/// tolerance) of O on its own face, or on a face continuing O's tangent plane there, the trivial
/// solution P = O of eq. 4 with whatever t came with it (a float descent once reported
/// 2t = 3.5e-6 mm there, on a 0.6 mm wall; a hinge sample 0.333 for 3.000).
size_t AtTheSample(const BRepModel& m, const SolverData& data, const std::vector<Sample>& samples,
  const std::vector<SampleResult>& res)
{
  size_t bad = 0;
  for (size_t i = 0; i < res.size(); ++i)
  {
    // (An osculating sphere touches O's own face at O by definition.)
    if (res[i].Type == ContactType::Failed || res[i].Type == ContactType::Osculating)
      continue;
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k)
      d2 += (res[i].Foot[k] - samples[i].Point[k]) * (res[i].Foot[k] - samples[i].Point[k]);
    if (!(d2 <= 4.0 * m.Tolerance * m.Tolerance))
      continue;
    bool trivial = res[i].OppositeFace == samples[i].Face;
    if (!trivial && res[i].Type == ContactType::SurfaceSurface)
    {
      // Or on a face continuing O's tangent plane (across a tangent edge, brt::TangentAtSample).
      const auto& uv = res[i].FootParameter;
      const PatchEval e = EvaluatePatch(
        m.Patches[FindPatchFast(m, data, res[i].OppositeFace, uv[0], uv[1])], uv[0], uv[1]);
      const std::array<double, 3> n{ e.Du[1] * e.Dv[2] - e.Du[2] * e.Dv[1],
        e.Du[2] * e.Dv[0] - e.Du[0] * e.Dv[2], e.Du[0] * e.Dv[1] - e.Du[1] * e.Dv[0] };
      const auto& dd = samples[i].Direction;
      const double cx = n[1] * dd[2] - n[2] * dd[1], cy = n[2] * dd[0] - n[0] * dd[2],
                   cz = n[0] * dd[1] - n[1] * dd[0];
      trivial = cx * cx + cy * cy + cz * cz <= 1e-6 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    }
    if (trivial)
    {
      ++bad;
      std::printf("[at the sample] sample %zu: %s 2t=%.6g face %d edge %d, foot %.2e from O\n", i,
        ContactTypeName(res[i].Type), res[i].Thickness, res[i].OppositeFace, res[i].OppositeEdge,
        std::sqrt(d2));
    }
  }
  return bad;
}

class KernelVsReference : public ::testing::TestWithParam<bool>
{
};

TEST_P(KernelVsReference, EveryDataModel)
{
  const bool useDouble = GetParam();
  std::string why;
  auto cl = Device(useDouble, &why);
  if (!cl)
    GTEST_SKIP() << why;
  std::printf("[opencl] %s, %s\n", cl->DeviceName().c_str(), useDouble ? "double" : "float");
  for (const auto& name : test::DataModels())
  {
    const BRepModel m = ConvertStepFile(test::DataFile(name), ConversionOptions());
    SolverOptions options;
    const SolverData data = PrepareSolver(m, options);
    const std::vector<Sample> samples = SamplesFromMesh(m, data);
    std::vector<SampleResult> ref, got;
    SolveReference(m, data, options, samples, ref);
    cl->Upload(m, data);
    cl->Solve(m, data, options, samples, got, 4096); // several chunks on every model
    std::vector<std::string> listed;
    // The solver's accuracy: the clearance (2x the tolerance by default) plus the patches' error.
    const double accuracy = 3.0 * m.Tolerance;
    const Disagreements dis = Compare(name, samples, ref, got, 1e-4, data.Scale, accuracy, &listed);
    const size_t bad = dis.Count;
    EXPECT_EQ(FootParameterMismatches(m, data, ref, 1e-3 * data.Scale), 0u) << name;
    EXPECT_EQ(FootParameterMismatches(m, data, got, 1e-3 * data.Scale), 0u) << name;
    EXPECT_EQ(AtTheSample(m, data, samples, ref), 0u) << name;
    EXPECT_EQ(AtTheSample(m, data, samples, got), 0u) << name;
    size_t clFailed = 0;
    for (const auto& r : got)
      clFailed += r.Type == ContactType::Failed;
    std::printf("[kernel vs reference] %s (%s): %zu samples, %zu disagree (%.3f%%), of which "
                "%zu are different spheres (%.3f%%); kernel failed %.3f%%\n",
      name.c_str(), useDouble ? "double" : "float", samples.size(), bad,
      100.0 * bad / samples.size(), dis.Different, 100.0 * dis.Different / samples.size(),
      100.0 * clFailed / samples.size());
    for (const auto& l : listed)
      std::printf("[disagreement] %s\n", l.c_str());
    // The target: 99.9% agreement. Measured on PoCL (docs/Solver.md): in double 100% on every
    // model (the kernels are the reference's source); in float, with the host's finish, 100% on
    // the analytic models and 99.90-99.99% on the real parts. The FRAMEWORK tile's 99.90% (54
    // samples) is the lowest: ties between osculating spheres next to O in its four corner
    // pockets, within 1e-2 of each other; the bound in float is 0.12% for that.
    EXPECT_LE(bad, samples.size() * (useDouble ? 10 : 12) / 10000) << name;
    // Different spheres (Compare), not ties between contacts of one sphere: measured 0 in
    // double and 0.009-0.047% in float on the real parts.
    EXPECT_LE(dis.Different, samples.size() * 10 / 10000) << name;
    // Failed samples (flagged, never reported as thicknesses): measured at most 0.055% of the
    // samples on the real parts (hinge), in the reference and in the kernels with their finish;
    // 0.19% before the shrinking ball, 0.26% before samples on convex edges could touch the face
    // across from within the clearance plus the tolerance outside it, 0.43% before the
    // clearance, 1.3% before the descent across edges, 5.7% before the descent.
    size_t refFailed = 0;
    for (const auto& r : ref)
      refFailed += r.Type == ContactType::Failed;
    EXPECT_LE(refFailed, samples.size() * 10 / 10000) << name;
    EXPECT_LE(clFailed, samples.size() * 10 / 10000) << name;
    // In float, the figures above include the host's finish: every contact polished and
    // certified again in double (NativeSolver::Polish, HoldsBoundary) and the samples the float
    // kernels leave failed solved by the native device. The kernels alone (the certification
    // included, in their precision) against the reference: in double the same code, so the same
    // results; in float measured 99.75-100% (FRAMEWORK tile the lowest: float ties between
    // osculating spheres in its corner pockets).
    std::vector<SampleResult> alone;
    cl->SetFinish(false);
    cl->Solve(m, data, options, samples, alone, 4096);
    cl->SetFinish(true);
    size_t handedBack = 0;
    for (const auto& r : alone)
      handedBack += r.Type == ContactType::Failed;
    const Disagreements disAlone = Compare(name, samples, ref, alone, 1e-4, data.Scale, accuracy, nullptr);
    EXPECT_EQ(AtTheSample(m, data, samples, alone), 0u) << name;
    const size_t badAlone = disAlone.Count;
    std::printf("[kernel alone] %s (%s): %zu disagree (%.3f%%), %zu different spheres "
                "(%.3f%%), %zu left failed by the kernels (%.3f%%)\n",
      name.c_str(), useDouble ? "double" : "float", badAlone, 100.0 * badAlone / samples.size(),
      disAlone.Different, 100.0 * disAlone.Different / samples.size(), handedBack,
      100.0 * handedBack / samples.size());
    EXPECT_LE(badAlone, useDouble ? 0 : samples.size() * 40 / 10000) << name;
    if (!useDouble)
      test::PrintResidualSummary(name + " (reference)", ref);
    test::PrintResidualSummary(name + (useDouble ? " (kernel double)" : " (kernel float)"), got);
  }
}

INSTANTIATE_TEST_SUITE_P(Precision, KernelVsReference, ::testing::Values(false, true),
  [](const ::testing::TestParamInfo<bool>& p) { return p.param ? "Double" : "Float"; });

// One source: the native device is the kernel source compiled as C++ in double, so on a device
// with double precision the OpenCL kernels alone must give the same results, up to the rounding
// of two compilers (fused multiply-adds, library functions).
TEST(NativeDevice, SameAsOpenCLDoubleKernels)
{
  std::string why;
  auto cl = Device(true, &why);
  if (!cl)
    GTEST_SKIP() << why;
  cl->SetFinish(false);
  for (const auto& name : test::DataModels())
  {
    const BRepModel m = ConvertStepFile(test::DataFile(name), ConversionOptions());
    SolverOptions options;
    options.Certify = false; // the kernels' own results
    const SolverData data = PrepareSolver(m, options);
    const std::vector<Sample> samples = SamplesFromMesh(m, data);
    std::vector<SampleResult> native, got;
    NativeSolver(m, data).Solve(options, samples, native);
    cl->Upload(m, data);
    cl->Solve(m, data, options, samples, got);
    size_t typeDiffers = 0, radiusDiffers = 0;
    std::vector<double> diffs;
    for (size_t i = 0; i < samples.size(); ++i)
    {
      if (native[i].Type != got[i].Type)
        ++typeDiffers;
      else if (native[i].Type != ContactType::Failed)
      {
        const double rel = std::fabs(native[i].Radius - got[i].Radius) / native[i].Radius;
        diffs.push_back(rel);
        radiusDiffers += rel > 1e-6;
      }
    }
    std::sort(diffs.begin(), diffs.end());
    std::printf("[native vs OpenCL double] %s: %zu samples, %zu other type, %zu radii differ by "
                "more than 1e-6 relative; relative difference: 99.9%% %.1e, max %.1e\n",
      name.c_str(), samples.size(), typeDiffers, radiusDiffers,
      diffs.empty() ? 0.0 : diffs[diffs.size() * 999 / 1000], diffs.empty() ? 0.0 : diffs.back());
    // Measured on PoCL: identical on the analytic models; 0-0.16% of the samples on the real
    // parts, where two compilers' rounding picks another of nearly tied spheres or contacts.
    EXPECT_LE(typeDiffers + radiusDiffers, samples.size() * 25 / 10000 + 1) << name;
  }
}

// The filter's call: a subset of the samples (`which`: those on closed solids, whole faces), the
// progress after each chunk, and a stop. The subset's results are the whole solve's, sample by
// sample (a face's chains depend on its own samples alone: ChainStarts); the others stay as
// SampleResult() leaves them; a stop after the first chunk leaves the rest failed and returns
// false.
TEST(OpenCLKernels, SubsetProgressAndStop)
{
  for (const bool useDouble : { false, true })
  {
    std::string why;
    auto cl = Device(useDouble, &why);
    if (!cl)
    {
      std::printf("[subset] %s: %s\n", useDouble ? "double" : "float", why.c_str());
      continue;
    }
    const BRepModel m = ConvertStepFile(test::DataFile("FRAMEWORK_DESKTOP_BLANK_TILE.stp"), ConversionOptions());
    SolverOptions options;
    const SolverData data = PrepareSolver(m, options);
    const std::vector<Sample> samples = SamplesFromMesh(m, data);
    std::vector<SampleResult> all, some, stopped;
    cl->Upload(m, data);
    ASSERT_TRUE(cl->Solve(m, data, options, samples, all, 4096));
    std::vector<size_t> which;
    for (size_t i = 0; i < samples.size(); ++i)
      if (samples[i].Face % 3 != 1)
        which.push_back(i);
    std::vector<size_t> calls;
    ASSERT_TRUE(cl->Solve(m, data, options, samples, some, 4096, &which, [&](size_t done) {
      calls.push_back(done);
      return true;
    }));
    // One call per chunk, counting up to the subset's size; a chunk holds whole chains, up to
    // 4096 samples (at most a chain, 64, short of it).
    ASSERT_FALSE(calls.empty());
    EXPECT_EQ(calls.back(), which.size());
    for (size_t k = 0; k < calls.size(); ++k)
    {
      const size_t step = calls[k] - (k ? calls[k - 1] : 0);
      EXPECT_LE(step, 4096u) << k;
      if (k + 1 < calls.size())
      {
        EXPECT_GT(step, 4096u - 64u) << k;
      }
    }
    std::vector<char> in(samples.size(), 0);
    for (size_t i : which)
      in[i] = 1;
    size_t differ = 0, touched = 0;
    for (size_t i = 0; i < samples.size(); ++i)
      if (in[i])
        differ += some[i].Type != all[i].Type || some[i].Thickness != all[i].Thickness ||
          some[i].OppositeFace != all[i].OppositeFace;
      else
        touched += some[i].Type != ContactType::Failed || some[i].Reason != FailReason::None;
    EXPECT_EQ(differ, 0u) << (useDouble ? "double" : "float");
    EXPECT_EQ(touched, 0u) << (useDouble ? "double" : "float");
    // A stop after the first chunk, into results that hold a whole solve: the samples after the
    // first chunk are failed again, not left as they were.
    stopped = all;
    size_t asked = 0;
    EXPECT_FALSE(cl->Solve(m, data, options, samples, stopped, 4096, nullptr, [&](size_t) {
      ++asked;
      return false;
    }));
    size_t solved = 0;
    for (const SampleResult& r : stopped)
      solved += r.Type != ContactType::Failed;
    EXPECT_EQ(asked, 1u);
    EXPECT_GT(solved, 4096u - 64u);
    EXPECT_LE(solved, 4096u);
    std::printf("[subset] %s: %zu of %zu samples, %zu progress calls, 0 differ; stopped after "
                "the first chunk: %zu solved\n",
      useDouble ? "double" : "float", which.size(), samples.size(), calls.size(), solved);
  }
}

// The float kernels' finish (polish, certification, solve again in double) runs on the device
// where it has double precision and on the host elsewhere: the same source, so the same results.
TEST(OpenCLKernels, FinishOnDeviceSameAsOnHost)
{
  std::string why;
  auto cl = Device(false, &why);
  if (!cl)
    GTEST_SKIP() << why;
  if (!cl->FinishesOnDevice())
    GTEST_SKIP() << cl->DeviceName() << " has no double precision: the finish runs on the host";
  for (const char* name : { "FRAMEWORK_DESKTOP_BLANK_TILE.stp", "l_bracket.step" })
  {
    const BRepModel m = ConvertStepFile(test::DataFile(name), ConversionOptions());
    SolverOptions options;
    const SolverData data = PrepareSolver(m, options);
    const std::vector<Sample> samples = SamplesFromMesh(m, data);
    std::vector<SampleResult> device, host;
    cl->Upload(m, data);
    cl->Solve(m, data, options, samples, device);
    cl->SetFinishOnHost(true);
    cl->Solve(m, data, options, samples, host);
    cl->SetFinishOnHost(false);
    size_t differ = 0;
    for (size_t i = 0; i < samples.size(); ++i)
    {
      const bool d = device[i].Type != host[i].Type ||
        std::fabs(device[i].Radius - host[i].Radius) > 1e-9 * std::max(1.0, host[i].Radius);
      if (d && differ < 5)
        std::printf("[finish differs] %s sample %zu: device %s 2t=%.12g, host %s 2t=%.12g\n", name, i,
          ContactTypeName(device[i].Type), device[i].Thickness, ContactTypeName(host[i].Type),
          host[i].Thickness);
      differ += d;
    }
    std::printf("[finish] %s: %zu samples, %zu differ between the device's and the host's finish\n",
      name, samples.size(), differ);
    EXPECT_EQ(differ, 0u) << name;
  }
}

// The ray thickness (brt_ray) on the OpenCL device against the native device: the same source,
// in double wherever the device has it, so identical (float kernels included). Float rays (a
// device without fp64) decided otherwise on 0.15% of the hole plate's and 0.5% of the
// ExpansionCard's samples (grazing rays), measured on PoCL by forcing them.
TEST(OpenCLKernels, RayThicknessSameAsNative)
{
  std::string why;
  auto cl64 = Device(true, &why), cl32 = Device(false, &why);
  if (!cl32)
    GTEST_SKIP() << why;
  for (const char* name : { "hole_plate.step", "tube.step", "ExpansionCard_SelfTapping.stp" })
  {
    const BRepModel m = ConvertStepFile(test::DataFile(name), ConversionOptions());
    const SolverData data = PrepareSolver(m, SolverOptions());
    const std::vector<Sample> samples = SamplesFromMesh(m, data);
    std::vector<double> native;
    NativeSolver(m, data).RayThickness(samples, native);
    for (OpenCLSolver* cl : { cl64.get(), cl32.get() })
    {
      if (!cl)
        continue;
      std::vector<double> device;
      cl->Upload(m, data);
      cl->RayThickness(m, data, samples, device);
      size_t differ = 0, missed = 0;
      double worst = 0.0;
      for (size_t i = 0; i < samples.size(); ++i)
      {
        missed += !std::isfinite(native[i]);
        if (std::isfinite(native[i]) != std::isfinite(device[i]))
        {
          ++differ;
          continue;
        }
        if (!std::isfinite(native[i]))
          continue;
        const double rel = std::fabs(device[i] - native[i]) / native[i];
        worst = std::max(worst, rel);
        differ += rel > 1e-12;
      }
      std::printf("[ray, %s kernels] %s: %zu samples, %zu differ from the native device (max "
                  "%.2e relative), %zu without a hit\n",
        cl->DoublePrecision() ? "double" : "float", name, samples.size(), differ, worst, missed);
      if (cl->DoublePrecision() || cl->FinishesOnDevice()) // the device has double precision
      {
        EXPECT_EQ(differ, 0u) << name;
      }
    }
  }
}

/// A closed-form shape solved on the device with the reader's and the solver's defaults: the
/// samples farther than h from every rim must be surface/surface contacts (checked here); the
/// largest |2t - h| / h among them, their count and most iterations, and the failed samples.
struct ClosedFormRun
{
  size_t Interior = 0, Failed = 0, Samples = 0;
  double Worst = 0.0;
  int MostIterations = 0;
};

ClosedFormRun SolveClosedForm(OpenCLSolver& cl, const TopoDS_Shape& shape, const char* name,
  double h, size_t* faces = nullptr)
{
  const BRepModel m = ConvertShape(shape, ConversionOptions()); // the reader's defaults
  if (faces)
    *faces = m.Faces.size();
  SolverOptions options;
  const SolverData data = PrepareSolver(m, options);
  const std::vector<Sample> samples = SamplesFromMesh(m, data);
  std::vector<SampleResult> got;
  cl.Upload(m, data);
  cl.Solve(m, data, options, samples, got);
  const std::vector<double> rim = test::RimDistances(m, samples);
  ClosedFormRun run;
  run.Samples = got.size();
  for (size_t i = 0; i < got.size(); ++i)
  {
    run.Failed += got[i].Type == ContactType::Failed;
    if (rim[i] < h)
      continue;
    ++run.Interior;
    EXPECT_EQ(got[i].Type, ContactType::SurfaceSurface)
      << name << " sample " << i << ": " << ContactTypeName(got[i].Type) << ", "
      << FailReasonName(got[i].Reason) << ", 2t " << got[i].Thickness << ", residual "
      << got[i].Residual << ", " << got[i].Iterations << " iterations";
    run.Worst = std::max(run.Worst, std::fabs(got[i].Thickness - h) / h);
    run.MostIterations = std::max(run.MostIterations, got[i].Iterations);
  }
  for (size_t i = 0, shown = 0; i < got.size() && shown < 5; ++i)
    if (got[i].Type == ContactType::Failed && ++shown)
      std::printf("[failed] %s sample %zu (rim distance %.3g): %s, residual %.2e\n", name, i,
        rim[i], FailReasonName(got[i].Reason), got[i].Residual);
  return run;
}

TEST(OpenCLKernels, ClosedFormsInFloat)
{
  std::string why;
  auto cl = Device(false, &why);
  if (!cl)
    GTEST_SKIP() << why;
  struct Shape
  {
    const char* Name;
    TopoDS_Shape S;
    double H;
  };
  const Shape shapes[] = { { "plate h=0.1", analytic::Plate(2, 1.5, 0.1), 0.1 },
    { "plate h=50", analytic::Plate(1000, 750, 50), 50 },
    { "plate 100x100x0.1", analytic::Plate(100, 100, 0.1), 0.1 },
    { "tube", analytic::Tube(20, 15, 80), 5 },
    { "spherical shell", analytic::SphericalShell(25, 20), 5 },
    { "toroidal shell", analytic::ToroidalShell(40, 10, 6), 4 },
    { "conical shell", analytic::ConicalShell(30, 15, 40, 3), 3 },
    // Faces past a cone's apex and on a spindle torus's lemon (PackExactSurface turns them).
    { "conical shell past the apex", analytic::ConicalShellPastApex(M_PI / 6, 4, -10, -30), 2 },
    { "lemon shell", analytic::LemonShell(5, 20, 22, 8), 2 },
    { "rod", analytic::Rod(5, 60), 10 }, { "ball", analytic::Ball(10), 20 },
    { "ring", analytic::Ring(30, 4), 8 },
    // Written as rational B-splines: the reader finds the analytic surfaces in them.
    { "tube as NURBS", BRepBuilderAPI_NurbsConvert(analytic::Tube(20, 15, 80)).Shape(), 5 },
    { "spherical shell as NURBS",
      BRepBuilderAPI_NurbsConvert(analytic::SphericalShell(25, 20)).Shape(), 5 } };
  for (const auto& s : shapes)
  {
    const ClosedFormRun run = SolveClosedForm(*cl, s.S, s.Name, s.H);
    std::printf("[closed form, float kernel] %s: %zu interior samples, max |2t-h|/h = %.2e, "
                "failed %zu of %zu\n",
      s.Name, run.Interior, run.Worst, run.Failed, run.Samples);
    EXPECT_LE(run.Worst, 1e-5) << s.Name;
    EXPECT_EQ(run.Failed, 0u) << s.Name;
  }
}

/// The tapered rod of SolverReference.TaperedRodAcrossItsAxis in float, whole and with its side in
/// halves: 2t = 2 R / cos of the half-angle within 1e-5 on the cone's samples away from its ends,
/// with the finish in double and with the float kernels' own results (where self_contact_foot
/// moves a foot next to O 60 degrees round the circle).
TEST(OpenCLKernels, TaperedRodInFloat)
{
  std::string why;
  auto cl = Device(false, &why);
  if (!cl)
    GTEST_SKIP() << why;
  const double R1 = 6, R2 = 4, H = 60;
  const double slope = (R1 - R2) / H, cosA = 1.0 / std::sqrt(1.0 + slope * slope);
  ShapeUpgrade_ShapeDivideClosed halves(BRepPrimAPI_MakeCone(R1, R2, H).Shape());
  halves.SetNbSplitPoints(1);
  halves.Perform();
  for (const bool finish : { true, false })
    for (const auto& shape : { BRepPrimAPI_MakeCone(R1, R2, H).Shape(), halves.Result() })
    {
      cl->SetFinish(finish);
      const BRepModel m = ConvertShape(shape, ConversionOptions());
      SolverOptions options;
      const SolverData data = PrepareSolver(m, options);
      const std::vector<Sample> samples = SamplesFromMesh(m, data);
      std::vector<SampleResult> got;
      cl->Upload(m, data);
      cl->Solve(m, data, options, samples, got);
      double worst = 0.0;
      size_t interior = 0;
      for (size_t i = 0; i < got.size(); ++i)
      {
        const Sample& q = samples[i];
        if (m.Faces[static_cast<size_t>(q.Face)].Kind != SurfaceKind::Cone || q.Point[2] < 15 ||
          q.Point[2] > H - 15)
          continue;
        ++interior;
        ASSERT_NE(got[i].Type, ContactType::Failed)
          << "sample " << i << ": " << FailReasonName(got[i].Reason);
        const double expected = 2.0 * (R1 - slope * q.Point[2]) / cosA;
        worst = std::max(worst, std::fabs(got[i].Thickness - expected) / expected);
      }
      std::printf("[closed form, float kernel%s] tapered rod (%zu faces): %zu samples, max "
                  "|2t - 2R/cos|/(2R/cos) = %.2e\n",
        finish ? "" : " alone", m.Faces.size(), interior, worst);
      EXPECT_GT(interior, 100u);
      EXPECT_LE(worst, 1e-5);
    }
  cl->SetFinish(true);
}

// A model metres across in float, the kernels' own results (no finish in double): a 508 mm
// slab 4 x 3 m, and a rod of radius 127 mm, 4 m long, whose side is written as two half
// cylinders, as many CAD systems write it. Eq. 4's Newton must converge at float's rounding of
// such coordinates, and a sample on one half must find the closed form's sphere across on the
// other half, where the contact is a whole circle and eq. 4 is singular: both once left the
// first solve failed, the descents after it straying and the certification restarting, on 16%
// of an assembly's samples (docs/Solver.md). Measured by the samples' iterations: the first
// Newton's few, not the restarts' hundreds.
TEST(OpenCLKernels, LargeModelsInFloatSolveAtOnce)
{
  std::string why;
  auto cl = Device(false, &why);
  if (!cl)
    GTEST_SKIP() << why;
  cl->SetFinish(false);
  ShapeUpgrade_ShapeDivideClosed halves(analytic::Rod(127, 4000));
  halves.SetNbSplitPoints(1);
  halves.Perform();
  struct Shape
  {
    const char* Name;
    TopoDS_Shape S;
    double H;
    size_t Faces;
  };
  const Shape shapes[] = { { "slab 4000 x 3000 x 508", analytic::Plate(4000, 3000, 508), 508, 6 },
    { "rod R127 L4000 in halves", halves.Result(), 254, 4 } };
  for (const auto& s : shapes)
  {
    size_t faces = 0;
    const ClosedFormRun run = SolveClosedForm(*cl, s.S, s.Name, s.H, &faces);
    EXPECT_EQ(faces, s.Faces) << s.Name;
    std::printf("[large, float kernel] %s: %zu interior samples, max |2t-h|/h = %.2e, at most "
                "%d iterations, failed %zu of %zu\n",
      s.Name, run.Interior, run.Worst, run.MostIterations, run.Failed, run.Samples);
    EXPECT_GT(run.Interior, 100u) << s.Name;
    EXPECT_LE(run.Worst, 1e-5) << s.Name;
    EXPECT_LE(run.MostIterations, 10) << s.Name;
    EXPECT_EQ(run.Failed, 0u) << s.Name;
  }
}

// Run by ctest with OCL_ICD_VENDORS pointing to an empty directory: the ICD loader then finds no
// platform. The solver must say so clearly, and the CPU reference must still work.
TEST(OpenCLNoPlatform, ClearErrorAndReferenceStillWorks)
{
  if (!std::getenv("BRT_EXPECT_NO_OPENCL"))
    GTEST_SKIP() << "only meaningful with OCL_ICD_VENDORS=<empty dir> (see Testing/CMakeLists.txt)";
  EXPECT_TRUE(OpenCLSolver::ListDevices().empty());
  try
  {
    OpenCLSolver solver;
    FAIL() << "an OpenCL device was found";
  }
  catch (const OpenCLError& e)
  {
    std::printf("[no platform] %s\n", e.what());
    EXPECT_NE(std::string(e.what()).find("no platform"), std::string::npos) << e.what();
  }
  const BRepModel m = ConvertShape(analytic::Plate(40, 30, 2), ConversionOptions());
  const SolverData data = PrepareSolver(m, SolverOptions());
  const std::vector<Sample> samples = SamplesFromMesh(m, data);
  std::vector<SampleResult> results;
  SolveReference(m, data, SolverOptions(), samples, results);
  ASSERT_FALSE(results.empty());
  for (const auto& r : results)
    ASSERT_EQ(r.Type, ContactType::SurfaceSurface);
}

TEST(OpenCLKernels, DeviceChoiceFailureListsDevices)
{
  if (OpenCLSolver::ListDevices().empty())
    GTEST_SKIP() << "no OpenCL device";
  try
  {
    OpenCLSolver bogus("no-such-device-xyz");
    FAIL() << "a device was found for a bogus name";
  }
  catch (const OpenCLError& e)
  {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("no-such-device-xyz"), std::string::npos) << msg;
    EXPECT_NE(msg.find(OpenCLSolver::ListDevices().front()), std::string::npos) << msg;
  }
}
/// The thin-wall flag is part of the kernel source: a plate 2e-4 thick at the default tolerance
/// fails with FailReason ThinWall on every device and precision, as on the native device (double:
/// the same samples; float solves some more of them, each within the wall), and after
/// CheckResults no sample reads thicker than the wall and 4 tolerances.
TEST(OpenCLKernels, WallBelowTheAccuracyIsFlagged)
{
  const double h = 2e-4, tol = ConversionOptions().Tolerance;
  const BRepModel m = ConvertShape(analytic::Plate(2, 1.5, h), ConversionOptions());
  const SolverData data = PrepareSolver(m, SolverOptions());
  const std::vector<Sample> samples = SamplesFromMesh(m, data);
  std::vector<SampleResult> native;
  NativeSolver(m, data).Solve(SolverOptions(), samples, native);
  size_t thinNative = 0;
  for (const SampleResult& r : native)
    thinNative += r.Reason == FailReason::ThinWall;
  EXPECT_GT(thinNative, samples.size() / 2);
  for (const bool useDouble : { false, true })
  {
    std::string why;
    auto cl = Device(useDouble, &why);
    if (!cl)
      GTEST_SKIP() << why;
    std::vector<SampleResult> device;
    cl->Upload(m, data);
    cl->Solve(m, data, SolverOptions(), samples, device);
    CheckResults(m, samples, device);
    size_t thin = 0, other = 0, thick = 0;
    for (const SampleResult& r : device)
    {
      thin += r.Reason == FailReason::ThinWall;
      other += r.Type == ContactType::Failed && r.Reason != FailReason::ThinWall &&
        r.Reason != FailReason::Unbounded;
      thick += r.Type != ContactType::Failed && r.Thickness > h + 4.0 * tol;
    }
    std::printf("[thin wall] plate 2e-4, OpenCL %s: %zu of %zu samples ThinWall (native %zu), %zu "
                "failed otherwise, %zu thicker than the wall and 4 tolerances\n",
      useDouble ? "double" : "float", thin, samples.size(), thinNative, other, thick);
    EXPECT_EQ(other, 0u);
    EXPECT_EQ(thick, 0u);
    if (useDouble)
      EXPECT_EQ(thin, thinNative);
    else
      EXPECT_GT(thin, samples.size() / 3);
  }
}
} // namespace
