#include "OpenCLSolver.h"

#include "KernelData.h"
#include "NativeSolver.h"

#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>

#include <algorithm>
#include <array>
#include <cctype>
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
    const char* options = useDouble ? "-DBRT_DOUBLE" : "";
    if (clBuildProgram(Program[k], 1, &Device, options, nullptr, nullptr) != CL_SUCCESS)
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
    cl_int err = CL_SUCCESS;
    made->Context = clCreateContext(nullptr, 1, &dev.Device, nullptr, nullptr, &err);
    Check(err, "clCreateContext");
    made->Queue = clCreateCommandQueue(made->Context, dev.Device, 0, &err);
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
  /// The model's buffers (kernel arguments 0..31), per precision: [0] float, [1] double; the
  /// launch's arguments follow them (LAUNCH_PARAMS in thickness.cl), then the outputs.
  static constexpr int ModelBuffers = 32;
  static constexpr int LaunchArg = ModelBuffers, OutArg = ModelBuffers + 13;
  Buffer Model[2][ModelBuffers];
  int PatchCount = 0;
  bool HasBoxes = false;
  /// What the buffers hold (Upload): Solve and RayThickness upload another model first.
  const BRepModel* UploadedModel = nullptr;
  const SolverData* UploadedData = nullptr;
  /// The float kernels' finish on the host, where the device has no double precision.
  std::unique_ptr<NativeSolver> Native;
  Buffer Samples[2], SampleFace, OutReal[2], OutInt[2], Redo;
  /// Per sample of the last Solve: 1 where the kernels' pass without clearance found it.
  std::vector<unsigned char> ExactPass;

  template <class T>
  void UploadAs(const BRepModel& m, const SolverData& data);
  /// Solves samples[which[j]] (all when which is null) with the kernels of precision T, `chunk`
  /// per launch; with `finish` (float only), each chunk is finished on the device in double.
  /// Returns the samples whose finish asks for a solve in double.
  template <class T>
  std::vector<size_t> SolveAs(const BRepModel& m, const SolverData& data,
    const SolverOptions& options, const std::vector<Sample>& samples,
    std::vector<SampleResult>& results, const std::vector<size_t>* which, size_t chunk,
    bool finish);
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

