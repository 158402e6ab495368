#include "NativeSolver.h"

#include "KernelData.h"
#include "KernelLanguage.h"

namespace brt
{
namespace kernel
{
// The kernel source, compiled here as C++ in double (KernelLanguage.h).
#include "thickness.cl"
} // namespace kernel

struct NativeSolver::Impl
{
  const BRepModel& Model;
  const SolverData& Data;
  KernelModel<double> K;

  Impl(const BRepModel& m, const SolverData& d)
    : Model(m)
    , Data(d)
    , K(PackKernelModel<double>(m, d))
  {
  }

  kernel::Model View(const KernelScalars& s) const
  {
    return kernel::Model{ K.Patches.data(), K.PatchAnchor.data(), K.PatchDomain.data(),
      K.FaceInfo.data(), K.FaceDomain.data(), K.Breaks.data(), K.Loops.data(), K.Trim.data(),
      K.TrimEdge.data(), K.TrimRange.data(), K.EdgeInfo.data(), K.EdgeRange.data(),
      K.EdgeSeg.data(), K.EdgeAnchor.data(), K.EdgeSegRange.data(), K.VertexInfo.data(), s.Slack,
      s.Clearance, s.S1Spacing, K.PatchFace.data(), K.EdgeSegEdge.data(), K.PatchBoxes.data(),
      K.EdgeBoxes.data(), K.BoxNodeBox.data(), K.BoxNodeInfo.data(), K.BoxItems.data(),
      static_cast<int>(Model.Patches.size()), s.Certify && K.HasBoxes() ? 1 : 0 };
  }
};

NativeSolver::NativeSolver(const BRepModel& model, const SolverData& data)
  : P(std::make_unique<Impl>(model, data))
{
}

NativeSolver::~NativeSolver() = default;

void NativeSolver::Solve(const SolverOptions& options, const std::vector<Sample>& samples,
  std::vector<SampleResult>& results, const std::vector<size_t>* which, unsigned threads,
  std::vector<unsigned char>* exactPass) const
{
  if (!which)
    results.assign(samples.size(), SampleResult());
  if (exactPass)
    exactPass->resize(samples.size(), 0);
  const size_t n = which ? which->size() : samples.size();
  if (P->Data.Nodes.empty())
  {
    for (size_t j = 0; j < n; ++j)
    {
      SampleResult& r = results[which ? (*which)[j] : j];
      r = SampleResult();
      r.Reason = FailReason::NoOppositePoint;
    }
    return;
  }
  const KernelScalars s = GetKernelScalars<double>(P->Model, P->Data, options);
  const kernel::Model view = P->View(s);
  const KernelModel<double>& K = P->K;
  ParallelFor(n, threads, [&](size_t j) {
    const size_t i = which ? (*which)[j] : j;
    double in[KernelSampleReals], outR[KernelOutReals];
    int outI[KernelOutInts];
    PackSample(P->Data, samples[i], in);
    kernel::solve_sample(view, K.S1Point.data(), K.S1Face.data(), K.S1UV.data(), K.NodeBox.data(),
      K.NodeInfo.data(), in, samples[i].Face, s.Scale, s.StepTol, s.NewtonTol, s.MaxIterations,
      s.MaxEdgeIterations, outR, outI);
    const bool exact = UnpackResult(samples[i], outR, outI, results[i]);
    if (exactPass)
      (*exactPass)[i] = exact ? 1 : 0;
  });
}

bool NativeSolver::HoldsBoundary(
  const SolverOptions& options, const Sample& sample, const SampleResult& r) const
{
  return SphereHoldsBoundary(P->Model, P->Data, options, sample, r);
}

void NativeSolver::Polish(const SolverOptions& options, const Sample& sample, SampleResult& r) const
{
  PolishResult(P->Model, P->Data, options, sample, r);
}

} // namespace brt
