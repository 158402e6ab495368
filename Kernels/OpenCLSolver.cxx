#include "OpenCLSolver.h"

#include "KernelData.h"
#include "NativeSolver.h"

#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
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

double Since(std::chrono::steady_clock::time_point t0)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Calls f(first, last) over [0, n) in blocks on every core; a few blocks' worth on the calling
/// thread alone (starting the threads costs more than packing them).
template <class F>
void ForBlocks(size_t n, F&& f)
{
  constexpr size_t block = 4096;
  if (n <= 2 * block)
  {
    f(size_t(0), n);
    return;
  }
  ParallelFor((n + block - 1) / block, 0, [&](size_t b) { f(b * block, std::min(n, (b + 1) * block)); });
}

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

/// Context and queue of one device, with its programs: the float one and, on a device with
/// cl_khr_fp64, the double one (built on first use; kept for the process, so the kernel source
/// is compiled once per device and precision).
struct Runtime
{
  cl_device_id Device = nullptr;
  cl_context Context = nullptr;
  cl_command_queue Queue = nullptr;
  cl_program Program[2] = { nullptr, nullptr }; ///< [0] float, [1] double
  cl_kernel Solve[2] = { nullptr, nullptr };
  cl_kernel Ray[2] = { nullptr, nullptr }; ///< brt_ray per precision
  cl_kernel Finish = nullptr; ///< the double program's brt_finish
  std::string Name;
  bool HasDouble = false;
  bool IsGpu = false; ///< chunks of at least 65,536 work-items there, 16,384 samples elsewhere
  std::mutex Lock; ///< one launch sequence at a time on the shared kernel objects
  ~Runtime()
  {
    for (int k = 0; k < 2; ++k)
    {
      if (Solve[k])
        clReleaseKernel(Solve[k]);
      if (Ray[k])
        clReleaseKernel(Ray[k]);
      if (Program[k])
        clReleaseProgram(Program[k]);
    }
    if (Finish)
      clReleaseKernel(Finish);
    if (Queue)
      clReleaseCommandQueue(Queue);
    if (Context)
      clReleaseContext(Context);
  }
  /// Builds the program of one precision (with its kernels) unless built.
  void Build(bool useDouble)
  {
    const int k = useDouble ? 1 : 0;
    if (Program[k])
      return;
    cl_int err = CL_SUCCESS;
    const char* src = ThicknessKernelSource;
    Program[k] = clCreateProgramWithSource(Context, 1, &src, nullptr, &err);
    Check(err, "clCreateProgramWithSource");
    // BRT_OPENCL_OPTIONS: more build options, for diagnostics (NVIDIA's -cl-nv-verbose prints
    // each function's registers and spills into the build log, BRT_OPENCL_BUILD_LOG shows it).
    std::string options = useDouble ? "-DBRT_DOUBLE" : "";
    if (const char* more = std::getenv("BRT_OPENCL_OPTIONS"))
      options += std::string(" ") + more;
    if (clBuildProgram(Program[k], 1, &Device, options.c_str(), nullptr, nullptr) != CL_SUCCESS)
    {
      size_t n = 0;
      clGetProgramBuildInfo(Program[k], Device, CL_PROGRAM_BUILD_LOG, 0, nullptr, &n);
      std::string log(n, '\0');
      clGetProgramBuildInfo(Program[k], Device, CL_PROGRAM_BUILD_LOG, n, log.data(), nullptr);
      clReleaseProgram(Program[k]);
      Program[k] = nullptr;
      throw OpenCLError("OpenCL: the thickness kernel does not build on " + Name + " (" +
        (useDouble ? "double" : "float") + "):\n" + log);
    }
    if (std::getenv("BRT_OPENCL_BUILD_LOG"))
    {
      size_t n = 0;
      clGetProgramBuildInfo(Program[k], Device, CL_PROGRAM_BUILD_LOG, 0, nullptr, &n);
      std::string log(n, '\0');
      clGetProgramBuildInfo(Program[k], Device, CL_PROGRAM_BUILD_LOG, n, log.data(), nullptr);
      std::fprintf(stderr, "OpenCL build log (%s, options '%s'):\n%s\n", useDouble ? "double" : "float",
        options.c_str(), log.c_str());
    }
    Solve[k] = clCreateKernel(Program[k], "brt_solve", &err);
    Check(err, "clCreateKernel");
    Ray[k] = clCreateKernel(Program[k], "brt_ray", &err);
    Check(err, "clCreateKernel");
    if (useDouble)
    {
      Finish = clCreateKernel(Program[k], "brt_finish", &err);
      Check(err, "clCreateKernel");
    }
  }
};

