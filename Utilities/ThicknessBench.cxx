// Benchmark of the maximal-sphere solver (a program that prints figures, not a test).
//   brt_thickness_bench [--device NAME|cpu|gpu|none] [--double] [--no-native]
//                       [--counts N1,N2,...] [--export DIR] [--values DIR] FILE.step|FILE.brtsolve ...
// For each model and sample count: samples/s of the native CPU device (the kernel source in double
// on every core, the reference) and of the OpenCL kernels,
// failed share, peak host memory and the kernels' device memory, as a table. --export writes
// each prepared model as DIR/<name>.brtsolve; the solver-only build (BRT_SOLVER_ONLY, no
// OpenCASCADE) reads those, e.g. on a GPU machine.
#ifdef BRT_HAVE_OCCT
#include "BRepConverter.h"
#endif
#include "Solver.h"
#include "NativeKernelWide.h"
#include "SolverIO.h"
#ifdef BRT_HAVE_OPENCL
#include "OpenCLSolver.h"
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace
{
double PeakRSSMiB()
{
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("VmHWM:", 0) == 0)
      return std::atof(line.c_str() + 6) / 1024.0;
  return 0.0;
}

/// Share of failed samples in percent; with BRT_BENCH_REASONS set, also prints the reasons.
double FailedPercent(const std::vector<brt::SampleResult>& results, const char* who)
{
  constexpr int kinds = static_cast<int>(brt::FailReason::ThinWall) + 1; // brt::FailReason's values
  int reasons[kinds] = { 0 };
  size_t failed = 0;
  for (const auto& r : results)
  {
    failed += r.Type == brt::ContactType::Failed;
    const int k = static_cast<int>(r.Reason);
    ++reasons[k >= 0 && k < kinds ? k : 0];
  }
  if (failed > 0 && std::getenv("BRT_BENCH_REASONS"))
    for (int k = 1; k < kinds; ++k)
      if (reasons[k])
        std::printf("  %s %s: %d\n", who, brt::FailReasonName(static_cast<brt::FailReason>(k)), reasons[k]);
  return results.empty() ? 0.0 : 100.0 * failed / results.size();
}

/// n samples drawn cyclically from the mesh samples (a sample count above the mesh's repeats
/// the vertices: the solver's cost does not depend on which vertex it is).
std::vector<brt::Sample> Take(const std::vector<brt::Sample>& all, size_t n)
{
  std::vector<brt::Sample> out(n);
  const size_t stride = all.size() > n ? all.size() / n : 1;
  for (size_t i = 0; i < n; ++i)
    out[i] = all[(i * stride) % all.size()];
  return out;
}
} // namespace

