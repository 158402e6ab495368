#include "StepIsolation.h"

#include "ModelIO.h"
#include "StepFile.h"

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <dlfcn.h>
#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

extern char** environ;

namespace brt
{
namespace
{
bool IsExecutable(const std::string& path)
{
  struct stat st{};
  return !path.empty() && ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) &&
    ::access(path.c_str(), X_OK) == 0;
}

std::string Folder(const std::string& path)
{
  const size_t slash = path.rfind('/');
  return slash == std::string::npos ? std::string(".") : path.substr(0, slash);
}

std::string Number(double v)
{
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

/// The worker process while it runs: killed and reaped if the caller leaves early.
class Worker
{
public:
  ~Worker()
  {
    if (this->Pid > 0)
    {
      ::kill(this->Pid, SIGKILL);
      int status = 0;
      while (::waitpid(this->Pid, &status, 0) < 0 && errno == EINTR)
      {
      }
    }
    if (this->Fd >= 0)
      ::close(this->Fd);
    if (!this->ModelFile.empty())
      ::unlink(this->ModelFile.c_str());
  }
  pid_t Pid = -1;
  int Fd = -1;
  std::string ModelFile;
};

std::string SignalText(int sig)
{
  const char* name = ::strsignal(sig);
  return "signal " + std::to_string(sig) + (name ? std::string(", ") + name : std::string());
}
} // namespace

std::string FindStepWorker()
{
  if (const char* env = std::getenv("BRT_STEP_WORKER"))
  {
    if (IsExecutable(env))
      return env;
    throw std::runtime_error(std::string("BRT_STEP_WORKER='") + env +
      "' is not an executable file");
  }
  std::vector<std::string> candidates;
  Dl_info info{};
  if (::dladdr(reinterpret_cast<void*>(&FindStepWorker), &info) && info.dli_fname)
    candidates.push_back(Folder(info.dli_fname) + "/brt_step_worker");
  char self[4096];
  const ssize_t n = ::readlink("/proc/self/exe", self, sizeof self - 1);
  if (n > 0)
  {
    self[n] = '\0';
    candidates.push_back(Folder(self) + "/brt_step_worker");
  }
#ifdef BRT_STEP_WORKER_PATH
  candidates.push_back(BRT_STEP_WORKER_PATH);
#endif
  for (const std::string& c : candidates)
    if (IsExecutable(c))
      return c;
  std::string tried;
  for (const std::string& c : candidates)
    tried += (tried.empty() ? "" : ", ") + c;
  throw std::runtime_error("the STEP worker brt_step_worker was not found (tried " + tried +
    "; set BRT_STEP_WORKER)");
}

BRepModel ConvertStepFileIsolated(const std::string& path, const ConversionOptions& options,
  const IsolationOptions& isolation)
{
  // The cheap checks run here: their errors need no worker.
  CheckStepFile(path);
  const std::string exe = isolation.Worker.empty() ? FindStepWorker() : isolation.Worker;

  Worker worker;
  {
    const char* tmp = std::getenv("TMPDIR");
    std::string templ = std::string(tmp && *tmp ? tmp : "/tmp") + "/brt-model-XXXXXX";
    std::vector<char> name(templ.begin(), templ.end());
    name.push_back('\0');
    const int fd = ::mkstemp(name.data());
    if (fd < 0)
      throw std::runtime_error("cannot create a temporary file in " + Folder(templ) + ": " +
        std::strerror(errno));
    ::close(fd);
    worker.ModelFile = name.data();
  }

  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0)
    throw std::runtime_error(std::string("cannot create a pipe: ") + std::strerror(errno));
  worker.Fd = fds[0];
  // The write end goes to the worker as fd 3; keep it off 0-3 so that dup2 copies it there.
  int writeFd = ::fcntl(fds[1], F_DUPFD_CLOEXEC, 10);
  ::close(fds[1]);
  if (writeFd < 0)
    throw std::runtime_error(std::string("cannot duplicate a pipe: ") + std::strerror(errno));

