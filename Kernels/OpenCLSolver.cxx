#include "OpenCLSolver.h"

#include "KernelData.h"
#include "NativeSolver.h"

#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <map>
#include <mutex>
#include <sstream>
#include <vector>

namespace brt
{
extern const char* const ThicknessKernelSource; // generated from thickness.cl at build time

namespace
{
constexpr size_t SampleReals = KernelSampleReals;
constexpr size_t OutReals = KernelOutReals;
constexpr size_t OutInts = KernelOutInts;

std::string Lower(std::string s)
{
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

void Check(cl_int err, const char* what)
{
  if (err != CL_SUCCESS)
    throw OpenCLError(std::string("OpenCL: ") + what + " failed (error " + std::to_string(err) + ")");
}

std::string Info(cl_platform_id p, cl_platform_info what)
{
  size_t n = 0;
  clGetPlatformInfo(p, what, 0, nullptr, &n);
  std::string s(n, '\0');
  clGetPlatformInfo(p, what, n, s.data(), nullptr);
  return s.c_str();
}

std::string Info(cl_device_id d, cl_device_info what)
{
  size_t n = 0;
  clGetDeviceInfo(d, what, 0, nullptr, &n);
  std::string s(n, '\0');
  clGetDeviceInfo(d, what, n, s.data(), nullptr);
  return s.c_str();
}

struct DeviceEntry
{
  cl_platform_id Platform;
  cl_device_id Device;
  cl_device_type Type;
  std::string Label; ///< "platform: device (type)"
};

std::vector<DeviceEntry> Devices()
{
  std::vector<DeviceEntry> out;
  cl_uint np = 0;
  if (clGetPlatformIDs(0, nullptr, &np) != CL_SUCCESS || np == 0)
    return out;
  std::vector<cl_platform_id> platforms(np);
  clGetPlatformIDs(np, platforms.data(), nullptr);
  for (cl_platform_id p : platforms)
  {
    cl_uint nd = 0;
    if (clGetDeviceIDs(p, CL_DEVICE_TYPE_ALL, 0, nullptr, &nd) != CL_SUCCESS || nd == 0)
      continue;
    std::vector<cl_device_id> devices(nd);
    clGetDeviceIDs(p, CL_DEVICE_TYPE_ALL, nd, devices.data(), nullptr);
    for (cl_device_id d : devices)
    {
      cl_device_type type = 0;
      clGetDeviceInfo(d, CL_DEVICE_TYPE, sizeof(type), &type, nullptr);
      const char* kind = (type & CL_DEVICE_TYPE_GPU) ? "GPU" : (type & CL_DEVICE_TYPE_CPU) ? "CPU" : "other";
      out.push_back({ p, d, type,
        Info(p, CL_PLATFORM_NAME) + ": " + Info(d, CL_DEVICE_NAME) + " (" + kind + ")" });
    }
  }
  return out;
}

/// Context, queue and built program of one device and precision; built once, kept for the
/// process (the kernel source is compiled once per context).
struct Runtime
{
  cl_context Context = nullptr;
  cl_command_queue Queue = nullptr;
  cl_program Program = nullptr;
  cl_kernel Kernel = nullptr;
  std::string Name;
  bool Double = false;
  std::mutex Lock; ///< one launch sequence at a time on the shared kernel object
  ~Runtime()
  {
    if (Kernel)
      clReleaseKernel(Kernel);
    if (Program)
      clReleaseProgram(Program);
    if (Queue)
      clReleaseCommandQueue(Queue);
    if (Context)
      clReleaseContext(Context);
  }
};

std::shared_ptr<Runtime> GetRuntime(const DeviceEntry& dev, bool useDouble)
{
  static std::mutex mutex;
  static std::map<std::pair<cl_device_id, bool>, std::shared_ptr<Runtime>> cache;
  std::lock_guard<std::mutex> guard(mutex);
  auto it = cache.find({ dev.Device, useDouble });
  if (it != cache.end())
    return it->second;
  auto rt = std::make_shared<Runtime>();
  rt->Name = dev.Label;
  rt->Double = useDouble;
  cl_int err = CL_SUCCESS;
  rt->Context = clCreateContext(nullptr, 1, &dev.Device, nullptr, nullptr, &err);
  Check(err, "clCreateContext");
  rt->Queue = clCreateCommandQueue(rt->Context, dev.Device, 0, &err);
  Check(err, "clCreateCommandQueue");
  const char* src = ThicknessKernelSource;
  rt->Program = clCreateProgramWithSource(rt->Context, 1, &src, nullptr, &err);
  Check(err, "clCreateProgramWithSource");
  const char* options = useDouble ? "-DBRT_DOUBLE" : "";
  if (clBuildProgram(rt->Program, 1, &dev.Device, options, nullptr, nullptr) != CL_SUCCESS)
  {
    size_t n = 0;
    clGetProgramBuildInfo(rt->Program, dev.Device, CL_PROGRAM_BUILD_LOG, 0, nullptr, &n);
    std::string log(n, '\0');
    clGetProgramBuildInfo(rt->Program, dev.Device, CL_PROGRAM_BUILD_LOG, n, log.data(), nullptr);
    throw OpenCLError("OpenCL: the thickness kernel does not build on " + dev.Label + ":\n" + log);
  }
  rt->Kernel = clCreateKernel(rt->Program, "brt_solve", &err);
  Check(err, "clCreateKernel");
  cache[{ dev.Device, useDouble }] = rt;
  return rt;
}

struct Buffer
{
  cl_mem Mem = nullptr;
  size_t Bytes = 0;
  Buffer() = default;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  ~Buffer() { Reset(); }
  void Reset()
  {
    if (Mem)
      clReleaseMemObject(Mem);
    Mem = nullptr;
    Bytes = 0;
  }
  template <class T>
  void Write(cl_context ctx, cl_command_queue q, const std::vector<T>& v)
  {
    const size_t bytes = std::max<size_t>(1, v.size()) * sizeof(T);
    if (bytes != Bytes)
    {
      Reset();
      cl_int err = CL_SUCCESS;
      Mem = clCreateBuffer(ctx, CL_MEM_READ_ONLY, bytes, nullptr, &err);
      Check(err, "clCreateBuffer");
      Bytes = bytes;
    }
    if (!v.empty())
      Check(clEnqueueWriteBuffer(q, Mem, CL_FALSE, 0, v.size() * sizeof(T), v.data(), 0, nullptr, nullptr),
        "clEnqueueWriteBuffer");
  }
  void Allocate(cl_context ctx, size_t bytes, cl_mem_flags flags)
  {
    if (bytes == Bytes && Mem)
      return;
    Reset();
    cl_int err = CL_SUCCESS;
    Mem = clCreateBuffer(ctx, flags, std::max<size_t>(1, bytes), nullptr, &err);
    Check(err, "clCreateBuffer");
    Bytes = bytes;
  }
};
} // namespace

struct OpenCLSolver::Impl
{
  std::shared_ptr<Runtime> RT;
  // Model buffers: 0..19 are kernel arguments 0..19, 20 (the vertex table) argument 33, 21..27
  // (the certification's) arguments 34..40.
  static constexpr int ModelBuffers = 28;
  int PatchCount = 0;
  bool HasBoxes = false;
  /// The same model for the native device: the float kernels' finish in double.
  std::unique_ptr<NativeSolver> Native;
  Buffer Model[ModelBuffers];
  Buffer Samples, SampleFace, OutReal, OutInt;
  /// Per sample of the last Solve: 1 where the kernels' pass without clearance found it.
  std::vector<unsigned char> ExactPass;