int main(int argc, char** argv)
{
  std::vector<size_t> counts{ 1000, 10000, 100000 };
  std::vector<std::string> files;
  std::string device = "any", exportDir, valuesDir;
  [[maybe_unused]] bool useDouble = false;
  bool finishOnHost = false, native = true, help = false, certify = true, phases = false;
  [[maybe_unused]] bool delaunay = false;
  [[maybe_unused]] double tolerance = 1e-4; // the reader's default conversion tolerance
  [[maybe_unused]] double maxEdge = 0.0;    // the reader's default sample spacing

  for (int i = 1; i < argc; ++i)
  {
    if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h"))
      help = true;
    else if (!std::strcmp(argv[i], "--device") && i + 1 < argc)
      device = argv[++i];
    else if (!std::strcmp(argv[i], "--double"))
      useDouble = true;
    else if (!std::strcmp(argv[i], "--finish-on-host"))
      finishOnHost = true;
    else if (!std::strcmp(argv[i], "--export") && i + 1 < argc)
      exportDir = argv[++i];
    else if (!std::strcmp(argv[i], "--values") && i + 1 < argc)
      valuesDir = argv[++i];
    else if (!std::strcmp(argv[i], "--tolerance") && i + 1 < argc)
      tolerance = std::stod(argv[++i]);
    else if (!std::strcmp(argv[i], "--max-edge") && i + 1 < argc)
      maxEdge = std::stod(argv[++i]);
    else if (!std::strcmp(argv[i], "--no-native") || !std::strcmp(argv[i], "--no-reference"))
      native = false;
    else if (!std::strcmp(argv[i], "--no-certify"))
      certify = false;
    else if (!std::strcmp(argv[i], "--delaunay"))
      delaunay = true;
    else if (!std::strcmp(argv[i], "--phases"))
      phases = true;
    else if (!std::strcmp(argv[i], "--counts") && i + 1 < argc)
    {
      counts.clear();
      std::stringstream ss(argv[++i]);
      std::string c;
      while (std::getline(ss, c, ','))
        counts.push_back(std::stoul(c));
    }
    else
      files.push_back(argv[i]);
  }
  if (files.empty() || help)
  {
    std::fprintf(help ? stdout : stderr,
      "usage: %s [options] FILE.step|FILE.brtsolve ...\n"
      "Benchmark of the thickness solver: for each model and sample count, samples/s of the native\n"
      "CPU device (the reference) and of the OpenCL kernels, failed share, agreement with the\n"
      "native results, peak host memory and the\n"
      "kernels' device memory, as a table.\n"
      "  --device NAME     OpenCL device: any (default), cpu, gpu, none, or a name\n"
      "  --double          double-precision kernels (default float)\n"
      "  --finish-on-host  float kernels: their finish in double on the host, not the device\n"
      "  --no-native       skip the native CPU device (--no-reference: the same)\n"
      "  --no-certify      skip the check of the spheres against the patches\n"
      "  --counts N,...    sample counts (default 1000,10000,100000; 0: every mesh vertex)\n"
      "  --tolerance T     Bezier conversion tolerance in mm (default 1e-4)\n"
      "  --max-edge L      display mesh (the samples): no edge longer than L mm (default 1/50 of\n"
      "                    the diagonal); a smaller L gives more distinct samples\n"
      "  --delaunay        display mesh (the samples) refined with Delaunay flips\n"
      "  --export DIR      write each prepared model as DIR/<name>.brtsolve\n"
      "  --values DIR      write the native device's 2t of every sample (the row of count 0,\n"
      "                    in the mesh's order, NaN where failed) as DIR/<name>.txt\n"
      "  --phases          after each OpenCL row, where its solve's time went (host and device)\n"
      "  --help            this text\n",
      argv[0]);
    return help ? 0 : 2;
  }
#ifdef BRT_HAVE_OPENCL
  std::unique_ptr<brt::OpenCLSolver> cl;
  if (device != "none")
  {
    try
    {
      // The constructor builds the kernel programs: on a GPU the first build of a process is
      // the driver's compiler at work (docs/Solver.md, "Compile time on GPUs").
      std::printf("OpenCL: building the kernel programs for --device %s\n", device.c_str());
      std::fflush(stdout);
      const auto built = std::chrono::steady_clock::now();
      cl = std::make_unique<brt::OpenCLSolver>(device, useDouble);
      cl->SetFinishOnHost(finishOnHost);
      std::printf("OpenCL device: %s (%s%s), programs built in %.1f s\n", cl->DeviceName().c_str(),
        useDouble ? "double" : "float",
        useDouble ? "" : cl->FinishesOnDevice() ? ", finished on the device" : ", finished on the host",
        std::chrono::duration<double>(std::chrono::steady_clock::now() - built).count());
      std::fflush(stdout);
    }
    catch (const std::exception& e)
    {
      std::printf("OpenCL unavailable: %s\n", e.what());
    }
  }
#endif
  if (native)
    std::printf("native device: the kernel source's %s build\n", brt::NativeKernelBuild());
  std::printf("%-32s %8s %8s %8s %12s %8s %12s %8s %8s %9s %9s\n", "model", "samples", "s1",
    "patches", "nat_samp/s", "nat_fail", "cl_samp/s", "cl_fail", "agree", "host_MiB", "dev_MiB");
  for (const auto& file : files)
  {
    brt::BRepModel model;
    brt::SolverOptions options;
    options.Certify = certify;
    brt::SolverData data;
    std::vector<brt::Sample> all;
    try
    {
      if (file.size() > 9 && file.compare(file.size() - 9, 9, ".brtsolve") == 0)
        brt::ReadSolve(file, model, data, all);
      else
      {
#ifdef BRT_HAVE_OCCT
        brt::ConversionOptions conversion;
        conversion.Tolerance = tolerance;
        conversion.DelaunayRefinement = delaunay;
        conversion.MaxEdgeLength = maxEdge;
        model = brt::ConvertStepFile(file, conversion);
        data = brt::PrepareSolver(model, options);
        all = brt::SamplesFromMesh(model, data);
#else
        throw std::runtime_error(file + ": this build reads only .brtsolve files (no OpenCASCADE)");
#endif
      }
    }
    catch (const std::exception& e)
    {
      std::fprintf(stderr, "%s\n", e.what());
      continue;
    }
    if (!exportDir.empty())
    {
      std::string base = file.substr(file.find_last_of('/') + 1);
      base = base.substr(0, base.find_last_of('.'));
      try
      {
        brt::WriteSolve(exportDir + "/" + base + ".brtsolve", model, data, all);
      }
      catch (const std::exception& e)
      {
        // One line naming the file (a folder that does not exist, a full disk), not an abort.
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
      }
    }
    const char* name = std::strrchr(file.c_str(), '/') ? std::strrchr(file.c_str(), '/') + 1 : file.c_str();
    for (size_t n : counts)
    {
      if (n == 0)
        n = all.size(); // 0: every mesh sample once
      const std::vector<brt::Sample> samples = Take(all, n);
      std::vector<brt::SampleResult> results;
      char phaseLine[256] = "";
      double refRate = 0.0, refFail = 0.0, clRate = 0.0, clFail = 0.0, devMiB = 0.0, agree = -1.0;
      if (native)
      {
        const auto t0 = std::chrono::steady_clock::now();
        brt::SolveReference(model, data, options, samples, results);
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        refRate = n / s;
        refFail = FailedPercent(results, "native");
        if (!valuesDir.empty() && n == all.size())
        {
          std::string base = file.substr(file.find_last_of('/') + 1);
          const std::string path = valuesDir + "/" + base.substr(0, base.find_last_of('.')) + ".txt";
          FILE* out = std::fopen(path.c_str(), "w");
          if (!out)
          {
            std::fprintf(stderr, "error: cannot write %s\n", path.c_str());
            return 1;
          }
          for (const brt::SampleResult& r : results)
            std::fprintf(out, "%.17g\n",
              r.Type == brt::ContactType::Failed ? std::nan("") : r.Thickness);
          std::fclose(out);
        }
      }
#ifdef BRT_HAVE_OPENCL
      if (cl)
      {
        cl->Upload(model, data);
        std::vector<brt::SampleResult> clResults;
        cl->Solve(model, data, options, samples, clResults); // warm-up (kernel build, transfers)
        const auto t0 = std::chrono::steady_clock::now();
        cl->Solve(model, data, options, samples, clResults);
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        clRate = n / s;
        clFail = FailedPercent(clResults, "OpenCL");
        const brt::OpenCLSolver::Phases& ph = cl->LastPhases();
        if (phases)
          std::snprintf(phaseLine, sizeof(phaseLine),
            "  phases: %.4f s in all; order %.4f s, pack and unpack %.4f s (every core), wait for the device %.4f s, kernels %.4f s (%.0f samples/s)\n",
            s, ph.Order, ph.Host, ph.Wait, ph.Kernels, ph.Kernels > 0 ? n / ph.Kernels : 0.0);
        devMiB = cl->DeviceBytes() / (1024.0 * 1024.0);
        if (!results.empty())
        {
          // Same criterion as Testing/Core/TestOpenCL.cxx: same contact type and
          // |delta 2t| <= 1e-4 * max(2t_ref, 1e-3 * model size).
          size_t same = 0;
          for (size_t i = 0; i < n; ++i)
          {
            const auto& a = results[i];
            const auto& b = clResults[i];
            const bool bothFailed = a.Type == brt::ContactType::Failed && b.Type == a.Type;
            const double err = std::fabs(a.Thickness - b.Thickness) /
              std::max(a.Thickness, 1e-3 * data.Scale);
            same += bothFailed || (a.Type == b.Type && err <= 1e-4);
          }
          agree = 100.0 * same / n;
        }
      }
#endif
      std::printf("%-32s %8zu %8zu %8d %12.0f %7.3f%% %12.0f %7.3f%% %7.2f%% %9.1f %9.1f\n", name,
        n, data.S1.size(), model.Stats.Patches, refRate, refFail, clRate, clFail, agree,
        PeakRSSMiB(), devMiB);
      std::fputs(phaseLine, stdout);
      std::fflush(stdout);
    }
  }
  return 0;
}