std::shared_ptr<Runtime> GetRuntime(const DeviceEntry& dev, bool useDouble)
{
  static std::mutex mutex;
  static std::map<cl_device_id, std::shared_ptr<Runtime>> cache;
  std::lock_guard<std::mutex> guard(mutex);
  std::shared_ptr<Runtime>& rt = cache[dev.Device];
  if (!rt)
  {
    auto made = std::make_shared<Runtime>();
    made->Device = dev.Device;
    made->Name = dev.Label;
    made->HasDouble = Info(dev.Device, CL_DEVICE_EXTENSIONS).find("cl_khr_fp64") != std::string::npos;
    made->IsGpu = (dev.Type & CL_DEVICE_TYPE_GPU) != 0;
    cl_int err = CL_SUCCESS;
    made->Context = clCreateContext(nullptr, 1, &dev.Device, nullptr, nullptr, &err);
    Check(err, "clCreateContext");
    // Profiling on: the kernels' own time (OpenCLSolver::LastPhases) costs two timestamps each.
    made->Queue = clCreateCommandQueue(made->Context, dev.Device, CL_QUEUE_PROFILING_ENABLE, &err);
    Check(err, "clCreateCommandQueue");
    rt = made;
  }
  std::lock_guard<std::mutex> launch(rt->Lock);
  rt->Build(useDouble);
  if (!useDouble && rt->HasDouble)
  {
    // The float solve's finish on the device. A driver that cannot build the double program
    // leaves the finish to the host rather than the float solve unusable.
    try
    {
      rt->Build(true);
    }
    catch (const OpenCLError&)
    {
      rt->HasDouble = false;
    }
  }
  return rt;
}

/// Host staging of one chunk in flight (OpenCLSolver::Impl::SolveAs), with its events.
template <class T>
struct HostSlot
{
  std::vector<T> In, OutR;
  std::vector<double> In64, OutR64;
  std::vector<int> OutI, Faces, Redo;
  std::vector<cl_int> Chains; ///< its chains' first samples (from First), then Count
  cl_event Kernel[2] = { nullptr, nullptr };
  cl_event Read = nullptr;
  size_t First = 0, Count = 0;
  HostSlot() = default;
  HostSlot(const HostSlot&) = delete;
  HostSlot& operator=(const HostSlot&) = delete;
  ~HostSlot() { Release(); }
  /// Room for `chunk` samples (never shrinks).
  void Grow(size_t chunk, bool finish)
  {
    auto grow = [](auto& v, size_t n) {
      if (v.size() < n)
        v.resize(n);
    };
    grow(In, chunk * SampleReals);
    grow(OutI, chunk * OutInts);
    grow(Faces, chunk);
    if (finish)
    {
      grow(In64, chunk * SampleReals);
      grow(OutR64, chunk * OutReals);
      grow(Redo, chunk);
    }
    else
      grow(OutR, chunk * OutReals);
  }
  void Release()
  {
    for (cl_event* e : { &Kernel[0], &Kernel[1], &Read })
      if (*e)
      {
        clReleaseEvent(*e);
        *e = nullptr;
      }
  }
};

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
  bool Double = false; ///< the precision asked for
  /// The model's buffers (kernel arguments 0..32), per precision: [0] float, [1] double; the
  /// launch's arguments follow them (LAUNCH_PARAMS in thickness.cl), then the outputs.
  static constexpr int ModelBuffers = 33;
  static constexpr int LaunchArg = ModelBuffers, OutArg = ModelBuffers + 13;
  Buffer Model[2][ModelBuffers];
  int PatchCount = 0;
  bool HasBoxes = false;
  /// What the buffers hold (Upload): Solve and RayThickness upload another model first.
  const BRepModel* UploadedModel = nullptr;
  const SolverData* UploadedData = nullptr;
  /// The float kernels' finish on the host, where the device has no double precision.
  std::unique_ptr<NativeSolver> Native;
  Buffer Samples[2], SampleFace, OutReal[2], OutInt[2], Redo, ChainFirst;
  /// The host staging of SolveAs, per precision.
  HostSlot<float> SlotsFloat[2];
  HostSlot<double> SlotsDouble[2];
  template <class T>
  HostSlot<T>* SlotsOf();
  /// Per sample of the last Solve: 1 where the kernels' pass without clearance found it.
  std::vector<unsigned char> ExactPass;
  /// Where the last Solve's time went.
  OpenCLSolver::Phases Times;

  template <class T>
  void UploadAs(const BRepModel& m, const SolverData& data);
  /// Solves samples[which[j]] (all when which is null) with the kernels of precision T, `chunk`
  /// per launch; with `finish` (float only), each chunk is finished on the device in double.
  /// Returns the samples whose finish asks for a solve in double.
  template <class T>
  std::vector<size_t> SolveAs(const BRepModel& m, const SolverData& data,
    const SolverOptions& options, const std::vector<Sample>& samples,
    std::vector<SampleResult>& results, const std::vector<size_t>* which, size_t chunk,
    bool finish, const std::function<bool(size_t)>* progress = nullptr, bool* stopped = nullptr);
  void SetArgs(cl_kernel k, int set, const Buffer& samples, int count, const KernelScalars& ks,
    bool asDouble);
  /// The chunk buffers of precision T for `chunk` samples.
  template <class T>
  void AllocateChunk(size_t chunk);
  /// Packs samples[index(i)], i < n, and queues them and their faces to the device (in and
  /// faces: host staging, at least n samples; kept until the queue's next blocking read).
  template <class T, class Index>
  void WriteChunk(const SolverData& data, const std::vector<Sample>& samples, Index index,
    size_t n, std::vector<T>& in, std::vector<int>& faces);
  template <class T>
  void RayAs(const BRepModel& m, const SolverData& data, const std::vector<Sample>& samples,
    std::vector<double>& thickness, std::vector<int>* face);
};