  template <class T>
  void UploadAs(const BRepModel& m, const SolverData& data);
  template <class T>
  void SolveAs(const BRepModel& m, const SolverData& data, const SolverOptions& options,
    const std::vector<Sample>& samples, std::vector<SampleResult>& results, size_t chunk);
};

OpenCLSolver::OpenCLSolver(const std::string& device, bool useDouble)
  : P(std::make_unique<Impl>())
{
  const std::vector<DeviceEntry> devices = Devices();
  if (devices.empty())
    throw OpenCLError("OpenCL: no platform or device found (the ICD loader found no driver; "
                      "install pocl-opencl-icd for the CPU or the GPU vendor's OpenCL driver)");
  const std::string want = Lower(device);
  const DeviceEntry* pick = nullptr;
  if (want == "any" || want.empty())
  {
    for (const auto& d : devices)
      if (d.Type & CL_DEVICE_TYPE_GPU)
      {
        pick = &d;
        break;
      }
    if (!pick)
      pick = &devices.front();
  }
  else
  {
    for (const auto& d : devices)
    {
      if ((want == "gpu" && (d.Type & CL_DEVICE_TYPE_GPU)) ||
        (want == "cpu" && (d.Type & CL_DEVICE_TYPE_CPU)) ||
        (want != "gpu" && want != "cpu" && Lower(d.Label).find(want) != std::string::npos))
      {
        pick = &d;
        break;
      }
    }
  }
  if (!pick)
  {
    std::ostringstream msg;
    msg << "OpenCL: no device matches '" << device << "'; devices found:";
    for (const auto& d : devices)
      msg << "\n  " << d.Label;
    throw OpenCLError(msg.str());
  }
  if (useDouble && Info(pick->Device, CL_DEVICE_EXTENSIONS).find("cl_khr_fp64") == std::string::npos)
    throw OpenCLError("OpenCL: " + pick->Label + " has no double precision (cl_khr_fp64)");
  P->RT = GetRuntime(*pick, useDouble);
}

OpenCLSolver::~OpenCLSolver() = default;

std::vector<std::string> OpenCLSolver::ListDevices()
{
  std::vector<std::string> out;
  for (const auto& d : Devices())
    out.push_back(d.Label);
  return out;
}

const std::string& OpenCLSolver::DeviceName() const
{
  return P->RT->Name;
}

bool OpenCLSolver::DoublePrecision() const
{
  return P->RT->Double;
}

size_t OpenCLSolver::DeviceBytes() const
{
  size_t n = P->Samples.Bytes + P->SampleFace.Bytes + P->OutReal.Bytes + P->OutInt.Bytes;
  for (const auto& b : P->Model)
    n += b.Bytes;
  return n;
}

template <class T>
void OpenCLSolver::Impl::UploadAs(const BRepModel& m, const SolverData& data)
{
  // Kept until the clFinish below: the writes do not block.
  const KernelModel<T> k = PackKernelModel<T>(m, data);
  cl_context ctx = RT->Context;
  cl_command_queue q = RT->Queue;
  Model[0].Write(ctx, q, k.Patches);
  Model[1].Write(ctx, q, k.PatchAnchor);
  Model[2].Write(ctx, q, k.PatchDomain);
  Model[3].Write(ctx, q, k.FaceInfo);
  Model[4].Write(ctx, q, k.FaceDomain);
  Model[5].Write(ctx, q, k.Breaks);
  Model[6].Write(ctx, q, k.Loops);
  Model[7].Write(ctx, q, k.Trim);
  Model[8].Write(ctx, q, k.TrimEdge);
  Model[9].Write(ctx, q, k.TrimRange);
  Model[10].Write(ctx, q, k.EdgeInfo);
  Model[11].Write(ctx, q, k.EdgeRange);
  Model[12].Write(ctx, q, k.EdgeSeg);
  Model[13].Write(ctx, q, k.EdgeAnchor);
  Model[14].Write(ctx, q, k.EdgeSegRange);
  Model[15].Write(ctx, q, k.S1Point);
  Model[16].Write(ctx, q, k.S1Face);
  Model[17].Write(ctx, q, k.S1UV);
  Model[18].Write(ctx, q, k.NodeBox);
  Model[19].Write(ctx, q, k.NodeInfo);
  Model[20].Write(ctx, q, k.VertexInfo);
  Model[21].Write(ctx, q, k.PatchFace);
  Model[22].Write(ctx, q, k.EdgeSegEdge);
  Model[23].Write(ctx, q, k.PatchBoxes);
  Model[24].Write(ctx, q, k.EdgeBoxes);
  Model[25].Write(ctx, q, k.BoxNodeBox);
  Model[26].Write(ctx, q, k.BoxNodeInfo);
  Model[27].Write(ctx, q, k.BoxItems);
  PatchCount = static_cast<int>(m.Patches.size());
  HasBoxes = k.HasBoxes();
  Native.reset();
  if (!RT->Double)
    Native = std::make_unique<NativeSolver>(m, data); // the float kernels' finish
  Check(clFinish(q), "clFinish");
}

template <class T>
void OpenCLSolver::Impl::SolveAs(const BRepModel& model, const SolverData& data,
  const SolverOptions& options, const std::vector<Sample>& samples,
  std::vector<SampleResult>& results, size_t chunk)
{
  results.assign(samples.size(), SampleResult());
  ExactPass.assign(samples.size(), 0);
  if (samples.empty())
    return;
  if (data.Nodes.empty())
  {
    for (auto& r : results)
      r.Reason = FailReason::NoOppositePoint;
    return;
  }
  const size_t perSample = (SampleReals + OutReals) * sizeof(T) + (OutInts + 1) * sizeof(int);
  if (chunk == 0)
    chunk = std::max<size_t>(1024, (64u << 20) / perSample);
  chunk = std::min(chunk, samples.size());
  cl_context ctx = RT->Context;
  cl_command_queue q = RT->Queue;
  cl_kernel k = RT->Kernel;
  Samples.Allocate(ctx, chunk * SampleReals * sizeof(T), CL_MEM_READ_ONLY);
  SampleFace.Allocate(ctx, chunk * sizeof(int), CL_MEM_READ_ONLY);
  OutReal.Allocate(ctx, chunk * OutReals * sizeof(T), CL_MEM_WRITE_ONLY);
  OutInt.Allocate(ctx, chunk * OutInts * sizeof(int), CL_MEM_WRITE_ONLY);
  const KernelScalars ks = GetKernelScalars<T>(model, data, options);
  const T scale = static_cast<T>(ks.Scale), stepTol = static_cast<T>(ks.StepTol),
          newtonTol = static_cast<T>(ks.NewtonTol), slack = static_cast<T>(ks.Slack),
          clearance = static_cast<T>(ks.Clearance), s1Spacing = static_cast<T>(ks.S1Spacing);
  const cl_int maxIt = ks.MaxIterations, maxEdgeIt = ks.MaxEdgeIterations;
  std::vector<T> in(chunk * SampleReals), outR(chunk * OutReals);
  std::vector<int> outI(chunk * OutInts), faces(chunk);

  std::lock_guard<std::mutex> guard(RT->Lock);
  for (cl_uint a = 0; a < 20; ++a)
    Check(clSetKernelArg(k, a, sizeof(cl_mem), &Model[a].Mem), "clSetKernelArg");
  Check(clSetKernelArg(k, 33, sizeof(cl_mem), &Model[20].Mem), "clSetKernelArg");
  for (cl_uint a = 21; a < ModelBuffers; ++a)
    Check(clSetKernelArg(k, a + 13, sizeof(cl_mem), &Model[a].Mem), "clSetKernelArg");
  const cl_int patchCount = PatchCount, certify = ks.Certify && HasBoxes ? 1 : 0;
  Check(clSetKernelArg(k, 41, sizeof(cl_int), &patchCount), "clSetKernelArg");
  Check(clSetKernelArg(k, 42, sizeof(cl_int), &certify), "clSetKernelArg");
  for (size_t first = 0; first < samples.size(); first += chunk)
  {
    const size_t n = std::min(chunk, samples.size() - first);
    for (size_t i = 0; i < n; ++i)
    {
      PackSample(data, samples[first + i], &in[SampleReals * i]);
      faces[i] = samples[first + i].Face;
    }
    Check(clEnqueueWriteBuffer(q, SampleFace.Mem, CL_FALSE, 0, n * sizeof(int), faces.data(), 0, nullptr, nullptr),
      "clEnqueueWriteBuffer");
    Check(clEnqueueWriteBuffer(q, Samples.Mem, CL_FALSE, 0, n * SampleReals * sizeof(T), in.data(), 0, nullptr, nullptr),
      "clEnqueueWriteBuffer");
    const cl_int count = static_cast<cl_int>(n);
    Check(clSetKernelArg(k, 20, sizeof(cl_mem), &Samples.Mem), "clSetKernelArg");
    Check(clSetKernelArg(k, 21, sizeof(cl_mem), &SampleFace.Mem), "clSetKernelArg");
    Check(clSetKernelArg(k, 22, sizeof(cl_int), &count), "clSetKernelArg");
    Check(clSetKernelArg(k, 23, sizeof(T), &scale), "clSetKernelArg");
    Check(clSetKernelArg(k, 24, sizeof(T), &stepTol), "clSetKernelArg");
    Check(clSetKernelArg(k, 25, sizeof(T), &newtonTol), "clSetKernelArg");
    Check(clSetKernelArg(k, 26, sizeof(T), &slack), "clSetKernelArg");
    Check(clSetKernelArg(k, 27, sizeof(T), &clearance), "clSetKernelArg");
    Check(clSetKernelArg(k, 28, sizeof(cl_int), &maxIt), "clSetKernelArg");
    Check(clSetKernelArg(k, 29, sizeof(cl_int), &maxEdgeIt), "clSetKernelArg");
    Check(clSetKernelArg(k, 30, sizeof(cl_mem), &OutReal.Mem), "clSetKernelArg");
    Check(clSetKernelArg(k, 31, sizeof(cl_mem), &OutInt.Mem), "clSetKernelArg");
    Check(clSetKernelArg(k, 32, sizeof(T), &s1Spacing), "clSetKernelArg");
    const size_t local = 64;
    const size_t global = (n + local - 1) / local * local;
    Check(clEnqueueNDRangeKernel(q, k, 1, nullptr, &global, &local, 0, nullptr, nullptr),
      "clEnqueueNDRangeKernel");
    Check(clEnqueueReadBuffer(q, OutReal.Mem, CL_FALSE, 0, n * OutReals * sizeof(T), outR.data(), 0, nullptr, nullptr),
      "clEnqueueReadBuffer");
    Check(clEnqueueReadBuffer(q, OutInt.Mem, CL_TRUE, 0, n * OutInts * sizeof(int), outI.data(), 0, nullptr, nullptr),
      "clEnqueueReadBuffer");
    for (size_t i = 0; i < n; ++i)
      ExactPass[first + i] = UnpackResult(samples[first + i], &outR[OutReals * i],
        &outI[OutInts * i], results[first + i]) ? 1 : 0;
  }
}

void OpenCLSolver::Upload(const BRepModel& model, const SolverData& data)
{
  if (P->RT->Double)
    P->UploadAs<double>(model, data);
  else
    P->UploadAs<float>(model, data);
}

void OpenCLSolver::Solve(const BRepModel& model, const SolverData& data,
  const SolverOptions& options, const std::vector<Sample>& samples,
  std::vector<SampleResult>& results, size_t chunk)
{
  if (P->RT->Double)
    P->SolveAs<double>(model, data, options, samples, results, chunk);
  else
    P->SolveAs<float>(model, data, options, samples, results, chunk);
  // The double kernels run the whole solve, the certification included: nothing is left to
  // the host. The float kernels' contacts are refined in double (NativeSolver::Polish: the
  // contact's own Newton, then the local part of the second look), every sphere is certified
  // again in double, and the samples the float kernels fail or that fail the certification are
  // solved by the native device: the same source in double, on every core.
  if (!HostFinish || P->RT->Double || !P->Native)
    return;
  std::vector<size_t> hard, solved;
  for (size_t i = 0; i < samples.size(); ++i)
    (results[i].Type == ContactType::Failed ? hard : solved).push_back(i);
  SolverOptions exact = options;
  exact.Clearance = 0.0;
  const std::vector<unsigned char>& pass = P->ExactPass;
  std::vector<unsigned char> redo(samples.size(), 0);
  const NativeSolver& native = *P->Native;
  ParallelFor(solved.size(), 0, [&](size_t j) {
    const size_t i = solved[j];
    const SolverOptions& o = pass[i] ? exact : options;
    native.Polish(o, samples[i], results[i]);
    redo[i] = options.Certify && native.HoldsBoundary(o, samples[i], results[i]);
  });
  for (size_t i : solved)
    if (redo[i])
      hard.push_back(i);
  if (!hard.empty())
    native.Solve(options, samples, results, &hard);
}

} // namespace brt
