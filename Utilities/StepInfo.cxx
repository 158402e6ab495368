// Reads and converts STEP files and prints what the reader produces and how long it took.
// Usage: brt_step_info [--tolerance T] [--max-edge L] FILE.step [FILE.step ...]
#include "BRepConverter.h"
#include "StepFile.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <map>

int main(int argc, char** argv)
{
  brt::ConversionOptions options;
  int status = 0, files = 0;
  std::printf("%-34s %6s %6s %7s %7s %6s %9s %9s %9s %7s %7s %7s %7s\n", "file", "solids",
    "faces", "patches", "trimseg", "edges", "meshpts", "maxdev", "maxgap", "read_s", "heal_s",
    "conv_s", "mesh_s");
  for (int i = 1; i < argc; ++i)
  {
    if (!std::strcmp(argv[i], "--tolerance") && i + 1 < argc)
    {
      options.Tolerance = std::atof(argv[++i]);
      continue;
    }
    if (!std::strcmp(argv[i], "--max-edge") && i + 1 < argc)
    {
      options.MaxEdgeLength = std::atof(argv[++i]);
      continue;
    }
    ++files;
    try
    {
      const brt::BRepModel m = brt::ConvertStepFile(argv[i], options);
      const auto& s = m.Stats;
      const char* name = std::strrchr(argv[i], '/') ? std::strrchr(argv[i], '/') + 1 : argv[i];
      std::printf("%-34s %6d %6d %7d %7d %6d %9zu %9.2e %9.2e %7.2f %7.2f %7.2f %7.2f\n", name,
        s.Solids, s.Faces, s.Patches, s.TrimSegments, s.Edges, m.Mesh.NumberOfPoints(),
        s.MaxPatchDeviation, s.MaxLoopGap, s.ReadSeconds, s.HealSeconds, s.ConvertSeconds,
        s.MeshSeconds);
      std::map<std::string, int> kinds;
      for (const auto& f : m.Faces)
        ++kinds[std::string(brt::SurfaceKindName(f.Kind)) + (f.Rational ? "(rational)" : "")];
      std::printf("  surfaces:");
      for (const auto& k : kinds)
        std::printf(" %s=%d", k.first.c_str(), k.second);
      std::printf("\n");
      for (const auto& w : s.Warnings)
        std::printf("  warning: %s\n", w.c_str());
    }
    catch (const std::exception& e)
    {
      std::fprintf(stderr, "error: %s\n", e.what());
      status = 1;
    }
  }
  if (files == 0)
  {
    std::fprintf(stderr, "usage: %s [--tolerance T] [--max-edge L] FILE.step ...\n", argv[0]);
    return 2;
  }
  return status;
}