template <>
HostSlot<float>* OpenCLSolver::Impl::SlotsOf<float>()
{
  return SlotsFloat;
}

template <>
HostSlot<double>* OpenCLSolver::Impl::SlotsOf<double>()
{
  return SlotsDouble;
}

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
  P->Double = useDouble;
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
  return P->Double;
}

bool OpenCLSolver::FinishesOnDevice() const
{
  return !P->Double && P->RT->HasDouble && !FinishOnHost;
}

const OpenCLSolver::Phases& OpenCLSolver::LastPhases() const
{
  return P->Times;
}

size_t OpenCLSolver::DeviceBytes() const
{
  size_t n = P->SampleFace.Bytes + P->Redo.Bytes + P->ChainFirst.Bytes;
  for (int k = 0; k < 2; ++k)
  {
    n += P->Samples[k].Bytes + P->OutReal[k].Bytes + P->OutInt[k].Bytes;
    for (const auto& b : P->Model[k])
      n += b.Bytes;
  }
  return n;
}

template <class T>
void OpenCLSolver::Impl::UploadAs(const BRepModel& m, const SolverData& data)
{
  // Kept until the clFinish below: the writes do not block.
  const KernelModel<T> k = PackKernelModel<T>(m, data);
  cl_context ctx = RT->Context;
  cl_command_queue q = RT->Queue;
  Buffer* b = Model[sizeof(T) == 8 ? 1 : 0];
  b[0].Write(ctx, q, k.Patches);
  b[1].Write(ctx, q, k.PatchAnchor);
  b[2].Write(ctx, q, k.PatchDomain);
  b[3].Write(ctx, q, k.FaceInfo);
  b[4].Write(ctx, q, k.FaceDomain);
  b[5].Write(ctx, q, k.Breaks);
  b[6].Write(ctx, q, k.Loops);
  b[7].Write(ctx, q, k.Trim);
  b[8].Write(ctx, q, k.TrimEdge);
  b[9].Write(ctx, q, k.TrimRange);
  b[10].Write(ctx, q, k.EdgeInfo);
  b[11].Write(ctx, q, k.EdgeRange);
  b[12].Write(ctx, q, k.EdgeSeg);
  b[13].Write(ctx, q, k.EdgeAnchor);
  b[14].Write(ctx, q, k.EdgeSegRange);
  b[15].Write(ctx, q, k.S1Point);
  b[16].Write(ctx, q, k.S1Face);
  b[17].Write(ctx, q, k.S1UV);
  b[18].Write(ctx, q, k.NodeBox);
  b[19].Write(ctx, q, k.NodeInfo);
  b[20].Write(ctx, q, k.VertexInfo);
  b[21].Write(ctx, q, k.PatchFace);
  b[22].Write(ctx, q, k.EdgeSegEdge);
  b[23].Write(ctx, q, k.PatchBoxes);
  b[24].Write(ctx, q, k.EdgeBoxes);
  b[25].Write(ctx, q, k.BoxNodeBox);
  b[26].Write(ctx, q, k.BoxNodeInfo);
  b[27].Write(ctx, q, k.BoxItems);
  b[28].Write(ctx, q, k.TrimNodeBox);
  b[29].Write(ctx, q, k.TrimNodeInfo);
  b[30].Write(ctx, q, k.TrimItems);
  b[31].Write(ctx, q, k.PatchSector);
  b[32].Write(ctx, q, k.PatchHull);
  PatchCount = static_cast<int>(m.Patches.size());
  HasBoxes = k.HasBoxes();
  Check(clFinish(q), "clFinish");
}

