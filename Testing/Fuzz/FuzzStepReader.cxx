// libFuzzer target of the reader core: one input is one STEP file, read, healed and converted in
// this process (the worker's code path: ConvertStepFile, with the text check first). With
// BRT_FUZZ_RAW=1 in the environment the text check is skipped (OpenCASCADE alone, as the reader
// read before the check existed), to measure what the check catches. Built only with
// -DBRT_FUZZ=ON and clang (Utilities/run-fuzzer.sh).
#include "BRepConverter.h"
#include "StepFile.h"

#include <STEPControl_Reader.hxx>
#include <Standard_Failure.hxx>
#include <TopoDS_Shape.hxx>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <unistd.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  static const bool raw = std::getenv("BRT_FUZZ_RAW") != nullptr;
  // In the working directory (run-fuzzer.sh's work folder), removed after each input: with
  // -fork each child process would otherwise leave its own file behind.
  static const std::string path = "brt-fuzz-" + std::to_string(::getpid()) + ".step";
  if (std::FILE* f = std::fopen(path.c_str(), "wb"))
  {
    std::fwrite(data, 1, size, f);
    std::fclose(f);
  }
  brt::ConversionOptions options;
  options.DeviationSamples = 50;
  try
  {
    if (raw)
    {
      STEPControl_Reader reader;
      if (reader.ReadFile(path.c_str()) == IFSelect_RetDone)
      {
        reader.TransferRoots();
        if (reader.NbShapes() > 0)
          (void)brt::ConvertShape(reader.OneShape(), options);
      }
    }
    else
      (void)brt::ConvertStepFile(path, options);
  }
  catch (const Standard_Failure&)
  {
  }
  catch (const std::exception&)
  {
  }
  std::remove(path.c_str());
  return 0;
}
