// brt_step_replay: runs STEP files through the reader and classifies each outcome, for the
// mutation corpus (Utilities/mutate_step.py) and the fuzzer's findings.
//
//   brt_step_replay [--mode isolated|checked|raw] [--time-limit S] [--expect-no-crash] FILE...
//
// isolated: ConvertStepFileIsolated, the reader's path (OpenCASCADE in the worker process).
// checked:  ConvertStepFile in a forked child (the text check, then OpenCASCADE in-process).
// raw:      OpenCASCADE's STEP reader, healing and the conversion in a forked child, without the
//           text check: the reader as it was before the check and the worker existed.
// Prints one line per file (ok / error / crash / hang) and the counts. With --expect-no-crash
// the exit status is 1 if any file crashed or hung, or failed without naming itself.
#include "BRepConverter.h"
#include "StepFile.h"
#include "StepIsolation.h"

#include <STEPControl_Reader.hxx>
#include <Standard_Failure.hxx>
#include <TopoDS_Shape.hxx>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <map>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace
{
const char* const Usage =
  "usage: brt_step_replay [--mode isolated|checked|raw] [--time-limit S] [--expect-no-crash] "
  "FILE...\n"
  "Reads each STEP file as the reader does and prints ok / error / crash / hang for each, then\n"
  "the counts. isolated (default): the worker process, as ParaView reads; checked: the text\n"
  "check and OpenCASCADE in a forked child; raw: OpenCASCADE alone in a forked child (the\n"
  "reader before its checks). --expect-no-crash: exit 1 if any file crashed, hung or failed\n"
  "without an error naming it.\n";

/// The raw path: what the reader did before the text check and the worker.
void ConvertRaw(const std::string& path)
{
  STEPControl_Reader reader;
  if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
    throw std::runtime_error("parser rejected it");
  reader.TransferRoots();
  if (reader.NbShapes() == 0)
    throw std::runtime_error("no shape");
  (void)brt::ConvertShape(reader.OneShape(), brt::ConversionOptions());
}

/// Runs `f` in a forked child with a time limit: "ok", "error <message>", "crash <signal>" or
/// "hang".
template <class F>
std::string InChild(F f, double limit)
{
  int fds[2];
  if (::pipe(fds) != 0)
    return "error pipe";
  const pid_t pid = ::fork();
  if (pid == 0)
  {
    ::close(fds[0]);
    ::alarm(0);
    std::string out = "ok";
    try
    {
      f();
    }
    catch (const Standard_Failure& e)
    {
      out = std::string("error OpenCASCADE: ") + e.GetMessageString();
    }
    catch (const std::exception& e)
    {
      out = std::string("error ") + e.what();
    }
    (void)!::write(fds[1], out.data(), out.size());
    ::_exit(0);
  }
  ::close(fds[1]);
  const auto t0 = std::chrono::steady_clock::now();
  int status = 0;
  for (;;)
  {
    const pid_t r = ::waitpid(pid, &status, WNOHANG);
    if (r == pid)
      break;
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > limit)
    {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      ::close(fds[0]);
      return "hang";
    }
    ::usleep(2000);
  }
  std::string out;
  char buf[4096];
  for (ssize_t n; (n = ::read(fds[0], buf, sizeof buf)) > 0;)
    out.append(buf, static_cast<size_t>(n));
  ::close(fds[0]);
  if (WIFSIGNALED(status))
    return "crash " + std::string(::strsignal(WTERMSIG(status)));
  return out.empty() ? "crash (no report)" : out;
}
} // namespace

int main(int argc, char** argv)
{
  std::string mode = "isolated";
  double limit = 30.0;
  bool expectNoCrash = false;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h")
    {
      std::fputs(Usage, stdout);
      return 0;
    }
    if (a == "--mode" && i + 1 < argc)
      mode = argv[++i];
    else if (a == "--time-limit" && i + 1 < argc)
      limit = std::atof(argv[++i]);
    else if (a == "--expect-no-crash")
      expectNoCrash = true;
    else if (a.size() > 2 && a.compare(0, 2, "--") == 0)
    {
      std::fprintf(stderr, "error: unknown option %s\n%s", a.c_str(), Usage);
      return 2;
    }
    else
      files.push_back(a);
  }
  if (files.empty() || (mode != "isolated" && mode != "checked" && mode != "raw"))
  {
    std::fputs(Usage, stderr);
    return 2;
  }
  std::map<std::string, int> counts;
  int bad = 0;
  for (const std::string& file : files)
  {
    const auto t0 = std::chrono::steady_clock::now();
    std::string outcome;
    if (mode == "isolated")
    {
      brt::IsolationOptions iso;
      iso.TimeLimit = limit;
      try
      {
        (void)brt::ConvertStepFileIsolated(file, brt::ConversionOptions(), iso);
        outcome = "ok";
      }
      catch (const std::exception& e)
      {
        outcome = std::string("error ") + e.what();
      }
    }
    else if (mode == "checked")
      outcome = InChild([&] { (void)brt::ConvertStepFile(file, brt::ConversionOptions()); }, limit);
    else
      outcome = InChild([&] { ConvertRaw(file); }, limit);
    const double s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const std::string kind = outcome.substr(0, outcome.find(' '));
    ++counts[kind];
    bool wrong = kind == "crash" || kind == "hang";
    if (kind == "error" && mode != "raw" && outcome.find(file) == std::string::npos)
    {
      wrong = true;
      ++counts["error-without-file-name"];
    }
    bad += wrong ? 1 : 0;
    std::printf("%-6s %6.2f s %s: %s\n", kind.c_str(), s, file.c_str(),
      kind == "ok" ? "" : outcome.substr(kind.size()).c_str());
    std::fflush(stdout);
  }
  std::printf("mode %s, %zu files:", mode.c_str(), files.size());
  for (const auto& c : counts)
    std::printf(" %s %d", c.first.c_str(), c.second);
  std::printf("\n");
  return expectNoCrash && bad > 0 ? 1 : 0;
}
