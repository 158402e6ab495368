// brt_step_worker: reads, heals and converts one STEP file and writes the model file that
// ConvertStepFileIsolated (StepIsolation.h) reads back. Runs as a child process of the reader so
// that a crash or a loop inside OpenCASCADE cannot take the caller down.
//
// Reports on the descriptor given by --report-fd, one line each: "progress F", "error MESSAGE",
// "done". Exit status 0 with a written model, 3 for bad input, 2 for bad arguments.
#include "BRepConverter.h"
#include "ModelIO.h"
#include "StepFile.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>
#include <sys/resource.h>
#include <unistd.h>

namespace
{
const char* const Usage =
  "usage: brt_step_worker [options] [--] IN.step OUT.brtmodel\n"
  "Reads, heals and converts IN.step (BRepThickness's reader, in its own process) and writes\n"
  "the converted model to OUT.brtmodel. Normally started by the reader, not by hand.\n"
  "  --tolerance T            Bezier conversion tolerance (mm, default 1e-4)\n"
  "  --no-heal                skip OpenCASCADE's ShapeFix\n"
  "  --linear-deflection D    display mesh chordal deviation (0: automatic)\n"
  "  --angular-deflection A   display mesh angular deflection (radians, default 0.35)\n"
  "  --max-edge-length L      longest display mesh edge (0: automatic)\n"
  "  --delaunay-refinement    display mesh refined with Delaunay flips (default: bisection)\n"
  "  --max-patch-size S       longest Bezier patch (0: automatic)\n"
  "  --memory-limit MIB       address-space limit of this process (0: none)\n"
  "  --report-fd N            write progress and errors to descriptor N (default 2)\n"
  "  --help                   this text\n";

FILE* Report = stderr;

void Say(const std::string& kind, const std::string& text)
{
  std::string line = text.empty() ? kind : kind + " " + text;
  for (char& c : line)
    if (c == '\n' || c == '\r')
      c = ' ';
  std::fprintf(Report, "%s\n", line.c_str());
  std::fflush(Report);
}
} // namespace

int main(int argc, char** argv)
{
  brt::ConversionOptions options;
  double memoryMiB = 0.0;
  int reportFd = 2;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    auto value = [&]() -> double {
      if (i + 1 >= argc)
      {
        std::fprintf(stderr, "brt_step_worker: %s needs a value\n%s", a.c_str(), Usage);
        std::exit(2);
      }
      char* end = nullptr;
      const double v = std::strtod(argv[++i], &end);
      if (end == argv[i] || *end != '\0')
      {
        std::fprintf(stderr, "brt_step_worker: %s: '%s' is not a number\n", a.c_str(), argv[i]);
        std::exit(2);
      }
      return v;
    };
    if (a == "--help" || a == "-h")
    {
      std::fputs(Usage, stdout);
      return 0;
    }
    else if (a == "--tolerance")
      options.Tolerance = value();
    else if (a == "--no-heal")
      options.Heal = false;
    else if (a == "--linear-deflection")
      options.LinearDeflection = value();
    else if (a == "--angular-deflection")
      options.AngularDeflection = value();
    else if (a == "--max-edge-length")
      options.MaxEdgeLength = value();
    else if (a == "--delaunay-refinement")
      options.DelaunayRefinement = true;
    else if (a == "--sliver-ratio")
      options.SliverRatio = value();
    else if (a == "--sliver-vertices")
      options.SliverVertices = static_cast<int>(value());
    else if (a == "--max-patch-size")
      options.MaxPatchSize = value();
    else if (a == "--memory-limit")
      memoryMiB = value();
    else if (a == "--report-fd")
      reportFd = static_cast<int>(value());
    else if (a == "--")
    {
      for (++i; i < argc; ++i)
        files.push_back(argv[i]);
    }
    else if (a.size() > 1 && a[0] == '-')
    {
      std::fprintf(stderr, "brt_step_worker: unknown option %s\n%s", a.c_str(), Usage);
      return 2;
    }
    else
      files.push_back(a);
  }
  if (files.size() != 2)
  {
    std::fputs(Usage, stderr);
    return 2;
  }
  if (reportFd != 2)
  {
    Report = ::fdopen(reportFd, "w");
    if (!Report)
    {
      std::fprintf(stderr, "brt_step_worker: descriptor %d cannot be written\n", reportFd);
      return 2;
    }
  }
#if defined(__SANITIZE_ADDRESS__)
  // AddressSanitizer reserves terabytes of address space for its shadow memory: an address-space
  // limit makes it abort at start (Utilities/run-sanitizers.sh).
  memoryMiB = 0.0;
#endif
  if (memoryMiB > 0.0)
  {
    rlimit limit{};
    limit.rlim_cur = limit.rlim_max = static_cast<rlim_t>(memoryMiB * 1048576.0);
    ::setrlimit(RLIMIT_AS, &limit);
  }
  double last = -1.0;
  options.Progress = [&](double f) {
    if (f - last >= 0.01 || f >= 1.0)
    {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.4f", f);
      Say("progress", buf);
      last = f;
    }
    return true;
  };
  try
  {
    const brt::BRepModel model = brt::ConvertStepFile(files[0], options);
    brt::WriteModel(files[1], model);
  }
  catch (const std::bad_alloc&)
  {
    Say("error", "STEP file '" + files[0] + "': reading and converting it ran out of memory" +
        (memoryMiB > 0.0 ? " (limit " + std::to_string(static_cast<long>(memoryMiB)) + " MiB)"
                         : std::string()));
    return 3;
  }
  catch (const brt::InputError& e)
  {
    Say("error", e.what());
    return 3;
  }
  catch (const std::exception& e)
  {
    Say("error", "STEP file '" + files[0] + "': " + e.what());
    return 3;
  }
  Say("done", "");
  return 0;
}
