// BRepThickness: reading untrusted STEP files in a separate process.
//
// OpenCASCADE's STEP import and healing can crash (null entity references in damaged files) or
// loop (non-finite numbers reaching the healing). The reader therefore runs them in a worker
// process, brt_step_worker, which hands the converted model back through a model file
// (ModelIO.h). A crash, a time-out or a memory exhaustion of the worker becomes one InputError
// naming the file and the cause; the calling process (ParaView, pvpython, the batch) stays up.
#pragma once

#include "BRepConverter.h"

#include <string>

namespace brt
{
struct IsolationOptions
{
  /// Seconds the worker may take for reading, healing and converting; <= 0: no limit.
  double TimeLimit = 300.0;
  /// Address-space limit of the worker in MiB; 0: three quarters of the physical memory,
  /// < 0: no limit.
  double MemoryLimitMiB = 0.0;
  /// The worker executable; empty: FindStepWorker().
  std::string Worker;
};

/// The worker executable: $BRT_STEP_WORKER if set, else brt_step_worker next to the binary or
/// shared library holding this code (the plugin's folder, the utilities' folder), else the one
/// in the build tree. Throws std::runtime_error if none exists.
std::string FindStepWorker();

/// ConvertStepFile (BRepConverter.h) run by the worker process. Throws InputError naming the file
/// for bad input, for a worker that crashed, ran out of time or of memory; std::runtime_error
/// for an aborted conversion (options.Progress returned false) or a missing worker.
BRepModel ConvertStepFileIsolated(const std::string& path, const ConversionOptions& options,
  const IsolationOptions& isolation = IsolationOptions());
} // namespace brt
