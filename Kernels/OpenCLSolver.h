// BRepThickness: OpenCL host layer of the maximal-sphere solver. Picks a platform and device,
// builds the embedded kernel once per device and precision (cached for the process), uploads
// the prepared model, and solves samples in chunks so device memory stays bounded. VTK-free.
#pragma once

#include "Solver.h"

#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace brt
{

/// No usable OpenCL platform or device, or a failed OpenCL call; the message says which and,
/// when a device choice fails, lists the devices found.
class OpenCLError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

class OpenCLSolver
{
public:
  /// `device`: "any" (the first GPU, else the first device), "gpu", "cpu", or a case-insensitive
  /// part of a device or platform name. `useDouble` needs cl_khr_fp64 on that device.
  explicit OpenCLSolver(const std::string& device = "any", bool useDouble = false);
  ~OpenCLSolver();
  OpenCLSolver(const OpenCLSolver&) = delete;
  OpenCLSolver& operator=(const OpenCLSolver&) = delete;

  /// "platform: device (type)" for every device of every platform; empty without a platform.
  static std::vector<std::string> ListDevices();

  const std::string& DeviceName() const;
  bool DoublePrecision() const;

  /// Copies the model and the solver data to the device (done once per model). Both must stay
  /// alive, unchanged, while Solve is called with them (the float finish reads them).
  void Upload(const BRepModel& model, const SolverData& data);

  /// Solves `samples` (after Upload with the same model and data; without it, or with another
  /// model or data, it uploads them first), `chunk` samples per launch (0: chunks of one size,
  /// each within 64 MiB of result and sample buffers: on a GPU four from 262,144 samples on and
  /// at least 65,536 each below, on a CPU device sixteen from 262,144 on and at least 16,384
  /// each below). With
  /// `which`, only samples[which[j]] (the others' results stay as SampleResult() leaves them).
  /// `progress(done)`, where given, is called after each chunk with the samples solved so far
  /// (of which->size() or samples.size()); false stops the solve: Solve returns false, the
  /// samples not yet solved left failed. One call keeps the device busy (the next chunk is
  /// packed while one is solved); the filter calls it once, not once per progress step.
  bool Solve(const BRepModel& model, const SolverData& data, const SolverOptions& options,
    const std::vector<Sample>& samples, std::vector<SampleResult>& results, size_t chunk = 0,
    const std::vector<size_t>* which = nullptr,
    const std::function<bool(size_t)>& progress = nullptr);

  /// The ray thickness of every sample (after Upload with the same model and data):
  /// NativeSolver::RayThickness on this device, in double wherever the device has it (in float
  /// only on a device without cl_khr_fp64).
  void RayThickness(const BRepModel& model, const SolverData& data,
    const std::vector<Sample>& samples, std::vector<double>& thickness,
    std::vector<int>* face = nullptr);

  /// Where the last Solve's time went, in seconds: Order, the samples' SpatialOrder; Host, their
  /// packing and the results' unpacking (on every core, overlapping the device's work); Wait,
  /// the host's wait for the device's results; Kernels, the kernels' own time on the device
  /// (OpenCL's profiling; 0 where the device reports none). The float finish on the host (a
  /// device without double precision) is in none of them.
  struct Phases
  {
    double Order = 0.0, Host = 0.0, Wait = 0.0, Kernels = 0.0;
  };
  const Phases& LastPhases() const;

  /// Bytes of device memory held (model, s1, BVH and the chunk buffers).
  size_t DeviceBytes() const;

  /// Whether Solve finishes the float kernels' results in double (default on; the double
  /// kernels' results are final): each contact polished and certified again, and the samples the
  /// float kernels leave failed or whose sphere holds boundary solved again in double. On a
  /// device with double precision (cl_khr_fp64) all of it runs on the device (FinishesOnDevice);
  /// elsewhere on the host, by the native device. Off, Solve returns the float kernels' own
  /// results: the tests measure the kernels alone that way.
  void SetFinish(bool on) { Finish = on; }
  bool GetFinish() const { return Finish; }

  /// True where the float kernels' finish runs on the device (float asked, cl_khr_fp64 there,
  /// not SetFinishOnHost).
  bool FinishesOnDevice() const;

  /// Runs the float kernels' finish on the host (the native device) even where the device has
  /// double precision: for a device whose double precision is slow (consumer GPUs run it at
  /// 1/16 to 1/64 of float), and for the tests that compare the two places.
  void SetFinishOnHost(bool on) { FinishOnHost = on; }

private:
  bool Finish = true;
  bool FinishOnHost = false;
  struct Impl;
  std::unique_ptr<Impl> P;
};

} // namespace brt