void OpenCLSolver::Impl::SetArgs(cl_kernel k, int set, const Buffer& samples, int count,
  const KernelScalars& ks, bool asDouble)
{
  for (cl_uint a = 0; a < ModelBuffers; ++a)
    Check(clSetKernelArg(k, a, sizeof(cl_mem), &Model[set][a].Mem), "clSetKernelArg");
  const cl_int n = count, maxIt = ks.MaxIterations, maxEdgeIt = ks.MaxEdgeIterations,
               patchCount = PatchCount, mode = ks.Mode(HasBoxes);
  Check(clSetKernelArg(k, LaunchArg, sizeof(cl_mem), &samples.Mem), "clSetKernelArg");
  Check(clSetKernelArg(k, LaunchArg + 1, sizeof(cl_mem), &SampleFace.Mem), "clSetKernelArg");
  Check(clSetKernelArg(k, LaunchArg + 2, sizeof(cl_int), &n), "clSetKernelArg");
  const double reals[] = { ks.Scale, ks.StepTol, ks.NewtonTol, ks.Slack, ks.Clearance };
  for (cl_uint a = 0; a < 5; ++a)
  {
    if (asDouble)
      Check(clSetKernelArg(k, LaunchArg + 3 + a, sizeof(double), &reals[a]), "clSetKernelArg");
    else
    {
      const float f = static_cast<float>(reals[a]);
      Check(clSetKernelArg(k, LaunchArg + 3 + a, sizeof(float), &f), "clSetKernelArg");
    }
  }
  Check(clSetKernelArg(k, LaunchArg + 8, sizeof(cl_int), &maxIt), "clSetKernelArg");
  Check(clSetKernelArg(k, LaunchArg + 9, sizeof(cl_int), &maxEdgeIt), "clSetKernelArg");
  if (asDouble)
    Check(clSetKernelArg(k, LaunchArg + 10, sizeof(double), &ks.S1Spacing), "clSetKernelArg");
  else
  {
    const float f = static_cast<float>(ks.S1Spacing);
    Check(clSetKernelArg(k, LaunchArg + 10, sizeof(float), &f), "clSetKernelArg");
  }
  Check(clSetKernelArg(k, LaunchArg + 11, sizeof(cl_int), &patchCount), "clSetKernelArg");
  Check(clSetKernelArg(k, LaunchArg + 12, sizeof(cl_int), &mode), "clSetKernelArg");
}

template <class T>
void OpenCLSolver::Impl::AllocateChunk(size_t chunk)
{
  const int set = sizeof(T) == 8 ? 1 : 0;
  cl_context ctx = RT->Context;
  Samples[set].Allocate(ctx, chunk * SampleReals * sizeof(T), CL_MEM_READ_ONLY);
  SampleFace.Allocate(ctx, chunk * sizeof(int), CL_MEM_READ_ONLY);
  OutReal[set].Allocate(ctx, chunk * OutReals * sizeof(T), CL_MEM_READ_WRITE);
  OutInt[set].Allocate(ctx, chunk * OutInts * sizeof(int), CL_MEM_READ_WRITE);
}

template <class T, class Index>
void OpenCLSolver::Impl::WriteChunk(const SolverData& data, const std::vector<Sample>& samples,
  Index index, size_t n, std::vector<T>& in, std::vector<int>& faces)
{
  const int set = sizeof(T) == 8 ? 1 : 0;
  ForBlocks(n, [&](size_t a, size_t b) {
    for (size_t i = a; i < b; ++i)
    {
      PackSample(data, samples[index(i)], &in[SampleReals * i]);
      faces[i] = samples[index(i)].Face;
    }
  });
  Check(clEnqueueWriteBuffer(RT->Queue, SampleFace.Mem, CL_FALSE, 0, n * sizeof(int), faces.data(),
          0, nullptr, nullptr),
    "clEnqueueWriteBuffer");
  Check(clEnqueueWriteBuffer(RT->Queue, Samples[set].Mem, CL_FALSE, 0,
          n * SampleReals * sizeof(T), in.data(), 0, nullptr, nullptr),
    "clEnqueueWriteBuffer");
}