size_t OpenCLSolver::DeviceBytes() const
{
  size_t n = P->SampleFace.Bytes + P->Redo.Bytes;
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
  for (size_t i = 0; i < n; ++i)
  {
    PackSample(data, samples[index(i)], &in[SampleReals * i]);
    faces[i] = samples[index(i)].Face;
  }
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
  std::vector<SampleResult>& results, const std::vector<size_t>* which, size_t chunk, bool finish)
{
  std::vector<size_t> again;
  const size_t total = which ? which->size() : samples.size();
  if (total == 0)
    return again;
  const int set = sizeof(T) == 8 ? 1 : 0;
  const size_t perSample = (SampleReals + OutReals) * (sizeof(T) + (finish ? 8 : 0)) +
    (2 * OutInts + 2) * sizeof(int);
  if (chunk == 0)
    chunk = std::max<size_t>(1024, (64u << 20) / perSample);
  chunk = std::min(chunk, total);
  cl_context ctx = RT->Context;
  cl_command_queue q = RT->Queue;
  AllocateChunk<T>(chunk);
  if (finish)
  {
    Samples[1].Allocate(ctx, chunk * SampleReals * sizeof(double), CL_MEM_READ_ONLY);
    OutReal[1].Allocate(ctx, chunk * OutReals * sizeof(double), CL_MEM_WRITE_ONLY);
    OutInt[1].Allocate(ctx, chunk * OutInts * sizeof(int), CL_MEM_WRITE_ONLY);
    Redo.Allocate(ctx, chunk * sizeof(int), CL_MEM_WRITE_ONLY);
  }
  const KernelScalars ks = GetKernelScalars<T>(model, data, options);
  const KernelScalars ks64 = GetKernelScalars<double>(model, data, options);
  std::vector<T> in(chunk * SampleReals), outR(chunk * OutReals);
  std::vector<double> in64, outR64;
  std::vector<int> outI(chunk * OutInts), faces(chunk), redo;
  if (finish)
  {
    in64.resize(chunk * SampleReals);
    outR64.resize(chunk * OutReals);
    redo.resize(chunk);
  }

  std::lock_guard<std::mutex> guard(RT->Lock);
  cl_kernel k = RT->Solve[set];
  for (size_t first = 0; first < total; first += chunk)
  {
    const size_t n = std::min(chunk, total - first);
    auto index = [&](size_t i) { return which ? (*which)[first + i] : first + i; };
    WriteChunk(data, samples, index, n, in, faces);
    if (finish)
      for (size_t i = 0; i < n; ++i)
        PackSample(data, samples[index(i)], &in64[SampleReals * i]);
    const size_t local = 64;
    const size_t global = (n + local - 1) / local * local;
    SetArgs(k, set, Samples[set], static_cast<int>(n), ks, sizeof(T) == 8);
    Check(clSetKernelArg(k, OutArg, sizeof(cl_mem), &OutReal[set].Mem), "clSetKernelArg");
    Check(clSetKernelArg(k, OutArg + 1, sizeof(cl_mem), &OutInt[set].Mem), "clSetKernelArg");
    Check(clEnqueueNDRangeKernel(q, k, 1, nullptr, &global, &local, 0, nullptr, nullptr),
      "clEnqueueNDRangeKernel");
    if (finish)
    {
      cl_kernel f = RT->Finish;
      Check(clEnqueueWriteBuffer(q, Samples[1].Mem, CL_FALSE, 0, n * SampleReals * sizeof(double), in64.data(), 0, nullptr, nullptr),
        "clEnqueueWriteBuffer");
      SetArgs(f, 1, Samples[1], static_cast<int>(n), ks64, true);
      Check(clSetKernelArg(f, OutArg, sizeof(cl_mem), &OutReal[0].Mem), "clSetKernelArg");
      Check(clSetKernelArg(f, OutArg + 1, sizeof(cl_mem), &OutInt[0].Mem), "clSetKernelArg");
      Check(clSetKernelArg(f, OutArg + 2, sizeof(cl_mem), &OutReal[1].Mem), "clSetKernelArg");
      Check(clSetKernelArg(f, OutArg + 3, sizeof(cl_mem), &OutInt[1].Mem), "clSetKernelArg");
      Check(clSetKernelArg(f, OutArg + 4, sizeof(cl_mem), &Redo.Mem), "clSetKernelArg");
      Check(clEnqueueNDRangeKernel(q, f, 1, nullptr, &global, &local, 0, nullptr, nullptr),
        "clEnqueueNDRangeKernel");
      Check(clEnqueueReadBuffer(q, OutReal[1].Mem, CL_FALSE, 0, n * OutReals * sizeof(double), outR64.data(), 0, nullptr, nullptr),
        "clEnqueueReadBuffer");
      Check(clEnqueueReadBuffer(q, Redo.Mem, CL_FALSE, 0, n * sizeof(int), redo.data(), 0, nullptr, nullptr),
        "clEnqueueReadBuffer");
      Check(clEnqueueReadBuffer(q, OutInt[1].Mem, CL_TRUE, 0, n * OutInts * sizeof(int), outI.data(), 0, nullptr, nullptr),
        "clEnqueueReadBuffer");
      for (size_t i = 0; i < n; ++i)
      {
        ExactPass[index(i)] = UnpackResult(samples[index(i)], &outR64[OutReals * i],
          &outI[OutInts * i], results[index(i)]) ? 1 : 0;
        if (redo[i])
          again.push_back(index(i));
      }
      continue;
    }
    Check(clEnqueueReadBuffer(q, OutReal[set].Mem, CL_FALSE, 0, n * OutReals * sizeof(T), outR.data(), 0, nullptr, nullptr),
      "clEnqueueReadBuffer");
    Check(clEnqueueReadBuffer(q, OutInt[set].Mem, CL_TRUE, 0, n * OutInts * sizeof(int), outI.data(), 0, nullptr, nullptr),
      "clEnqueueReadBuffer");
    for (size_t i = 0; i < n; ++i)
      ExactPass[index(i)] = UnpackResult(samples[index(i)], &outR[OutReals * i],
        &outI[OutInts * i], results[index(i)]) ? 1 : 0;
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

void OpenCLSolver::Solve(const BRepModel& model, const SolverData& data,
  const SolverOptions& options, const std::vector<Sample>& samples,
  std::vector<SampleResult>& results, size_t chunk)
{
  results.assign(samples.size(), SampleResult());
  P->ExactPass.assign(samples.size(), 0);
  if (samples.empty())
    return;
  // Without Upload (or after one of another model) the kernels would read buffers that are not
  // this model's: a crash in the kernels.
  if (&model != P->UploadedModel || &data != P->UploadedData)
    Upload(model, data);
  if (data.Nodes.empty())
  {
    for (auto& r : results)
      r.Reason = FailReason::NoOppositePoint;
    return;
  }
  // Neighbours in one work-group walk the same nodes (SpatialOrder).
  const std::vector<size_t> order = SpatialOrder(samples, nullptr);
  // The double kernels run the whole solve, the certification included: they are final.
  if (P->Double)
  {
    P->SolveAs<double>(model, data, options, samples, results, &order, chunk, false);
    return;
  }
  // The float kernels, then their finish in double: every contact polished (polish_result: its
  // own Newton, then the local part of the second look) and certified again, and the samples the
  // float kernels fail or whose sphere holds boundary solved again by the double kernels. On a
  // device with double precision all of it runs there (brt_finish); elsewhere on the host, by
  // the native device (the same source).
  const bool onDevice = Finish && FinishesOnDevice();
  std::vector<size_t> hard =
    P->SolveAs<float>(model, data, options, samples, results, &order, chunk, onDevice);
  if (!Finish)
    return;
  if (onDevice)
  {
    if (!hard.empty())
      P->SolveAs<double>(model, data, options, samples, results, &hard, chunk, false);
    return;
  }
  std::vector<size_t> solved;
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
    // (A contact the polish finds from outside fails: solved again in double.)
    redo[i] = results[i].Type == ContactType::Failed ||
      (options.Certify && native.HoldsBoundary(o, samples[i], results[i]));
  });
  for (size_t i : solved)
    if (redo[i])
      hard.push_back(i);
  if (!hard.empty())
    native.Solve(options, samples, results, &hard);
}

} // namespace brt