  double memory = isolation.MemoryLimitMiB;
  if (memory == 0.0)
  {
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
    memory = pages > 0 && page > 0 ? 0.75 * double(pages) * double(page) / 1048576.0 : -1.0;
  }
  std::vector<std::string> args{ exe, "--report-fd", "3", "--tolerance",
    Number(options.Tolerance), "--linear-deflection", Number(options.LinearDeflection),
    "--angular-deflection", Number(options.AngularDeflection), "--max-edge-length",
    Number(options.MaxEdgeLength), "--max-patch-size", Number(options.MaxPatchSize),
    "--sliver-ratio", Number(options.SliverRatio), "--sliver-vertices",
    Number(options.SliverVertices),
    "--memory-limit", Number(memory > 0.0 ? memory : 0.0) };
  if (!options.Heal)
    args.push_back("--no-heal");
  if (options.DelaunayRefinement)
    args.push_back("--delaunay-refinement");
  args.push_back("--");
  args.push_back(path);
  args.push_back(worker.ModelFile);
  std::vector<char*> argv;
  for (std::string& a : args)
    argv.push_back(a.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, writeFd, 3);
  // OpenCASCADE prints to stdout and stderr; the worker reports through fd 3 only.
  const bool verbose = std::getenv("BRT_STEP_WORKER_VERBOSE") != nullptr;
  if (!verbose)
  {
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  }
  pid_t pid = -1;
  const int err = ::posix_spawn(&pid, exe.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(writeFd);
  if (err != 0)
    throw std::runtime_error("cannot start the STEP worker '" + exe + "': " + std::strerror(err));
  worker.Pid = pid;

  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  std::string buffer, error;
  bool done = false;
  for (bool open = true; open;)
  {
    const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
    if (isolation.TimeLimit > 0.0 && elapsed > isolation.TimeLimit)
    {
      char limit[32];
      std::snprintf(limit, sizeof limit, "%g", isolation.TimeLimit);
      throw InputError("STEP file '" + path + "': reading, healing and converting it took longer "
        "than the time limit of " + limit + " s and was stopped (OpenCASCADE may loop on "
        "damaged geometry; raise the limit, e.g. the reader's TimeLimit property, for a very "
        "large part)");
    }
    pollfd p{ worker.Fd, POLLIN, 0 };
    const int ready = ::poll(&p, 1, 100);
    if (ready < 0 && errno != EINTR)
      throw std::runtime_error(std::string("poll failed: ") + std::strerror(errno));
    if (ready <= 0)
      continue;
    char chunk[4096];
    const ssize_t got = ::read(worker.Fd, chunk, sizeof chunk);
    if (got < 0 && errno == EINTR)
      continue;
    if (got <= 0)
    {
      open = false;
      continue;
    }
    buffer.append(chunk, static_cast<size_t>(got));
    for (size_t eol; (eol = buffer.find('\n')) != std::string::npos; buffer.erase(0, eol + 1))
    {
      const std::string line = buffer.substr(0, eol);
      if (line.compare(0, 9, "progress ") == 0)
      {
        const double f = std::atof(line.c_str() + 9);
        if (options.Progress && !options.Progress(f))
          throw std::runtime_error("conversion aborted");
      }
      else if (line.compare(0, 6, "error ") == 0)
        error = line.substr(6);
      else if (line == "done")
        done = true;
    }
  }
  // The report pipe is closed: the worker has ended or is about to.
  int status = 0;
  for (;;)
  {
    const pid_t r = ::waitpid(worker.Pid, &status, 0);
    if (r == worker.Pid)
      break;
    if (r < 0 && errno != EINTR)
      throw std::runtime_error(std::string("waitpid failed: ") + std::strerror(errno));
  }
  worker.Pid = -1;
  if (WIFSIGNALED(status))
  {
    const int sig = WTERMSIG(status);
    throw InputError("STEP file '" + path + "': OpenCASCADE crashed while reading or converting "
      "it (" + SignalText(sig) + (sig == SIGKILL ? ", possibly out of memory" : "") +
      "); the file is damaged or holds a structure OpenCASCADE cannot read. The reading ran in "
      "a separate process, so nothing else was affected");
  }
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (!error.empty())
  {
    if (error == "conversion aborted")
      throw std::runtime_error(error);
    throw InputError(error);
  }
  if (code != 0 || !done)
    throw InputError("STEP file '" + path + "': the STEP worker ended with status " +
      std::to_string(code) + " without a result");
  try
  {
    return ReadModel(worker.ModelFile);
  }
  catch (const std::runtime_error& e)
  {
    throw InputError("STEP file '" + path + "': the converted model could not be read back: " +
      e.what());
  }
}
} // namespace brt