template <class T>
std::vector<size_t> OpenCLSolver::Impl::SolveAs(const BRepModel& model, const SolverData& data,
  const SolverOptions& options, const std::vector<Sample>& samples,
  std::vector<SampleResult>& results, const std::vector<size_t>* which, size_t chunk, bool finish,
  const std::function<bool(size_t)>* progress, bool* stopped)
{
  std::vector<size_t> again;
  const size_t total = which ? which->size() : samples.size();
  if (total == 0)
    return again;
  const int set = sizeof(T) == 8 ? 1 : 0;
  const size_t perSample = (SampleReals + OutReals) * (sizeof(T) + (finish ? 8 : 0)) +
    (2 * OutInts + 2) * sizeof(int);
  if (chunk == 0)
  {
    // At most 64 MiB of buffers, and several chunks where each still fills the device: the host
    // packs one chunk and unpacks another while the device solves a third, and the caller's
    // progress and abort come between chunks. A GPU: four chunks of at least 65,536 work-items
    // (the H200 holds about 34,000 of the kernel's threads at once), a work-item a chain of
    // samples (SolverOptions::Chain), so with chains of 8 at least 524,288 samples and their
    // buffers (147 MiB in float with the finish); a CPU device (PoCL): sixteen of at least
    // 16,384 samples, for the progress bar of a slow device.
    const size_t chainLength = static_cast<size_t>(ChainLength(options, RT->IsGpu));
    const size_t parts = RT->IsGpu ? 4 : 16, least = RT->IsGpu ? 65536 * chainLength : 16384;
    chunk = std::max<size_t>(1024, (64u << 20) / perSample);
    if (RT->IsGpu)
      chunk = std::max(chunk, least);
    chunk = std::min(chunk, std::max(least, (total + parts - 1) / parts));
    // Chunks of one size: 100,000 samples as two of 50,000, not 65,536 and a last one that
    // fills a GPU a third.
    const size_t count = (total + chunk - 1) / chunk;
    chunk = (total + count - 1) / count;
  }
  chunk = std::min(chunk, total);
  const KernelScalars ks = GetKernelScalars<T>(model, data, options);
  const KernelScalars ks64 = GetKernelScalars<double>(model, data, options);
  // The chains (solve_chain, ChainStarts: the native device's): a chunk holds whole ones (a
  // chain is at most KernelMaxChain samples, a chunk at least 1024 or all).
  std::vector<size_t> indices;
  if (!which)
  {
    indices.resize(total);
    for (size_t j = 0; j < total; ++j)
      indices[j] = j;
  }
  const std::vector<size_t> starts =
    ChainStarts(samples, which ? *which : indices, ChainLength(options, RT->IsGpu));
  cl_context ctx = RT->Context;
  cl_command_queue q = RT->Queue;
  AllocateChunk<T>(chunk);
  ChainFirst.Allocate(ctx, (chunk + 1) * sizeof(cl_int), CL_MEM_READ_ONLY);
  if (finish)
  {
    Samples[1].Allocate(ctx, chunk * SampleReals * sizeof(double), CL_MEM_READ_ONLY);
    OutReal[1].Allocate(ctx, chunk * OutReals * sizeof(double), CL_MEM_WRITE_ONLY);
    OutInt[1].Allocate(ctx, chunk * OutInts * sizeof(int), CL_MEM_WRITE_ONLY);
    Redo.Allocate(ctx, chunk * sizeof(int), CL_MEM_WRITE_ONLY);
  }

  // Two host slots: the queue runs in order, so one set of device buffers does, while the host
  // staging of a chunk must outlive its transfers (until its last read completes). Kept from
  // call to call: fresh staging for a million samples (about 120 MiB) cost its page faults and
  // zeroing on every solve.
  using Slot = HostSlot<T>;
  Slot* slots = SlotsOf<T>();
  for (int k = 0; k < 2; ++k)
    slots[k].Grow(chunk, finish);
  auto at = [&](size_t j) { return which ? (*which)[j] : j; };

  // Packs a slot's samples and queues their solve (and finish) and the read of the results.
  auto launch = [&](Slot& s) {
    const size_t first = s.First, n = s.Count;
    const auto t0 = std::chrono::steady_clock::now();
    WriteChunk(data, samples, [&](size_t i) { return at(first + i); }, n, s.In, s.Faces);
    if (finish)
      ForBlocks(n, [&](size_t a, size_t b) {
        for (size_t i = a; i < b; ++i)
          PackSample(data, samples[at(first + i)], &s.In64[SampleReals * i]);
      });
    Times.Host += Since(t0);
    // One work-item per chain; the finish, one per sample.
    const cl_int chains = static_cast<cl_int>(s.Chains.size() - 1);
    Check(clEnqueueWriteBuffer(q, ChainFirst.Mem, CL_FALSE, 0, s.Chains.size() * sizeof(cl_int),
            s.Chains.data(), 0, nullptr, nullptr),
      "clEnqueueWriteBuffer");
    const size_t local = 64;
    const size_t global = (static_cast<size_t>(chains) + local - 1) / local * local;
    const size_t globalFinish = (n + local - 1) / local * local;
    cl_kernel k = RT->Solve[set];
    SetArgs(k, set, Samples[set], static_cast<int>(n), ks, sizeof(T) == 8);
    Check(clSetKernelArg(k, OutArg, sizeof(cl_mem), &OutReal[set].Mem), "clSetKernelArg");
    Check(clSetKernelArg(k, OutArg + 1, sizeof(cl_mem), &OutInt[set].Mem), "clSetKernelArg");
    Check(clSetKernelArg(k, OutArg + 2, sizeof(cl_mem), &ChainFirst.Mem), "clSetKernelArg");
    Check(clSetKernelArg(k, OutArg + 3, sizeof(cl_int), &chains), "clSetKernelArg");
    Check(clEnqueueNDRangeKernel(q, k, 1, nullptr, &global, &local, 0, nullptr, &s.Kernel[0]),
      "clEnqueueNDRangeKernel");
    if (finish)
    {
      cl_kernel f = RT->Finish;
      Check(clEnqueueWriteBuffer(q, Samples[1].Mem, CL_FALSE, 0, n * SampleReals * sizeof(double), s.In64.data(), 0, nullptr, nullptr),
        "clEnqueueWriteBuffer");
      SetArgs(f, 1, Samples[1], static_cast<int>(n), ks64, true);
      Check(clSetKernelArg(f, OutArg, sizeof(cl_mem), &OutReal[0].Mem), "clSetKernelArg");
      Check(clSetKernelArg(f, OutArg + 1, sizeof(cl_mem), &OutInt[0].Mem), "clSetKernelArg");
      Check(clSetKernelArg(f, OutArg + 2, sizeof(cl_mem), &OutReal[1].Mem), "clSetKernelArg");
      Check(clSetKernelArg(f, OutArg + 3, sizeof(cl_mem), &OutInt[1].Mem), "clSetKernelArg");
      Check(clSetKernelArg(f, OutArg + 4, sizeof(cl_mem), &Redo.Mem), "clSetKernelArg");
      Check(clEnqueueNDRangeKernel(q, f, 1, nullptr, &globalFinish, &local, 0, nullptr, &s.Kernel[1]),
        "clEnqueueNDRangeKernel");
      Check(clEnqueueReadBuffer(q, OutReal[1].Mem, CL_FALSE, 0, n * OutReals * sizeof(double), s.OutR64.data(), 0, nullptr, nullptr),
        "clEnqueueReadBuffer");
      Check(clEnqueueReadBuffer(q, Redo.Mem, CL_FALSE, 0, n * sizeof(int), s.Redo.data(), 0, nullptr, nullptr),
        "clEnqueueReadBuffer");
      Check(clEnqueueReadBuffer(q, OutInt[1].Mem, CL_FALSE, 0, n * OutInts * sizeof(int), s.OutI.data(), 0, nullptr, &s.Read),
        "clEnqueueReadBuffer");
    }
    else
    {
      Check(clEnqueueReadBuffer(q, OutReal[set].Mem, CL_FALSE, 0, n * OutReals * sizeof(T), s.OutR.data(), 0, nullptr, nullptr),
        "clEnqueueReadBuffer");
      Check(clEnqueueReadBuffer(q, OutInt[set].Mem, CL_FALSE, 0, n * OutInts * sizeof(int), s.OutI.data(), 0, nullptr, &s.Read),
        "clEnqueueReadBuffer");
    }
    Check(clFlush(q), "clFlush");
  };
  // Waits for a slot's results and unpacks them.
  auto collect = [&](Slot& s) {
    const size_t first = s.First, n = s.Count;
    auto t0 = std::chrono::steady_clock::now();
    Check(clWaitForEvents(1, &s.Read), "clWaitForEvents");
    Times.Wait += Since(t0);
    for (cl_event e : s.Kernel)
    {
      cl_ulong start = 0, end = 0;
      if (e && clGetEventProfilingInfo(e, CL_PROFILING_COMMAND_START, sizeof(start), &start, nullptr) == CL_SUCCESS &&
        clGetEventProfilingInfo(e, CL_PROFILING_COMMAND_END, sizeof(end), &end, nullptr) == CL_SUCCESS && end > start)
        Times.Kernels += 1e-9 * static_cast<double>(end - start);
    }
    s.Release();
    t0 = std::chrono::steady_clock::now();
    const std::vector<T>& outR = s.OutR;
    const std::vector<double>& outR64 = s.OutR64;
    ForBlocks(n, [&](size_t a, size_t b) {
      for (size_t i = a; i < b; ++i)
      {
        const size_t j = at(first + i);
        ExactPass[j] = (finish ? UnpackResult(samples[j], &outR64[OutReals * i], &s.OutI[OutInts * i], results[j])
                               : UnpackResult(samples[j], &outR[OutReals * i], &s.OutI[OutInts * i], results[j]))
          ? 1 : 0;
      }
    });
    if (finish)
      for (size_t i = 0; i < n; ++i)
        if (s.Redo[i])
          again.push_back(at(first + i));
    Times.Host += Since(t0);
  };

  std::lock_guard<std::mutex> guard(RT->Lock);
  Slot* pending = nullptr;
  // After a chunk's results: false where the caller's progress asks to stop.
  auto goOn = [&](const Slot& s) {
    if (!progress || !*progress || (*progress)(s.First + s.Count))
      return true;
    if (stopped)
      *stopped = true;
    return false;
  };
  try
  {
    for (size_t ci = 0, c = 0; ci + 1 < starts.size(); ++c)
    {
      // Whole chains, up to `chunk` samples.
      size_t cj = ci + 1;
      while (cj + 1 < starts.size() && starts[cj + 1] - starts[ci] <= chunk)
        ++cj;
      Slot& s = slots[c % 2];
      s.First = starts[ci];
      s.Count = starts[cj] - starts[ci];
      s.Chains.clear();
      for (size_t k = ci; k <= cj; ++k)
        s.Chains.push_back(static_cast<cl_int>(starts[k] - s.First));
      ci = cj;
      launch(s);
      if (pending)
      {
        collect(*pending);
        if (!goOn(*pending))
        {
          // The chunk in flight is dropped: its samples and those after it are failed.
          Check(clFinish(q), "clFinish");
          s.Release();
          for (size_t j = s.First; j < total; ++j)
            results[at(j)] = SampleResult();
          return again;
        }
      }
      pending = &s;
    }
    collect(*pending);
    goOn(*pending);
  }
  catch (...)
  {
    // The device may still read or write the slots' staging: done before it goes.
    clFinish(q);
    for (int k = 0; k < 2; ++k)
      slots[k].Release();
    throw;
  }
  return again;
}

