// BRepThickness: the native device. The solver's kernel source (Kernels/thickness.cl) compiled as
// C++ in double precision and run on every core: the solver's reference and the CPU device a
// machine without OpenCL runs at full speed (docs/Solver.md, "One source"). VTK-free,
// OpenCL-free.
#pragma once

#include "Solver.h"

#include <memory>
#include <vector>

namespace brt
{

class NativeSolver
{
public:
  /// Packs the model and its solver data (KernelData.h); both must outlive this object.
  NativeSolver(const BRepModel& model, const SolverData& data);
  ~NativeSolver();
  NativeSolver(const NativeSolver&) = delete;
  NativeSolver& operator=(const NativeSolver&) = delete;

  /// Solves samples[i] into results[i] for every i in `which` (all samples when null; results
  /// sized to the samples first), on `threads` threads (0: one per core). exactPass, when given,
  /// gets 1 at i where the pass without clearance found the contact.
  void Solve(const SolverOptions& options, const std::vector<Sample>& samples,
    std::vector<SampleResult>& results, const std::vector<size_t>* which = nullptr,
    unsigned threads = 0, std::vector<unsigned char>* exactPass = nullptr) const;

  /// SphereHoldsBoundary (Solver.h) on the packed model.
  bool HoldsBoundary(const SolverOptions& options, const Sample& sample, const SampleResult& r) const;

  /// PolishResult (Solver.h) on the packed model.
  void Polish(const SolverOptions& options, const Sample& sample, SampleResult& r) const;

private:
  struct Impl;
  std::unique_ptr<Impl> P;
};

} // namespace brt