void OpenCLSolver::RayThickness(const BRepModel& model, const SolverData& data,
  const std::vector<Sample>& samples, std::vector<double>& thickness, std::vector<int>* face)
{
  thickness.assign(samples.size(), std::numeric_limits<double>::quiet_NaN());
  if (face)
    face->assign(samples.size(), -1);
  if (!samples.empty() && (&model != P->UploadedModel || &data != P->UploadedData))
    Upload(model, data);
  if (samples.empty() || !P->HasBoxes)
    return;
  // In double wherever the device has it (the float kernels' model is there for their finish):
  // a float ray that grazes a face or runs along one decides otherwise on 0.1-0.5% of the samples,
  // and a ray costs little next to a sphere.
  if (P->Double || P->RT->HasDouble)
    P->RayAs<double>(model, data, samples, thickness, face);
  else
    P->RayAs<float>(model, data, samples, thickness, face);
}

template <class T>
void OpenCLSolver::Impl::RayAs(const BRepModel& model, const SolverData& data,
  const std::vector<Sample>& samples, std::vector<double>& thickness, std::vector<int>* face)
{
  const int set = sizeof(T) == 8 ? 1 : 0;
  const size_t chunk = std::min<size_t>(samples.size(), 1u << 16);
  cl_command_queue q = RT->Queue;
  AllocateChunk<T>(chunk);
  KernelScalars ks = GetKernelScalars<T>(model, data, SolverOptions());
  ks.Certify = 1; // the ray walks the certification's boxes
  std::vector<T> in(chunk * SampleReals), out(chunk);
  std::vector<int> faces(chunk), hit(chunk);
  std::lock_guard<std::mutex> guard(RT->Lock);
  cl_kernel k = RT->Ray[set];
  for (size_t first = 0; first < samples.size(); first += chunk)
  {
    const size_t n = std::min(chunk, samples.size() - first);
    WriteChunk(data, samples, [first](size_t i) { return first + i; }, n, in, faces);
    SetArgs(k, set, Samples[set], static_cast<int>(n), ks, sizeof(T) == 8);
    Check(clSetKernelArg(k, OutArg, sizeof(cl_mem), &OutReal[set].Mem), "clSetKernelArg");
    Check(clSetKernelArg(k, OutArg + 1, sizeof(cl_mem), &OutInt[set].Mem), "clSetKernelArg");
    const size_t local = 64;
    const size_t global = (n + local - 1) / local * local;
    Check(clEnqueueNDRangeKernel(q, k, 1, nullptr, &global, &local, 0, nullptr, nullptr),
      "clEnqueueNDRangeKernel");
    Check(clEnqueueReadBuffer(q, OutReal[set].Mem, CL_FALSE, 0, n * sizeof(T), out.data(), 0, nullptr, nullptr),
      "clEnqueueReadBuffer");
    Check(clEnqueueReadBuffer(q, OutInt[set].Mem, CL_TRUE, 0, n * sizeof(int), hit.data(), 0, nullptr, nullptr),
      "clEnqueueReadBuffer");
    for (size_t i = 0; i < n; ++i)
    {
      if (hit[i] < 0 || !(out[i] < std::numeric_limits<T>::max()))
        continue;
      thickness[first + i] = static_cast<double>(out[i]);
      if (face)
        (*face)[first + i] = hit[i];
    }
  }
}

void OpenCLSolver::Upload(const BRepModel& model, const SolverData& data)
{
  P->Native.reset();
  if (P->Double || P->RT->HasDouble)
    P->UploadAs<double>(model, data);
  if (!P->Double)
    P->UploadAs<float>(model, data);
  if (!P->Double)
    P->Native = std::make_unique<NativeSolver>(model, data); // the float finish on the host
  P->UploadedModel = &model;
  P->UploadedData = &data;
}

bool OpenCLSolver::Solve(const BRepModel& model, const SolverData& data,
  const SolverOptions& options, const std::vector<Sample>& samples,
  std::vector<SampleResult>& results, size_t chunk, const std::vector<size_t>* which,
  const std::function<bool(size_t)>& progress)
{
  // Every sample solved is unpacked over a fresh SampleResult, so a whole solve needs no reset
  // first (zeroing a million results, 130 MiB, took a tenth of a GPU's solve); a subset, a
  // stop and a model without walls do.
  if (which || data.Nodes.empty())
    results.assign(samples.size(), SampleResult());
  else
    results.resize(samples.size());
  P->ExactPass.assign(samples.size(), 0);
  P->Times = Phases();
  if (samples.empty() || (which && which->empty()))
    return true;
  // Without Upload (or after one of another model) the kernels would read buffers that are not
  // this model's: a crash in the kernels.
  if (&model != P->UploadedModel || &data != P->UploadedData)
    Upload(model, data);
  // Neighbours in one work-group walk the same nodes (SpatialOrder).
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<size_t> order = SpatialOrder(samples, which);
  P->Times.Order = Since(t0);
  if (data.Nodes.empty())
  {
    for (size_t i : order)
      results[i].Reason = FailReason::NoOppositePoint;
    return !progress || progress(order.size());
  }
  bool stopped = false;
  // The double kernels run the whole solve, the certification included: they are final.
  if (P->Double)
  {
    P->SolveAs<double>(model, data, options, samples, results, &order, chunk, false, &progress, &stopped);
    return !stopped;
  }
  // The float kernels, then their finish in double: every contact polished (polish_result: its
  // own Newton, then the local part of the second look) and certified again, and the samples the
  // float kernels fail or whose sphere holds boundary solved again by the double kernels. On a
  // device with double precision all of it runs there (brt_finish); elsewhere on the host, by
  // the native device (the same source).
  const bool onDevice = Finish && FinishesOnDevice();
  std::vector<size_t> hard =
    P->SolveAs<float>(model, data, options, samples, results, &order, chunk, onDevice, &progress, &stopped);
  if (stopped)
    return false;
  if (!Finish)
    return true;
  if (onDevice)
  {
    if (!hard.empty())
      P->SolveAs<double>(model, data, options, samples, results, &hard, chunk, false);
    return true;
  }
  std::vector<size_t> solved;
  for (size_t i : order)
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
    // (A contact the polish finds from outside fails: solved again in double.)
    redo[i] = results[i].Type == ContactType::Failed ||
      (options.Certify && native.HoldsBoundary(o, samples[i], results[i]));
  });
  for (size_t i : solved)
    if (redo[i])
      hard.push_back(i);
  if (!hard.empty())
    native.Solve(options, samples, results, &hard);
  return true;
}

} // namespace brt
